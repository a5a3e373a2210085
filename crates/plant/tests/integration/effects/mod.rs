//! The effects catalog: augmentations, limits that reduce to the linear model, derivatives.

use plant::nonlinear::{smooth_limit, smooth_limit_with_knee};
use plant::{ModeKind, ParamId, SlewingModel};

mod limits;
mod sensors;

fn with_effects(effects: &str) -> SlewingModel {
    let text = plant::PAPER_MODEL_RON
        .replace("    bounds: {", &format!("    effects: [{effects}],\n    bounds: {{"));
    SlewingModel::from_ron(&text, "effects.ron").unwrap()
}

#[test]
fn uncoupled_extra_mode_appears_at_its_own_frequency() {
    let m = with_effects("UnmodeledMode(frequency_hz: 4.2, damping_ratio: 0.03, coupling: 0.0)");
    assert_eq!(m.n_states(), 10);
    let modes = m.modal().unwrap();
    let extra = modes.iter().find(|r| (r.frequency_hz - 4.2).abs() < 1e-9).expect("a 4.2 Hz mode");
    assert!((extra.damping_ratio - 0.03).abs() < 1e-12);
    // The paper's modes are unchanged.
    let base = SlewingModel::paper().modal().unwrap();
    let servo = modes.iter().find(|r| r.kind == ModeKind::Servo).unwrap();
    assert!((servo.frequency_hz - base[0].frequency_hz).abs() < 1e-12);
}

#[test]
fn effect_parameters_have_exact_derivatives() {
    let m = with_effects(
        "UnmodeledMode(frequency_hz: 4.2, damping_ratio: 0.03, coupling: 0.05, stiffness_coupling: Some(0.4)), TimeDelay(delay: 0.02), SensorLag(sensor: StrainGauge, lag: 0.004)",
    );
    let ids: Vec<ParamId> = [
        "lag_strain",
        "ei_over_rho",
        "extra_mode_frequency",
        "extra_mode_damping",
        "extra_mode_coupling",
        "extra_mode_stiffness_coupling",
        "delay",
        "kp",
    ]
    .iter()
    .map(|n| m.parameter(n).unwrap())
    .collect();
    let lin = m.linearization(&ids).unwrap();
    for (k, &id) in ids.iter().enumerate() {
        let v = m.get(id);
        let h = 1e-6 * v.abs();
        let eval = |x: f64| {
            let mut mm = m.clone();
            mm.set(id, x).unwrap();
            mm.state_space().unwrap()
        };
        let (p, q) = (eval(v + h), eval(v - h));
        let scale = lin.a.norm_max().max(1.0);
        for i in 0..lin.a.nrows() {
            for j in 0..lin.a.ncols() {
                let fd = (p.a[(i, j)] - q.a[(i, j)]) / (2.0 * h);
                assert!(
                    (fd - lin.da[k][(i, j)]).abs() < 1e-6 * (fd.abs() + scale / v.abs() * 1e-3),
                    "∂A[{i},{j}]/∂{}",
                    id.name()
                );
            }
        }
        for i in 0..lin.c.nrows() {
            for j in 0..lin.c.ncols() {
                let fd = (p.c[(i, j)] - q.c[(i, j)]) / (2.0 * h);
                assert!(
                    (fd - lin.dc[k][(i, j)]).abs() < 1e-6 * fd.abs().max(1e-3),
                    "∂C[{i},{j}]/∂{}",
                    id.name()
                );
            }
        }
    }
}

#[test]
fn effects_are_validated() {
    let text = plant::PAPER_MODEL_RON
        .replace("    bounds: {", "    effects: [TimeDelay(delay: -1.0)],\n    bounds: {");
    let msg = SlewingModel::from_ron(&text, "bad.ron").unwrap_err().to_string();
    assert!(msg.contains("delay") && msg.contains("1e-9"), "{msg}");
    let text = plant::PAPER_MODEL_RON.replace(
        "    bounds: {",
        "    effects: [QuadraticDrag(hub: 0.1), QuadraticDrag(hub: 0.2)],\n    bounds: {",
    );
    assert!(SlewingModel::from_ron(&text, "bad.ron").unwrap_err().to_string().contains("twice"));
}

#[test]
fn setting_a_parameter_of_an_absent_effect_is_an_error() {
    let mut m = plant::SlewingModel::paper();
    let err = m.set(plant::ParamId::CurrentLimit, 1.0).unwrap_err().to_string();
    assert!(err.contains("current_limit") && err.contains("cv"), "{err}");
}

/// The eigenvalues of A as complex numbers (upper half plane and real axis).
fn eigenvalues(m: &SlewingModel) -> Vec<(f64, f64)> {
    let a = m.dynamics_with(|v| *v).unwrap().a;
    let a = faer::Mat::from_fn(a.nrows(), a.ncols(), |i, j| a[(i, j)]);
    plant::modes_of(&a, m.layout().n_dof).unwrap().into_iter().map(|r| r.eigenvalue).collect()
}
