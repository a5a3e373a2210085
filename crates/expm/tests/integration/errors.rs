//! Every bad input gives a typed error, never a panic.

use expm::ExpmError;
use faer::{Mat, mat};

#[test]
fn non_square_is_rejected() {
    let a = Mat::<f64>::zeros(2, 3);
    assert!(matches!(expm::expm(a.as_ref()), Err(ExpmError::NotSquare { nrows: 2, ncols: 3, .. })));
    assert!(matches!(expm::ExpmFrechet::new(a.as_ref()), Err(ExpmError::NotSquare { .. })));
}

#[test]
fn nan_and_infinity_are_rejected_with_position() {
    let a = mat![[0.0, 1.0], [f64::NAN, 0.0]];
    assert!(matches!(expm::expm(a.as_ref()), Err(ExpmError::NonFinite { row: 1, col: 0, .. })));
    let good = mat![[0.0, 1.0], [0.0, 0.0]];
    let bad_e = mat![[0.0, f64::INFINITY], [0.0, 0.0]];
    let err = expm::expm_frechet(good.as_ref(), bad_e.as_ref()).unwrap_err();
    assert!(matches!(err, ExpmError::NonFinite { name: "e", row: 0, col: 1, .. }), "{err}");
}

#[test]
fn mismatched_direction_is_rejected() {
    let a = Mat::<f64>::identity(3, 3);
    let e = Mat::<f64>::zeros(2, 2);
    assert!(matches!(expm::expm_frechet(a.as_ref(), e.as_ref()), Err(ExpmError::ShapeMismatch { .. })));
}

#[test]
fn overflow_is_reported() {
    let a = mat![[800.0, 0.0], [0.0, 1.0]];
    assert!(matches!(expm::expm(a.as_ref()), Err(ExpmError::Overflow { .. })));
    let huge = mat![[1e200, 1e200], [-1e200, 1e200]];
    assert!(matches!(expm::expm(huge.as_ref()), Err(ExpmError::Overflow { .. })));
}

#[test]
fn nilpotent_with_huge_norm_is_exact() {
    // ‖A‖ = 1e40 but A² = 0: e^A = I + A exactly, though the power-norm bounds must cope.
    let a = mat![[0.0, 1e40], [0.0, 0.0]];
    let x = expm::expm(a.as_ref()).unwrap();
    assert_eq!(x[(0, 1)], 1e40);
    assert_eq!(x[(0, 0)], 1.0);
}

#[test]
fn propagator_arguments_are_checked() {
    let a = Mat::<f64>::identity(2, 2) * faer::Scale(-1.0);
    let c = mat![[1.0, 0.0]];
    for h in [0.0, -1.0, f64::NAN] {
        assert!(matches!(
            expm::SensitivityPropagator::new(a.as_ref(), &[], c.as_ref(), h),
            Err(ExpmError::InvalidInterval { .. })
        ));
    }
    let wide_c = Mat::<f64>::zeros(1, 3);
    assert!(expm::SensitivityPropagator::new(a.as_ref(), &[], wide_c.as_ref(), 0.1).is_err());
    let prop = expm::SensitivityPropagator::new(a.as_ref(), &[], c.as_ref(), 0.1).unwrap();
    assert!(matches!(prop.propagate(&[1.0], None, 3), Err(ExpmError::ShapeMismatch { name: "x0", .. })));
    assert!(matches!(prop.propagate(&[1.0, f64::NAN], None, 3), Err(ExpmError::NonFinite { .. })));
}

/// κ_exp(A) is estimated, and an exponential whose answer cannot be trusted says so: for a
/// diagonal A it matches the closed form; a strongly non-normal A = [[−1, b], [0, −1.0001]]
/// with b = 1e10 has ‖L(A)‖ ≈ b·e^{-1}, so κ ≈ b² and κ·u ≫ 1e-6.
#[test]
fn ill_conditioned_exponentials_are_flagged() {
    let calm = mat![[-1.0, 0.0], [0.0, -2.0]];
    let work = expm::ExpmFrechet::new(calm.as_ref()).unwrap();
    let kappa = work.condition(calm.as_ref(), 6).unwrap();
    // For diagonal A, L(A, E)_ij = E_ij (e^{λi} − e^{λj})/(λi − λj) (e^{λi} for i = j): the largest
    // gain is e^{-1}, so κ = e^{-1}·‖A‖_F/‖e^A‖_F.
    let expected = (-1.0f64).exp() * 5f64.sqrt() / ((-2.0f64).exp() + (-4.0f64).exp()).sqrt();
    assert!((kappa - expected).abs() < 1e-3 * expected, "{kappa} vs {expected}");
    assert!(work.ill_conditioned(calm.as_ref(), 1e-6).unwrap().is_none());
    let wild = mat![[-1.0, 1e10], [0.0, -1.0001]];
    let work = expm::ExpmFrechet::new(wild.as_ref()).unwrap();
    let flag = work.ill_conditioned(wild.as_ref(), 1e-6).unwrap().expect("flagged");
    assert!(flag.condition > 1e9 && flag.error_bound > 1e-6, "{flag:?}");
    assert!(flag.to_string().contains("ill-conditioned"));
}
