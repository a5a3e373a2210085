//! Effects on a structure model file (`structure::effects`): the forces at coordinates against an
//! independent fourth-order Runge–Kutta simulation of the same building written out here by
//! hand, their sensitivities against central differences, the unmodeled mode against its closed
//! form, the sensor terms against their definition, and the file's errors and round trip.

use crate::common::{assert_central_differences, respond, with_effects_in};
use expm::Response;
use mem::Grid;
use models::Model;

const FILE: &str = include_str!("../../../../fixtures/shear_building.ron");

/// The fixture with `effects` added to its file.
fn with_effects(effects: &str) -> Model {
    with_effects_in(FILE, effects)
}

/// The nominal building, by hand: M = 1000 I, K from k1..k3, D = αM + βK.
fn building() -> ([[f64; 3]; 3], [[f64; 3]; 3]) {
    let (m, k1, k2, k3, alpha, beta) = (1000.0, 2.5e6, 2.25e6, 1.875e6, 0.375, 1.25e-3);
    let k = [[k1 + k2, -k2, 0.0], [-k2, k2 + k3, -k3], [0.0, -k3, k3]];
    let mut d = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            d[i][j] = beta * k[i][j] + if i == j { alpha * m } else { 0.0 };
        }
    }
    (k, d)
}

/// The largest error of outputs q1 and q3 against the Runge–Kutta's, and q3's peak there.
fn worst_against(out: &Response, reference: &[[f64; 3]]) -> (f64, f64) {
    let peak = reference.iter().map(|r| r[1].abs()).fold(0.0, f64::max);
    let worst = (0..reference.len())
        .map(|s| {
            (out.outputs[(s, 0)] - reference[s][0]).abs().max((out.outputs[(s, 1)] - reference[s][1]).abs())
        })
        .fold(0.0, f64::max);
    (worst, peak)
}

/// The asymmetric part k₂ of the spring at q1 in [`EFFECTS`].
const QUADRATIC: f64 = 2e8;
/// Its quintic part k₅.
const QUINTIC: f64 = 5e13;
/// Its one-sided part kₛ (f += kₛq⁴|q|): stiffer for q1 > 0.
const SIDED: f64 = 3e13;
/// The rate k₁′ at which its linear stiffness changes (f += k₁′·t·q1): −8 % of k1 a second.
const RATE: f64 = -2e5;

/// RK4 with a fine fixed step of the building with a spring k₃q³ + k₂q² + k₅q⁵ + kₛq⁴|q| + k₁′·t·q
/// at q1 (k₂ = [`QUADRATIC`], k₅ = [`QUINTIC`], kₛ = [`SIDED`], k₁′ = [`RATE`]), drag at q3 and dry friction at q2;
/// returns q1, q3, and the acceleration of q3 at every `h`.
fn rk4(k_samples: usize, h: f64, cubic: f64, drag: (f64, f64), friction: (f64, f64)) -> Vec<[f64; 3]> {
    rk4_with(k_samples, h, (cubic, 1.0), drag, (friction.0, friction.1, 0.0, 1.0))
}

/// [`rk4`] with the spring's k₂, k₅, kₛ and k₁′ scaled by `spring.1` (0: a cubic spring alone), and
/// the friction (F_c, v_s, ΔF, v_st) with a static peak ΔF falling over v_st.
fn rk4_with(
    k_samples: usize,
    h: f64,
    spring: (f64, f64),
    drag: (f64, f64),
    friction: (f64, f64, f64, f64),
) -> Vec<[f64; 3]> {
    let (cubic, others) = spring;
    integrate(k_samples, h, |t, q, v| {
        let mut f = [0.0; 3];
        f[0] -= cubic * q[0].powi(3)
            + others
                * (QUADRATIC * q[0] * q[0]
                    + QUINTIC * q[0].powi(5)
                    + SIDED * q[0].powi(4) * q[0].abs()
                    + RATE * t * q[0]);
        f[2] -= drag.0 * v[2] * v[2].abs().powf(drag.1 - 1.0);
        let level = friction.0 + friction.2 * (-(v[1] / friction.3).powi(2)).exp();
        f[1] -= level * v[1] / (v[1] * v[1] + friction.1 * friction.1).sqrt();
        f
    })
}

