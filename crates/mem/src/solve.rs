//! The least-squares step of Eqs. 11–13 by a truncated SVD, with Levenberg–Marquardt damping.
//!
//! S is column-equilibrated, S̃ = S D⁻¹ with D = diag(‖S_{:,i}‖), and decomposed once per
//! iteration: a Householder QR S̃ = Q R (2mj² flops; faer's blocked QR and SVD carry more
//! overhead than arithmetic for the tall, narrow S of the MEM, j ≪ m) and faer's thin SVD of the
//! j×j factor, R = U_R Σ Vᵀ, so S̃ = (Q U_R) Σ Vᵀ — the thin SVD of S̃, with Uᵀr = U_Rᵀ(Qᵀr). Singular values below `rank_cutoff`·σ_max are
//! dropped (the step has no component along them). For damping μ ≥ 0 the step minimises
//! ‖S δ − r‖² + μ‖D δ‖²: δ = D⁻¹ V diag(σ_i/(σ_i² + μ)) Uᵀ r — μ = 0 is the Gauss–Newton step
//! of the paper (with the SVD instead of (SᵀS)⁻¹, which is never formed). Trying several μ
//! costs O(j²) each: the SVD is reused.

use crate::MemError;
use crate::vector::{dot, subtract_scaled, sum_squares};
use faer::{Mat, MatRef};

/// One iteration's decomposition of S and the projections of r.
pub(crate) struct StepSolver {
    /// Column scales D.
    pub scale: Vec<f64>,
    /// Singular values of S̃ (descending).
    pub singular_values: Vec<f64>,
    /// V (j × j).
    pub v: Mat<f64>,
    /// Uᵀ r.
    utr: Vec<f64>,
    /// Number of singular values kept.
    pub rank: usize,
}

impl StepSolver {
    /// Decomposes S (m × j, taken by value: it is overwritten) for the residual r.
    pub fn from_owned(s: Mat<f64>, r: &[f64], rank_cutoff: f64) -> Result<Self, MemError> {
        let j = s.ncols();
        if s.nrows() < j {
            return Err(MemError::Shape(format!("{} residuals cannot determine {j} parameters", s.nrows())));
        }
        let (r_factor, qtr, scale) = householder_qr(s, r);
        let SquareSvd { singular_values: sv, u, v } = square_svd(r_factor.as_ref())?;
        let utr: Vec<f64> = (0..j).map(|c| (0..j).map(|i| u[(i, c)] * qtr[i]).sum()).collect();
        let threshold = rank_cutoff * sv.first().copied().unwrap_or(0.0);
        let rank = sv.iter().filter(|x| **x > threshold && **x > 0.0).count();
        Ok(Self { scale, singular_values: sv, v, utr, rank })
    }

    /// The step for damping μ, and the decrease of ‖r − Sδ‖² it predicts.
    pub fn step(&self, mu: f64) -> (Vec<f64>, f64) {
        let j = self.scale.len();
        let mut delta = vec![0.0; j];
        let mut predicted = 0.0;
        for i in 0..self.rank {
            let sigma = self.singular_values[i];
            let coefficient = sigma / (sigma * sigma + mu) * self.utr[i];
            let kept = mu / (sigma * sigma + mu);
            predicted += self.utr[i] * self.utr[i] * (1.0 - kept * kept);
            for c in 0..j {
                delta[c] += self.v[(c, i)] * coefficient;
            }
        }
        for c in 0..j {
            delta[c] /= self.scale[c];
        }
        (delta, predicted)
    }

    /// The largest diagonal entry of S̃ᵀS̃ (= 1 after equilibration unless a column is zero).
    pub fn max_scaled_diagonal(&self) -> f64 {
        self.singular_values.first().map_or(1.0, |s| s * s)
    }
}

/// The least-squares solution δ of S δ ≈ r (m × j, m ≥ j) by the same column-equilibrated,
/// truncated SVD as the MEM's step (Eqs. 11–13 at μ = 0): singular values below
/// `rank_cutoff`·σ_max are dropped, so near-equal columns give the minimum-norm combination
/// instead of cancelling giants. For any linear least-squares problem a workflow poses (a
/// correction by a handful of basis functions, say), without forming SᵀS.
///
/// # Errors
/// [`MemError::Shape`] for fewer rows than columns or `r` of another length; [`MemError::Svd`].
pub fn truncated_svd_solve(s: Mat<f64>, r: &[f64], rank_cutoff: f64) -> Result<Vec<f64>, MemError> {
    if r.len() != s.nrows() {
        return Err(MemError::Shape(format!("{} residuals for a matrix of {} rows", r.len(), s.nrows())));
    }
    Ok(StepSolver::from_owned(s, r, rank_cutoff)?.step(0.0).0)
}

/// faer's SVD of the small j × j factor R: singular values (descending), U and V. Sequential,
/// with its workspace sized by faer: for j ≪ m the thread-pool dispatch of `Mat::thin_svd`
/// costs more than the decomposition.
fn square_svd(r: MatRef<'_, f64>) -> Result<SquareSvd, MemError> {
    use faer::linalg::svd::{ComputeSvdVectors, svd, svd_scratch};
    let j = r.nrows();
    let mut s = faer::diag::Diag::<f64>::zeros(j);
    let mut u = Mat::<f64>::zeros(j, j);
    let mut v = Mat::<f64>::zeros(j, j);
    let scratch = svd_scratch::<f64>(
        j,
        j,
        ComputeSvdVectors::Thin,
        ComputeSvdVectors::Thin,
        faer::Par::Seq,
        Default::default(),
    );
    let mut buffer = faer::dyn_stack::MemBuffer::new(scratch);
    svd(
        r,
        s.as_mut(),
        Some(u.as_mut()),
        Some(v.as_mut()),
        faer::Par::Seq,
        faer::dyn_stack::MemStack::new(&mut buffer),
        Default::default(),
    )
    .map_err(|_| MemError::Svd)?;
    Ok(SquareSvd { singular_values: (0..j).map(|i| s[i]).collect(), u, v })
}

