//! Non-identifiability, the safeguard, bounds as constraints, the start checks, and the
//! validation of what a user gives.

use faer::{Mat, mat};
use mem::{
    BoxedError, DerivativeCheck, Exact, Experiment, Fit, Grid, Interval, LinearModel, LinearResponse,
    Linearized, MemError, Parameter, Problem, Response, ResponseModel, Safeguard, Side, Termination, Warning,
};
use std::sync::atomic::{AtomicUsize, Ordering};
use test_problems::{
    HandDerivedBuilding, ProductOscillator, ShearBuilding, SpringChain, add_noise, parameters,
    simulate_measurement,
};

#[test]
fn product_of_two_parameters_gets_no_interval_and_a_sentence() {
    let model = LinearResponse(ProductOscillator);
    let truth = [2.0, 3.0, 0.2]; // stiffness 6
    let data = add_noise(&simulate_measurement(&model, &truth, 0.05, 300, 0.0, 0), 0.01, 3);
    let start = [1.5, 3.5, 0.3]; // product 5.25, ratio 0.43
    let problem =
        Problem::new(vec![Experiment::new(&model, &data)], parameters(&["a", "b", "c"], &start)).unwrap();
    let report = Fit::new().run(&problem).unwrap();
    let p = &report.parameters;
    assert!((p[0] * p[1] / 6.0 - 1.0).abs() < 0.01, "product {}", p[0] * p[1]);
    // No wandering: the undetermined ratio stays near where it started.
    assert!((p[0] / p[1] / (1.5 / 3.5) - 1.0).abs() < 0.3, "ratio {}", p[0] / p[1]);
    assert_eq!(report.rank, 2, "the rank cutoff must drop the null direction");
    // a and b: no standard error, no interval; c: an ordinary one.
    assert_eq!(report.std_error(0), None);
    assert_eq!(report.std_error(1), None);
    assert_eq!(report.statistics.intervals[0], Interval::Undetermined);
    assert!(report.std_error(2).is_some_and(|s| s > 0.0 && s.is_finite()));
    let undetermined = &report.identifiability.undetermined;
    assert_eq!(undetermined.len(), 1, "{:?}", report.identifiability);
    let v = &undetermined[0].direction;
    // ln a − ln b (the ratio) is the undetermined direction.
    assert!((v[0] - 1.0).abs() < 1e-6 && (v[1] + 1.0).abs() < 1e-6 && v[2].abs() < 1e-6, "{v:?}");
    let warning = report.warnings().iter().find_map(|w| match w {
        Warning::RankDeficient { sentence, parameters, .. } => Some((sentence.clone(), parameters.clone())),
        _ => None,
    });
    let (sentence, involved) = warning.expect("a rank-deficiency warning");
    assert_eq!(involved, vec!["a".to_string(), "b".to_string()]);
    assert!(sentence.contains("only the product a·b is determined"), "{sentence}");
    let json = serde_json::to_value(&report).unwrap();
    assert!(json["statistics"]["std_errors"][0].is_null());
    assert_eq!(json["warnings"][0]["kind"], "rank_deficient");
}

#[test]
fn scaling_every_mass_and_stiffness_together_is_named_and_gets_no_interval() {
    let building = ShearBuilding { free_masses: true, ..ShearBuilding::displacements() };
    let model = LinearResponse(Exact(building));
    let truth = [1000.0, 1000.0, 1000.0, 2.5e6, 2.25e6, 1.875e6, 0.375, 1.25e-3];
    let data = add_noise(&simulate_measurement(&model, &truth, 0.005, 2001, 0.0, 0), 0.01, 5);
    let start = [900.0, 1100.0, 950.0, 2.3e6, 2.4e6, 1.7e6, 0.4, 1.1e-3];
    let names = ["m1", "m2", "m3", "k1", "k2", "k3", "alpha", "beta"];
    let problem =
        Problem::new(vec![Experiment::normalized(&model, &data)], parameters(&names, &start)).unwrap();
    let report = Fit::new().run(&problem).unwrap();
    for i in 0..6 {
        assert_eq!(report.std_error(i), None, "{} must have no finite interval: {report}", names[i]);
    }
    for i in 6..8 {
        assert!(report.std_error(i).is_some(), "{} is determined: {report}", names[i]);
    }
    let sentence = report
        .warnings()
        .iter()
        .find_map(
            |w| if let Warning::RankDeficient { sentence, .. } = w { Some(sentence.clone()) } else { None },
        )
        .expect("a rank-deficiency warning");
    assert!(sentence.starts_with("scaling m1, m2, m3, k1, k2 and k3 together"), "{sentence}");
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
    fn output_names(&self) -> Vec<String> {
        vec!["y0".into()]
    }
    fn linearize(&self, p: &[f64]) -> Result<Linearized, Self::Error> {
        Ok(Linearized::new(
            mat![[0.0, 1.0], [-p[1], -p[0]]],
            vec![mat![[0.0, 0.0], [0.0, -1.0]], mat![[0.0, 0.0], [-1.0, 0.0]]],
            mat![[1.0, 0.0]],
            vec![1.0, 0.0],
        ))
    }
}

