//! The exponential integrator against the adaptive solver, and its sensitivities against central
//! differences of itself (they are the exact derivatives of its recursion).

use expm::Response;
use mem::{Grid, ResponseModel};
use models::exponential::DEFAULT_MAX_STEP;
use models::{ExponentialResponse, NonlinearResponse};
use plant::SlewingModel;

fn with_effects(effects: &str) -> SlewingModel {
    let text = plant::PAPER_MODEL_RON
        .replace("    bounds: {", &format!("    effects: [{effects}],\n    bounds: {{"));
    SlewingModel::from_ron(&text, "effects.ron").unwrap()
}

/// Every nonlinear effect of the catalog, at strengths that visibly change the response, sharp
/// friction included.
const CASES: [(&str, &[&str]); 11] = [
    ("AmplifierSaturation(current_limit: 1.2, sharp: false)", &["cv", "kp", "current_limit"]),
    ("VoltageSaturation(voltage_limit: 2.5, sharp: false)", &["cv", "kp", "voltage_limit"]),
    ("VoltageSaturation(voltage_limit: 4.0, knee: Some(2.0))", &["cv", "voltage_limit", "voltage_knee"]),
    ("AmplifierSaturation(current_limit: 1.2, knee: Some(30.0))", &["kp", "current_limit", "current_knee"]),
    (
        "CoulombFriction(torque: 0.004, smoothing_velocity: 0.0002)",
        &["cv", "kp", "coulomb_torque", "hub_inertia"],
    ),
    (
        "CoulombFriction(torque: 0.004, smoothing_velocity: 0.0002, static_peak: Some(0.003), stribeck_velocity: Some(0.02))",
        &["cv", "coulomb_torque", "static_peak", "stribeck_velocity"],
    ),
    ("QuadraticDrag(hub: 0.05, exponent: Some(1.6))", &["cv", "drag_hub", "drag_exponent", "ei_over_rho"]),
    (
        "CubicStiffness(coefficient: -0.2, linear: Some(0.02)), TimeDelay(delay: 0.05)",
        &["kp", "cubic_stiffness", "hub_stiffness", "delay", "modal_damping_1"],
    ),
    (
        "CubicStiffness(coefficient: 0.3, quintic: Some(-0.5), rate: Some(0.004))",
        &["kp", "cubic_stiffness", "quintic_stiffness", "stiffness_rate"],
    ),
    (
        "UnmodeledMode(frequency_hz: 0.8, damping_ratio: 0.02, coupling: 0.1), AmplifierSaturation(current_limit: 1.5, sharp: false)",
        &["cv", "extra_mode_frequency", "extra_mode_coupling", "current_limit"],
    ),
    (
        "Backlash(dead_band: 0.004, gear_frequency_hz: 12.0)",
        &["cv", "kp", "backlash", "gear_frequency", "motor_inertia"],
    ),
];

fn respond(model: &dyn ResponseModel, p: &[f64], k: usize, h: f64) -> Response {
    let mut out = Response::zeros(k, 3, p.len());
    model.respond(p, &Grid::free(h), &mut out).unwrap();
    out
}

fn scale(m: &faer::Mat<f64>, col: impl Fn(usize) -> bool) -> f64 {
    let mut worst = 0.0f64;
    for c in 0..m.ncols() {
        if col(c) {
            for r in 0..m.nrows() {
                worst = worst.max(m[(r, c)].abs());
            }
        }
    }
    worst
}

