//! A structure with a force effect driven by measured inputs (a forced response that is not
//! linear), on the exponential integrator: with the force at zero it is the exact linear forced
//! response of the `mem` path, for either hold and a record that starts late; with a hardening
//! spring it is the record of an independent simulator
//! (`fixtures/independent/shear_building_forced_cubic.py`, scipy), and a fit recovers the
//! simulator's truth from its noisy copy.

use expm::Response;
use faer::Mat;
use mem::{Grid, Hold, Inputs, Measurement, ResponseModel};
use models::{Model, StructureExponential};
use structure::StructureModel;

const FILE: &str = include_str!("../../../../fixtures/shear_building_forced.ron");
const FREE: [&str; 5] = ["k1", "k2", "k3", "alpha", "beta"];
/// The simulator's truth: k1..k3, α, β (`fixtures/independent/README.md`).
const TRUTH: [f64; 5] = [2.62e6, 2.16e6, 1.96e6, 0.42, 1.18e-3];
/// The simulator's cubic coefficient on storey 1 \[N/m³\] (printed by its script).
const CUBIC: f64 = 1.03e12;

/// The forced building's file with `effects` added.
fn with_effects(effects: &str) -> String {
    FILE.trim_end().trim_end_matches(')').to_string() + &format!("    effects: [{effects}],\n)\n")
}

/// A record of `k` samples holding a seeded random force `u` (1500 N RMS) and zero outputs,
/// held as `hold`, its first sample at `start`.
fn drive(k: usize, h: f64, start: f64, hold: Hold) -> Measurement {
    let mut r = test_problems::rng(20261128);
    let values = Mat::from_fn(k, 4, |_, c| {
        if c == 0 { 1500.0 * rand::Rng::sample::<f64, _>(&mut r, rand_distr::StandardNormal) } else { 0.0 }
    });
    let names = ["u", "a1", "a2", "a3"].map(String::from).to_vec();
    Measurement::new(names, start, h, values).unwrap().with_inputs(&["u"], hold).unwrap()
}

fn respond(model: &dyn ResponseModel, p: &[f64], data: &Measurement) -> Response {
    let k = data.n_samples();
    let mut out = Response::zeros(k, 3, p.len());
    let inputs: Option<&Inputs> = data.inputs();
    model
        .respond(p, &Grid { start: data.start(), interval: data.interval(), inputs }, &mut out)
        .expect("it simulates");
    out
}

/// With the cubic coefficient at zero the integrator's model is linear, and its forced response
/// is the exact one of the linear path (`mem`'s exponential with the input's hold): outputs and
/// sensitivities agree to round-off for a zero-order and a first-order hold, from t = 0 and from
/// a first sample at 0.0123 s (the input zero before it).
#[test]
fn with_the_force_at_zero_the_forced_response_is_the_linear_paths() {
    let nonlinear = StructureModel::from_ron(
        &with_effects("CubicStiffness(coordinate: \"q1\", coefficient: 0)"),
        "b.ron",
    )
    .unwrap();
    let linear = StructureModel::from_ron(FILE, "b.ron").unwrap();
    let p = [2.6e6, 2.2e6, 1.9e6, 0.4, 1.2e-3];
    let integrator = StructureExponential::new(nonlinear, &FREE).unwrap();
    let exact = models::StructureFitModel::new(linear, &FREE).unwrap().response();
    for (hold, start) in
        [(Hold::Zero, 0.0), (Hold::FirstOrder, 0.0), (Hold::Zero, 0.0123), (Hold::FirstOrder, 0.0123)]
    {
        let data = drive(400, 0.005, start, hold);
        let (got, want) = (respond(&integrator, &p, &data), respond(&exact, &p, &data));
        let peak = want.outputs.norm_max();
        let worst = (&got.outputs - &want.outputs).norm_max();
        assert!(
            peak > 0.1 && worst < 1e-9 * peak,
            "{hold:?} from {start} s: outputs off by {worst:e} of {peak:e}"
        );
        for i in 0..FREE.len() {
            let scale = want.sensitivities.col(i).norm_max();
            let off = (0..want.sensitivities.nrows())
                .map(|r| (got.sensitivities[(r, i)] - want.sensitivities[(r, i)]).abs())
                .fold(0.0, f64::max);
            assert!(
                scale > 0.0 && off < 1e-8 * scale,
                "{hold:?} from {start} s, ∂/∂{}: off by {off:e} of {scale:e}",
                FREE[i]
            );
        }
    }
}

