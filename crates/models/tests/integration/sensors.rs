//! Sensor effects' parameters may stand anywhere in the free list: the response and every
//! sensitivity column follow the caller's order (a regression: they were once assumed last).

use expm::Response;
use mem::Grid;
use models::Model;
use plant::SlewingModel;

fn model() -> Model {
    let text = plant::PAPER_MODEL_RON.replace(
        "    bounds: {",
        "    effects: [OutputOffset(sensor: Potentiometer, offset: 0.01), \
         SensorScale(sensor: StrainGauge, scale: 0.05)],\n    bounds: {",
    );
    Model::Slewing(SlewingModel::from_ron(&text, "sensors.ron").unwrap())
}

fn respond(names: &[&str], p: &[f64]) -> Response {
    let response = model().response(names).unwrap();
    let mut out = Response::zeros(120, 3, names.len());
    response.respond(p, &Grid::free(1.0 / 12.8), &mut out).unwrap();
    out
}

/// Every sensitivity column of `at` (the response `run` gives at `p`) against central
/// differences of `run`'s outputs, step 10⁻⁶·max(|p_i|, 10⁻³), to 10⁻⁶ of the column's largest
/// entry (which must not be zero).
fn assert_central_differences(run: impl Fn(&[f64]) -> Response, p: &[f64], at: &Response, names: &[&str]) {
    let (k, n_out) = (at.outputs.nrows(), at.outputs.ncols());
    for i in 0..p.len() {
        let step = 1e-6 * p[i].abs().max(1e-3);
        let shifted = |sign: f64| {
            let mut q = p.to_vec();
            q[i] += sign * step;
            run(&q)
        };
        let (plus, minus) = (shifted(1.0), shifted(-1.0));
        let scale = (0..k * n_out).map(|r| at.sensitivities[(r, i)].abs()).fold(0.0, f64::max);
        assert!(scale > 0.0, "{} has a sensitivity", names[i]);
        for s in 0..k {
            for o in 0..n_out {
                let fd = (plus.outputs[(s, o)] - minus.outputs[(s, o)]) / (2.0 * step);
                let exact = at.sensitivities[(s * n_out + o, i)];
                assert!(
                    (fd - exact).abs() <= 1e-6 * scale,
                    "{} sample {s} output {o}: {fd} vs {exact}",
                    names[i]
                );
            }
        }
    }
}

#[test]
fn sensor_parameters_in_any_position_follow_the_callers_order() {
    let first = ["offset_theta", "cv", "scale_strain", "kp"];
    let p_first = [0.01, 0.06, 0.05, 8.0];
    let last = ["cv", "kp", "offset_theta", "scale_strain"];
    let p_last = [0.06, 8.0, 0.01, 0.05];
    let a = respond(&first, &p_first);
    let b = respond(&last, &p_last);
    assert_eq!(a.outputs, b.outputs);
    // Column i of `first` is column map[i] of `last`.
    let map = [2, 0, 3, 1];
    for (i, &j) in map.iter().enumerate() {
        for r in 0..a.sensitivities.nrows() {
            assert_eq!(a.sensitivities[(r, i)], b.sensitivities[(r, j)], "{} row {r}", first[i]);
        }
    }
    // And each column is the derivative of the outputs (central differences, the model is
    // linear so the exact path's sensitivities are exact to rounding).
    assert_central_differences(|q| respond(&first, q), &p_first, &a, &first);
}

/// A drift that levels off with a time constant far beyond the record is the drift at a
/// constant rate, d·t, to rounding (1 − e^{−t/τ} is not formed by subtraction).
#[test]
fn a_drift_that_levels_off_after_ages_is_a_constant_rate() {
    let d = 2e-3;
    let read = |effect: &str| {
        let text = plant::PAPER_MODEL_RON
            .replace("    bounds: {", &format!("    effects: [{effect}],\n    bounds: {{"));
        let model = Model::Slewing(SlewingModel::from_ron(&text, "drift.ron").unwrap());
        let mut out = Response::zeros(400, 3, 0);
        model.response(&[]).unwrap().respond(&[], &Grid::free(1.0 / 12.8), &mut out).unwrap();
        out
    };
    let constant = read(&format!("SensorDrift(sensor: Potentiometer, rate: {d:e})"));
    let ages = read(&format!("SensorDrift(sensor: Potentiometer, rate: {d:e}, time_constant: Some(1e300))"));
    for s in 0..400 {
        let (a, b) = (constant.outputs[(s, 0)], ages.outputs[(s, 0)]);
        assert!((a - b).abs() <= 1e-15 * a.abs().max(1.0), "sample {s}: {a} vs {b}");
    }
}

