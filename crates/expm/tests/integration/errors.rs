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

/// A forced propagator's own arguments: the count of ∂B (one per ∂A), D on a free decay, the
/// count of ∂D and ∂C, a forced propagator run without its input, and an input of the wrong
/// length or with a NaN — each a typed error naming the argument.
#[test]
fn forced_propagator_arguments_are_checked() {
    let a = mat![[0.0, 1.0], [-4.0, -0.2]];
    let da = mat![[0.0, 0.0], [-1.0, 0.0]];
    let b = mat![[0.0], [1.0]];
    let c = mat![[1.0, 0.0]];
    let d = mat![[0.5]];
    let (da, b_ref) = ([da.as_ref()], b.as_ref());
    let name = |e: ExpmError| match e {
        ExpmError::ShapeMismatch { name, .. } | ExpmError::NonFinite { name, .. } => name,
        other => panic!("{other}"),
    };
    let forced = |db: &[faer::MatRef<'_, f64>]| {
        expm::SensitivityPropagator::forced(a.as_ref(), &da, b_ref, db, c.as_ref(), 0.1, expm::Hold::Zero)
    };
    assert_eq!(name(forced(&[b_ref, b_ref]).unwrap_err()), "db");
    let free = expm::SensitivityPropagator::new(a.as_ref(), &da, c.as_ref(), 0.1).unwrap();
    assert_eq!(name(free.with_feedthrough(d.as_ref(), None).unwrap_err()), "d");
    let prop = forced(&[b_ref]).unwrap();
    assert_eq!(name(prop.clone().with_feedthrough(d.as_ref(), Some(&[])).unwrap_err()), "dd");
    assert_eq!(name(prop.clone().with_output_derivatives(&[]).unwrap_err()), "dc");
    let mut out = expm::Response::zeros(4, 1, 1);
    assert_eq!(name(prop.propagate_into(&[0.0, 0.0], None, &mut out).unwrap_err()), "u");
    let short = Mat::<f64>::zeros(3, 1);
    assert_eq!(
        name(prop.propagate_forced_into(&[0.0, 0.0], None, short.as_ref(), &mut out).unwrap_err()),
        "u"
    );
    let nan = Mat::from_fn(4, 1, |k, _| if k == 2 { f64::NAN } else { 1.0 });
    assert_eq!(name(prop.propagate_forced_into(&[0.0, 0.0], None, nan.as_ref(), &mut out).unwrap_err()), "u");
    // And the same propagator, given what it asks for, answers.
    let u = Mat::from_fn(4, 1, |k, _| k as f64);
    assert!(prop.propagate_forced_into(&[0.0, 0.0], None, u.as_ref(), &mut out).is_ok());
}