/// Singular values (descending), U and V of a small square matrix.
struct SquareSvd {
    singular_values: Vec<f64>,
    u: Mat<f64>,
    v: Mat<f64>,
}

/// Column scales D (the column norms, 1 for a zero column) and the Householder QR of
/// S·D⁻¹ (m × j, m ≥ j), overwriting S: returns R (j × j, upper triangular), the first j
/// entries of Qᵀ r and D. O(m j²).
fn householder_qr(mut s: Mat<f64>, r: &[f64]) -> (Mat<f64>, Vec<f64>, Vec<f64>) {
    let (m, j) = (s.nrows(), s.ncols());
    let mut columns: Vec<&mut [f64]> = s
        .as_mut()
        .col_iter_mut()
        .map(|c| c.try_as_col_major_mut().expect("an owned Mat is column-major").as_slice_mut())
        .collect();
    let mut scale = Vec::with_capacity(j);
    for column in columns.iter_mut() {
        let mut norm = sum_squares(column).sqrt();
        if !norm.is_finite() {
            // Entries beyond 1e154 overflow the plain sum of squares; faer's norm rescales.
            norm = faer::ColRef::from_slice(column).norm_l2();
        }
        let d = if norm > 0.0 { norm } else { 1.0 };
        let inverse = 1.0 / d;
        column.iter_mut().for_each(|v| *v *= inverse);
        scale.push(d);
    }
    let mut b = r.to_vec();
    let mut diag = vec![0.0; j];
    for k in 0..j.min(m) {
        let (head, tail) = columns.split_at_mut(k + 1);
        let col = &mut head[k];
        let norm = sum_squares(&col[k..]).sqrt();
        if norm == 0.0 {
            diag[k] = 0.0;
            continue;
        }
        let alpha = if col[k] > 0.0 { -norm } else { norm };
        // ‖x − αe₁‖² = 2‖x‖(‖x‖ + |x₁|) with α = −sign(x₁)‖x‖: no cancellation, no extra pass.
        let vnorm2 = 2.0 * norm * (norm + col[k].abs());
        col[k] -= alpha; // v = x − αe₁, stored in place
        diag[k] = alpha;
        let apply = |target: &mut [f64]| {
            let f = 2.0 * dot(&col[k..], &target[k..]) / vnorm2;
            subtract_scaled(&mut target[k..], f, &col[k..]);
        };
        for target in tail.iter_mut() {
            apply(target);
        }
        apply(&mut b);
    }
    let r_factor = Mat::from_fn(j, j, |i, c| {
        if i == c {
            diag[c]
        } else if i < c {
            columns[c][i]
        } else {
            0.0
        }
    });
    (r_factor, b[..j].to_vec(), scale)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The QR route gives faer's thin SVD of the column-equilibrated matrix (singular values to
    /// rounding, right singular vectors up to sign), also with badly scaled columns, and the
    /// step at μ = 0 is the least-squares solution.
    #[test]
    fn qr_route_matches_the_direct_thin_svd_and_solves_least_squares() {
        let s = Mat::<f64>::from_fn(300, 3, |i, c| {
            ((7 * i + 3 * c) as f64 * 0.37).sin() * 10f64.powi(3 * c as i32)
        });
        let r: Vec<f64> = (0..300).map(|i| (i as f64 * 0.11).cos()).collect();
        let solver = StepSolver::from_owned(s.clone(), &r, 1e-12).unwrap();
        let norms: Vec<f64> = (0..3).map(|c| s.col(c).norm_l2()).collect();
        let equilibrated = Mat::from_fn(300, 3, |i, c| s[(i, c)] / norms[c]);
        let direct = equilibrated.thin_svd().unwrap();
        for i in 0..3 {
            assert!((solver.singular_values[i] - direct.S()[i]).abs() <= 1e-12 * direct.S()[0], "σ_{i}");
            let dot: f64 = (0..3).map(|row| solver.v[(row, i)] * direct.V()[(row, i)]).sum();
            assert!((dot.abs() - 1.0).abs() < 1e-9, "v_{i}");
        }
        // Normal equations hold at the least-squares step: Sᵀ(r − Sδ) = 0.
        let (delta, _) = solver.step(0.0);
        assert_eq!(truncated_svd_solve(s.clone(), &r, 1e-12).unwrap(), delta);
        assert!(matches!(truncated_svd_solve(s.clone(), &r[1..], 1e-12), Err(MemError::Shape(_))));
        for c in 0..3 {
            let g: f64 = (0..300)
                .map(|i| s[(i, c)] * (r[i] - (0..3).map(|l| s[(i, l)] * delta[l]).sum::<f64>()))
                .sum();
            assert!(g.abs() < 1e-9 * norms[c], "gradient {c}: {g}");
        }
    }
}
