//! The ODE path against the exact exponential path, and its sensitivities against differences.

use expm::Response;
use mem::{Experiment, Fit, Grid, Problem, ResponseModel, Termination};
use models::{NonlinearResponse, SlewingFitModel};
use plant::SlewingModel;

fn with_effects(effects: &str) -> SlewingModel {
    let text = plant::PAPER_MODEL_RON
        .replace("    bounds: {", &format!("    effects: [{effects}],\n    bounds: {{"));
    SlewingModel::from_ron(&text, "effects.ron").unwrap()
}

#[test]
fn ode_path_matches_matrix_exponential_on_a_linear_model() {
    // ODE tolerances rtol 1e-9, atol 1e-11: outputs and sensitivities agree to ~1e-7 of scale.
    let model = SlewingModel::paper();
    let exact = SlewingFitModel::new(model.clone(), &["cv", "kp"]).unwrap().response();
    let ode = NonlinearResponse::new(model, &["cv", "kp"]).unwrap();
    let p = [0.0528, 8.0];
    let (mut a, mut b) = (Response::zeros(300, 3, 2), Response::zeros(300, 3, 2));
    exact.respond(&p, &Grid::free(1.0 / 12.8), &mut a).unwrap();
    ode.respond(&p, &Grid::free(1.0 / 12.8), &mut b).unwrap();
    for o in 0..3 {
        let scale = (0..300).map(|k| a.outputs[(k, o)].abs()).fold(0.0, f64::max);
        for k in 0..300 {
            assert!((a.outputs[(k, o)] - b.outputs[(k, o)]).abs() < 1e-6 * scale, "output {o} sample {k}");
        }
    }
    for i in 0..2 {
        let scale = (0..900).map(|r| a.sensitivities[(r, i)].abs()).fold(0.0, f64::max);
        for r in 0..900 {
            assert!(
                (a.sensitivities[(r, i)] - b.sensitivities[(r, i)]).abs() < 1e-6 * scale,
                "sens {i} row {r}"
            );
        }
    }
}

#[test]
fn nonlinear_sensitivities_match_central_differences() {
    let model = with_effects(
        "AmplifierSaturation(current_limit: 1.5), QuadraticDrag(hub: 0.05), CoulombFriction(torque: 0.005, smoothing_velocity: 0.02)",
    );
    let names = ["cv", "current_limit", "drag_hub", "coulomb_torque", "kp"];
    let ode = NonlinearResponse::new(model, &names).unwrap();
    let p = [0.06, 1.5, 0.05, 0.005, 8.0];
    let k = 200;
    let mut base = Response::zeros(k, 3, 5);
    ode.respond(&p, &Grid::free(1.0 / 12.8), &mut base).unwrap();
    for i in 0..5 {
        // Step 1e-5 relative with tight ODE tolerances: difference error ~1e-9 of scale.
        let h = 1e-5 * p[i];
        let run = |sign: f64| {
            let mut q = p;
            q[i] += sign * h;
            let mut out = Response::zeros(k, 3, 5);
            ode.respond(&q, &Grid::free(1.0 / 12.8), &mut out).unwrap();
            out
        };
        let (plus, minus) = (run(1.0), run(-1.0));
        let scale = (0..3 * k).map(|r| base.sensitivities[(r, i)].abs()).fold(0.0, f64::max);
        let mut worst = 0.0f64;
        for step in 0..k {
            for o in 0..3 {
                let fd = (plus.outputs[(step, o)] - minus.outputs[(step, o)]) / (2.0 * h);
                worst = worst.max((fd - base.sensitivities[(step * 3 + o, i)]).abs());
            }
        }
        assert!(worst < 1e-4 * scale, "{}: worst {worst:e} of scale {scale:e}", names[i]);
    }
}

#[test]
fn drag_coefficient_is_recovered_by_the_mem_iteration() {
    let truth = with_effects("QuadraticDrag(hub: 0.08)");
    let data_model = NonlinearResponse::new(truth.clone(), &["drag_hub"]).unwrap();
    let data = test_problems::simulate_measurement(&data_model, &[0.08], 1.0 / 12.8, 300, 0.0, 0);
    let fit_model = NonlinearResponse::new(truth, &["cv", "drag_hub"]).unwrap();
    let problem = Problem::unnamed(vec![Experiment::normalized(&fit_model, &data)], &[0.07, 0.03]).unwrap();
    let report = Fit::new().run(&problem).unwrap();
    assert_eq!(report.termination, Termination::Converged);
    assert!((report.parameters[1] / 0.08 - 1.0).abs() < 1e-5, "{:?}", report.parameters);
    assert!((report.parameters[0] / 0.0528 - 1.0).abs() < 1e-5, "{:?}", report.parameters);
}

#[test]
fn ode_path_matches_matrix_exponential_for_every_physical_parameter() {
    // The structural parameters' sensitivities (beam stiffness, inertias, modal damping) pass
    // through the beam's modes: both paths must differentiate them alike.
    let model = SlewingModel::paper();
    let names = ["ei_over_rho", "hub_inertia", "modal_damping_1", "motor_inertia", "rho", "length"];
    let exact = SlewingFitModel::new(model.clone(), &names).unwrap().response();
    let ode = NonlinearResponse::new(model.clone(), &names).unwrap();
    let p: Vec<f64> = names.iter().map(|n| model.get(model.parameter(n).unwrap())).collect();
    let (mut a, mut b) = (Response::zeros(300, 3, 6), Response::zeros(300, 3, 6));
    exact.respond(&p, &Grid::free(1.0 / 12.8), &mut a).unwrap();
    ode.respond(&p, &Grid::free(1.0 / 12.8), &mut b).unwrap();
    for (i, name) in names.iter().enumerate() {
        let scale = (0..900).map(|r| a.sensitivities[(r, i)].abs()).fold(0.0, f64::max);
        let worst =
            (0..900).map(|r| (a.sensitivities[(r, i)] - b.sensitivities[(r, i)]).abs()).fold(0.0, f64::max);
        assert!(worst < 1e-5 * scale, "{name}: worst {worst:.3e} of {scale:.3e}");
    }
}
