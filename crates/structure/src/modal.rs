//! Modal damping over any scalar: D = M Φ diag(2ζ_iω_i) Φᵀ M.
//!
//! Φ holds the mass-normalised modes of K φ = ω² M φ (ΦᵀMΦ = I, ΦᵀKΦ = diag ω²). With the
//! Cholesky factor M = LLᵀ the problem becomes the symmetric eigenproblem S v = ω² v for
//! S = L⁻¹KL⁻ᵀ, Φ = L⁻ᵀV, and M Φ = L V, so D = (LV) diag(2ζ_iω_i) (LV)ᵀ. S is diagonalised by
//! cyclic Jacobi rotations computed in the caller's scalar: for a dual number every rotation
//! annihilates its off-diagonal entry exactly, value and derivative alike, so once the values
//! have converged one more sweep makes the derivatives exact too. Comparisons (pivots,
//! convergence, the order of the modes) use the real parts only.

use mem::Scalar;
use mem::nalgebra::DMatrix;
use num_dual::DualNum;

/// Sweeps before the eigen-solver gives up (it needs about ten for any size met in practice).
const MAX_SWEEPS: usize = 100;

/// Why modal damping cannot be formed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum ModalFailure {
    /// M or K is not symmetric.
    NotSymmetric,
    /// M is not positive definite.
    MassNotPositiveDefinite,
    /// Some ω² ≤ 0.
    StiffnessNotPositiveDefinite,
    /// Jacobi did not converge.
    NoConvergence,
}

impl std::fmt::Display for ModalFailure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            ModalFailure::NotSymmetric => "modal damping needs symmetric M and K",
            ModalFailure::MassNotPositiveDefinite => "modal damping needs a positive definite mass matrix",
            ModalFailure::StiffnessNotPositiveDefinite => {
                "modal damping needs a positive definite stiffness matrix (every ω² > 0, no rigid-body mode)"
            }
            ModalFailure::NoConvergence => "the Jacobi eigen-solver did not converge",
        })
    }
}

/// D = M Φ diag(2ζ_iω_i) Φᵀ M, with ζ_i given in order of increasing ω_i.
pub(crate) fn modal_damping<D: Scalar>(
    m: &DMatrix<D>,
    k: &DMatrix<D>,
    zeta: &[D],
) -> Result<DMatrix<D>, ModalFailure> {
    let n = m.nrows();
    if !symmetric(m) || !symmetric(k) || zeta.len() != n {
        return Err(ModalFailure::NotSymmetric);
    }
    let l = cholesky(m).ok_or(ModalFailure::MassNotPositiveDefinite)?;
    // S = L⁻¹ K L⁻ᵀ = L⁻¹ (L⁻¹ K)ᵀ for symmetric K.
    let x = forward_substitute(&l, k);
    let mut s = forward_substitute(&l, &x.transpose());
    for i in 0..n {
        for j in 0..i {
            let mean = (s[(i, j)] + s[(j, i)]) * 0.5;
            s[(i, j)] = mean;
            s[(j, i)] = mean;
        }
    }
    let v = jacobi(&mut s).ok_or(ModalFailure::NoConvergence)?;
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&a, &b| s[(a, a)].re().total_cmp(&s[(b, b)].re()));
    if order.iter().any(|&i| s[(i, i)].re() <= 0.0) {
        return Err(ModalFailure::StiffnessNotPositiveDefinite);
    }
    // W = L V; D = Σ_modes c_i w_i w_iᵀ with c_i = 2ζ_iω_i for the i-th lowest mode.
    let w = &l * &v;
    let mut d = DMatrix::from_element(n, n, D::zero());
    for (rank, &mode) in order.iter().enumerate() {
        let c = zeta[rank] * DualNum::sqrt(&s[(mode, mode)]) * 2.0;
        for i in 0..n {
            let ci = c * w[(i, mode)];
            for j in 0..n {
                d[(i, j)] += ci * w[(j, mode)];
            }
        }
    }
    Ok(d)
}

/// Whether a square matrix is symmetric to rounding (real parts).
fn symmetric<D: Scalar>(a: &DMatrix<D>) -> bool {
    let n = a.nrows();
    if a.ncols() != n {
        return false;
    }
    let scale = a.iter().map(|v| v.re().abs()).fold(0.0, f64::max);
    (0..n).all(|i| (0..i).all(|j| (a[(i, j)].re() - a[(j, i)].re()).abs() <= 1e-12 * scale))
}

/// The lower Cholesky factor L of a symmetric positive definite M = LLᵀ (its lower triangle is
/// read), or `None` if a pivot is not positive.
pub(crate) fn cholesky<D: Scalar>(m: &DMatrix<D>) -> Option<DMatrix<D>> {
    let n = m.nrows();
    let mut l = DMatrix::from_element(n, n, D::zero());
    for j in 0..n {
        let mut pivot = m[(j, j)];
        for k in 0..j {
            pivot -= l[(j, k)] * l[(j, k)];
        }
        let value = pivot.re();
        if !(value.is_finite() && value > 0.0) {
            return None;
        }
        let diagonal = DualNum::sqrt(&pivot);
        l[(j, j)] = diagonal;
        for i in j + 1..n {
            let mut sum = m[(i, j)];
            for k in 0..j {
                sum -= l[(i, k)] * l[(j, k)];
            }
            l[(i, j)] = sum / diagonal;
        }
    }
    Some(l)
}

