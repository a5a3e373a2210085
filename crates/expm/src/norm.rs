//! One-norms: exact, and estimated for matrix powers without forming them.
//!
//! The estimator is Hager's method (Higham 1988, LAPACK `dlacon`) with Higham's extra
//! alternating-sign test vector, applied to an operator given only through products with a
//! vector and its transpose, so that ‖Bᵖ‖₁ costs O(p·n²) instead of O(n³).

use faer::MatRef;

/// Induced one-norm: the largest absolute column sum.
pub fn norm1(a: MatRef<'_, f64>) -> f64 {
    (0..a.ncols()).map(|j| (0..a.nrows()).map(|i| a[(i, j)].abs()).sum::<f64>()).fold(0.0, f64::max)
}

/// A linear operator known only through y = B x and y = Bᵀ x.
pub(crate) trait Operator {
    fn dim(&self) -> usize;
    fn apply(&self, x: &[f64], y: &mut [f64], transpose: bool);
}

/// The product of a list of square matrices, B = F₁ F₂ ⋯ F_q (each applied to a vector).
pub(crate) struct Product<'a> {
    pub factors: Vec<MatRef<'a, f64>>,
}

impl Operator for Product<'_> {
    fn dim(&self) -> usize {
        self.factors[0].nrows()
    }

    fn apply(&self, x: &[f64], y: &mut [f64], transpose: bool) {
        let n = self.dim();
        let mut cur = x.to_vec();
        let mut next = vec![0.0; n];
        let order: Vec<&MatRef<'_, f64>> =
            if transpose { self.factors.iter().collect() } else { self.factors.iter().rev().collect() };
        for f in order {
            for v in next.iter_mut() {
                *v = 0.0;
            }
            for j in 0..n {
                for i in 0..n {
                    let fij = if transpose { f[(j, i)] } else { f[(i, j)] };
                    next[i] += fij * cur[j];
                }
            }
            std::mem::swap(&mut cur, &mut next);
        }
        y.copy_from_slice(&cur);
    }
}

/// Estimate of ‖B‖₁ (a lower bound, almost always exact or within a small factor).
pub(crate) fn estimate_norm1(op: &dyn Operator) -> f64 {
    let n = op.dim();
    if n == 0 {
        return 0.0;
    }
    let l1 = |v: &[f64]| v.iter().map(|x| x.abs()).sum::<f64>();
    let mut x = vec![1.0 / n as f64; n];
    let mut y = vec![0.0; n];
    let mut z = vec![0.0; n];
    let mut estimate = 0.0;
    let mut last_j = usize::MAX;
    for iteration in 0..5 {
        op.apply(&x, &mut y, false);
        let est = l1(&y);
        if iteration > 0 && est <= estimate {
            break;
        }
        estimate = est;
        let xi: Vec<f64> = y.iter().map(|v| if *v >= 0.0 { 1.0 } else { -1.0 }).collect();
        op.apply(&xi, &mut z, true);
        let (j, zmax) = z
            .iter()
            .enumerate()
            .map(|(i, v)| (i, v.abs()))
            .fold((0, -1.0), |acc, v| if v.1 > acc.1 { v } else { acc });
        let ztx: f64 = z.iter().zip(&x).map(|(a, b)| a * b).sum();
        if iteration > 0 && (zmax <= ztx || j == last_j) {
            break;
        }
        last_j = j;
        x.iter_mut().for_each(|v| *v = 0.0);
        x[j] = 1.0;
    }
    // Higham's alternating test vector guards against the rare badly underestimated case.
    let alt: Vec<f64> = (0..n)
        .map(|i| {
            let sign = if i % 2 == 0 { 1.0 } else { -1.0 };
            sign * (1.0 + i as f64 / (n.max(2) - 1) as f64)
        })
        .collect();
    op.apply(&alt, &mut y, false);
    estimate.max(2.0 * l1(&y) / (3.0 * n as f64))
}

/// Estimate of ‖F₁ F₂ ⋯ F_q‖₁ without forming the product.
pub(crate) fn estimate_product_norm1(factors: &[MatRef<'_, f64>]) -> f64 {
    estimate_norm1(&Product { factors: factors.to_vec() })
}

/// ‖ |A|ᵖ ‖₁ exactly: for a nonnegative matrix B the largest column sum is max(1ᵀB), so p
/// vector–matrix products with |A| give it without an estimator.
pub(crate) fn abs_power_norm1(a: MatRef<'_, f64>, p: usize) -> f64 {
    let n = a.nrows();
    // |A| column by column, contiguous, so each product 1ᵀ|A| is n dot products of slices.
    let abs: Vec<f64> = (0..n).flat_map(|j| (0..n).map(move |i| a[(i, j)].abs())).collect();
    let mut v = vec![1.0; n];
    let mut next = vec![0.0; n];
    for _ in 0..p {
        for (t, column) in next.iter_mut().zip(abs.chunks_exact(n.max(1))) {
            *t = v.iter().zip(column).map(|(x, y)| x * y).sum();
        }
        std::mem::swap(&mut v, &mut next);
    }
    v.into_iter().fold(0.0, f64::max)
}
