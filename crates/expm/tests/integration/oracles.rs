//! L(A, E) against two independent oracles, and algebraic properties by proptest.

use faer::Mat;
use nalgebra::DMatrix;
use num_dual::Dual64;
use proptest::prelude::*;

fn rel(x: &Mat<f64>, y: &Mat<f64>) -> f64 {
    (x - y).norm_l2() / y.norm_l2().max(f64::MIN_POSITIVE)
}

/// exp(A + εE) in dual numbers: the ε part is exactly L(A, E).
///
/// nalgebra's own `exp()` cannot take `Dual64` (it calls `ceil` on the scalar, which num-dual
/// refuses), so the oracle is a plain Taylor series with scaling and squaring on nalgebra
/// matrices of `Dual64`: the scaling 2⁻ˢ is chosen from the real part so that ‖2⁻ˢA‖₁ ≤ 1/2,
/// and 30 terms make the truncation error below 0.5³⁰/30! ≈ 1e-42. No code is shared with the
/// Padé implementation under test.
fn dual_oracle(a: &Mat<f64>, e: &Mat<f64>) -> (Mat<f64>, Mat<f64>) {
    let n = a.nrows();
    let m = DMatrix::<Dual64>::from_fn(n, n, |i, j| Dual64::new(a[(i, j)], e[(i, j)]));
    let norm = expm::norm1(a.as_ref());
    let s = if norm > 0.5 { (norm / 0.5).log2().ceil() as i32 } else { 0 };
    let scaled = m * Dual64::from(0.5f64.powi(s));
    let mut term = DMatrix::<Dual64>::identity(n, n);
    let mut x = term.clone();
    for k in 1..=30 {
        term = &term * &scaled / Dual64::from(k as f64);
        x += &term;
    }
    for _ in 0..s {
        x = &x * &x;
    }
    (Mat::from_fn(n, n, |i, j| x[(i, j)].re), Mat::from_fn(n, n, |i, j| x[(i, j)].eps))
}

/// The top-right block of exp([[A, E], [0, A]]) (Eq. 9 in block form), via our own expm.
fn block_oracle(a: &Mat<f64>, e: &Mat<f64>) -> Mat<f64> {
    let n = a.nrows();
    let mut big = Mat::<f64>::zeros(2 * n, 2 * n);
    big.as_mut().submatrix_mut(0, 0, n, n).copy_from(a);
    big.as_mut().submatrix_mut(n, n, n, n).copy_from(a);
    big.as_mut().submatrix_mut(0, n, n, n).copy_from(e);
    expm::expm(big.as_ref()).unwrap().as_ref().submatrix(0, n, n, n).to_owned()
}

/// Tolerance for the cross-checks on well-conditioned seeded random matrices (κ ≈ 5–10,
/// see the reference cases): a few hundred ulps covers both algorithms' rounding.
const CROSS_TOL: f64 = 1e-12;

#[test]
fn frechet_agrees_with_dual_number_exponential() {
    for (n, seed) in [(4, 1), (8, 2), (16, 3)] {
        let a = test_problems::random_stable(n, seed);
        let e = test_problems::gaussian(n, n, seed + 100);
        let (x, l) = expm::expm_frechet(a.as_ref(), e.as_ref()).unwrap();
        let (x_dual, l_dual) = dual_oracle(&a, &e);
        assert!(rel(&x, &x_dual) < CROSS_TOL, "n={n}: e^A differs {}", rel(&x, &x_dual));
        assert!(rel(&l, &l_dual) < CROSS_TOL, "n={n}: L differs {}", rel(&l, &l_dual));
    }
}

#[test]
fn frechet_agrees_with_block_form() {
    for (n, seed) in [(3, 4), (8, 5), (20, 6)] {
        let a = test_problems::random_stable(n, seed) * faer::Scale(3.0);
        let e = test_problems::gaussian(n, n, seed + 100);
        let (_, l) = expm::expm_frechet(a.as_ref(), e.as_ref()).unwrap();
        let l_block = block_oracle(&a, &e);
        assert!(rel(&l, &l_block) < CROSS_TOL, "n={n}: {}", rel(&l, &l_block));
    }
}

#[test]
fn many_directions_equal_single_directions() {
    let a = test_problems::random_stable(10, 7) * faer::Scale(5.0);
    let es: Vec<Mat<f64>> = (0..4).map(|k| test_problems::gaussian(10, 10, 50 + k)).collect();
    let refs: Vec<_> = es.iter().map(|e| e.as_ref()).collect();
    let (x, ls) = expm::expm_frechet_many(a.as_ref(), &refs).unwrap();
    for (e, l) in es.iter().zip(&ls) {
        let (x1, l1) = expm::expm_frechet(a.as_ref(), e.as_ref()).unwrap();
        assert_eq!((&x - &x1).norm_max(), 0.0);
        assert_eq!((l - &l1).norm_max(), 0.0);
    }
}

fn small_matrix() -> impl Strategy<Value = Mat<f64>> {
    (2usize..7, any::<u64>(), 0.05f64..4.0).prop_map(|(n, seed, scale)| {
        test_problems::gaussian(n, n, seed) * faer::Scale(scale / (n as f64).sqrt())
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn exp_times_exp_of_negative_is_identity(a in small_matrix()) {
        let n = a.nrows();
        let x = expm::expm(a.as_ref()).unwrap();
        let y = expm::expm((&a * faer::Scale(-1.0)).as_ref()).unwrap();
        // ‖e^A‖‖e^{−A}‖ bounds how much rounding the product can show.
        let tol = 1e-13 * x.norm_l2() * y.norm_l2();
        prop_assert!((&x * &y - Mat::<f64>::identity(n, n)).norm_l2() <= tol);
    }

    #[test]
    fn exp_is_square_of_half(a in small_matrix()) {
        let x = expm::expm(a.as_ref()).unwrap();
        let h = expm::expm((&a * faer::Scale(0.5)).as_ref()).unwrap();
        prop_assert!(rel(&(&h * &h), &x) <= 1e-13 * h.norm_l2().powi(2) / x.norm_l2());
    }

    #[test]
    fn frechet_is_linear_in_e(a in small_matrix(), seed in any::<u64>(), alpha in -3.0f64..3.0) {
        let n = a.nrows();
        let e1 = test_problems::gaussian(n, n, seed);
        let e2 = test_problems::gaussian(n, n, seed ^ 0x5555);
        let work = expm::ExpmFrechet::new(a.as_ref()).unwrap();
        let combined = &e1 * faer::Scale(alpha) + &e2;
        let lhs = work.derivative(combined.as_ref()).unwrap();
        let rhs = work.derivative(e1.as_ref()).unwrap() * faer::Scale(alpha) + work.derivative(e2.as_ref()).unwrap();
        prop_assert!((&lhs - &rhs).norm_l2() <= 1e-13 * (lhs.norm_l2() + rhs.norm_l2()).max(1e-300));
    }

    #[test]
    fn frechet_in_own_direction_is_a_exp_a(a in small_matrix()) {
        let (x, l) = expm::expm_frechet(a.as_ref(), a.as_ref()).unwrap();
        let expected = &a * &x;
        prop_assert!((&l - &expected).norm_l2() <= 1e-13 * a.norm_l2() * x.norm_l2());
    }
}