#[test]
fn bad_start_diverges_plainly_and_is_rescued_by_the_safeguard() {
    let model = LinearResponse(Oscillator);
    let truth = [0.2, 4.0];
    let data = simulate_measurement(&model, &truth, 0.05, 400, 0.0, 0);
    let start = [0.2, 9.0]; // 50 % frequency error: the linearisation is poor
    let problem = Problem::unnamed(vec![Experiment::new(&model, &data)], &start).unwrap();
    let plain =
        Fit::new().with_safeguard(Safeguard::None).with_max_iterations(30).unwrap().run(&problem).unwrap();
    let plain_ok = plain.termination == Termination::Converged
        && plain.parameters.iter().zip(truth).all(|(a, b)| (a / b - 1.0).abs() < 1e-6);
    assert!(
        !plain_ok,
        "this start should defeat plain Gauss–Newton: {:?} {:?}",
        plain.termination, plain.parameters
    );
    let safe = Fit::new().run(&problem).unwrap();
    assert_eq!(safe.termination, Termination::Converged, "{:?}", safe.parameters);
    for (a, b) in safe.parameters.iter().zip(truth) {
        assert!((a / b - 1.0).abs() < 1e-8, "{a} vs {b}");
    }
    for w in safe.error_history.windows(2) {
        assert!(w[1] <= w[0], "an accepted step increased the error");
    }
}

/// A response that counts how it is asked: with sensitivities or for the outputs alone.
struct Counting {
    inner: LinearResponse<Oscillator>,
    full: AtomicUsize,
    outputs: AtomicUsize,
}
impl ResponseModel for Counting {
    fn n_params(&self) -> usize {
        self.inner.n_params()
    }
    fn output_names(&self) -> Vec<String> {
        self.inner.output_names()
    }
    fn respond(&self, p: &[f64], grid: &Grid<'_>, out: &mut Response) -> Result<(), BoxedError> {
        self.full.fetch_add(1, Ordering::Relaxed);
        self.inner.respond(p, grid, out)
    }
    fn respond_outputs(&self, p: &[f64], grid: &Grid<'_>, out: &mut Response) -> Result<(), BoxedError> {
        assert_eq!(out.sensitivities.ncols(), 0, "the outputs alone are asked for without columns");
        self.outputs.fetch_add(1, Ordering::Relaxed);
        self.inner.respond_outputs(p, grid, out)
    }
}

#[test]
fn a_rejected_trial_costs_its_outputs_alone() {
    let plain = LinearResponse(Oscillator);
    let data = simulate_measurement(&plain, &[0.2, 4.0], 0.05, 400, 0.0, 0);
    let model = Counting {
        inner: LinearResponse(Oscillator),
        full: AtomicUsize::new(0),
        outputs: AtomicUsize::new(0),
    };
    // The start of the test above: the damping rejects several trials.
    let problem = Problem::unnamed(vec![Experiment::new(&model, &data)], &[0.2, 9.0]).unwrap();
    let report = Fit::new().with_derivative_check(DerivativeCheck::Skip).run(&problem).unwrap();
    assert_eq!(report.termination, Termination::Converged);
    let retried: Vec<usize> = report.records.iter().map(|r| r.rejected_trials).filter(|&r| r > 0).collect();
    assert!(!retried.is_empty(), "the start must make the damping reject a trial");
    // An iteration's first trial is simulated in full; after it is rejected, each retry is
    // costed on its outputs (the r − 1 rejected ones and the accepted one), and the accepted
    // one simulated again in full. The start is simulated in full once.
    let full = 1 + report.iterations + retried.len();
    assert_eq!(model.full.load(Ordering::Relaxed), full);
    assert_eq!(model.outputs.load(Ordering::Relaxed), retried.iter().sum::<usize>());
    // And the fit is the one of the plain model, bit for bit.
    let problem = Problem::unnamed(vec![Experiment::new(&plain, &data)], &[0.2, 9.0]).unwrap();
    let again = Fit::new().with_derivative_check(DerivativeCheck::Skip).run(&problem).unwrap();
    assert_eq!(report.parameters, again.parameters);
    assert_eq!(report.error_history, again.error_history);
}

