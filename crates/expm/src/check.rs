//! Argument validation shared by every entry point.

use crate::ExpmError;
use faer::MatRef;

/// Fails unless `a` is square.
pub(crate) fn square(name: &'static str, a: MatRef<'_, f64>) -> Result<usize, ExpmError> {
    if a.nrows() != a.ncols() {
        return Err(ExpmError::NotSquare { name, nrows: a.nrows(), ncols: a.ncols() });
    }
    Ok(a.nrows())
}

/// Fails unless `a` is `rows × cols`.
pub(crate) fn shape(
    name: &'static str,
    a: MatRef<'_, f64>,
    rows: usize,
    cols: usize,
) -> Result<(), ExpmError> {
    if a.nrows() != rows || a.ncols() != cols {
        return Err(ExpmError::ShapeMismatch {
            name,
            nrows: a.nrows(),
            ncols: a.ncols(),
            expected_rows: rows,
            expected_cols: cols,
        });
    }
    Ok(())
}

/// Fails on the first NaN or infinite entry (column-major order).
pub(crate) fn finite(name: &'static str, a: MatRef<'_, f64>) -> Result<(), ExpmError> {
    for col in 0..a.ncols() {
        for row in 0..a.nrows() {
            let value = a[(row, col)];
            if !value.is_finite() {
                return Err(ExpmError::NonFinite { name, row, col, value });
            }
        }
    }
    Ok(())
}

/// Fails unless a list has one entry per parameter.
pub(crate) fn count(name: &'static str, len: usize, expected: usize) -> Result<(), ExpmError> {
    if len != expected {
        return Err(ExpmError::Count { name, len, expected });
    }
    Ok(())
}
