//! # models — model descriptions as `mem` models (the adapter layer)
//!
//! `mem` fits any model that gives outputs and sensitivities; `plant` describes the slewing rig
//! of Garcia & Inman (Eqs. 17–21) and knows nothing of identification. This crate is the one
//! place where a description becomes something `mem` can fit, simulate or analyse:
//!
//! * [`slewing`]: a linear slewing model's free parameters as the MEM's P, with A(P), C(P)
//!   and their exact derivatives from the plant's num-dual assembly — the exact exponential path
//!   (paper Eq. 9);
//! * [`ode`]: a slewing model with nonlinear effects (saturation, dry friction, drag), whose
//!   outputs and sensitivities come from the forward sensitivity equations integrated by diffsol,
//!   with exact Jacobian products in num-dual;
//! * [`simulate()`](fn@simulate): a model's response, by whichever path it needs;
//! * [`structure`]: a structure model file's free parameters as a `mem::StateSpaceModel`, its
//!   expressions evaluated over num-dual for exact ∂A/∂P, ∂B/∂P, ∂C/∂P, ∂D/∂P, ∂x(0)/∂P;
//! * [`exponential`]: a model with nonlinear forces — the slewing rig with effects, or a
//!   structure with forces at its coordinates ([`StructureExponential`]) — by an exponential
//!   integrator whose kernel both share, with the exact derivatives of its recursion;
//! * [`sensors`]: a sensor's offset, scale and drift on any model's outputs;
//! * [`model`]: both kinds behind one [`Model`], the kind chosen from the file in one place;
//! * [`fit()`](fn@fit): fitting a model to a measured record (aligning its columns, weighting, the
//!   quantized readings of its sensors), with the curves around the fit.

pub mod exponential;
pub mod fit;
pub mod model;
pub mod ode;
pub mod sensors;
pub mod simulate;
pub mod slewing;
pub mod structure;

pub use exponential::{ExponentialResponse, StructureExponential};
pub use fit::{ExperimentOutcome, FitOutcome, FitRequest, align, fit, fit_experiments};
pub use model::{Integrator, ModeRow, Model, ModelEffect, ModelKind};
pub use ode::{NonlinearError, NonlinearResponse};
pub use simulate::{simulate, simulate_model};
pub use slewing::SlewingFitModel;
pub use structure::StructureFitModel;

/// The model's columns a record lacks, in words.
fn absent(missing: &[String]) -> String {
    if missing.is_empty() {
        "each is there, but in another order or role".into()
    } else {
        format!("missing: {}", missing.join(", "))
    }
}

/// What can go wrong between a model description and `mem`.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ModelError {
    /// The plant rejected something.
    #[error(transparent)]
    Plant(#[from] plant::PlantError),
    /// The structure model file rejected something.
    #[error(transparent)]
    Structure(#[from] ::structure::StructureError),
    /// A file could not be read.
    #[error("cannot read {path}: {source}")]
    Io {
        /// The file.
        path: String,
        /// The system's error.
        source: std::io::Error,
    },
    /// A parameter name the model does not have.
    #[error("unknown parameter `{name}`; the model's parameters are {valid}")]
    UnknownParameter {
        /// The name given.
        name: String,
        /// The valid names.
        valid: String,
    },
    /// A result that must be finite is not.
    #[error("{what} is not finite (the model's matrices overflow); check the model's values")]
    NonFinite {
        /// What was computed.
        what: String,
    },
    /// The identification failed.
    #[error(transparent)]
    Mem(#[from] mem::MemError),
    /// A simulation failed.
    #[error(transparent)]
    Simulation(#[from] NonlinearError),
    /// An effect of one kind of model added to the other.
    #[error("{effect} is an effect of the other kind of model; this is a {model:?} model")]
    WrongKind {
        /// The effect.
        effect: String,
        /// The model's kind.
        model: ModelKind,
    },
    /// The data's columns are not the model's outputs and inputs.
    #[error(
        "the data columns {data:?} do not match the model's outputs and inputs {model:?}; {}; name the header's columns as the model file does",
        absent(missing)
    )]
    Columns {
        /// Columns of the data (after the time column).
        data: Vec<String>,
        /// Outputs of the model, then its inputs.
        model: Vec<String>,
        /// The model's columns the data do not hold (empty: all are there, in another order
        /// or role).
        missing: Vec<String>,
    },
    /// A parameter asked to be both shared by every experiment and estimated per experiment.
    #[error(
        "parameter `{name}` is given both as shared (--free) and per experiment (--per-experiment); give it in one of them"
    )]
    SharedAndOwn {
        /// The parameter.
        name: String,
    },
}
