//! e^A by scaling and squaring (Al-Mohy & Higham 2009a).

use crate::pade::{self, Target};
use crate::{ExpmError, check};
use faer::{Mat, MatRef};

/// The matrix exponential e^A.
///
/// Scaling and squaring with a diagonal Padé approximant of degree 3, 5, 7, 9 or 13, chosen by
/// the backward-error bounds of Al-Mohy & Higham (2009, "A new scaling and squaring algorithm
/// for the matrix exponential"), which use norms of matrix powers to avoid over-scaling.
///
/// # Errors
/// [`ExpmError::NotSquare`] for a non-square `a`, [`ExpmError::NonFinite`] for a NaN or
/// infinite entry, [`ExpmError::Overflow`] when e^A does not fit in `f64`.
///
/// # Example
/// ```
/// use faer::mat;
/// // The rotation generator: e^A is a rotation by one radian.
/// let a = mat![[0.0, 1.0], [-1.0, 0.0]];
/// let e = expm::expm(a.as_ref()).unwrap();
/// assert!((e[(0, 0)] - 1f64.cos()).abs() < 1e-15);
/// assert!((e[(0, 1)] - 1f64.sin()).abs() < 1e-15);
/// ```
pub fn expm(a: MatRef<'_, f64>) -> Result<Mat<f64>, ExpmError> {
    let n = check::square("a", a)?;
    check::finite("a", a)?;
    if n == 0 {
        return Ok(Mat::zeros(0, 0));
    }
    if is_upper_triangular(a.transpose()) && !is_upper_triangular(a) {
        // e^{Aᵀ} = (e^A)ᵀ: a lower triangular matrix gets the triangular treatment too.
        return Ok(expm(a.transpose())?.transpose().to_owned());
    }
    let scaled = pade::choose(&a.to_owned(), Target::Exponential)?;
    let parts = pade::evaluate(&scaled);
    let mut r = pade::quotient(&parts.u, &parts.v).0;
    let triangular = is_upper_triangular(a);
    if triangular {
        exact_diagonals(&mut r, a, scaled.squarings);
    }
    for i in (0..scaled.squarings).rev() {
        r = crate::kernel::mul(&r, &r);
        if triangular {
            exact_diagonals(&mut r, a, i);
        }
    }
    overflow_check(r, a, scaled.squarings)
}

fn is_upper_triangular(a: MatRef<'_, f64>) -> bool {
    (0..a.ncols()).all(|j| (j + 1..a.nrows()).all(|i| a[(i, j)] == 0.0))
}

/// Code Fragment 2.1 of Al-Mohy & Higham (2009a): when T is upper triangular, the diagonal of
/// e^{2⁻ⁱT} is exp(2⁻ⁱ t_kk) and its first superdiagonal has the closed form of Higham
/// (2008, Eq. 10.42); recomputing them after each squaring removes the error that squaring
/// would otherwise amplify.
fn exact_diagonals(x: &mut Mat<f64>, t: MatRef<'_, f64>, i: u32) {
    let scale = 0.5f64.powi(i as i32);
    let n = t.nrows();
    for k in 0..n {
        x[(k, k)] = (scale * t[(k, k)]).exp();
    }
    for k in 0..n.saturating_sub(1) {
        let (l1, l2, t12) = (scale * t[(k, k)], scale * t[(k + 1, k + 1)], scale * t[(k, k + 1)]);
        let mean = 0.5 * (l1 + l2);
        let half_gap = 0.5 * (l1 - l2);
        x[(k, k + 1)] = t12 * mean.exp() * sinch(half_gap);
    }
}

/// sinh(x)/x, by its Taylor series near zero where the quotient would cancel.
fn sinch(x: f64) -> f64 {
    let x2 = x * x;
    if x.abs() < 0.0135 { 1.0 + (x2 / 6.0) * (1.0 + (x2 / 20.0) * (1.0 + x2 / 42.0)) } else { x.sinh() / x }
}

/// Returns `m` if all its entries are finite, else [`ExpmError::Overflow`].
fn overflow_check(m: Mat<f64>, a: MatRef<'_, f64>, squarings: u32) -> Result<Mat<f64>, ExpmError> {
    if check::finite("result", m.as_ref()).is_err() {
        return Err(ExpmError::Overflow { norm: crate::norm1(a), squarings });
    }
    Ok(m)
}
