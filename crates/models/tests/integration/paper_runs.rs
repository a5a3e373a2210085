//! The paper's Run 1 (C_v alone) and Run 2 (C_v and K_p, from Run 1's result), re-enacted on
//! synthetic data of the slewing plant whose damping and gain differ from the model's.

use mem::{Experiment, Fit, Problem, Termination};
use models::SlewingFitModel;
use plant::SlewingModel;
use test_problems::simulate_measurement;

/// Potentiometer only (the paper identified from the position response), 12.8 Hz, 400 samples.
fn position_only() -> SlewingModel {
    let text = plant::PAPER_MODEL_RON
        .replace("outputs: [Potentiometer, Tachometer, StrainGauge]", "outputs: [Potentiometer]");
    SlewingModel::from_ron(&text, "position-only").unwrap()
}

#[test]
fn run1_then_run2_decrease_the_error_monotonically() {
    let truth_values = [0.13, 6.6];
    let truth = SlewingFitModel::new(position_only(), &["cv", "kp"]).unwrap().response();
    let data = simulate_measurement(&truth, &truth_values, 1.0 / 12.8, 400, 0.01, 7);
    // Run 1: C_v alone, from the paper's initial 0.0528.
    let run1_model = SlewingFitModel::new(position_only(), &["cv"]).unwrap();
    let run1_response = run1_model.clone().response();
    let run1 = Fit::new()
        .run(&Problem::new(vec![Experiment::new(&run1_response, &data)], run1_model.parameters()).unwrap())
        .unwrap();
    assert_eq!(run1.termination, Termination::Converged);
    for w in run1.error_history.windows(2) {
        assert!(w[1] < w[0], "run 1 error increased: {:?}", run1.error_history);
    }
    let (e0, e1) = run1.error_change();
    assert!(e1 < 0.5 * e0, "run 1 should at least halve the error: {e0} → {e1}");
    // Run 2: C_v and K_p, started from Run 1's result.
    let start = run1_model.model_at(&run1.parameters).unwrap();
    let run2_model = SlewingFitModel::new(start, &["cv", "kp"]).unwrap();
    let run2_response = run2_model.clone().response();
    let run2 = Fit::new()
        .run(&Problem::new(vec![Experiment::new(&run2_response, &data)], run2_model.parameters()).unwrap())
        .unwrap();
    assert_eq!(run2.termination, Termination::Converged);
    for w in run2.error_history.windows(2) {
        assert!(w[1] < w[0], "run 2 error increased: {:?}", run2.error_history);
    }
    assert!(run2.error_history.last().unwrap() < &e1);
    // With data from the same model family the truth is recovered within a few standard errors.
    for (i, want) in truth_values.iter().enumerate() {
        let (got, se) = (run2.parameters[i], run2.std_error(i).expect("determined"));
        assert!((got - want).abs() < 5.0 * se + 1e-9, "parameter {i}: {got} ± {se} vs {want}");
    }
}

#[test]
fn strain_output_sensitivities_include_the_mode_shape_change() {
    // All three sensors, K_p free: the derivative check covers ∂C/∂K_p through φ″(0).
    let model = SlewingFitModel::new(SlewingModel::paper(), &["cv", "kp"]).unwrap();
    let parameters = model.parameters();
    let response = model.response();
    let data = simulate_measurement(&response, &[0.12, 7.0], 1.0 / 12.8, 200, 0.0, 0);
    let report = Fit::new()
        .run(&Problem::new(vec![Experiment::normalized(&response, &data)], parameters).unwrap())
        .unwrap();
    let check = report.derivative_check.unwrap();
    assert!(check.worst_relative_mismatch < 1e-5, "{check:?}");
    assert!((report.parameters[1] / 7.0 - 1.0).abs() < 1e-6);
}

#[test]
fn unknown_parameter_name_lists_valid_ones() {
    let err = SlewingFitModel::new(SlewingModel::paper(), &["cv", "bogus"]).unwrap_err().to_string();
    assert!(err.contains("bogus") && err.contains("kp"), "{err}");
}