/// A drift that levels off, y + d·τ(1 − e^{−t/τ}), against its closed form on the bare model's
/// outputs, and its two sensitivities (d and τ, freed beside C_v) against central differences.
#[test]
fn a_drift_that_levels_off_is_its_closed_form_with_exact_sensitivities() {
    let (d, tau) = (2e-3, 4.0);
    let text = plant::PAPER_MODEL_RON.replace(
        "    bounds: {",
        &format!(
            "    effects: [SensorDrift(sensor: Potentiometer, rate: {d:e}, time_constant: Some({tau:e}))],\n    bounds: {{"
        ),
    );
    let model = Model::Slewing(SlewingModel::from_ron(&text, "drift.ron").unwrap());
    let names = ["cv", "drift_theta", "drift_time_theta"];
    let p = [model.value("cv").unwrap(), d, tau];
    let (k, h) = (400, 1.0 / 12.8);
    let run = |q: &[f64]| {
        let mut out = Response::zeros(k, 3, names.len());
        model.response(&names).unwrap().respond(q, &Grid::free(h), &mut out).unwrap();
        out
    };
    let with = run(&p);
    let bare = Model::Slewing(SlewingModel::paper());
    let mut without = Response::zeros(k, 3, 0);
    bare.response(&[]).unwrap().respond(&[], &Grid::free(h), &mut without).unwrap();
    for s in 0..k {
        let t = s as f64 * h;
        let drift = d * tau * (1.0 - (-t / tau).exp());
        assert!((with.outputs[(s, 0)] - (without.outputs[(s, 0)] + drift)).abs() < 1e-12, "sample {s}");
        for o in 1..3 {
            assert_eq!(with.outputs[(s, o)], without.outputs[(s, o)], "sample {s}, output {o}");
        }
    }
    assert_central_differences(run, &p, &with, &names);
}

/// Crosstalk: the strain channel picking up the tachometer reads y_strain + g·y_θ̇, computed
/// here from the plain model's response; every sensitivity column (g's is y_θ̇, the dynamics'
/// gain g·∂y_θ̇/∂P) matches central differences, with a scale on the same channel beside it.
#[test]
fn a_channel_picking_up_another_reads_both_and_its_sensitivities_are_exact() {
    let (g, s) = (0.8, 0.05);
    let effects = format!(
        "SensorScale(sensor: StrainGauge, scale: {s}), SensorCrosstalk(sensor: StrainGauge, from: Tachometer, gain: {g})"
    );
    let text = plant::PAPER_MODEL_RON
        .replace("    bounds: {", &format!("    effects: [{effects}],\n    bounds: {{"));
    let model = Model::Slewing(SlewingModel::from_ron(&text, "crosstalk.ron").unwrap());
    let plain = Model::Slewing(SlewingModel::paper());
    let names = ["cv", "crosstalk_strain_theta_dot", "kp", "scale_strain"];
    let p0 = [0.06, g, 8.0, s];
    let respond = |m: &Model, names: &[&str], p: &[f64]| {
        let mut out = Response::zeros(120, 3, names.len());
        m.response(names).unwrap().respond(p, &Grid::free(1.0 / 12.8), &mut out).unwrap();
        out
    };
    let a = respond(&model, &names, &p0);
    let base = respond(&plain, &["cv", "kp"], &[0.06, 8.0]);
    for k in 0..120 {
        assert_eq!(a.outputs[(k, 0)], base.outputs[(k, 0)]);
        assert_eq!(a.outputs[(k, 1)], base.outputs[(k, 1)]);
        let want = (1.0 + s) * base.outputs[(k, 2)] + g * base.outputs[(k, 1)];
        assert!((a.outputs[(k, 2)] - want).abs() <= 1e-12 * want.abs().max(1.0), "sample {k}");
    }
    assert!(a.sensitivities.nrows() == 360 && (0..120).any(|k| a.sensitivities[(k * 3 + 2, 1)] != 0.0));
    assert_central_differences(|q| respond(&model, &names, q), &p0, &a, &names);
}

