//! # discrepancy — fit slewing models, find what physics they miss
//!
//! [`fitting`] fits any slewing model (linear: exact exponential path; with nonlinear effects:
//! ODE path) to a measurement and returns the models and responses around the fit.

pub mod fitting;

pub use fitting::{FitOutcome, FitRequest, align, fit, response_model};

/// What can go wrong in a workflow.
#[derive(Debug, thiserror::Error)]
pub enum WorkflowError {
    /// The plant rejected something.
    #[error(transparent)]
    Plant(#[from] plant::PlantError),
    /// The identification failed.
    #[error(transparent)]
    Mem(#[from] mem::MemError),
    /// A simulation failed.
    #[error(transparent)]
    Simulation(#[from] nonlinear::NonlinearError),
    /// ERA failed.
    #[error(transparent)]
    Era(#[from] era::EraError),
    /// The data's columns are not the model's outputs.
    #[error("the data columns {data:?} do not match the model's outputs {model:?}")]
    Columns {
        /// Columns of the data (after the time column).
        data: Vec<String>,
        /// Outputs of the model.
        model: Vec<String>,
    },
}