#[test]
fn a_parameter_held_on_its_bound_gets_a_one_sided_interval_and_a_warning() {
    let model = LinearResponse(Oscillator);
    let truth = [0.2, 4.0];
    let data = add_noise(&simulate_measurement(&model, &truth, 0.05, 400, 0.0, 0), 0.01, 9);
    let params = vec![
        Parameter::new("c", 0.5).with_bounds(0.3, 1.0),
        Parameter::new("k", 3.5).with_bounds(0.1, 100.0),
    ];
    let report =
        Fit::new().run(&Problem::new(vec![Experiment::new(&model, &data)], params).unwrap()).unwrap();
    // Exactly on the bound, converged, and said so.
    assert_eq!(report.parameters[0], 0.3);
    assert_eq!(report.termination, Termination::Converged, "{report}");
    assert_eq!(report.on_bound[0], Some(Side::Lower));
    assert_eq!(report.std_error(0), None);
    match report.statistics.intervals[0] {
        Interval::OneSided { lower, upper } => {
            assert!(lower == 0.3 && upper > 0.3 && upper < 0.35, "{lower} {upper}")
        }
        other => panic!("expected a one-sided interval, got {other:?}"),
    }
    assert!(report.warnings().iter().any(
        |w| matches!(w, Warning::ActiveBound { parameter, side: Side::Lower, release_gain, .. } if parameter == "c" && *release_gain > 0.1)
    ));
    assert!(matches!(report.statistics.intervals[1], Interval::Symmetric { .. }));
}

/// The oscillator with its damping fixed: k alone is free.
struct OscillatorWithDamping(f64);
impl LinearModel for OscillatorWithDamping {
    type Error = std::convert::Infallible;
    fn n_states(&self) -> usize {
        2
    }
    fn n_params(&self) -> usize {
        1
    }
    fn output_names(&self) -> Vec<String> {
        Oscillator.output_names()
    }
    fn linearize(&self, p: &[f64]) -> Result<Linearized, Self::Error> {
        let mut full = Oscillator.linearize(&[self.0, p[0]])?;
        full.da.remove(0);
        Ok(full)
    }
}

/// A test that holds a bound parameter at its estimate conditions on it: k's standard error
/// given c (held on its bound) is the one a fit with c fixed there reports, while the plain
/// standard error carries c's local uncertainty and is wider.
#[test]
fn holding_a_bound_parameter_gives_the_standard_error_of_a_fit_without_it() {
    let model = LinearResponse(Oscillator);
    let data = add_noise(&simulate_measurement(&model, &[0.2, 4.0], 0.05, 400, 0.0, 0), 0.01, 9);
    let params = vec![
        Parameter::new("c", 0.5).with_bounds(0.3, 1.0),
        Parameter::new("k", 3.5).with_bounds(0.1, 100.0),
    ];
    let fit = Fit::new().with_covariance(mem::Covariance::White);
    let report = fit.run(&Problem::new(vec![Experiment::new(&model, &data)], params).unwrap()).unwrap();
    assert_eq!(report.on_bound[0], Some(Side::Lower));
    let stats = &report.statistics;
    assert!(stats.covariance[(0, 1)].is_nan(), "the reported covariance blanks a bound row");
    assert!(stats.local_covariance[(0, 0)] > 0.0 && stats.local_covariance[(0, 1)].is_finite());
    let plain = report.std_error(1).unwrap();
    let held = stats.conditional_std_error(1, &[0]).unwrap();
    let fixed_model = LinearResponse(OscillatorWithDamping(0.3));
    let fixed = fit
        .run(
            &Problem::new(
                vec![Experiment::new(&fixed_model, &data)],
                vec![Parameter::new("k", report.parameters[1])],
            )
            .unwrap(),
        )
        .unwrap();
    assert!((fixed.parameters[0] / report.parameters[1] - 1.0).abs() < 1e-6, "{fixed}");
    let want = fixed.std_error(0).unwrap();
    // The two fits' σ̂² differ only by their degrees of freedom, (m − 1)/(m − 2).
    assert!((held / want - 1.0).abs() < 5e-3, "held {held} vs fixed {want}");
    assert!(plain > held, "plain {plain} vs held {held}");
    // Holding nothing, or the parameter itself, is the plain standard error.
    assert_eq!(stats.conditional_std_error(1, &[]), Some(plain));
    assert_eq!(stats.conditional_std_error(1, &[1]), Some(plain));
    assert_eq!(stats.conditional_std_error(0, &[1]), None);
}