/// A crosstalk from the sensor itself, or from one the file does not read, is refused with the
/// field named.
#[test]
fn a_crosstalk_needs_another_sensor_that_is_read() {
    for (from, outputs) in
        [("StrainGauge", None), ("Tachometer", Some("outputs: [Potentiometer, StrainGauge],"))]
    {
        let mut text = plant::PAPER_MODEL_RON.replace(
            "    bounds: {",
            &format!("    effects: [SensorCrosstalk(sensor: StrainGauge, from: {from}, gain: 0.1)],\n    bounds: {{"),
        );
        if let Some(o) = outputs {
            text = text.replace("outputs: [Potentiometer, Tachometer, StrainGauge],", o);
        }
        let err = SlewingModel::from_ron(&text, "crosstalk.ron").unwrap_err().to_string();
        assert!(err.contains("effects.from") && err.contains("another sensor"), "{err}");
    }
}

/// A sensor read late by τ_s (`SensorLag`, Padé(1,1) in the state space) reads what the
/// unlagged model's sensor read τ_s earlier: checked on a grid of step τ_s/2, where the
/// unlagged response two samples back is the delayed reading itself (no interpolation). The
/// Padé's error is of order (ωτ_s)³/12 in phase on the fastest mode the sensor sees.
#[test]
fn a_sensor_read_late_reads_the_signal_of_a_moment_before() {
    let lag = 0.002;
    let with = |effects: &str| {
        let text = plant::PAPER_MODEL_RON
            .replace("    bounds: {", &format!("    effects: [{effects}],\n    bounds: {{"));
        Model::Slewing(SlewingModel::from_ron(&text, "lag.ron").unwrap())
    };
    let lagged =
        with("SensorLag(sensor: Potentiometer, lag: 0.002), SensorLag(sensor: StrainGauge, lag: 0.002)");
    let plain = Model::Slewing(SlewingModel::paper());
    let n = 3000;
    let grid = Grid::free(lag / 2.0);
    let (a, b) = (lagged.simulate(&grid, n).unwrap(), plain.simulate(&grid, n).unwrap());
    for (o, tolerance) in [(0, 1e-4), (1, 1e-12), (2, 2e-3)] {
        let peak = (0..n).map(|k| b[(k, o)].abs()).fold(0.0, f64::max);
        let worst = (2..n).map(|k| (a[(k, o)] - b[(k - 2, o)]).abs()).fold(0.0, f64::max);
        // Against the unlagged reading at the same time, the lag is plainly there.
        let moved = (2..n).map(|k| (a[(k, o)] - b[(k, o)]).abs()).fold(0.0, f64::max);
        if o == 1 {
            assert!(moved < 1e-9 * peak, "the tachometer is not lagged: {moved}");
        } else {
            assert!(worst < tolerance * peak, "output {o}: {worst} of {peak}");
            assert!(moved > 10.0 * worst, "output {o}: the lag moves it by {moved}, {worst} left");
        }
    }
}

#[test]
fn a_fit_never_steps_below_the_least_a_parameter_may_take() {
    // A file's lower bound below a parameter's domain (0 for a delay, −5 for a damping) is raised
    // to the least value the plant accepts, so a fit clamped to its bounds never asks the model
    // for a value it refuses; parameters without bounds get their sign rule's domain.
    let text = plant::PAPER_MODEL_RON.replace(
        "    bounds: {",
        "    effects: [TimeDelay(delay: 0.01), SensorLag(sensor: StrainGauge, lag: 0.002)],\n    \
         bounds: {\n        \"delay\": (0.0, 1.0),\n        \"cv\": (-5.0, 10.0),",
    );
    let model = SlewingModel::from_ron(&text, "bounds.ron").unwrap();
    let fit =
        models::SlewingFitModel::new(model, &["delay", "cv", "lag_strain", "kp", "ei_over_rho"]).unwrap();
    assert_eq!(
        fit.bounds(),
        vec![
            (plant::MIN_DELAY, 1.0),
            (0.0, 10.0),
            (plant::MIN_DELAY, f64::INFINITY),
            (0.1, 100.0),
            (f64::MIN_POSITIVE, f64::INFINITY)
        ]
    );
}