#[test]
fn exponential_integrator_matches_the_adaptive_solver() {
    let (k, h) = (3841, 1.0 / 128.0);
    for (effects, names) in CASES {
        let model = with_effects(effects);
        let p: Vec<f64> = names.iter().map(|n| model.get(model.parameter(n).unwrap())).collect();
        let exact = NonlinearResponse::new(model.clone(), names).unwrap().with_tolerances(1e-11, 1e-13);
        let a = respond(&exact, &p, k, h);
        for (step, loosen) in [(DEFAULT_MAX_STEP, 1.0), (2.0 * DEFAULT_MAX_STEP, 4.0)] {
            let fast = ExponentialResponse::new(model.clone(), names).unwrap().with_max_step(step);
            let b = respond(&fast, &p, k, h);
            for o in 0..3 {
                let s = (0..k).map(|t| a.outputs[(t, o)].abs()).fold(0.0, f64::max);
                let err = (0..k).map(|t| (a.outputs[(t, o)] - b.outputs[(t, o)]).abs()).fold(0.0, f64::max);
                println!("{step:.2e} {effects}: output {o} error {:.2e} of {s:.2e}", err / s);
                // A dead band's corners (the smooth limiter over a 4 mrad band, crossed by a 12 Hz
                // gear) are the sharpest forcing here; second order in the substep, they hold the
                // motor's rate to 10⁻⁴ (still a hundredth of the smallest sensor noise studied).
                // Twice the substep (diagnose's, for the slewing rig) is held to four times as much.
                let tolerance = if effects.starts_with("Backlash") { 3e-4 } else { 1e-5 };
                assert!(err < loosen * tolerance * s, "{effects}: output {o}: {err:.3e} of {s:.3e}");
            }
            for i in 0..names.len() {
                let s = (0..3 * k).map(|r| a.sensitivities[(r, i)].abs()).fold(0.0, f64::max);
                let err = (0..3 * k)
                    .map(|r| (a.sensitivities[(r, i)] - b.sensitivities[(r, i)]).abs())
                    .fold(0.0, f64::max);
                println!("{step:.2e} {effects}: ∂/∂{} error {:.2e} of {s:.2e}", names[i], err / s);
                let tolerance = if effects.starts_with("Backlash") { 3e-3 } else { 1e-3 };
                assert!(
                    err < loosen * tolerance * s,
                    "{effects}: sensitivity {}: {err:.3e} of {s:.3e}",
                    names[i]
                );
            }
        }
    }
}

#[test]
fn exponential_sensitivities_are_the_derivatives_of_its_recursion() {
    let (k, h) = (300, 1.0 / 12.8);
    for (effects, names) in CASES {
        let model = with_effects(effects);
        let p: Vec<f64> = names.iter().map(|n| model.get(model.parameter(n).unwrap())).collect();
        let fast = ExponentialResponse::new(model, names).unwrap();
        let base = respond(&fast, &p, k, h);
        for i in 0..names.len() {
            let step = STEP * p[i].abs().max(1e-3);
            let shifted = |sign: f64| {
                let mut q = p.clone();
                q[i] += sign * step;
                respond(&fast, &q, k, h).outputs
            };
            let (up, down) = (shifted(1.0), shifted(-1.0));
            let s = scale(&base.sensitivities, |c| c == i);
            let mut err = 0.0f64;
            for t in 0..k {
                for o in 0..3 {
                    let fd = (up[(t, o)] - down[(t, o)]) / (2.0 * step);
                    err = err.max((fd - base.sensitivities[(t * 3 + o, i)]).abs());
                }
            }
            assert!(err < 1e-5 * s, "{effects}: ∂/∂{}: {err:.3e} of {s:.3e}", names[i]);
        }
    }
}

/// Relative step of the central differences: 10⁻⁵ balances their truncation error against the
/// rounding of 38 400 substeps (both near 10⁻⁶ of the sensitivity's scale).
const STEP: f64 = 1e-5;

/// The outputs alone (`respond_outputs`, what the fitter's trial points cost) are the bits of
/// the full response's outputs, for every effect of the catalog, bare and behind sensor terms.
#[test]
fn outputs_alone_are_the_bits_of_the_full_response() {
    let grid = Grid::free(1.0 / 12.8);
    let same = |model: &dyn ResponseModel, p: &[f64], what: &str| {
        let full = respond(model, p, 200, 1.0 / 12.8);
        let mut alone = Response::zeros(200, 3, 0);
        model.respond_outputs(p, &grid, &mut alone).unwrap();
        for k in 0..200 {
            for o in 0..3 {
                assert_eq!(
                    alone.outputs[(k, o)].to_bits(),
                    full.outputs[(k, o)].to_bits(),
                    "{what}: sample {k}, output {o}"
                );
            }
        }
        assert!(full.sensitivities.norm_max() > 0.0, "{what}: the full response has sensitivities");
    };
    for (effects, free) in CASES {
        let model = with_effects(effects);
        let p: Vec<f64> = free.iter().map(|n| model.get(model.parameter(n).unwrap())).collect();
        let bare = ExponentialResponse::new(model.clone(), free).unwrap();
        same(&bare, &p, effects);
        // Behind an offset, a scale and a drift, each freed (the sensor adapter's own path).
        let sensed = format!(
            "{effects}, OutputOffset(sensor: Tachometer, offset: 0.01), SensorScale(sensor: StrainGauge, \
             scale: 0.05), SensorDrift(sensor: Potentiometer, rate: 0.001)"
        );
        let model = models::Model::Slewing(with_effects(&sensed));
        let mut names: Vec<&str> = free.to_vec();
        names.extend(["offset_theta_dot", "scale_strain", "drift_theta"]);
        let response = model
            .response_with(&names, models::Integrator::Exponential { max_step: DEFAULT_MAX_STEP })
            .unwrap();
        let q: Vec<f64> = names.iter().map(|n| model.value(n).unwrap()).collect();
        same(response.as_ref(), &q, &sensed);
    }
}

