//! The validation of what a user gives: derivatives, columns, lengths, stability, data and
//! settings are refused by name.

use super::*;

#[test]
fn a_wrong_hand_written_derivative_is_an_error_naming_the_parameter() {
    let names = ["k1", "k2", "k3", "alpha", "beta"];
    let truth = [2.62e6, 2.16e6, 1.96e6, 0.42, 1.18e-3];
    let right = LinearResponse(HandDerivedBuilding { sign_error: false });
    let data = simulate_measurement(&right, &truth, 0.005, 2001, 0.0, 0);
    let start = ShearBuilding::NOMINAL;
    let problem =
        |model| Problem::new(vec![Experiment::normalized(model, &data)], parameters(&names, &start)).unwrap();
    let report = Fit::new().run(&problem(&right)).unwrap();
    assert!(report.derivative_check.as_ref().unwrap().worst_relative_mismatch < 1e-6);
    let wrong = LinearResponse(HandDerivedBuilding { sign_error: true });
    match Fit::new().run(&problem(&wrong)) {
        Err(MemError::DerivativeMismatch { parameter, mismatch, .. }) => {
            assert_eq!(parameter, "k1");
            assert!(mismatch > 0.5, "{mismatch}");
        }
        other => panic!("expected a derivative mismatch, got {other:?}"),
    }
    // Asked to warn only, the fit runs and says so.
    let warned = Fit::new()
        .with_derivative_check(DerivativeCheck::Warn)
        .with_max_iterations(3)
        .unwrap()
        .run(&problem(&wrong))
        .unwrap();
    assert!(
        warned
            .warnings()
            .iter()
            .any(|w| matches!(w, Warning::DerivativeMismatch { parameter, .. } if parameter == "k1"))
    );
}

#[test]
fn swapped_output_columns_are_refused() {
    let model = LinearResponse(Exact(ShearBuilding::displacements()));
    let data = simulate_measurement(&model, &ShearBuilding::NOMINAL, 0.005, 200, 0.0, 0);
    let swapped = data.select(&["q3", "q1"]).unwrap();
    let error =
        Problem::unnamed(vec![Experiment::new(&model, &swapped)], &ShearBuilding::NOMINAL).err().unwrap();
    assert!(matches!(error, MemError::OutputNames { .. }), "{error}");
    assert!(error.to_string().contains("[q1, q3]") && error.to_string().contains("[q3, q1]"), "{error}");
}

#[test]
fn parameter_lists_of_the_wrong_length_are_refused() {
    let model = LinearResponse(Oscillator);
    let data = simulate_measurement(&model, &[0.2, 4.0], 0.05, 50, 0.0, 0);
    assert!(Problem::unnamed(vec![Experiment::new(&model, &data)], &[0.2]).is_err());
    assert!(
        Problem::new(vec![Experiment::new(&model, &data)], parameters(&["c", "k", "x"], &[0.2, 4.0, 1.0]))
            .is_err()
    );
    let repeated = parameters(&["c", "c"], &[0.2, 4.0]);
    assert!(Problem::new(vec![Experiment::new(&model, &data)], repeated).is_err());
}

#[test]
fn a_short_list_of_derivatives_is_named() {
    let data = simulate_measurement(&LinearResponse(Oscillator), &[0.2, 4.0], 0.05, 50, 0.0, 0);
    let model = LinearResponse(ShortDerivatives);
    let error = Fit::new()
        .run(&Problem::unnamed(vec![Experiment::new(&model, &data)], &[0.2, 4.0]).unwrap())
        .err()
        .unwrap();
    assert!(error.to_string().contains("linearize returned 1 ∂A/∂P, but n_params() is 2"), "{error}");
}

#[test]
fn an_unstable_start_is_refused() {
    let model = LinearResponse(Exact(ShearBuilding::displacements()));
    let data = simulate_measurement(&model, &ShearBuilding::NOMINAL, 0.005, 2001, 0.0, 0);
    let start = [2.5e6, 2.25e6, 1.875e6, -22.0, 1.25e-3];
    let error = Fit::new()
        .run(&Problem::unnamed(vec![Experiment::new(&model, &data)], &start).unwrap())
        .err()
        .unwrap();
    assert!(matches!(error, MemError::Unstable { .. }), "{error}");
    assert!(error.to_string().contains("unstable"), "{error}");
}

#[test]
fn all_zero_data_are_refused() {
    let model = LinearResponse(Oscillator);
    let zeros = mem::Measurement::new(vec!["y0".into()], 0.0, 0.05, Mat::zeros(100, 1)).unwrap();
    let error = Fit::new()
        .run(&Problem::unnamed(vec![Experiment::new(&model, &zeros)], &[0.2, 4.0]).unwrap())
        .err()
        .unwrap();
    assert!(matches!(error, MemError::NothingToFit { .. }), "{error}");
}

#[test]
fn invalid_settings_are_rejected() {
    assert!(Fit::new().with_tolerance(0.0).is_err());
    assert!(Fit::new().with_tolerance(2.0).is_err());
    assert!(Fit::new().with_max_iterations(0).is_err());
    assert!(Fit::new().with_rank_cutoff(-1.0).is_err());
    let model = LinearResponse(Oscillator);
    let data = simulate_measurement(&model, &[0.2, 4.0], 0.05, 50, 0.0, 0);
    let bad_bounds = vec![Parameter::new("c", 0.5).with_bounds(1.0, 0.0), Parameter::new("k", 4.0)];
    assert!(Problem::new(vec![Experiment::new(&model, &data)], bad_bounds).is_err());
}

/// Moving data and a response that depends on nothing are refused at the start, whether or not
/// the derivative check runs (a fit that skips it must not skip this check too).
#[test]
fn a_response_that_depends_on_nothing_is_refused_with_or_without_the_derivative_check() {
    let values = Mat::from_fn(100, 1, |k, _| (k as f64 * 0.3).sin());
    let data = mem::Measurement::new(vec!["y0".into()], 0.0, 0.05, values).unwrap();
    for check in [DerivativeCheck::Skip, DerivativeCheck::Warn, DerivativeCheck::Error] {
        let error = Fit::new()
            .with_derivative_check(check)
            .run(&Problem::unnamed(vec![Experiment::new(&AtRest, &data)], &[1.0]).unwrap())
            .err()
            .unwrap();
        assert!(matches!(error, MemError::NothingToFit { .. }), "{check:?}: {error}");
        assert!(error.to_string().contains("does not change with any parameter"), "{error}");
    }
}

#[test]
fn fewer_readings_than_parameters_are_refused_by_count() {
    let model = LinearResponse(Exact(ShearBuilding::displacements()));
    // Two samples of two outputs: four readings for five parameters.
    let two = simulate_measurement(&model, &ShearBuilding::NOMINAL, 0.005, 2, 0.0, 0);
    let error = Problem::unnamed(vec![Experiment::new(&model, &two)], &ShearBuilding::NOMINAL).err().unwrap();
    assert!(matches!(error, MemError::InvalidData(_)), "{error}");
    assert!(
        error.to_string().contains("4 readings") && error.to_string().contains("5 parameters"),
        "{error}"
    );
    let three = simulate_measurement(&model, &ShearBuilding::NOMINAL, 0.005, 3, 0.0, 0);
    assert!(Problem::unnamed(vec![Experiment::new(&model, &three)], &ShearBuilding::NOMINAL).is_ok());
}
