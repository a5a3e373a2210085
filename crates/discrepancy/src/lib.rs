//! # discrepancy — fit slewing models, find what physics they miss
//!
//! [`diagnose`] goes where the paper stopped: when the linear model's optimum does not
//! reproduce the data, it
//! 1. fits the baseline model;
//! 2. **localises** the residual ([`localise`]): which output and which part of the record carry
//!    it, whether it is white (Ljung–Box), whether damping depends on amplitude (half-cycle log
//!    decrement against amplitude), whether it holds a mode the model lacks (ERA on the residual);
//! 3. refits with each **candidate effect** of the catalog (`plant::Effect`; starting values from
//!    the data and the localisation), in parallel;
//! 4. **scores** each by its error and the Bayesian information criterion with one Gaussian
//!    AR(1) error process per output, its innovation variance estimated from the fit,
//!    ΔBIC = Σ_o K ln(U_o,c/U_o,b) + Δk ln m ([`stats::delta_bic`], [`stats::ar1_innovations`]),
//!    and names the effect with the lowest ΔBIC if it is below −10 (very strong evidence) and
//!    its strength is resolved from zero (|value| > 2σ), else `"none"`;
//! 5. returns the augmented model, which can be diagnosed again for the next effect.
//!
//! Sensor quantization is not differentiable: it is found as a lattice in the samples
//! ([`quantization`]); the model is then refitted with that sensor's readings as intervals
//! [y − Δ/2, y + Δ/2] (`mem::Experiment::with_quantization`), so that the model is charged only
//! for leaving a reading's interval, not for the quantizer's rounding.

pub mod diagnose;
pub mod localise;
pub mod quantization;
pub mod stats;
pub mod study;
pub mod study_run;

pub use diagnose::{Candidate, DiagnoseOptions, Diagnosis, EffectParameter, diagnose};
pub use localise::{Localisation, OutputDiscrepancy, localise};
pub use models::{FitOutcome, FitRequest, Model, align, fit};

/// What can go wrong in a workflow.
#[derive(Debug, thiserror::Error)]
pub enum WorkflowError {
    /// The plant rejected something.
    #[error(transparent)]
    Plant(#[from] plant::PlantError),
    /// The identification failed.
    #[error(transparent)]
    Mem(#[from] mem::MemError),
    /// The model could not be fitted or simulated.
    #[error(transparent)]
    Model(#[from] models::ModelError),
    /// ERA failed.
    #[error(transparent)]
    Era(#[from] era::EraError),
}

/// The names of the catalog's effects (what `--only` accepts).
pub fn catalog_names() -> Vec<&'static str> {
    vec![
        "amplifier_saturation",
        "coulomb_friction",
        "quadratic_drag",
        "sensor_quantization",
        "output_offset",
        "time_delay",
        "unmodeled_mode",
    ]
}