/// RK4 with a fine fixed step of the nominal building released from q(0) = (0.01, 0.02, 0.03) m
/// with the forces `forces(t, q, q̇)` added: q1, q3, and the acceleration of q3 at every `h`.
fn integrate(
    k_samples: usize,
    h: f64,
    forces: impl Fn(f64, [f64; 3], [f64; 3]) -> [f64; 3],
) -> Vec<[f64; 3]> {
    let (k, d) = building();
    let rhs = |t: f64, x: &[f64; 6]| -> [f64; 6] {
        let (q, v) = ([x[0], x[1], x[2]], [x[3], x[4], x[5]]);
        let f = forces(t, q, v);
        let mut out = [v[0], v[1], v[2], 0.0, 0.0, 0.0];
        for i in 0..3 {
            let force: f64 = f[i] - (0..3).map(|j| k[i][j] * q[j] + d[i][j] * v[j]).sum::<f64>();
            out[3 + i] = force / 1000.0;
        }
        out
    };
    let mut x = [0.01, 0.02, 0.03, 0.0, 0.0, 0.0];
    let sub = 200;
    let dt = h / sub as f64;
    let mut out = Vec::with_capacity(k_samples);
    for sample in 0..k_samples {
        out.push([x[0], x[2], rhs(sample as f64 * h, &x)[5]]);
        for step in 0..sub {
            let t = sample as f64 * h + step as f64 * dt;
            let add = |a: &[f64; 6], b: &[f64; 6], s: f64| std::array::from_fn(|i| a[i] + s * b[i]);
            let k1 = rhs(t, &x);
            let k2 = rhs(t + dt / 2.0, &add(&x, &k1, dt / 2.0));
            let k3 = rhs(t + dt / 2.0, &add(&x, &k2, dt / 2.0));
            let k4 = rhs(t + dt, &add(&x, &k3, dt));
            x = std::array::from_fn(|i| x[i] + dt / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]));
        }
    }
    out
}

const EFFECTS: &str = "CubicStiffness(coordinate: \"q1\", coefficient: 3e10, quadratic: Some(2e8), quintic: Some(5e13), \
     sided: Some(3e13), rate: Some(-2e5)), \
     Drag(coordinate: \"q3\", coefficient: 800, exponent: 2.0), \
     DryFriction(coordinate: \"q2\", force: 150, smoothing_velocity: 0.01)";

#[test]
fn forces_at_coordinates_match_an_independent_runge_kutta() {
    let model = with_effects(EFFECTS);
    assert!(!model.is_linear());
    let (k, h) = (400, 0.005);
    let reference = rk4(k, h, 3e10, (800.0, 2.0), (150.0, 0.01));
    let out = respond(model.response(&[]).unwrap().as_ref(), &[], k, h);
    let (worst, peak) = worst_against(&out, &reference);
    assert!(worst < 1e-4 * peak, "worst {worst:e} against a peak {peak:e}");
    // The forces do act: the linear building is far from this response.
    let linear = Model::from_ron(FILE, "building.ron").unwrap();
    let plain = respond(linear.response(&[]).unwrap().as_ref(), &[], k, h);
    let apart = (0..k).map(|s| (plain.outputs[(s, 1)] - reference[s][1]).abs()).fold(0.0, f64::max);
    assert!(apart > 100.0 * worst, "the effects change the response by {apart:e} only");
}

/// Dry friction with a static peak at q2, (F_c + ΔF e^{−(v/v_st)²})·v/√(v² + v_s²), against the
/// independent Runge–Kutta; and its sensitivities to F_c, ΔF and v_st against central
/// differences.
#[test]
fn a_friction_with_a_static_peak_matches_an_independent_runge_kutta() {
    let model = with_effects(
        "DryFriction(coordinate: \"q2\", force: 150, smoothing_velocity: 0.01, static_peak: Some(120), \
         stribeck_velocity: Some(0.03))",
    );
    let (k, h) = (400, 0.005);
    let reference = rk4_with(k, h, (0.0, 0.0), (0.0, 1.0), (150.0, 0.01, 120.0, 0.03));
    let out = respond(model.response(&[]).unwrap().as_ref(), &[], k, h);
    let (worst, peak) = worst_against(&out, &reference);
    assert!(worst < 1e-4 * peak, "worst {worst:e} against a peak {peak:e}");
    let without = rk4_with(k, h, (0.0, 0.0), (0.0, 1.0), (150.0, 0.01, 0.0, 1.0));
    let apart = (0..k).map(|s| (without[s][1] - reference[s][1]).abs()).fold(0.0, f64::max);
    assert!(apart > 100.0 * worst, "the peak changes the response by {apart:e} only");
    let free = ["friction_q2", "static_peak_q2", "stribeck_velocity_q2", "k2"];
    let response = model.response(&free).unwrap();
    let p: Vec<f64> = free.iter().map(|n| model.value(n).unwrap()).collect();
    let out = respond(response.as_ref(), &p, 300, h);
    for i in 0..free.len() {
        assert_central_differences(response.as_ref(), &p, &out, i, h, 1e-5);
    }
    let half =
        "DryFriction(coordinate: \"q2\", force: 150, smoothing_velocity: 0.01, static_peak: Some(120))";
    let text = FILE.trim_end().trim_end_matches(')').to_string() + &format!("    effects: [{half}],\n)\n");
    let err = Model::from_ron(&text, "b.ron").expect_err("a peak without its velocity is refused");
    assert!(err.to_string().contains("together"), "{err}");
}

