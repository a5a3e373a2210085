//! Quantized readings as intervals (`Experiment::with_quantization`).

use mem::{DerivativeCheck, Experiment, Fit, LinearResponse, Measurement, Problem};
use test_problems::{ModalFamily, simulate_measurement};

/// Rounds every output to the lattice of `step`.
fn quantize(data: &Measurement, step: f64) -> Measurement {
    let values = faer::Mat::from_fn(data.n_samples(), data.n_outputs(), |k, o| {
        step * (data.values()[(k, o)] / step).round()
    });
    Measurement::new(data.names().to_vec(), data.start(), data.interval(), values).unwrap()
}

#[test]
fn the_truth_is_not_charged_for_rounding_and_a_coarse_quantizer_still_identifies() {
    let family = ModalFamily::new(3, 2, 2, 7);
    let model = LinearResponse(family.clone());
    let truth: Vec<f64> = family.p_nominal.iter().map(|v| v * 1.04).collect();
    let exact = simulate_measurement(&model, &truth, 1.0 / 12.8, 400, 0.0, 1);
    // A coarse step: 5 % of the largest reading.
    let step = 0.05 * exact.values().norm_max();
    let data = quantize(&exact, step);
    let steps = vec![Some(step); data.n_outputs()];

    // At the truth every reading's interval holds the model's output: the interval error is
    // exactly zero, while the plain residual keeps the rounding (Δ²/12 per sample in mean).
    let interval = || Experiment::new(&model, &data).with_quantization(&steps);
    let once = Fit::new().with_max_iterations(1).unwrap().with_derivative_check(DerivativeCheck::Skip);
    let at_truth = once.run(&Problem::unnamed(vec![interval()], &truth).unwrap()).unwrap();
    assert_eq!(at_truth.error_history[0], 0.0);
    let plain = Problem::unnamed(vec![Experiment::new(&model, &data)], &truth).unwrap();
    let plain_at_truth = once.run(&plain).unwrap();
    let rounding = data.n_samples() as f64 * data.n_outputs() as f64 * step * step / 12.0;
    assert!(plain_at_truth.error_history[0] > 0.5 * rounding, "{}", plain_at_truth.error_history[0]);

    // From 10 % off, the interval fit comes back to the truth: every reading's interval is a
    // constraint, and with 800 of them the feasible set is small. Tolerance: 1 %, the width
    // of that set here (measured: 0.02 % and 0.24 %).
    let start: Vec<f64> = family.p_nominal.iter().map(|v| v * 0.94).collect();
    let report = Fit::new().run(&Problem::unnamed(vec![interval()], &start).unwrap()).unwrap();
    for (fitted, true_value) in report.parameters.iter().zip(&truth) {
        assert!((fitted / true_value - 1.0).abs() < 0.01, "{:?} vs {truth:?}", report.parameters);
    }
    assert!(*report.error_history.last().unwrap() < 1e-3 * rounding);
}

#[test]
fn a_negative_step_is_rejected() {
    let family = ModalFamily::new(2, 2, 1, 3);
    let model = LinearResponse(family.clone());
    let data = simulate_measurement(&model, &family.p_nominal, 0.1, 50, 0.0, 1);
    let experiment = Experiment::new(&model, &data).with_quantization(&[Some(-0.1)]);
    let error = Problem::unnamed(vec![experiment], &family.p_nominal).err().unwrap();
    assert!(error.to_string().contains("quantization step"), "{error}");
}
