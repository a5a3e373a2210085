//! # discrepancy — fit slewing models, find what physics they miss
//!
//! [`fitting`] fits any slewing model (linear: exact exponential path; with nonlinear effects:
//! ODE path) to a measurement and returns the models and responses around the fit.
//!
//! [`diagnose`] goes where the paper stopped: when the linear model's optimum does not
//! reproduce the data, it
//! 1. fits the baseline model;
//! 2. **localises** the residual ([`localise`]): which output and which part of the record carry
//!    it, whether it is white (Ljung–Box), whether damping depends on amplitude (half-cycle log
//!    decrement against amplitude), whether it holds a mode the model lacks (ERA on the residual);
//! 3. refits with each **candidate effect** of the catalog (`plant::Effect`; starting values from
//!    the data and the localisation), in parallel;
//! 4. **scores** each by its error and the Bayesian information criterion with the noise
//!    variance estimated from the fit, ΔBIC = m ln(‖E_c‖²/‖E_b‖²) + Δk ln m, and names the effect
//!    with the lowest ΔBIC if it is below −10 (very strong evidence), else `"none"`;
//! 5. returns the augmented model, which can be diagnosed again for the next effect.
//!
//! Sensor quantization is not differentiable: it is found as a lattice in the samples
//! ([`quantization`]) and scored by quantizing the baseline's output.

pub mod diagnose;
pub mod fitting;
pub mod localise;
pub mod quantization;
pub mod stats;
pub mod study;
pub mod study_run;

pub use diagnose::{Candidate, DiagnoseOptions, Diagnosis, EffectParameter, diagnose};
pub use fitting::{FitOutcome, FitRequest, align, fit, response_model};
pub use localise::{Localisation, OutputDiscrepancy, localise};

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