/// The delta method's standard error of a derived quantity, the ratio k/c, against its spread
/// over 200 seeded noise realisations of the same record (independent of the covariance); the
/// gradient e_i gives the parameter's own standard error, and a quantity that depends on a
/// parameter held on its bound has none.
#[test]
fn a_derived_quantity_gets_the_delta_method_standard_error() {
    let model = LinearResponse(Oscillator);
    let clean = simulate_measurement(&model, &[0.2, 4.0], 0.05, 400, 0.0, 0);
    let fit = Fit::new().with_covariance(mem::Covariance::White);
    let run = |seed: u64| {
        let data = add_noise(&clean, 0.01, seed);
        let params = vec![
            Parameter::new("c", 0.25).with_bounds(0.01, 1.0),
            Parameter::new("k", 3.8).with_bounds(0.1, 100.0),
        ];
        fit.run(&Problem::new(vec![Experiment::new(&model, &data)], params).unwrap()).unwrap()
    };
    let report = run(1000);
    let (c, k) = (report.parameters[0], report.parameters[1]);
    let predicted = report.statistics.std_error_of(&[-k / (c * c), 1.0 / c]).unwrap();
    let ratios: Vec<f64> = (0..200).map(run).map(|r| r.parameters[1] / r.parameters[0]).collect();
    let mean = ratios.iter().sum::<f64>() / ratios.len() as f64;
    let spread = (ratios.iter().map(|r| (r - mean).powi(2)).sum::<f64>() / (ratios.len() - 1) as f64).sqrt();
    assert!((predicted / spread - 1.0).abs() < 0.2, "delta method {predicted} vs spread {spread}");
    assert_eq!(report.statistics.std_error_of(&[0.0, 1.0]), report.std_error(1));
    assert_eq!(report.statistics.std_error_of(&[1.0]), None, "one entry per parameter");
    // c held on its lower bound: k/c has no standard error, k alone still has one.
    let data = add_noise(&clean, 0.01, 9);
    let bound = vec![
        Parameter::new("c", 0.5).with_bounds(0.3, 1.0),
        Parameter::new("k", 3.5).with_bounds(0.1, 100.0),
    ];
    let held = fit.run(&Problem::new(vec![Experiment::new(&model, &data)], bound).unwrap()).unwrap();
    assert_eq!(held.on_bound[0], Some(Side::Lower));
    assert_eq!(held.statistics.std_error_of(&[1.0, 1.0]), None);
    assert!(held.statistics.std_error_of(&[0.0, 1.0]).is_some());
}

#[test]
fn a_start_outside_the_bounds_is_refused_naming_the_parameter() {
    let model = LinearResponse(Oscillator);
    let data = simulate_measurement(&model, &[0.2, 4.0], 0.05, 50, 0.0, 0);
    let params = vec![Parameter::new("c", 0.1).with_bounds(0.3, 1.0), Parameter::new("k", 3.5)];
    let error = Problem::new(vec![Experiment::new(&model, &data)], params).err().unwrap().to_string();
    assert!(error.contains("`c`") && error.contains("outside its bounds"), "{error}");
}