/// A record that starts after the release: the forces read the time since the release (the
/// spring's rate k₁′·t·q1), not since the first sample.
#[test]
fn a_late_first_sample_reads_the_time_since_the_release() {
    let model = with_effects(EFFECTS);
    let (k, h, late) = (200, 0.005, 60);
    let reference = rk4(late + k, h, 3e10, (800.0, 2.0), (150.0, 0.01));
    let response = model.response(&[]).unwrap();
    let mut out = Response::zeros(k, 2, 0);
    let grid = Grid { start: late as f64 * h, interval: h, inputs: None };
    response.respond(&[], &grid, &mut out).expect("it simulates");
    let peak = reference.iter().map(|r| r[1].abs()).fold(0.0, f64::max);
    let worst = (0..k)
        .map(|s| {
            let r = &reference[late + s];
            (out.outputs[(s, 0)] - r[0]).abs().max((out.outputs[(s, 1)] - r[1]).abs())
        })
        .fold(0.0, f64::max);
    assert!(worst < 1e-4 * peak, "worst {worst:e} against a peak {peak:e}");
}

#[test]
fn an_acceleration_output_reads_the_forces_too() {
    let text = FILE.replace(
        "(column: \"q3\", measures: Displacement(\"q3\"), unit: \"m\"),",
        "(column: \"a3\", measures: Acceleration(\"q3\"), unit: \"m/s^2\"),",
    );
    let text = text.trim_end().trim_end_matches(')').to_string() + &format!("    effects: [{EFFECTS}],\n)\n");
    let model = Model::from_ron(&text, "building.ron").unwrap();
    let (k, h) = (400, 0.005);
    let reference = rk4(k, h, 3e10, (800.0, 2.0), (150.0, 0.01));
    let out = respond(model.response(&[]).unwrap().as_ref(), &[], k, h);
    let peak = reference.iter().map(|r| r[2].abs()).fold(0.0, f64::max);
    let worst = (0..k).map(|s| (out.outputs[(s, 1)] - reference[s][2]).abs()).fold(0.0, f64::max);
    assert!(worst < 1e-3 * peak, "worst {worst:e} against a peak {peak:e}");
}

/// A drag of exponent 1 held there is a linear damper: with `drag_exponent_q3` fixed the exact
/// exponential path applies (c in D at q3), and it follows the hand-written Runge–Kutta; freed,
/// the exponent sends the model down the nonlinear path.
#[test]
fn a_linear_damper_takes_the_exact_path() {
    let c = 4000.0;
    let model = with_effects(&format!("Drag(coordinate: \"q3\", coefficient: {c:e}, exponent: 1.0)"));
    let structure = model.as_structure().unwrap();
    assert!(structure.is_linear_for(&["k1", "beta", "drag_q3"]));
    assert!(!structure.is_linear_for(&["k1", "drag_q3", "drag_exponent_q3"]));
    let free = ["k1", "beta", "drag_q3"];
    let p: Vec<f64> = free.iter().map(|n| model.value(n).unwrap()).collect();
    let (k, h) = (400, 0.005);
    let reference = rk4_with(k, h, (0.0, 0.0), (c, 1.0), (0.0, 0.01, 0.0, 1.0));
    let response = model.response(&free).unwrap();
    let out = respond(response.as_ref(), &p, k, h);
    let (worst, peak) = worst_against(&out, &reference);
    assert!(worst < 1e-7 * peak, "worst {worst:e} against a peak {peak:e}");
    // The damper acts: the bare building is far from it.
    let plain = rk4_with(k, h, (0.0, 0.0), (0.0, 1.0), (0.0, 0.01, 0.0, 1.0));
    let apart = (0..k).map(|s| (plain[s][1] - reference[s][1]).abs()).fold(0.0, f64::max);
    assert!(apart > 1e3 * worst, "the damper changes the response by {apart:e} only");
    // Its sensitivity is the derivative of the response.
    assert_central_differences(response.as_ref(), &p, &out, 2, h, 1e-6);
}

