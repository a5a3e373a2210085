//! The crate's error type.

/// What can go wrong when computing beam modes.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BeamError {
    /// A property must be finite and positive (length, EI, ρ) or non-negative (a, k).
    #[error("beam property `{name}` = {value} is invalid: it must be {requirement}")]
    InvalidProperty {
        /// The property's name.
        name: &'static str,
        /// The value given.
        value: f64,
        /// What it must be.
        requirement: &'static str,
    },
    /// Zero modes were requested.
    #[error("at least one mode must be requested (n_modes = 0)")]
    NoModes,
    /// The root finder did not converge (should not happen for valid input).
    #[error("the root of mode {mode} was not found in [{lower}, {upper}] (κ = {kappa})")]
    RootNotFound {
        /// 1-based mode number.
        mode: usize,
        /// Lower end of the bracket.
        lower: f64,
        /// Upper end of the bracket.
        upper: f64,
        /// Dimensionless root stiffness.
        kappa: f64,
    },
}
