//! Structure of the assembled matrices and closed-form limits.

use plant::{ModeKind, ParamId, SlewingModel};

fn fixture() -> SlewingModel {
    SlewingModel::paper()
}

#[test]
fn mass_matrix_is_symmetric_positive_definite_with_paper_entries() {
    let m = fixture();
    let ss = m.state_space().unwrap();
    let c = m.constants();
    let (a, l, rho) = (c.hub_radius, c.length, c.mass_per_length);
    let expected_00 = rho * ((a + l).powi(3) - a.powi(3)) / 3.0 + c.hub_inertia + c.motor_inertia;
    assert!((ss.m[(0, 0)] - expected_00).abs() < 1e-15);
    for i in 0..4 {
        for j in 0..4 {
            assert_eq!(ss.m[(i, j)], ss.m[(j, i)]);
        }
    }
    let chol = nalgebra::DMatrix::from_fn(4, 4, |i, j| ss.m[(i, j)]).cholesky();
    assert!(chol.is_some(), "M must be positive definite");
    // Damping: C_v + K_bK_t/R_a and the modal terms on the diagonal.
    assert!(
        (ss.d[(0, 0)]
            - (c.viscous_damping + c.back_emf_constant * c.torque_constant / c.armature_resistance))
            .abs()
            < 1e-15
    );
    assert_eq!(ss.d[(1, 1)], 0.5);
    // K: servo stiffness at (0,0), zero above the diagonal, participation column below.
    let ks = c.amplifier_gain * c.position_gain * c.torque_constant / c.armature_resistance;
    assert!((ss.k[(0, 0)] - ks).abs() < 1e-15);
    for j in 1..4 {
        assert_eq!(ss.k[(0, j)], 0.0);
    }
}

#[test]
fn stiff_light_beam_limit_is_a_rigid_servo() {
    // With a very stiff beam the servo mode is the rigid-body oscillator
    // J_total θ̈ + c θ̇ + k_s θ = 0: ω² = k_s/J_total, 2ζω = c/J_total.
    let mut m = fixture();
    m.set(ParamId::EiOverRho, 1e6).unwrap();
    let c = m.constants().clone();
    let j_total = c.mass_per_length * ((c.hub_radius + c.length).powi(3) - c.hub_radius.powi(3)) / 3.0
        + c.hub_inertia
        + c.motor_inertia;
    let ks = c.amplifier_gain * c.position_gain * c.torque_constant / c.armature_resistance;
    let damping = c.viscous_damping + c.back_emf_constant * c.torque_constant / c.armature_resistance;
    let omega = (ks / j_total).sqrt();
    let zeta = damping / (2.0 * j_total * omega);
    let servo = m.modal().unwrap().into_iter().find(|r| r.kind == ModeKind::Servo).unwrap();
    // Residual coupling to modes at ≥ 300 Hz shifts the servo mode by O((ω/ω₁)²) ≈ 1e-7.
    assert!((servo.frequency_hz * 2.0 * std::f64::consts::PI / omega - 1.0).abs() < 1e-5);
    assert!((servo.damping_ratio / zeta - 1.0).abs() < 1e-5);
}

#[test]
fn first_order_form_reproduces_second_order_equations() {
    // For random x = [q; v]: A x = [v; M⁻¹(−K q − D v)], i.e. M (A x)_v + K q + D v = 0.
    let m = fixture();
    let ss = m.state_space().unwrap();
    let n = 4;
    let x: Vec<f64> = (0..8).map(|i| (i as f64 * 0.7).sin()).collect();
    let ax: Vec<f64> = (0..8).map(|i| (0..8).map(|j| ss.a[(i, j)] * x[j]).sum()).collect();
    for i in 0..n {
        assert!((ax[i] - x[n + i]).abs() < 1e-15);
        let r: f64 =
            (0..n).map(|j| ss.m[(i, j)] * ax[n + j] + ss.k[(i, j)] * x[j] + ss.d[(i, j)] * x[n + j]).sum();
        assert!(r.abs() < 1e-12, "row {i}: {r}");
    }
}

#[test]
fn json_export_carries_the_matrices() {
    let m = fixture();
    let json = m.matrices_json().unwrap();
    let ss = m.state_space().unwrap();
    for key in ["M", "D", "K", "B", "A", "C", "x0", "states", "outputs"] {
        assert!(json.get(key).is_some(), "missing {key}");
    }
    assert_eq!(json["A"][5][1].as_f64().unwrap(), ss.a[(5, 1)]);
    assert_eq!(json["outputs"][2], "strain");
    assert_eq!(json["states"].as_array().unwrap().len(), 8);
}