/// The bounded building converges about as fast as the unbounded one when the bounds are
/// inactive at the optimum, and lands exactly on a bound that is active.
#[test]
fn bounds_are_constraints_not_clamps() {
    let model = LinearResponse(Exact(ShearBuilding::displacements()));
    let names = ["k1", "k2", "k3", "alpha", "beta"];
    let truth = [2.62e6, 2.16e6, 1.96e6, 0.42, 1.18e-3];
    let data = add_noise(&simulate_measurement(&model, &truth, 0.005, 2001, 0.0, 0), 0.01, 11);
    let start = [2.0e6, 3.0e6, 1.5e6, 1.0, 0.5e-3];
    let run = |bounded: bool, data: &mem::Measurement| {
        let params = names
            .iter()
            .zip(start)
            .map(|(n, v)| {
                let p = Parameter::new(*n, v);
                if bounded { p.with_bounds(0.0, f64::INFINITY) } else { p }
            })
            .collect();
        Fit::new().run(&Problem::new(vec![Experiment::normalized(&model, data)], params).unwrap()).unwrap()
    };
    let free = run(false, &data);
    let bounded = run(true, &data);
    assert_eq!(free.termination, Termination::Converged, "{free}");
    assert_eq!(bounded.termination, Termination::Converged, "{bounded}");
    assert!(
        bounded.iterations <= 2 * free.iterations.max(1),
        "{} vs {}",
        bounded.iterations,
        free.iterations
    );
    for (a, b) in bounded.parameters.iter().zip(&free.parameters) {
        assert!((a / b - 1.0).abs() < 1e-6);
    }
    // Truth with α = 0 and noise: the data pull α below zero half the time; with α ≥ 0 it must
    // end exactly on 0 or inside, never outside, and converge.
    let zero_alpha = [2.62e6, 2.16e6, 1.96e6, 0.0, 1.18e-3];
    let data = add_noise(&simulate_measurement(&model, &zero_alpha, 0.005, 2001, 0.0, 0), 0.01, 12);
    let report = run(true, &data);
    assert_eq!(report.termination, Termination::Converged, "{report}");
    assert!(report.parameters[3] >= 0.0);
    for (got, want) in report.parameters.iter().zip(zero_alpha).take(3) {
        assert!((got / want - 1.0).abs() < 0.01, "{report}");
    }
}

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