#[test]
fn force_sensitivities_are_central_differences() {
    let model = with_effects(EFFECTS);
    let free = [
        "k1",
        "beta",
        "cubic_q1",
        "quadratic_q1",
        "quintic_q1",
        "sided_q1",
        "stiffness_rate_q1",
        "drag_q3",
        "drag_exponent_q3",
        "friction_q2",
    ];
    let response = model.response(&free).unwrap();
    let p: Vec<f64> = free.iter().map(|n| model.value(n).unwrap()).collect();
    let (k, h) = (300, 0.005);
    let out = respond(response.as_ref(), &p, k, h);
    for i in 0..free.len() {
        assert_central_differences(response.as_ref(), &p, &out, i, h, 1e-5);
    }
}

/// A linear stiffness at q1 that changes with time by a law of its own: Δk(t) rises from 0 to
/// −2·10⁵ N/m at 0.3 s, then to +10⁵ at 0.8 s, and stays there (f += Δk(t)·q1).
const CHANGE: &str = "CubicStiffness(coordinate: \"q1\", coefficient: 0, \
     change: Some((times: [0.3, 0.8], values: [-2e5, 1e5])))";

/// [`CHANGE`]'s law written out here: piecewise linear through (0, 0), (0.3, −2e5), (0.8, 1e5).
fn change_law(t: f64) -> f64 {
    if t <= 0.3 {
        -2e5 * t / 0.3
    } else if t <= 0.8 {
        -2e5 + 3e5 * (t - 0.3) / 0.5
    } else {
        1e5
    }
}

#[test]
fn a_stiffness_that_changes_with_time_follows_its_law() {
    let model = with_effects(CHANGE);
    assert!(!model.is_linear());
    let names = model.parameter_names();
    assert!(
        names.iter().any(|n| n == "stiffness_change_q1_1")
            && names.iter().any(|n| n == "stiffness_change_q1_2")
    );
    let (k, h) = (300, 0.005);
    let reference = integrate(k, h, |t, q, _| [-change_law(t) * q[0], 0.0, 0.0]);
    let out = respond(model.response(&[]).unwrap().as_ref(), &[], k, h);
    let (worst, peak) = worst_against(&out, &reference);
    assert!(worst < 1e-5 * peak, "worst {worst:e} against a peak {peak:e}");
    // The law acts: the bare building is far from it.
    let plain = integrate(k, h, |_, _, _| [0.0; 3]);
    let apart = (0..k).map(|s| (plain[s][0] - reference[s][0]).abs()).fold(0.0, f64::max);
    assert!(apart > 1e3 * worst, "the law changes the response by {apart:e} only");
    // Its values' sensitivities, beside k1's, are the derivatives of the response.
    let free = ["k1", "stiffness_change_q1_1", "stiffness_change_q1_2"];
    let response = model.response(&free).unwrap();
    let p: Vec<f64> = free.iter().map(|n| model.value(n).unwrap()).collect();
    let out = respond(response.as_ref(), &p, k, h);
    for i in 0..free.len() {
        assert_central_differences(response.as_ref(), &p, &out, i, h, 1e-5);
    }
}

#[test]
fn a_law_in_time_without_ordered_positive_times_is_refused() {
    for (law, says) in [
        ("(times: [0.3, 0.8], values: [1e5])", "one value per time"),
        ("(times: [0.8, 0.3], values: [1e5, 2e5])", "each after the one before"),
        ("(times: [0.0], values: [1e5])", "positive times"),
        ("(times: [], values: [])", "one or more"),
    ] {
        let text = FILE.trim_end().trim_end_matches(')').to_string()
            + &format!(
                "    effects: [CubicStiffness(coordinate: \"q1\", coefficient: 0, change: Some({law}))],\n)\n"
            );
        let Err(error) = Model::from_ron(&text, "building.ron") else { panic!("{law}: refused") };
        let error = error.to_string();
        assert!(error.contains(says) && error.contains("building.ron"), "{law}: {error}");
        assert_eq!(error.lines().count(), 1, "{error}");
    }
}

