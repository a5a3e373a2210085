//! The crate's error type.

/// What can go wrong with a slewing model.
#[derive(Debug, thiserror::Error)]
pub enum PlantError {
    /// The model file is not valid RON or does not match the schema.
    #[error("{origin}:{line}:{column}: {message}")]
    Syntax {
        /// File name (or `<string>`).
        origin: String,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// What is wrong.
        message: String,
    },
    /// A value is physically impossible.
    #[error("{origin}:{line}:{column}: field `{field}` = {value}: {requirement}")]
    InvalidValue {
        /// File name (or `<string>`).
        origin: String,
        /// 1-based line of the field (0 when the value did not come from a file).
        line: usize,
        /// 1-based column of the field.
        column: usize,
        /// Field path, e.g. `beam.length`.
        field: String,
        /// The value given.
        value: f64,
        /// What it must be.
        requirement: String,
    },
    /// A parameter name is not one of the model's.
    #[error("unknown parameter `{name}`; valid names are: {valid}")]
    UnknownParameter {
        /// The name given.
        name: String,
        /// Comma-separated list of valid names.
        valid: String,
    },
    /// The file could not be read.
    #[error("cannot read model file {path}: {source}")]
    Io {
        /// Path of the file.
        path: String,
        /// The operating-system error.
        source: std::io::Error,
    },
    /// The beam layer rejected the derived beam.
    #[error(transparent)]
    Beam(#[from] beam_modes::BeamError),
    /// The eigen-decomposition did not converge.
    #[error("the eigen-decomposition of A did not converge: {0}")]
    Eigen(String),
    /// The mass matrix is singular (cannot happen for physical values).
    #[error("the mass matrix is singular; check the inertias")]
    SingularMass,
}
