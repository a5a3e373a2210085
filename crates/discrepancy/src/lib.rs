//! # discrepancy — find what physics a fitted slewing model misses
//!
//! [`diagnose()`] goes where the paper stopped: when the linear model's optimum does not
//! reproduce the data, it
//! 1. fits the baseline model;
//! 2. **localises** the residual ([`localise()`](localise::localise)): which output and which part of the record carry
//!    it, whether it is white (Ljung–Box), whether damping depends on amplitude, whether it holds
//!    a mode the model lacks (ERA on the residual, which seeds the unmodeled-mode candidate; on
//!    a record forced by measured inputs, the frequencies where a mode driven by them would
//!    explain most of the residual, [`frf`]; on a forced structure, the bodies hung on a
//!    coordinate whose reaction — the exact sensitivity of the outputs to a vanishing appendage's
//!    mass, mem's Eq. 9 — explains more of the whitened residual than a rigid mass there,
//!    [`frf::AppendageScan`]);
//! 3. refits with each **candidate effect** of the catalog ([`diagnose::catalog`]; starting
//!    values from the model and the data), in parallel;
//! 4. **scores** every candidate by the same likelihood of the same data — Gaussian AR(1) noise
//!    per output, its parameters profiled ([`diagnose::evidence`]); on a record whose measured
//!    force carries noise, that noise (its level read from the force's own quiet band where it
//!    has one) through a linear model's exact sampled response (the discrete Lyapunov
//!    equation, [`frf::NoiseResponse`]) beside the sensor's floor, predicted to the order at
//!    which its error converges (errors in variables; Pintelon & Schoukens 2012, §7.2) — in
//!    sample (ΔBIC) and on
//!    held-out blocks (fitted on alternate blocks, scored on the others), with the model's own
//!    linear parameters freed as well so that a parameter mismatch is not named as an effect;
//! 5. names the effect that passes every test with the most held-out evidence, or answers
//!    `none` with what the residual still holds ([`diagnose::ResidualStructure`]);
//! 6. returns the augmented model, which can be diagnosed again for the next effect.
//!
//! Sensor quantization is a measurement model, found as a lattice in the raw readings while the
//! signal moves ([`quantization`]), named only when its step is comparable to the noise. Single
//! readings far outside the record's own motion — spikes, dropouts — are set aside first and
//! reported ([`glitch`]).

pub mod diagnose;
pub mod frf;
pub mod glitch;
pub mod localise;
pub mod quantization;
pub mod stats;

pub use diagnose::{
    Candidate, DiagnoseOptions, Diagnosis, EffectParameter, Evidence, Observe, Quiet, RIVAL_MARGIN, Verdict,
    diagnose, diagnose_observed,
};
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
    /// A candidate without a full refit cannot be scored out of sample.
    #[error("candidate `{0}` has no full refit to start its held-out refits from")]
    Unscored(String),
    /// A slewing model driven by measured inputs: the rig's catalog sizes its candidates from
    /// the step the servo answers (a structure file may be driven).
    #[error(
        "diagnose takes the slewing rig's step response only: this slewing model is driven by {inputs}; remove its `inputs` and give the step-response record"
    )]
    Driven {
        /// The input columns.
        inputs: String,
    },
    /// Too few readings to score candidates on half the record each.
    #[error(
        "the record is too short to diagnose: {residuals} readings for the models it asks to try, of up to \
         {parameters} parameters; each half of the record must hold 10 readings per parameter, so give at least \
         {needed} readings (samples × outputs; a longer record may show more to try, and ask for more)"
    )]
    TooShort {
        /// Samples × outputs of the record as fitted.
        residuals: usize,
        /// The largest candidate's parameter count. The catalog's trials depend on what the
        /// record's residual shows (a mode seeded where it rings), so a longer record may ask
        /// for more.
        parameters: usize,
        /// The readings needed.
        needed: usize,
    },
    /// A setting of the diagnosis is outside its range.
    #[error("diagnose setting `{field}` is {value}: it must be {need}")]
    Setting {
        /// The [`DiagnoseOptions`] field.
        field: &'static str,
        /// Its value.
        value: f64,
        /// What it must be.
        need: &'static str,
    },
}

/// The effect kinds `diagnose` tries (what `--only` accepts): the whole catalog but a sensor's
/// crosstalk and a sensor read late, which are set against a named effect, not named
/// themselves.
pub fn catalog_kinds() -> Vec<plant::EffectKind> {
    use plant::EffectKind::{SensorCrosstalk, SensorLag};
    plant::EffectKind::ALL.into_iter().filter(|k| !matches!(k, SensorCrosstalk | SensorLag)).collect()
}