#[test]
fn a_mode_whose_frequency_overflows_is_refused() {
    let text = FILE.trim_end().trim_end_matches(')').to_string()
        + "    effects: [UnmodeledMode(frequency_hz: 1e200, damping_ratio: 0.02, amplitudes: [(1e-3, 0), (0, 0)])],\n)\n";
    let Err(error) = Model::from_ron(&text, "building.ron") else { panic!("refused") };
    let error = error.to_string();
    assert!(error.contains("overflows") && error.contains("building.ron"), "{error}");
    assert_eq!(error.lines().count(), 1, "{error}");
}

#[test]
fn an_unmodeled_mode_adds_its_closed_form() {
    let (f, zeta, (a1, b1), (a3, b3)): (f64, f64, (f64, f64), (f64, f64)) =
        (23.0, 0.02, (1e-3, -5e-4), (2e-4, 7e-4));
    let model = with_effects(&format!(
        "UnmodeledMode(frequency_hz: {f}, damping_ratio: {zeta}, amplitudes: [({a1}, {b1}), ({a3}, {b3})])"
    ));
    assert!(model.is_linear(), "a mode is linear: the exact path applies");
    let plain = Model::from_ron(FILE, "building.ron").unwrap();
    let (k, h) = (500, 0.002);
    let with = respond(model.response(&[]).unwrap().as_ref(), &[], k, h);
    let without = respond(plain.response(&[]).unwrap().as_ref(), &[], k, h);
    let w = 2.0 * std::f64::consts::PI * f;
    let wd = w * (1.0 - zeta * zeta).sqrt();
    for s in 0..k {
        let t = s as f64 * h;
        let decay = (-zeta * w * t).exp();
        let eta = decay * ((wd * t).cos() + zeta * w / wd * (wd * t).sin());
        let rate = -w * w / wd * decay * (wd * t).sin();
        for (o, (a, b)) in [(a1, b1), (a3, b3)].into_iter().enumerate() {
            let expected = without.outputs[(s, o)] + a * eta + b * rate / w;
            assert!((with.outputs[(s, o)] - expected).abs() < 1e-10, "sample {s} output {o}");
        }
    }
}

/// The building's free decay with `effects` (sensor terms) and without, 200 samples at `h`.
fn sensed_and_bare(effects: &str) -> (Response, Response, f64) {
    let plain = Model::from_ron(FILE, "building.ron").unwrap();
    let (k, h) = (200, 0.005);
    let with = respond(with_effects(effects).response(&[]).unwrap().as_ref(), &[], k, h);
    let without = respond(plain.response(&[]).unwrap().as_ref(), &[], k, h);
    (with, without, h)
}

#[test]
fn sensor_terms_act_on_structure_outputs() {
    let (with, without, h) = sensed_and_bare(
        "OutputOffset(output: \"q1\", offset: 1e-3), SensorScale(output: \"q3\", scale: 0.05), \
         SensorDrift(output: \"q3\", rate: -2e-4)",
    );
    for s in 0..with.outputs.nrows() {
        let t = s as f64 * h;
        assert!((with.outputs[(s, 0)] - (without.outputs[(s, 0)] + 1e-3)).abs() < 1e-12);
        assert!((with.outputs[(s, 1)] - (1.05 * without.outputs[(s, 1)] - 2e-4 * t)).abs() < 1e-12);
    }
}

/// A structure's drift that levels off: its closed form on the output, and its time constant
/// freed by name (`drift_time_q3`) with a sensitivity that is the central difference.
#[test]
fn a_drift_that_levels_off_acts_on_a_structure_output() {
    let (d, tau) = (-2e-4, 0.3);
    let effect = format!("SensorDrift(output: \"q3\", rate: {d:e}, time_constant: Some({tau}))");
    let (with, without, h) = sensed_and_bare(&effect);
    let k = with.outputs.nrows();
    for s in 0..k {
        let t = s as f64 * h;
        assert_eq!(with.outputs[(s, 0)], without.outputs[(s, 0)]);
        let expected = without.outputs[(s, 1)] + d * tau * (1.0 - (-t / tau).exp());
        assert!((with.outputs[(s, 1)] - expected).abs() < 1e-12, "sample {s}");
    }
    let response = with_effects(&effect).response(&["drift_q3", "drift_time_q3"]).unwrap();
    let p = [d, tau];
    let out = respond(response.as_ref(), &p, k, h);
    for i in 0..2 {
        assert_central_differences(response.as_ref(), &p, &out, i, h, 1e-6);
    }
}