/// The hardening building of the independent simulator, simulated by memid at the truth from
/// rest under the record's force, against the simulator's noise-free record: within 10⁻⁴ of each
/// acceleration's peak at the default substep (the spring changes the accelerations' RMS by
/// 15–35 %), and converging on it at second order in the substep — 7, 13 and 26 substeps per
/// sample measured 4.5·10⁻⁵, 1.3·10⁻⁵ and 3.3·10⁻⁶ of a1's peak, the ratios (13/7)² and
/// (26/13)² of a second-order error: the two models are the same, and the distance is the
/// integrator's.
#[test]
fn a_forced_hardening_building_is_the_independent_simulators() {
    let model = Model::from_ron(
        &with_effects(&format!("CubicStiffness(coordinate: \"q1\", coefficient: {CUBIC:e})")),
        "b.ron",
    )
    .unwrap();
    let clean = Measurement::from_csv(
        include_str!("../../../../fixtures/independent/clean/shear_forced_cubic_q1.csv"),
        "shear_forced_cubic_q1.csv",
    )
    .unwrap();
    let data = models::align(&model, &clean).unwrap();
    // The largest error over the three accelerations, relative to each one's peak.
    let error = |max_step: f64| {
        let response = model.response_with(&FREE, models::Integrator::Exponential { max_step }).unwrap();
        let out = respond(response.as_ref(), &TRUTH, &data);
        (0..3)
            .map(|o| {
                let reference = data.values().col(o);
                let worst = (0..data.n_samples())
                    .map(|k| (out.outputs[(k, o)] - reference[k]).abs())
                    .fold(0.0, f64::max);
                worst / reference.norm_max()
            })
            .fold(0.0, f64::max)
    };
    let default = error(models::exponential::DEFAULT_MAX_STEP);
    let (finer, finest) = (error(1.0 / 2560.0), error(1.0 / 5120.0));
    assert!(default < 1e-4, "{default:e}");
    // 7 → 13 → 26 substeps per sample of 5 ms.
    assert!(default / finer > 0.8 * (13.0f64 / 7.0).powi(2), "{default:e} → {finer:e}");
    assert!(finer / finest > 0.8 * 4.0, "{finer:e} → {finest:e}");
}

/// From the model file's nominal values, the storeys' stiffnesses, the damping and the spring's
/// cubic coefficient are fitted from the simulator's noisy record (1 % noise): each within three
/// standard errors and 2 % of its truth, the cubic resolved from zero by more than five, after a
/// derivative check at the start that the sensitivities pass with a wide margin.
#[test]
fn a_hardening_spring_is_fitted_from_a_forced_record() {
    let model =
        Model::from_ron(&with_effects("CubicStiffness(coordinate: \"q1\", coefficient: 5e11)"), "b.ron")
            .unwrap();
    let noisy = Measurement::from_csv(
        include_str!("../../../../fixtures/independent/effects/shear_forced_cubic_q1.csv"),
        "shear_forced_cubic_q1.csv",
    )
    .unwrap();
    let free: Vec<&str> = FREE.iter().copied().chain(["cubic_q1"]).collect();
    let outcome = models::fit(&model, &noisy, &models::FitRequest::new(&free)).unwrap();
    let report = &outcome.report;
    for (i, truth) in TRUTH.iter().chain([&CUBIC]).enumerate() {
        let (value, se) = (report.parameters[i], report.std_error(i).expect("determined"));
        assert!(
            (value - truth).abs() < 3.0 * se && (value / truth - 1.0).abs() < 0.02,
            "{}: {value} ± {se} (truth {truth})",
            free[i]
        );
    }
    let (cubic, se) = (report.parameters[5], report.std_error(5).unwrap());
    assert!(cubic / se > 5.0, "cubic {cubic} ± {se}");
    // The derivative check's central differences, stepped for a recursion smooth in P to
    // rounding, agree with the exact sensitivities by a wide margin (measured 4.8e-7; with steps
    // of 10⁻³ of each parameter their own truncation gave 4.8e-5, near the 1e-4 tolerance).
    let check = report.derivative_check.as_ref().expect("the check ran");
    assert!(check.worst_relative_mismatch < 1e-5, "{check:?}");
}

