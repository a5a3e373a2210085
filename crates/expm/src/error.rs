//! The crate's error type.

/// Everything that can go wrong in this crate. Each variant names the offending argument.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ExpmError {
    /// A matrix that must be square is not.
    #[error("matrix `{name}` must be square, but it is {nrows}×{ncols}")]
    NotSquare {
        /// Which argument.
        name: &'static str,
        /// Its number of rows.
        nrows: usize,
        /// Its number of columns.
        ncols: usize,
    },
    /// Two arguments have shapes that do not fit together.
    #[error("matrix `{name}` is {nrows}×{ncols}, but {expected_rows}×{expected_cols} is required")]
    ShapeMismatch {
        /// Which argument.
        name: &'static str,
        /// Its number of rows.
        nrows: usize,
        /// Its number of columns.
        ncols: usize,
        /// The rows it must have.
        expected_rows: usize,
        /// The columns it must have.
        expected_cols: usize,
    },
    /// An entry is NaN or infinite.
    #[error("matrix `{name}` has a non-finite entry {value} at row {row}, column {col}")]
    NonFinite {
        /// Which argument.
        name: &'static str,
        /// Row of the first bad entry.
        row: usize,
        /// Column of the first bad entry.
        col: usize,
        /// The bad value.
        value: f64,
    },
    /// The sample interval is not a finite positive number.
    #[error("the sample interval must be finite and positive, got {h}")]
    InvalidInterval {
        /// The interval given.
        h: f64,
    },
    /// A matrix has no rows and columns.
    #[error("matrix `{name}` is 0×0: a model needs at least one state")]
    Empty {
        /// Which argument.
        name: &'static str,
    },
    /// A list of matrices has the wrong length.
    #[error("`{name}` holds {len} matrices, but there are {expected} parameters")]
    Count {
        /// Which argument.
        name: &'static str,
        /// Its length.
        len: usize,
        /// The number of parameters.
        expected: usize,
    },
    /// The time of the first sample is negative or not finite.
    #[error("the first sample's time must be finite and ≥ 0 (x(0) holds at t = 0), got {t0}")]
    InvalidStart {
        /// The time given.
        t0: f64,
    },
    /// The 1-norm of the matrix itself overflows `f64`.
    #[error("the 1-norm of the matrix to exponentiate overflows (entries near {largest:e}); scale the model")]
    NormOverflow {
        /// Its largest entry in magnitude.
        largest: f64,
    },
    /// A computed result holds NaN or infinite values although the arguments were finite.
    #[error("{what} is not finite (an overflow); scale the model or shorten the record")]
    NonFiniteResult {
        /// What was being computed.
        what: &'static str,
    },
    /// The result does not fit in `f64` (‖A‖ is too large, or e^A too large).
    #[error(
        "the matrix exponential overflowed (‖A‖₁ = {norm:e}, {squarings} squarings); \
         scale the model or shorten the sample interval"
    )]
    Overflow {
        /// One-norm of the matrix that was exponentiated.
        norm: f64,
        /// Number of squarings that were needed.
        squarings: u32,
    },
}