/// A hub spring without its cubic part is linear: with `cubic_stiffness` fixed at zero the
/// exact exponential path applies (k₁ in A), and its response and sensitivities are those of
/// the adaptive solver; freed, the cubic part sends the model down the nonlinear path.
#[test]
fn a_hub_spring_without_its_cubic_part_takes_the_exact_path() {
    let bare = SlewingModel::paper();
    let k1 = 0.3 * plant::assemble::servo_stiffness(bare.constants());
    let model = with_effects(&format!("CubicStiffness(coefficient: 0.0, linear: Some({k1:e}))"));
    let id = |n: &str| model.parameter(n).unwrap();
    assert!(model.is_linear_for(&[id("cv"), id("kp"), id("hub_stiffness")]));
    assert!(!model.is_linear_for(&[id("cv"), id("hub_stiffness"), id("cubic_stiffness")]));
    assert!(!with_effects("CubicStiffness(coefficient: 0.5)").is_linear_for(&[id("cv")]));
    // A quintic or time-varying part, even fixed, is not linear time-invariant physics.
    for form in ["quintic: Some(1.0)", "rate: Some(0.001)"] {
        let m = with_effects(&format!("CubicStiffness(coefficient: 0.0, {form})"));
        assert!(!m.is_linear_for(&[id("cv")]), "{form}");
    }
    let names = ["cv", "kp", "hub_stiffness"];
    let p: Vec<f64> = names.iter().map(|n| model.get(id(n))).collect();
    let (k, h) = (1281, 1.0 / 128.0);
    let exact = models::Model::Slewing(model.clone())
        .response_with(&names, models::Integrator::Exponential { max_step: DEFAULT_MAX_STEP })
        .unwrap();
    let a = respond(exact.as_ref(), &p, k, h);
    let adaptive = NonlinearResponse::new(model.clone(), &names).unwrap().with_tolerances(1e-11, 1e-13);
    let b = respond(&adaptive, &p, k, h);
    for o in 0..3 {
        let s = (0..k).map(|t| b.outputs[(t, o)].abs()).fold(0.0, f64::max);
        let err = (0..k).map(|t| (a.outputs[(t, o)] - b.outputs[(t, o)]).abs()).fold(0.0, f64::max);
        assert!(err < 1e-7 * s, "output {o}: {err:.3e} of {s:.3e}");
    }
    for i in 0..names.len() {
        let s = scale(&b.sensitivities, |c| c == i);
        let err =
            (0..3 * k).map(|r| (a.sensitivities[(r, i)] - b.sensitivities[(r, i)]).abs()).fold(0.0, f64::max);
        assert!(s > 0.0 && err < 1e-6 * s, "∂/∂{}: {err:.3e} of {s:.3e}", names[i]);
    }
    // The spring changes the response (the hub is held back toward rest).
    let plain = respond(&ExponentialResponse::new(bare.clone(), &["cv", "kp"]).unwrap(), &p[..2], k, h);
    let moved = (0..k).map(|t| (plain.outputs[(t, 0)] - a.outputs[(t, 0)]).abs()).fold(0.0, f64::max);
    assert!(moved > 1e-3 * scale(&a.outputs, |c| c == 0), "the spring moves θ by {moved:.3e}");
}
