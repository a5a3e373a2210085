//! Reductions over long vectors (residuals and sensitivity columns have K·p entries).
//!
//! A plain `iter().sum()` is one dependent chain of additions — bound by the adder's latency,
//! because floating-point addition may not be reassociated. faer's inner product keeps several
//! SIMD partial sums and is compiled for the machine's instruction set at run time; the result
//! differs from the sequential sum only by rounding.

use faer::linalg::matmul::dot::inner_prod;
use faer::{ColRef, Conj, RowRef};

/// Σ aᵢ bᵢ.
pub(crate) fn dot(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len(), "dot of vectors of different lengths");
    inner_prod(RowRef::from_slice(a), Conj::No, ColRef::from_slice(b), Conj::No)
}

/// Σ aᵢ².
pub(crate) fn sum_squares(a: &[f64]) -> f64 {
    dot(a, a)
}

/// y ← y − f·x.
pub(crate) fn subtract_scaled(y: &mut [f64], f: f64, x: &[f64]) {
    assert_eq!(x.len(), y.len(), "axpy of vectors of different lengths");
    for (t, v) in y.iter_mut().zip(x) {
        *t -= f * v;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dot_matches_the_exact_sum_of_integer_products() {
        // Integer-valued entries: every partial sum is exact, so any order gives the same value.
        let a: Vec<f64> = (0..37).map(|i| (i % 7) as f64 - 3.0).collect();
        let b: Vec<f64> = (0..37).map(|i| (i % 5) as f64 + 1.0).collect();
        let exact: i64 = (0..37i64).map(|i| (i % 7 - 3) * (i % 5 + 1)).sum();
        assert_eq!(dot(&a, &b), exact as f64);
        assert_eq!(sum_squares(&a[..3]), 9.0 + 4.0 + 1.0);
        let mut y = b.clone();
        subtract_scaled(&mut y, 2.0, &a);
        assert!(y.iter().zip(a.iter().zip(&b)).all(|(t, (x, v))| *t == v - 2.0 * x));
    }
}
