//! Sensor effects and delays: listed for the adapter, leaving the dynamics (and the modes) alone;
//! a delay or lag too short to mean anything is refused.

use super::*;

#[test]
fn short_delay_barely_moves_the_modes() {
    // Padé(1,1) of a 1 ms delay: the servo mode (0.15 Hz) moves by O(ωτ) ≈ 1e-3 relative.
    let m = with_effects("TimeDelay(delay: 0.001)");
    let base = SlewingModel::paper().modal().unwrap();
    let servo = m.modal().unwrap().into_iter().find(|r| r.kind == ModeKind::Servo).unwrap();
    assert!((servo.frequency_hz / base[0].frequency_hz - 1.0).abs() < 2e-3);
    // x(0) holds the delay line in steady state: θ_d(0) = −θ(0) + w(0) = θ(0).
    let x0 = m.initial_state();
    let w = m.layout().delay.unwrap();
    assert_eq!(-x0[0] + x0[w], x0[0]);
}

#[test]
fn sensor_effects_are_listed_for_the_adapter_and_leave_the_dynamics_alone() {
    let m = with_effects(
        "OutputOffset(sensor: Potentiometer, offset: 0.02), SensorScale(sensor: Tachometer, scale: 0.05), SensorDrift(sensor: StrainGauge, rate: 0.1)",
    );
    // Measurement-side: the state space is the paper's.
    assert_eq!(m.n_states(), SlewingModel::paper().n_states());
    let listed: Vec<(usize, plant::EffectKind)> =
        m.sensor_effects().iter().map(|(o, e)| (*o, e.kind())).collect();
    assert_eq!(
        listed,
        vec![
            (0, plant::EffectKind::OutputOffset),
            (1, plant::EffectKind::SensorScale),
            (2, plant::EffectKind::SensorDrift)
        ]
    );
    for name in ["offset_theta", "scale_theta_dot", "drift_strain"] {
        assert!(m.parameter(name).is_ok(), "{name}");
    }
    assert!(m.parameter("offset_strain").is_err());
}

#[test]
fn a_sensor_read_late_holds_its_reading_at_rest_and_leaves_the_dynamics_alone() {
    let m = with_effects(
        "SensorLag(sensor: Potentiometer, lag: 0.003), SensorLag(sensor: StrainGauge, lag: 0.001)",
    );
    let paper = SlewingModel::paper();
    assert_eq!(m.n_states(), paper.n_states() + 2);
    // The lag states are outside the loop: the rig's eigenvalues are the paper's, with the two
    // Padé poles −2/τ_s beside them.
    let mut with_lag = eigenvalues(&m);
    let base = eigenvalues(&paper);
    for pole in [-2.0 / 0.003, -2.0 / 0.001] {
        let i = with_lag.iter().position(|(re, im)| (re / pole - 1.0).abs() < 1e-9 && *im == 0.0);
        with_lag.remove(i.unwrap_or_else(|| panic!("a pole at {pole}")));
    }
    assert_eq!(with_lag.len(), base.len());
    let by_place = |a: &(f64, f64), b: &(f64, f64)| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1));
    let mut base = base;
    with_lag.sort_by(by_place);
    base.sort_by(by_place);
    // (To the eigensolver's accuracy on the stiffer matrix: 10⁻⁸ of the eigenvalue's size.)
    for ((re, im), (bre, bim)) in with_lag.iter().zip(&base) {
        let size = bre.hypot(*bim);
        assert!((re - bre).hypot(im - bim) < 1e-8 * size, "({re}, {im}) against ({bre}, {bim})");
    }
    // Held at the release: each lagged reading −y + w is the reading itself.
    let ss = m.state_space().unwrap();
    let x0 = m.initial_state();
    let reading = |row: usize| (0..x0.len()).map(|j| ss.c[(row, j)] * x0[j]).sum::<f64>();
    assert!((reading(0) - x0[0]).abs() < 1e-15, "θ read {} against {}", reading(0), x0[0]);
    assert_eq!(reading(2), 0.0);
    assert!(m.parameter("lag_theta").is_ok() && m.parameter("lag_theta_dot").is_err());
    // The export names every state, the lags' last, in the layout's order.
    let json = with_effects("SensorLag(sensor: StrainGauge, lag: 0.001), TimeDelay(delay: 0.01), SensorLag(sensor: Potentiometer, lag: 0.003)")
        .matrices_json()
        .unwrap();
    let states: Vec<&str> = json["states"].as_array().unwrap().iter().map(|s| s.as_str().unwrap()).collect();
    assert_eq!(states.len(), json["A"].as_array().unwrap().len());
    assert_eq!(states[states.len() - 3..], ["delay_w", "lag_w_strain", "lag_w_theta"]);
    let bad = plant::PAPER_MODEL_RON
        .replace("    bounds: {", "    effects: [SensorLag(sensor: Tachometer, lag: 0.0)],\n    bounds: {");
    let msg = SlewingModel::from_ron(&bad, "bad.ron").unwrap_err().to_string();
    assert!(msg.contains("lag") && msg.contains("1e-9"), "{msg}");
}