/// An unmodeled mode driven by the measured input is that input's response through
/// η̈ + 2ζω η̇ + ω² η = ω² u from rest: for a unit step held from t = 0 the closed form
/// η = 1 − e^{−ζωt}(cos ω_d t + ζω/ω_d sin ω_d t), η̇ = (ω²/ω_d) e^{−ζωt} sin ω_d t, added to each
/// output as a η + b η̇/ω. A free ringing (no `driven_by`) in the same file starts from η = 1
/// instead, and a `driven_by` that names no input is refused by name.
#[test]
fn a_driven_unmodeled_mode_adds_its_step_response() {
    let (f, zeta, (a1, b1), (a3, b3)): (f64, f64, (f64, f64), (f64, f64)) =
        (17.0, 0.03, (2e-6, -1e-6), (-5e-7, 3e-6));
    let mode = |drive: &str| {
        format!(
            "UnmodeledMode(frequency_hz: {f}, damping_ratio: {zeta}, amplitudes: [({a1}, {b1}), ({a1}, {b1}), \
             ({a3}, {b3})]{drive})"
        )
    };
    let driven = Model::from_ron(&with_effects(&mode(", driven_by: \"u\"")), "f.ron").unwrap();
    let plain = Model::from_ron(FILE, "f.ron").unwrap();
    let (k, h) = (400, 0.002);
    let names = ["u", "a1", "a2", "a3"].map(String::from).to_vec();
    let step = Measurement::new(names, 0.0, h, Mat::from_fn(k, 4, |_, c| if c == 0 { 1.0 } else { 0.0 }))
        .unwrap()
        .with_inputs(&["u"], Hold::Zero)
        .unwrap();
    let with = respond(driven.response(&[]).unwrap().as_ref(), &[], &step);
    let without = respond(plain.response(&[]).unwrap().as_ref(), &[], &step);
    let w = 2.0 * std::f64::consts::PI * f;
    let wd = w * (1.0 - zeta * zeta).sqrt();
    for s in 0..k {
        let t = s as f64 * h;
        let decay = (-zeta * w * t).exp();
        let eta = 1.0 - decay * ((wd * t).cos() + zeta * w / wd * (wd * t).sin());
        let rate = w * w / wd * decay * (wd * t).sin();
        for (o, (a, b)) in [(a1, b1), (a1, b1), (a3, b3)].into_iter().enumerate() {
            let expected = without.outputs[(s, o)] + a * eta + b * rate / w;
            assert!((with.outputs[(s, o)] - expected).abs() < 1e-12, "sample {s} output {o}");
        }
    }
    // The free ringing starts at a_o (η(0) = 1): the driven mode at 0.
    let ringing = Model::from_ron(&with_effects(&mode("")), "f.ron").unwrap();
    let rung = respond(ringing.response(&[]).unwrap().as_ref(), &[], &step);
    assert!((rung.outputs[(0, 0)] - without.outputs[(0, 0)] - a1).abs() < 1e-15);
    assert!((with.outputs[(0, 0)] - without.outputs[(0, 0)]).abs() < 1e-15);
    let err = Model::from_ron(&with_effects(&mode(", driven_by: \"v\"")), "f.ron").unwrap_err().to_string();
    assert!(err.contains("driven_by = `v`") && err.contains("the inputs are u"), "{err}");
}

/// A strong dry friction smoothed over a small velocity (4,500 N at q2 over 0.9 mm/s, the
/// catalog's trial on draw 20261355's `A_friction_strong_s1`) under the seeded random force:
/// below v_s it is a damper F/v_s of 5·10⁶ N·s/m on a floor of 1,000 kg, which the integrator's
/// explicit force step does not hold at the default substep (1/1280 s: h·F/(v_s m) = 6; there
/// a1 was 1.6·10⁻² of its peak off). The substep follows the friction (a quarter of v_s m / F),
/// and the response agrees with one at a fortieth of the default substep to 10⁻³ of the
/// accelerations' peaks away from the friction, and to 3·10⁻² at its own floor, whose
/// acceleration holds the force that reverses while the floor sticks.
#[test]
fn a_strong_sharp_friction_is_integrated_at_a_substep_it_holds() {
    let model = Model::from_ron(
        &with_effects("DryFriction(coordinate: \"q2\", force: 4500, smoothing_velocity: 0.0009)"),
        "b.ron",
    )
    .unwrap();
    let data = drive(400, 0.005, 0.0, Hold::Zero);
    let p = [2.6e6, 2.2e6, 1.9e6, 0.4, 1.2e-3];
    let at = |max_step: f64| {
        let response = model.response_with(&FREE, models::Integrator::Exponential { max_step }).unwrap();
        respond(response.as_ref(), &p, &data)
    };
    let default = at(models::exponential::DEFAULT_MAX_STEP);
    let fine = at(models::exponential::DEFAULT_MAX_STEP / 40.0);
    for (o, tolerance) in [(0, 1e-3), (1, 3e-2), (2, 1e-3)] {
        let peak = fine.outputs.col(o).norm_max();
        let worst = (0..data.n_samples())
            .map(|k| (default.outputs[(k, o)] - fine.outputs[(k, o)]).abs())
            .fold(0.0, f64::max);
        assert!(peak > 0.0 && worst < tolerance * peak, "a{}: off by {worst:e} of {peak:e}", o + 1);
    }
}
