//! Bounds as constraints: a parameter on its bound is held, gets a one-sided interval and a
//! warning, and conditions what is tested.

use super::*;

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
