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