/// L⁻¹ B for lower triangular L.
fn forward_substitute<D: Scalar>(l: &DMatrix<D>, b: &DMatrix<D>) -> DMatrix<D> {
    let mut x = b.clone();
    for col in 0..b.ncols() {
        for i in 0..l.nrows() {
            let mut sum = x[(i, col)];
            for k in 0..i {
                sum -= l[(i, k)] * x[(k, col)];
            }
            x[(i, col)] = sum / l[(i, i)];
        }
    }
    x
}

/// Diagonalises the symmetric S in place by cyclic Jacobi rotations and returns the orthogonal
/// V with S_in = V S_out Vᵀ (eigenvectors in columns), or `None` without convergence.
pub(crate) fn jacobi<D: Scalar>(s: &mut DMatrix<D>) -> Option<DMatrix<D>> {
    let n = s.nrows();
    let mut v = DMatrix::from_fn(n, n, |i, j| if i == j { D::one() } else { D::zero() });
    for _ in 0..MAX_SWEEPS {
        let off: f64 =
            (0..n).flat_map(|i| (0..i).map(move |j| (i, j))).map(|(i, j)| s[(i, j)].re().powi(2)).sum();
        let diagonal: f64 = (0..n).map(|i| s[(i, i)].re().powi(2)).sum();
        if !(off.is_finite() && diagonal.is_finite()) {
            return None;
        }
        // Once the values have converged, one more sweep annihilates what is left of the
        // derivatives' off-diagonal part (each rotation zeroes its entry exactly).
        let polish = off <= f64::EPSILON * f64::EPSILON * (diagonal + 2.0 * off);
        for p in 0..n {
            for q in p + 1..n {
                rotate(s, &mut v, p, q);
            }
        }
        if polish {
            return Some(v);
        }
    }
    None
}

/// One Jacobi rotation in the (p, q) plane that zeroes S_pq (value and derivatives).
fn rotate<D: Scalar>(s: &mut DMatrix<D>, v: &mut DMatrix<D>, p: usize, q: usize) {
    let b = s[(p, q)];
    let d = (s[(q, q)] - s[(p, p)]) * 0.5;
    if b.re() == 0.0 && d.re() == 0.0 {
        return; // a repeated eigenvalue with nothing to rotate: leave it
    }
    // t = tan θ, the smaller root of b t² + 2 d t − b = 0 (|θ| ≤ π/4).
    let root = DualNum::sqrt(&(d * d + b * b));
    let t = if d.re() >= 0.0 { b / (d + root) } else { b / (d - root) };
    let c = DualNum::recip(&DualNum::sqrt(&(t * t + D::one())));
    let sn = t * c;
    let n = s.nrows();
    s[(p, p)] -= t * b;
    s[(q, q)] += t * b;
    s[(p, q)] = D::zero();
    s[(q, p)] = D::zero();
    for r in 0..n {
        if r != p && r != q {
            let (srp, srq) = (s[(r, p)], s[(r, q)]);
            let new_p = c * srp - sn * srq;
            let new_q = sn * srp + c * srq;
            s[(r, p)] = new_p;
            s[(p, r)] = new_p;
            s[(r, q)] = new_q;
            s[(q, r)] = new_q;
        }
        let (vrp, vrq) = (v[(r, p)], v[(r, q)]);
        v[(r, p)] = c * vrp - sn * vrq;
        v[(r, q)] = sn * vrp + c * vrq;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn jacobi_diagonalises_a_symmetric_matrix() {
        let n = 7;
        // A Hilbert matrix plus a diagonal: symmetric with distinct eigenvalues.
        let s0 = DMatrix::from_fn(n, n, |i, j| {
            1.0 / (i + j + 1) as f64 + if i == j { i as f64 * 0.3 } else { 0.0 }
        });
        let mut s = s0.clone();
        let v = jacobi(&mut s).unwrap();
        let identity = DMatrix::<f64>::identity(n, n);
        assert!((v.transpose() * &v - &identity).amax() < 1e-14);
        let diagonal = DMatrix::from_diagonal(&s.diagonal());
        assert!((&v * diagonal * v.transpose() - &s0).amax() < 1e-13 * s0.amax());
        let scale = s.diagonal().amax();
        assert!((0..n).all(|i| (0..n).all(|j| i == j || s[(i, j)].abs() <= 1e-20 * scale)), "{s}");
    }

    #[test]
    fn cholesky_rejects_what_is_not_positive_definite() {
        let m = DMatrix::from_row_slice(2, 2, &[4.0, 2.0, 2.0, 5.0]);
        let l = cholesky(&m).unwrap();
        assert!((&l * l.transpose() - &m).amax() < 1e-15);
        assert!(cholesky(&DMatrix::from_row_slice(2, 2, &[1.0, 2.0, 2.0, 1.0])).is_none());
        assert!(cholesky(&DMatrix::from_row_slice(1, 1, &[f64::NAN])).is_none());
        let k = DMatrix::from_row_slice(2, 2, &[1.0, 0.0, 0.0, -1.0]);
        assert_eq!(modal_damping(&m, &k, &[0.1, 0.1]), Err(ModalFailure::StiffnessNotPositiveDefinite));
        let skew = DMatrix::from_row_slice(2, 2, &[1.0, 0.5, 0.0, 1.0]);
        assert_eq!(modal_damping(&m, &skew, &[0.1, 0.1]), Err(ModalFailure::NotSymmetric));
    }
}
