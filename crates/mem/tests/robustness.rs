//! Non-identifiability, the safeguard, bounds and initial-state estimation.

use faer::{Mat, mat};
use mem::{Experiment, Fit, LinearModel, LinearResponse, Linearized, Safeguard, Termination};
use test_problems::{ProductOscillator, simulate_measurement};

#[test]
fn product_of_two_parameters_is_reported_not_wandered() {
    let model = LinearResponse(ProductOscillator);
    let truth = [2.0, 3.0, 0.2]; // stiffness 6
    let data = simulate_measurement(&model, &truth, 0.05, 300, 0.0, 0);
    let start = [1.5, 3.5, 0.3]; // product 5.25, ratio 0.43
    let names = vec!["a".to_string(), "b".to_string(), "c".to_string()];
    let report =
        Fit::new().with_parameter_names(names).run(&[Experiment::new(&model, &data)], &start).unwrap();
    let p = &report.parameters;
    assert!((p[0] * p[1] / 6.0 - 1.0).abs() < 1e-8, "product {}", p[0] * p[1]);
    assert!((p[2] / 0.2 - 1.0).abs() < 1e-8);
    // No wandering: the undetermined ratio stays near where it started.
    assert!((p[0] / p[1] / (1.5 / 3.5) - 1.0).abs() < 0.3, "ratio {}", p[0] / p[1]);
    assert_eq!(report.rank, 2, "the rank cutoff must drop the null direction");
    let undetermined = &report.identifiability.undetermined;
    assert_eq!(undetermined.len(), 1, "{:?}", report.identifiability);
    let v = &undetermined[0].direction;
    // ln a − ln b (the ratio) is the undetermined direction: v ≈ ±(1, −1, 0)/√2.
    assert!(
        (v[0].abs() - std::f64::consts::FRAC_1_SQRT_2).abs() < 1e-6
            && (v[0] + v[1]).abs() < 1e-6
            && v[2].abs() < 1e-6
    );
    let text = &undetermined[0].description;
    assert!(
        text.contains("a^") && text.contains("b^") && text.contains("^-") && !text.contains("c^"),
        "{text}"
    );
}

/// x'' + c x' + k x = 0 from x(0) = 1 observed for 20 s: stiffness far off makes the first
/// Gauss–Newton step overshoot.
struct Oscillator;
impl LinearModel for Oscillator {
    type Error = std::convert::Infallible;
    fn n_states(&self) -> usize {
        2
    }
    fn n_params(&self) -> usize {
        2
    }
    fn n_outputs(&self) -> usize {
        1
    }
    fn linearize(&self, p: &[f64]) -> Result<Linearized, Self::Error> {
        Ok(Linearized {
            a: mat![[0.0, 1.0], [-p[1], -p[0]]],
            da: vec![mat![[0.0, 0.0], [0.0, -1.0]], mat![[0.0, 0.0], [-1.0, 0.0]]],
            c: mat![[1.0, 0.0]],
            dc: None,
            x0: vec![1.0, 0.0],
            dx0: None,
        })
    }
}

#[test]
fn bad_start_diverges_plainly_and_is_rescued_by_the_safeguard() {
    let model = LinearResponse(Oscillator);
    let truth = [0.2, 4.0];
    let data = simulate_measurement(&model, &truth, 0.05, 400, 0.0, 0);
    let start = [0.2, 9.0]; // 50 % frequency error: the linearisation is poor
    let experiments = [Experiment::new(&model, &data)];
    let plain = Fit::new()
        .with_safeguard(Safeguard::None)
        .with_max_iterations(30)
        .unwrap()
        .run(&experiments, &start)
        .unwrap();
    let plain_ok = plain.termination == Termination::Converged
        && plain.parameters.iter().zip(truth).all(|(a, b)| (a / b - 1.0).abs() < 1e-6);
    assert!(
        !plain_ok,
        "this start should defeat plain Gauss–Newton: {:?} {:?}",
        plain.termination, plain.parameters
    );
    let increases = plain.error_history.windows(2).filter(|w| w[1] > w[0]).count();
    assert!(increases > 0 || plain.termination == Termination::Diverged);
    let safe = Fit::new().run(&experiments, &start).unwrap();
    assert_eq!(safe.termination, Termination::Converged, "{:?}", safe.parameters);
    for (a, b) in safe.parameters.iter().zip(truth) {
        assert!((a / b - 1.0).abs() < 1e-8, "{a} vs {b}");
    }
    for w in safe.error_history.windows(2) {
        assert!(w[1] <= w[0], "an accepted step increased the error");
    }
}

#[test]
fn bounds_are_respected() {
    let model = LinearResponse(Oscillator);
    let data = simulate_measurement(&model, &[0.2, 4.0], 0.05, 400, 0.0, 0);
    let report = Fit::new()
        .with_bounds(vec![(0.3, 1.0), (0.1, 100.0)])
        .unwrap()
        .run(&[Experiment::new(&model, &data)], &[0.5, 3.5])
        .unwrap();
    assert!(report.parameters[0] >= 0.3 && report.parameters[0] <= 0.3 + 1e-12, "{:?}", report.parameters);
    let out_of_bounds = Fit::new()
        .with_bounds(vec![(0.3, 1.0), (0.1, 100.0)])
        .unwrap()
        .run(&[Experiment::new(&model, &data)], &[0.1, 3.5]);
    assert!(out_of_bounds.is_err());
}