/// A model whose linearize returns one ∂A/∂P too few.
struct ShortDerivatives;
impl LinearModel for ShortDerivatives {
    type Error = std::convert::Infallible;
    fn n_states(&self) -> usize {
        2
    }
    fn n_params(&self) -> usize {
        2
    }
    fn output_names(&self) -> Vec<String> {
        vec!["y0".into()]
    }
    fn linearize(&self, p: &[f64]) -> Result<Linearized, Self::Error> {
        let mut lin = Oscillator.linearize(p)?;
        lin.da.pop();
        Ok(lin)
    }
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

/// The oscillator with its initial displacement and velocity as parameters: ∂x(0)/∂P = [0, I].
struct OscillatorWithUnknownStart;
impl LinearModel for OscillatorWithUnknownStart {
    type Error = std::convert::Infallible;
    fn n_states(&self) -> usize {
        2
    }
    fn n_params(&self) -> usize {
        4
    }
    fn output_names(&self) -> Vec<String> {
        vec!["y0".into()]
    }
    fn linearize(&self, p: &[f64]) -> Result<Linearized, Self::Error> {
        let mut lin = Oscillator.linearize(&p[..2])?;
        lin.da.extend([Mat::zeros(2, 2), Mat::zeros(2, 2)]);
        lin.x0 = vec![p[2], p[3]];
        lin.dx0 = Some(mat![[0.0, 0.0, 1.0, 0.0], [0.0, 0.0, 0.0, 1.0]]);
        Ok(lin)
    }
}

#[test]
fn an_initial_state_near_zero_is_estimated_without_a_false_alarm() {
    let model = LinearResponse(OscillatorWithUnknownStart);
    let truth = [0.2, 4.0, 0.8, 1e-9];
    let data = add_noise(&simulate_measurement(&model, &truth, 0.05, 300, 0.0, 0), 0.01, 2);
    let problem = Problem::new(
        vec![Experiment::new(&model, &data)],
        vec![
            Parameter::new("c", 0.3),
            Parameter::new("k", 3.5),
            Parameter::new("x0", 1.0),
            Parameter::new("v0", 0.0),
        ],
    )
    .unwrap();
    let report = Fit::new().run(&problem).unwrap();
    assert!(report.identifiability.undetermined.is_empty(), "{:?}", report.identifiability);
    assert!(report.statistics.std_errors.iter().all(|s| s.is_some_and(f64::is_finite)), "{report}");
}

#[test]
fn a_record_that_starts_later_is_fitted_from_the_models_t0() {
    let model = LinearResponse(Oscillator);
    let truth = [0.2, 4.0];
    let full = simulate_measurement(&model, &truth, 0.05, 400, 0.0, 0);
    // The record from t = 1 s on (samples 20..): the model's x(0) still holds at t = 0.
    let values = Mat::from_fn(380, 1, |k, _| full.values()[(k + 20, 0)]);
    let late = mem::Measurement::new(vec!["y0".into()], 1.0, 0.05, values).unwrap();
    let report = Fit::new()
        .run(&Problem::unnamed(vec![Experiment::new(&model, &late)], &[0.3, 3.5]).unwrap())
        .unwrap();
    assert_eq!(report.termination, Termination::Converged);
    for (a, b) in report.parameters.iter().zip(truth) {
        assert!((a / b - 1.0).abs() < 1e-8, "{a} vs {b}");
    }
    // A record said to start before t = 0 is refused.
    let early =
        mem::Measurement::new(vec!["y0".into()], -1.0, 0.05, Mat::from_fn(10, 1, |k, _| k as f64)).unwrap();
    assert!(Problem::unnamed(vec![Experiment::new(&model, &early)], &[0.3, 3.5]).is_err());
}

#[test]
fn a_perfect_fit_is_converged() {
    let model = LinearResponse(Oscillator);
    let data = simulate_measurement(&model, &[0.2, 4.0], 0.05, 400, 0.0, 0);
    let report = Fit::new()
        .run(&Problem::unnamed(vec![Experiment::new(&model, &data)], &[0.2, 4.0]).unwrap())
        .unwrap();
    assert_eq!(report.termination, Termination::Converged, "{report}");
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

#[test]
fn step_equals_the_pseudo_inverse_from_faers_own_thin_svd() {
    // gauss_newton_step uses Householder QR + SVD of R; compare with faer's thin SVD of S
    // applied directly (an independent route to the same least-squares solution).
    let model = LinearResponse(test_problems::SpringChain { x0: [0.0, 0.01] });
    let data = simulate_measurement(&model, &test_problems::SpringChain::TRUE, 0.02, 300, 0.01, 4);
    let p = [35.0, 17.0, 0.35];
    let problem = Problem::unnamed(vec![Experiment::new(&model, &data)], &p).unwrap();
    let step = mem::gauss_newton_step(&problem, &p, 1e-10).unwrap();
    let mut out = expm::Response::zeros(300, 2, 3);
    mem::ResponseModel::respond(&model, &p, &Grid::free(0.02), &mut out).unwrap();
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

/// A response that depends on no parameter (a model at rest, not driven).
struct AtRest;

impl mem::ResponseModel for AtRest {
    fn n_params(&self) -> usize {
        1
    }
    fn output_names(&self) -> Vec<String> {
        vec!["y0".into()]
    }
    fn respond(&self, _p: &[f64], _grid: &Grid<'_>, out: &mut mem::Response) -> Result<(), mem::BoxedError> {
        out.outputs.fill(0.0);
        out.sensitivities.fill(0.0);
        Ok(())
    }
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

/// The spring chain with its coupling spring k₂ fixed: k₁ and c free.
struct ChainWithCoupling(f64);
impl LinearModel for ChainWithCoupling {
    type Error = std::convert::Infallible;
    fn n_states(&self) -> usize {
        4
    }
    fn n_params(&self) -> usize {
        2
    }
    fn output_names(&self) -> Vec<String> {
        vec!["y0".into(), "y1".into()]
    }
    fn linearize(&self, p: &[f64]) -> Result<Linearized, Self::Error> {
        let mut full = SpringChain { x0: [0.0, 0.1] }.linearize(&[p[0], self.0, p[1]])?;
        full.da.remove(1);
        Ok(full)
    }
}

/// A parameter on its bound whose descent direction points into the box is released, but the
/// Gauss–Newton step, moving k₁ with it, would push k₂ back out: projected, that step moves k₁
/// as if k₂ had moved, and the damping rejects it until it is tiny. Held, k₂ stays on its bound
/// and the step is solved for k₁ and c — no trial is rejected, and the fit ends where the fit
/// with k₂ fixed there does.
#[test]
fn a_parameter_the_step_would_push_through_its_bound_is_held_not_projected() {
    let model = LinearResponse(SpringChain { x0: [0.0, 0.1] });
    let data = add_noise(&simulate_measurement(&model, &SpringChain::TRUE, 0.02, 500, 0.0, 0), 0.01, 4);
    let bound = 16.0; // the truth's k₂ is 15: the constrained optimum is on the bound
    let params = vec![
        Parameter::new("k1", 45.0).with_bounds(1.0, 100.0),
        Parameter::new("k2", bound).with_bounds(bound, 100.0),
        Parameter::new("c", 0.3).with_bounds(0.01, 5.0),
    ];
    let fit = Fit::new().with_derivative_check(DerivativeCheck::Skip);
    let report = fit.run(&Problem::new(vec![Experiment::new(&model, &data)], params).unwrap()).unwrap();
    assert_eq!(report.termination, Termination::Converged);
    assert_eq!(report.parameters[1], bound);
    let first = &report.records[0];
    assert_eq!(first.step[1], 0.0, "k₂ held on its bound: {:?}", first.step);
    let rejected: Vec<usize> = report.records.iter().map(|r| r.rejected_trials).collect();
    assert!(rejected.iter().all(|&r| r == 0), "rejected trials per iteration {rejected:?}");
    let fixed_model = LinearResponse(ChainWithCoupling(bound));
    let fixed = fit
        .run(
            &Problem::new(vec![Experiment::new(&fixed_model, &data)], parameters(&["k1", "c"], &[45.0, 0.3]))
                .unwrap(),
        )
        .unwrap();
    for (got, want) in
        [(report.parameters[0], fixed.parameters[0]), (report.parameters[2], fixed.parameters[1])]
    {
        assert!((got / want - 1.0).abs() < 1e-6, "{got} against {want}");
    }
}

/// The oscillator with a third parameter the outputs do not depend on.
struct OscillatorWithInert;
impl LinearModel for OscillatorWithInert {
    type Error = std::convert::Infallible;
    fn n_states(&self) -> usize {
        2
    }
    fn n_params(&self) -> usize {
        3
    }
    fn output_names(&self) -> Vec<String> {
        Oscillator.output_names()
    }
    fn linearize(&self, p: &[f64]) -> Result<Linearized, Self::Error> {
        let mut full = Oscillator.linearize(&p[..2])?;
        full.da.push(Mat::zeros(2, 2));
        Ok(full)
    }
}

/// A parameter resting on its bound that the data do not determine gets no interval, as the
/// rank-deficiency warning says, not a one-sided one from the bound to infinity, and no warning
/// that the data pull it beyond the bound. (Its finite differences, one-sided at the bound, are
/// pure rounding: the derivative check must not call that a mismatch.)
#[test]
fn a_parameter_on_its_bound_that_the_data_do_not_determine_gets_no_interval() {
    let model = LinearResponse(OscillatorWithInert);
    let data = add_noise(&simulate_measurement(&model, &[0.2, 4.0, 1.0], 0.05, 400, 0.0, 0), 0.01, 9);
    let params = vec![
        Parameter::new("c", 0.25).with_bounds(0.01, 1.0),
        Parameter::new("k", 3.5).with_bounds(0.1, 100.0),
        Parameter::new("inert", 1.0).with_bounds(1.0, 2.0),
    ];
    let report =
        Fit::new().run(&Problem::new(vec![Experiment::new(&model, &data)], params).unwrap()).unwrap();
    assert_eq!(report.parameters[2], 1.0, "{report}");
    assert!(
        report.warnings().iter().any(
            |w| matches!(w, Warning::RankDeficient { parameters, .. } if parameters == &["inert".to_string()])
        ),
        "inert must be named undetermined: {report}"
    );
    assert_eq!(report.on_bound[2], Some(Side::Lower), "it does rest on its bound");
    assert!(
        !report.warnings().iter().any(|w| matches!(w, Warning::ActiveBound { .. })),
        "no data pull it beyond its bound: {report}"
    );
    assert_eq!(report.std_error(2), None);
    assert_eq!(report.statistics.intervals[2], Interval::Undetermined, "{report}");
    assert!(report.to_string().contains("none: not determined by the data"), "{report}");
    for i in 0..2 {
        assert!(matches!(report.statistics.intervals[i], Interval::Symmetric { .. }), "{report}");
    }
}
