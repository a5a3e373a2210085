//! The crate's error type.

/// A boxed error from a user's model.
pub type BoxedError = Box<dyn std::error::Error + Send + Sync + 'static>;

/// What can go wrong in an identification.
#[derive(Debug, thiserror::Error)]
pub enum MemError {
    /// The exponential layer failed (shape, NaN, overflow).
    #[error(transparent)]
    Expm(#[from] expm::ExpmError),
    /// The user's model failed to evaluate at some parameters.
    #[error("the model of experiment {experiment} could not be evaluated at P = {parameters:?}: {source}")]
    Model {
        /// Index of the experiment.
        experiment: usize,
        /// Parameters at which it failed.
        parameters: Vec<f64>,
        /// The model's own error.
        source: BoxedError,
    },
    /// A setting of the solver is out of range.
    #[error("setting `{name}` = {value} is invalid: {requirement}")]
    InvalidSetting {
        /// The setting.
        name: &'static str,
        /// The value given.
        value: f64,
        /// What it must be.
        requirement: &'static str,
    },
    /// Measured data are unusable.
    #[error("invalid data: {0}")]
    InvalidData(String),
    /// One sample of the measured data is unusable (0-based sample index).
    #[error("invalid data at sample {sample}: {message}")]
    Sample {
        /// Index of the sample.
        sample: usize,
        /// What is wrong with it.
        message: String,
    },
    /// Shapes of model, data and settings do not fit together.
    #[error("shape mismatch: {0}")]
    Shape(String),
    /// The SVD did not converge.
    #[error("the singular value decomposition did not converge")]
    Svd,
}