/// A structure's crosstalk: output q3 picking up q1 reads y_q3 + g·y_q1; its gain is freed by
/// name (`crosstalk_q3_q1`) with a sensitivity that is the central difference; a crosstalk from
/// the output itself is refused.
#[test]
fn a_crosstalk_acts_on_a_structure_output() {
    let g = 0.3;
    let effect = format!("SensorCrosstalk(output: \"q3\", from: \"q1\", gain: {g})");
    let (with, without, h) = sensed_and_bare(&effect);
    let k = with.outputs.nrows();
    for s in 0..k {
        assert_eq!(with.outputs[(s, 0)], without.outputs[(s, 0)]);
        let expected = without.outputs[(s, 1)] + g * without.outputs[(s, 0)];
        assert!((with.outputs[(s, 1)] - expected).abs() < 1e-12 * expected.abs().max(1e-3), "sample {s}");
    }
    let response = with_effects(&effect).response(&["crosstalk_q3_q1", "k1"]).unwrap();
    let p = [g, with_effects(&effect).value("k1").unwrap()];
    let out = respond(response.as_ref(), &p, k, h);
    for i in 0..2 {
        assert_central_differences(response.as_ref(), &p, &out, i, h, 1e-6);
    }
    let text = FILE.trim_end().trim_end_matches(')').to_string()
        + "    effects: [SensorCrosstalk(output: \"q3\", from: \"q3\", gain: 0.1)],\n)\n";
    let err = Model::from_ron(&text, "building.ron").unwrap_err().to_string();
    assert!(err.contains("another output") && !err.contains('\n'), "{err}");
}

#[test]
fn effects_are_checked_where_they_stand_and_written_back() {
    let text = FILE.trim_end().trim_end_matches(')').to_string()
        + "    effects: [Drag(coordinate: \"q9\", coefficient: 1, exponent: 2)],\n)\n";
    let err = Model::from_ron(&text, "building.ron").unwrap_err().to_string();
    assert!(err.starts_with("building.ron:") && err.contains("q9") && !err.contains('\n'), "{err}");
    let line = text.lines().position(|l| l.contains("q9")).unwrap() + 1;
    assert!(err.contains(&format!(":{line}:")), "{err}");
    // Written back with the effects and their values.
    let mut model = with_effects(EFFECTS);
    model.set("cubic_q1", 1e10).unwrap();
    let again = Model::from_ron(&model.to_ron(), "again.ron").unwrap();
    assert_eq!(again.value("cubic_q1").unwrap(), 1e10);
    assert_eq!(again.value("friction_q2").unwrap(), 150.0);
    assert_eq!(again.value("quadratic_q1").unwrap(), QUADRATIC);
    assert_eq!(again.value("quintic_q1").unwrap(), QUINTIC);
    assert!(!again.is_linear());
}

/// The outputs alone (`respond_outputs`, what the fitter's trial points cost) are the bits of
/// the full response's outputs.
#[test]
fn outputs_alone_are_the_bits_of_the_full_response() {
    let model = with_effects(EFFECTS);
    let free = ["k1", "beta", "cubic_q1", "drag_q3", "friction_q2"];
    let response = model.response(&free).unwrap();
    let p: Vec<f64> = free.iter().map(|n| model.value(n).unwrap()).collect();
    let full = respond(response.as_ref(), &p, 300, 0.005);
    let mut alone = Response::zeros(300, 2, 0);
    response.respond_outputs(&p, &Grid::free(0.005), &mut alone).unwrap();
    let bits = |m: &faer::Mat<f64>| {
        (0..300).flat_map(|k| [m[(k, 0)].to_bits(), m[(k, 1)].to_bits()]).collect::<Vec<_>>()
    };
    assert_eq!(bits(&alone.outputs), bits(&full.outputs));
    assert!(full.sensitivities.norm_max() > 0.0);
}