#[test]
fn a_delay_or_lag_shorter_than_a_nanosecond_is_refused_with_its_place() {
    // So short a delay puts entries of 4/τ in A, and the exponential of so stiff a matrix loses
    // the other states' accuracy: the file is refused at the line that sets it, not simulated.
    for (effect, field) in [
        ("TimeDelay(delay: 1e-12)", "delay"),
        ("SensorLag(sensor: StrainGauge, lag: 1e-300)", "lag"),
        ("SensorLag(sensor: Potentiometer, lag: 5e-10)", "lag"),
    ] {
        let text = plant::PAPER_MODEL_RON
            .replace("    bounds: {", &format!("    effects: [\n        {effect},\n    ],\n    bounds: {{"));
        let line = text.lines().position(|l| l.contains(effect)).unwrap() + 1;
        let msg = SlewingModel::from_ron(&text, "short.ron").unwrap_err().to_string();
        assert!(
            msg.contains("short.ron") && msg.contains(&format!(":{line}:")) && msg.contains(field),
            "{effect}: {msg}"
        );
        assert!(msg.contains("1e-9") && !msg.contains('\n'), "{effect}: {msg}");
    }
    // A nanosecond is accepted and is no delay at all: the closed-loop modes are the paper's,
    // and the delay's Padé pole is named as such, near −2/τ.
    let m = with_effects("TimeDelay(delay: 1e-9), SensorLag(sensor: StrainGauge, lag: 1e-9)");
    let rows = m.modal().unwrap();
    for base in SlewingModel::paper().modal().unwrap() {
        let row = rows.iter().find(|r| r.kind == base.kind).unwrap();
        assert!((row.frequency_hz / base.frequency_hz - 1.0).abs() < 1e-6, "{row:?} {base:?}");
        assert!((row.damping_ratio / base.damping_ratio - 1.0).abs() < 1e-4, "{row:?} {base:?}");
    }
    let delay = rows.iter().find(|r| r.kind == ModeKind::Delay).unwrap();
    assert!((delay.eigenvalue.0 / -2e9 - 1.0).abs() < 1e-6, "{delay:?}");
    assert_eq!(rows.len(), 5, "the lag's pole is no mode of the rig: {rows:?}");
    // Setting a parameter is held to the same floor.
    let mut m = with_effects("TimeDelay(delay: 0.01)");
    assert!(m.set(ParamId::Delay, 1e-10).is_err());
    m.set(ParamId::Delay, plant::MIN_DELAY).unwrap();
    // A bound that leaves no room above the floor is refused.
    let text = plant::PAPER_MODEL_RON.replace(
        "    bounds: {",
        "    effects: [TimeDelay(delay: 0.01)],\n    bounds: {\n        \"delay\": (0.0, 1e-10),",
    );
    let msg = SlewingModel::from_ron(&text, "bounds.ron").unwrap_err().to_string();
    assert!(msg.contains("bounds") && msg.contains("delay") && msg.contains("1e-9"), "{msg}");
}

#[test]
fn a_channel_read_late_leaves_the_modes_exactly_as_they_were() {
    // The lag is outside the loop (A block triangular), so the modes are those of the loop's
    // block, bit for bit, however short the lag and however stiff its pole.
    let base = SlewingModel::paper().modal().unwrap();
    for lag in [1e-9, 1e-6, 0.004] {
        let m = with_effects(&format!(
            "SensorLag(sensor: Tachometer, lag: {lag}), SensorLag(sensor: StrainGauge, lag: {lag})"
        ));
        let rows = m.modal().unwrap();
        assert_eq!(rows.len(), base.len());
        for (r, b) in rows.iter().zip(&base) {
            assert_eq!((r.kind, r.eigenvalue), (b.kind, b.eigenvalue), "lag {lag}");
        }
    }
}
