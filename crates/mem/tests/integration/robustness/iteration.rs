//! The Gauss–Newton iteration: the safeguard, what a rejected trial costs, where a record starts,
//! convergence, and the step against faer's own SVD.

use super::*;

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
