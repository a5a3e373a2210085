//! The crate's error type.

/// A boxed error from a user's model.
pub type BoxedError = Box<dyn std::error::Error + Send + Sync + 'static>;

/// What can go wrong in an identification.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum MemError {
    /// The exponential layer failed (shape, non-finite values, overflow).
    #[error(transparent)]
    Expm(#[from] expm::ExpmError),
    /// The user's model failed to evaluate at some parameters.
    #[error("the model of experiment {experiment} could not be evaluated at {parameters}: {source}")]
    Model {
        /// Index of the experiment.
        experiment: usize,
        /// The parameters at which it failed, as `name = value` pairs.
        parameters: String,
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
    /// A parameter's specification is unusable.
    #[error("parameter `{name}`: {message}")]
    Parameter {
        /// The parameter's name.
        name: String,
        /// What is wrong.
        message: String,
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
    /// A CSV record is unusable (1-based line and column).
    #[error("{origin}:{line}{}: {message}", column.map(|c| format!(":{c}")).unwrap_or_default())]
    Csv {
        /// The file (or other origin) of the text.
        origin: String,
        /// 1-based line.
        line: usize,
        /// 1-based column (field), when one field is at fault.
        column: Option<usize>,
        /// What is wrong.
        message: String,
    },
    /// A file could not be read.
    #[error("cannot read {path}: {source}")]
    Io {
        /// The file.
        path: String,
        /// The system's error.
        source: std::io::Error,
    },
    /// Shapes of model, data and settings do not fit together.
    #[error("shape mismatch: {0}")]
    Shape(String),
    /// The model's outputs and the data's columns differ.
    #[error(
        "experiment {experiment}: the model's outputs are [{}] but the data's are [{}]; \
         select or reorder the data's columns to match",
        model.join(", "),
        data.join(", ")
    )]
    OutputNames {
        /// Index of the experiment.
        experiment: usize,
        /// The model's output names.
        model: Vec<String>,
        /// The data's output names.
        data: Vec<String>,
    },
    /// The model's inputs and the data's inputs differ.
    #[error(
        "experiment {experiment}: the model is driven by [{}] but the data carry the inputs [{}]",
        model.join(", "),
        data.join(", ")
    )]
    InputNames {
        /// Index of the experiment.
        experiment: usize,
        /// The model's input names.
        model: Vec<String>,
        /// The data's input names.
        data: Vec<String>,
    },
    /// The analytic sensitivities disagree with central differences.
    #[error(
        "the sensitivities of `{parameter}` disagree with central differences (relative mismatch \
         {mismatch:.2e}, tolerance {tolerance:.1e}): the model's derivative (∂A/∂P, ∂C/∂P or ∂x(0)/∂P) \
         is wrong; fix it, or skip the check if the model is known to be right"
    )]
    DerivativeMismatch {
        /// The parameter whose column disagrees.
        parameter: String,
        /// ‖S_fd − S‖/‖S‖ for its column.
        mismatch: f64,
        /// The tolerance it exceeded.
        tolerance: f64,
    },
    /// The model is unstable at the start.
    #[error(
        "experiment {experiment}: the model is unstable at the start values (an eigenvalue with real part \
         {growth:.3e} 1/s: the response grows by e^{:.1} over the record); start from values that give a \
         stable model",
        growth * duration
    )]
    Unstable {
        /// Index of the experiment.
        experiment: usize,
        /// The largest real part of the eigenvalues of A.
        growth: f64,
        /// The record's duration.
        duration: f64,
    },
    /// Nothing to fit: the data or the model's response carry no information.
    #[error("experiment {experiment}: {message}")]
    NothingToFit {
        /// Index of the experiment.
        experiment: usize,
        /// What is empty.
        message: String,
    },
    /// The SVD did not converge.
    #[error("the singular value decomposition did not converge")]
    Svd,
}
