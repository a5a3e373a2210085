//! Closed-form exponentials, independent of any reference file.

use faer::{Mat, mat};

/// Entrywise tolerance for closed forms whose entries are O(1): a few ulps of rounding in the
/// Padé evaluation and the squarings.
const TOL: f64 = 1e-14;

fn assert_close(x: &Mat<f64>, expected: &Mat<f64>, tol: f64) {
    let diff = (x - expected).norm_max();
    let scale = expected.norm_max().max(1.0);
    assert!(diff <= tol * scale, "max difference {diff:e}\n{x:?}\nexpected\n{expected:?}");
}

#[test]
fn rotation_generator() {
    for theta in [0.1, 1.0, 3.0, 25.0] {
        let a = mat![[0.0, theta], [-theta, 0.0]];
        let (c, s) = (f64::cos(theta), f64::sin(theta));
        // The condition number grows like θ, so the tolerance does too.
        assert_close(&expm::expm(a.as_ref()).unwrap(), &mat![[c, s], [-s, c]], TOL * theta.max(1.0));
    }
}

#[test]
fn repeated_eigenvalue_jordan_2x2() {
    for lambda in [-3.0, -0.5, 0.0, 2.0] {
        let a = mat![[lambda, 1.0], [0.0, lambda]];
        let el = f64::exp(lambda);
        assert_close(&expm::expm(a.as_ref()).unwrap(), &mat![[el, el], [0.0, el]], TOL);
    }
}

#[test]
fn nilpotent_jordan_block_is_a_finite_series() {
    let n = 7;
    let a = Mat::<f64>::from_fn(n, n, |i, j| if j == i + 1 { 1.0 } else { 0.0 });
    // e^N = Σ N^k / k!: entry (i, j) = 1/(j−i)! for j ≥ i.
    let factorial = |k: usize| (1..=k).map(|v| v as f64).product::<f64>();
    let expected = Mat::<f64>::from_fn(n, n, |i, j| if j >= i { 1.0 / factorial(j - i) } else { 0.0 });
    assert_close(&expm::expm(a.as_ref()).unwrap(), &expected, TOL);
}

#[test]
fn moler_van_loan_hard_case() {
    let a = mat![[-49.0, 24.0], [-64.0, 31.0]];
    let (e1, e17) = (f64::exp(-1.0), f64::exp(-17.0));
    // Eigenvectors: (3, 4) for −17 and (1, 2) for −1; e^A = V diag(e^{−17}, e^{−1}) V⁻¹.
    let v = mat![[3.0, 1.0], [4.0, 2.0]];
    let v_inv = mat![[1.0, -0.5], [-2.0, 1.5]];
    let d = mat![[e17, 0.0], [0.0, e1]];
    let expected = &v * &d * &v_inv;
    assert_close(&expm::expm(a.as_ref()).unwrap(), &expected, 1e-13);
}

#[test]
fn diagonal_with_widely_spread_eigenvalues() {
    // For a normal matrix the relative condition number of e^A is ‖A‖₂ (here 1e3): squaring
    // amplifies the rounding in the small eigenvalues' entries, so the bound is normwise,
    // 20·u·‖A‖₂ relative to ‖e^A‖₂ = max_i e^{λ_i}, as for every other case.
    let values: Vec<f64> = (0..13).map(|k| -(10f64).powf(-3.0 + 0.5 * k as f64)).collect();
    let a = Mat::<f64>::from_fn(13, 13, |i, j| if i == j { values[i] } else { 0.0 });
    let x = expm::expm(a.as_ref()).unwrap();
    let norm_exp = values.iter().map(|v| v.exp()).fold(0.0, f64::max);
    let bound = 20.0 * 1.1102230246251565e-16 * 1e3 * norm_exp;
    for i in 0..13 {
        let expected = values[i].exp();
        assert!((x[(i, i)] - expected).abs() <= bound, "entry {i}: {} vs {expected}", x[(i, i)]);
    }
    assert_eq!((&x - Mat::from_fn(13, 13, |i, j| if i == j { x[(i, i)] } else { 0.0 })).norm_max(), 0.0);
}

#[test]
fn zero_and_empty_matrices() {
    assert_close(&expm::expm(Mat::<f64>::zeros(3, 3).as_ref()).unwrap(), &Mat::identity(3, 3), 0.0);
    assert_eq!(expm::expm(Mat::<f64>::zeros(0, 0).as_ref()).unwrap().nrows(), 0);
}