/// The oscillator with its initial displacement as a third parameter: ∂x(0)/∂P₃ = e₁, so the
/// sensitivity is C e^{At} e₁ exactly.
struct OscillatorWithUnknownStart;
impl LinearModel for OscillatorWithUnknownStart {
    type Error = std::convert::Infallible;
    fn n_states(&self) -> usize {
        2
    }
    fn n_params(&self) -> usize {
        3
    }
    fn n_outputs(&self) -> usize {
        1
    }
    fn linearize(&self, p: &[f64]) -> Result<Linearized, Self::Error> {
        let mut lin = Oscillator.linearize(&p[..2])?;
        lin.da.push(Mat::zeros(2, 2));
        lin.x0 = vec![p[2], 0.0];
        lin.dx0 = Some(mat![[0.0, 0.0, 1.0], [0.0, 0.0, 0.0]]);
        Ok(lin)
    }
}

#[test]
fn unknown_initial_state_is_estimated() {
    let model = LinearResponse(OscillatorWithUnknownStart);
    let truth = [0.2, 4.0, 0.8];
    let data = simulate_measurement(&model, &truth, 0.05, 300, 0.0, 0);
    let report = Fit::new()
        .with_derivative_check(true)
        .run(&[Experiment::new(&model, &data)], &[0.3, 3.5, 1.0])
        .unwrap();
    for (a, b) in report.parameters.iter().zip(truth) {
        assert!((a / b - 1.0).abs() < 1e-8);
    }
    assert!(report.derivative_check.unwrap().worst_relative_mismatch < 1e-6);
}

#[test]
fn invalid_settings_are_rejected() {
    assert!(Fit::new().with_tolerance(0.0).is_err());
    assert!(Fit::new().with_tolerance(2.0).is_err());
    assert!(Fit::new().with_max_iterations(0).is_err());
    assert!(Fit::new().with_rank_cutoff(-1.0).is_err());
    assert!(Fit::new().with_bounds(vec![(1.0, 0.0)]).is_err());
}

#[test]
fn mismatched_shapes_are_errors() {
    let model = LinearResponse(Oscillator);
    let data = simulate_measurement(&model, &[0.2, 4.0], 0.05, 50, 0.0, 0);
    assert!(Fit::new().run(&[Experiment::new(&model, &data)], &[0.2]).is_err());
    let two_outputs =
        mem::Measurement::new(vec!["a".into(), "b".into()], 0.0, 0.05, Mat::zeros(10, 2)).unwrap();
    assert!(Fit::new().run(&[Experiment::new(&model, &two_outputs)], &[0.2, 4.0]).is_err());
}

#[test]
fn step_equals_the_pseudo_inverse_from_faers_own_thin_svd() {
    // gauss_newton_step uses Householder QR + SVD of R; compare with faer's thin SVD of S
    // applied directly (an independent route to the same least-squares solution).
    let model = LinearResponse(test_problems::SpringChain { x0: [0.0, 0.01] });
    let data = simulate_measurement(&model, &test_problems::SpringChain::TRUE, 0.02, 300, 0.01, 4);
    let p = [35.0, 17.0, 0.35];
    let step = mem::gauss_newton_step(&[Experiment::new(&model, &data)], &p, 1e-10).unwrap();
    let mut out = expm::Response::zeros(300, 2, 3);
    mem::ResponseModel::respond(&model, &p, 0.02, &mut out).unwrap();
    let residual: Vec<f64> = (0..300)
        .flat_map(|k| (0..2).map(move |o| (k, o)))
        .map(|(k, o)| data.values()[(k, o)] - out.outputs[(k, o)])
        .collect();
    let scale: Vec<f64> = (0..3).map(|c| out.sensitivities.col(c).norm_l2()).collect();
    let scaled = Mat::from_fn(600, 3, |i, c| out.sensitivities[(i, c)] / scale[c]);
    let svd = scaled.thin_svd().unwrap();
    for i in 0..3 {
        assert!((svd.S()[i] / step.singular_values[i] - 1.0).abs() < 1e-10, "σ_{i}");
    }
    let (u, v) = (svd.U(), svd.V());
    for c in 0..3 {
        let delta: f64 = (0..3)
            .map(|i| v[(c, i)] * (0..600).map(|r| u[(r, i)] * residual[r]).sum::<f64>() / svd.S()[i])
            .sum::<f64>()
            / scale[c];
        assert!(
            (delta - step.delta[c]).abs() < 1e-9 * (delta.abs() + 1e-12),
            "ΔP_{c}: {delta} vs {}",
            step.delta[c]
        );
    }
}
