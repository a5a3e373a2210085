//! The crate's error type.

use crate::ExprError;

/// What can go wrong with a structure model file or its model.
///
/// Errors found in a file carry its origin (the path, or whatever name the text was given) and
/// the 1-based line and column of the offending value — for an expression, of the offending
/// character inside the string literal — and print as `origin:line:column: …` on one line.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum StructureError {
    /// The file could not be read.
    #[error("cannot read model file {path}: {source}")]
    Io {
        /// Path of the file.
        path: String,
        /// The operating-system error.
        source: std::io::Error,
    },
    /// The text is not valid RON or does not fit the schema (unknown or missing fields, wrong
    /// types).
    #[error("{origin}:{line}:{column}: {message}")]
    Syntax {
        /// File name (or the origin given to [`crate::StructureModel::from_ron`]).
        origin: String,
        /// 1-based line.
        line: usize,
        /// 1-based column (in characters).
        column: usize,
        /// What is wrong, as RON reports it.
        message: String,
    },
    /// An entry's expression does not parse, or names something that is not a parameter.
    #[error("{origin}:{line}:{column}: in `{field}`: {source}")]
    Expression {
        /// File name.
        origin: String,
        /// 1-based line of the offending character.
        line: usize,
        /// 1-based column of the offending character.
        column: usize,
        /// Path of the entry, e.g. `structure.stiffness[0][1]`.
        field: String,
        /// What is wrong with the expression.
        source: ExprError,
    },
    /// A number is impossible where it stands (not finite, outside its bounds, …).
    #[error("{origin}:{line}:{column}: `{field}` = {value}: {requirement}")]
    InvalidValue {
        /// File name.
        origin: String,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// Path of the value, e.g. `parameters.k1.bounds`.
        field: String,
        /// The value found.
        value: f64,
        /// What it must be.
        requirement: String,
    },
    /// The file is well-formed RON but describes an impossible model: a matrix of the wrong
    /// size, an unknown or repeated name, a singular mass matrix, …
    #[error("{origin}:{line}:{column}: `{field}`: {message}")]
    Invalid {
        /// File name.
        origin: String,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// Path of the offending part, e.g. `outputs[1].measures`.
        field: String,
        /// What is wrong and what to do.
        message: String,
    },
    /// A parameter name that the model does not declare.
    #[error("unknown parameter `{name}`; valid names are: {valid}")]
    UnknownParameter {
        /// The name given.
        name: String,
        /// Comma-separated list of the model's parameter names.
        valid: String,
    },
    /// A parameter set to NaN or an infinity.
    #[error("parameter `{name}` cannot be set to {value}; give a finite number")]
    NotFinite {
        /// The parameter.
        name: String,
        /// The value given.
        value: f64,
    },
    /// A parameter set outside its declared bounds.
    #[error("parameter `{name}` cannot be set to {value}: its bounds are [{lower}, {upper}]")]
    OutOfBounds {
        /// The parameter.
        name: String,
        /// The value given.
        value: f64,
        /// Its lower bound.
        lower: f64,
        /// Its upper bound.
        upper: f64,
    },
    /// A parameter vector of the wrong length.
    #[error(
        "{got} parameter values given, but the model has {expected} parameters (all of them, in declaration order)"
    )]
    ParameterCount {
        /// The number of parameters the model declares.
        expected: usize,
        /// The number of values given.
        got: usize,
    },
    /// The matrices cannot be assembled at the given parameter values.
    #[error("cannot assemble {part} at these parameter values: {reason}")]
    Assembly {
        /// What failed, e.g. `the mass matrix M`.
        part: String,
        /// Why, and what to check.
        reason: String,
    },
    /// An effect that cannot act on this model.
    #[error("invalid effect: {reason}")]
    InvalidEffect {
        /// What is wrong and what to do.
        reason: String,
    },
    /// The eigenvalues of A could not be computed.
    #[error("the eigenvalues of A could not be computed: {reason}")]
    Eigen {
        /// The eigen-solver's report.
        reason: String,
    },
}
