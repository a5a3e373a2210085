//! Nonlinear effects: the forms they reduce to, their linear limits, the limiters' closed forms and
//! backlash against the lumped model.

use super::*;

#[test]
fn new_nonlinear_effects_reduce_to_known_forms() {
    // A huge voltage limit is the linear model; drag with exponent 2 is the quadratic drag.
    let linear = with_effects("VoltageSaturation(voltage_limit: 1e9)");
    let quadratic = with_effects("QuadraticDrag(hub: 0.05)");
    let power =
        with_effects("QuadraticDrag(hub: 0.05, exponent: Some(2.0)), CubicStiffness(coefficient: 0.0)");
    let a = SlewingModel::paper().state_space().unwrap().a;
    let x: Vec<f64> = (0..a.nrows()).map(|i| 0.3 * (i as f64 + 1.0).sin()).collect();
    let rhs = |m: &SlewingModel| {
        let mut f = vec![0.0; x.len()];
        m.dynamics_with(|v| *v).unwrap().rhs(0.0, &x, &mut f);
        f
    };
    let (fl, fq, fp) = (rhs(&linear), rhs(&quadratic), rhs(&power));
    for i in 0..x.len() {
        let lin: f64 = (0..x.len()).map(|j| a[(i, j)] * x[j]).sum();
        assert!((fl[i] - lin).abs() < 1e-9 * (1.0 + lin.abs()), "voltage row {i}");
        assert!((fq[i] - fp[i]).abs() < 1e-12 * (1.0 + fq[i].abs()), "drag row {i}");
    }
    // A cubic stiffness adds −k₃θ³ to the hub's equation: compare with the linear right-hand side.
    let cubic = with_effects("CubicStiffness(coefficient: 2.0)");
    let fc = rhs(&cubic);
    let fb = rhs(&SlewingModel::paper());
    let hub = cubic.layout().n_dof;
    assert!(fc[hub] < fb[hub], "a hardening spring pulls θ = {} back", x[0]);
    // Its linear part k₁θ acts where the cubic does: at θ, k₁ = k₃θ² gives the same torque,
    // so the same right-hand side, as the cubic alone (and twice the change with both).
    let k1 = 2.0 * x[0] * x[0];
    let linear = with_effects(&format!("CubicStiffness(coefficient: 0.0, linear: Some({k1:e}))"));
    let both = with_effects(&format!("CubicStiffness(coefficient: 2.0, linear: Some({k1:e}))"));
    let (f1, f2) = (rhs(&linear), rhs(&both));
    for i in 0..x.len() {
        assert!((f1[i] - fc[i]).abs() < 1e-12 * (1.0 + fc[i].abs()), "row {i}: {} vs {}", f1[i], fc[i]);
        let twice = fb[i] + 2.0 * (fc[i] - fb[i]);
        assert!((f2[i] - twice).abs() < 1e-12 * (1.0 + twice.abs()), "row {i}");
    }
    assert!(linear.parameter("hub_stiffness").is_ok(), "a parameter when given");
    assert!(cubic.parameter("hub_stiffness").is_err(), "not one when absent");
    // The form's refinements: k₅θ⁵ at θ is the cubic with k₃ = k₅θ², and k₁′·t·θ at time t is
    // the linear part k₁ = k₁′t, which at t = 0 is nothing.
    let k5 = 2.0 / (x[0] * x[0]);
    let quintic = with_effects(&format!("CubicStiffness(coefficient: 0.0, quintic: Some({k5:e}))"));
    let rate = with_effects("CubicStiffness(coefficient: 0.0, rate: Some(0.05))");
    let at = |m: &SlewingModel, t: f64| {
        let mut f = vec![0.0; x.len()];
        m.dynamics_with(|v| *v).unwrap().rhs(t, &x, &mut f);
        f
    };
    let (f5, f_late, f_start) = (rhs(&quintic), at(&rate, 2.0 * x[0] * x[0] / 0.05), at(&rate, 0.0));
    for i in 0..x.len() {
        assert!((f5[i] - fc[i]).abs() < 1e-12 * (1.0 + fc[i].abs()), "quintic row {i}");
        assert!((f_late[i] - f1[i]).abs() < 1e-12 * (1.0 + f1[i].abs()), "rate row {i}");
        assert!((f_start[i] - fb[i]).abs() < 1e-12 * (1.0 + fb[i].abs()), "rate at release, row {i}");
    }
    assert!(quintic.parameter("quintic_stiffness").is_ok() && rate.parameter("stiffness_rate").is_ok());
    assert!(cubic.parameter("stiffness_rate").is_err(), "not one when absent");
}

#[test]
fn nonlinear_effects_reduce_to_the_linear_model_in_their_limits() {
    let m = with_effects(
        "AmplifierSaturation(current_limit: 1e6), CoulombFriction(torque: 0.0, smoothing_velocity: 0.01), QuadraticDrag(hub: 0.0)",
    );
    assert!(!m.is_linear());
    let dynamics = m.dynamics_with(|v| *v).unwrap();
    let a = m.state_space().unwrap().a;
    let x: Vec<f64> = (0..m.n_states()).map(|i| 0.3 * (i as f64 + 1.0).sin()).collect();
    let mut f = vec![0.0; x.len()];
    dynamics.rhs(0.0, &x, &mut f);
    for i in 0..x.len() {
        let linear: f64 = (0..x.len()).map(|j| a[(i, j)] * x[j]).sum();
        assert!((f[i] - linear).abs() < 1e-12 * (1.0 + linear.abs()), "row {i}: {} vs {linear}", f[i]);
    }
}

/// Dry friction with a static peak (Stribeck): at hub rate v the friction torque is
/// (F_c + ΔF e^{−(v/v_st)²}) tanh(v/v_s), so against the Coulomb friction alone every row of
/// the right-hand side's change from the linear model is scaled by (F_c + ΔF e^{−(v/v_st)²})/F_c
/// — e.g. (F_c + ΔF/e)/F_c at v = v_st — and by 1 far above v_st.
#[test]
fn a_static_peak_raises_the_friction_near_rest_and_fades_above_the_stribeck_velocity() {
    let (fc, peak, v_st) = (0.004, 0.003, 0.02);
    let coulomb = with_effects(&format!("CoulombFriction(torque: {fc}, smoothing_velocity: 0.0002)"));
    let stribeck = with_effects(&format!(
        "CoulombFriction(torque: {fc}, smoothing_velocity: 0.0002, static_peak: Some({peak}), stribeck_velocity: Some({v_st}))"
    ));
    assert_eq!(stribeck.parameter("static_peak").unwrap(), ParamId::StaticPeak);
    assert!(coulomb.parameter("stribeck_velocity").is_err(), "not a parameter when absent");
    let paper = SlewingModel::paper();
    let n = paper.n_states();
    let hub_rate = paper.layout().n_dof;
    for (v, expected) in [
        (v_st, (fc + peak / std::f64::consts::E) / fc),
        (0.5 * v_st, (fc + peak * (-0.25f64).exp()) / fc),
        (20.0 * v_st, 1.0),
    ] {
        let mut x: Vec<f64> = (0..n).map(|i| 0.01 * (i as f64 + 1.0).cos()).collect();
        x[hub_rate] = v;
        let rhs = |m: &SlewingModel| {
            let mut f = vec![0.0; n];
            m.dynamics_with(|v| *v).unwrap().rhs(0.0, &x, &mut f);
            f
        };
        let (fl, fcoul, fs) = (rhs(&paper), rhs(&coulomb), rhs(&stribeck));
        for i in 0..n {
            let (dc, ds) = (fcoul[i] - fl[i], fs[i] - fl[i]);
            assert!(
                (ds - expected * dc).abs() <= 1e-12 * (1.0 + ds.abs()),
                "v = {v}, row {i}: {ds} vs {expected}·{dc}"
            );
        }
    }
    let half = plant::PAPER_MODEL_RON.replace(
        "    bounds: {",
        "    effects: [CoulombFriction(torque: 0.004, smoothing_velocity: 0.0002, static_peak: Some(0.003))],\n    bounds: {",
    );
    let msg = SlewingModel::from_ron(&half, "half.ron").unwrap_err().to_string();
    assert!(msg.contains("static_peak") && msg.contains("together"), "{msg}");
}

#[test]
fn smooth_limiter_is_linear_below_and_clamped_above() {
    for i in [0.1f64, 0.3, 0.59] {
        assert!((smooth_limit(i, 1.0) / i - 1.0).abs() < 0.01, "{i}");
    }
    for i in [2.0f64, 5.0, 50.0] {
        assert!(
            (smooth_limit(i, 1.0) - 1.0).abs() < 0.01 && (smooth_limit(-i, 1.0) + 1.0).abs() < 0.01,
            "{i}"
        );
    }
}

/// The limiter and its derivatives against the closed form y = i(1 + (i/I)⁸)^{−1/8},
/// ∂y/∂i = (1 + r⁸)^{−9/8}, ∂y/∂I = r⁹(1 + r⁸)^{−9/8} (r = i/I), on both sides of the limit and
/// at ratios whose eighth power overflows (a dead band fitted down to nothing).
#[test]
fn smooth_limiter_derivatives_stay_finite_for_any_ratio() {
    use num_dual::Dual64;
    for (i, limit) in
        [(0.3, 1.0), (-0.9, 1.0), (1.1, 1.0), (-4.0, 1.0), (0.01, 1e-40), (-0.02, 1e-300), (1e-3, 2e-3)]
    {
        let r: f64 = i / limit;
        // r⁸ by logarithms, so the reference does not overflow either.
        let q = (8.0 * r.abs().ln()).exp();
        let (value, d_i, d_limit) = if q.is_finite() {
            let w = (1.0 + q).powf(-1.0 / 8.0);
            (i * w, w / (1.0 + q), r * w / (1.0 + q) * q)
        } else {
            (limit * r.signum(), 0.0, r.signum())
        };
        let by_i = smooth_limit(Dual64::new(i, 1.0), Dual64::from(limit));
        let by_limit = smooth_limit(Dual64::from(i), Dual64::new(limit, 1.0));
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-12 * b.abs().max(1e-300);
        assert!(close(by_i.re, value), "value at ({i}, {limit}): {} vs {value}", by_i.re);
        assert!(
            close(by_i.eps, d_i) || (d_i.abs() < 1e-300 && by_i.eps.abs() < 1e-280),
            "∂/∂i at ({i}, {limit}): {} vs {d_i}",
            by_i.eps
        );
        assert!(close(by_limit.eps, d_limit), "∂/∂I at ({i}, {limit}): {} vs {d_limit}", by_limit.eps);
    }
}

/// The limiter with a knee n against closed forms: n = 2 is i/√(1 + (i/I)²) with
/// ∂y/∂i = (1 + r²)^{−3/2}; n = 8 is [`smooth_limit`]; and ∂y/∂n =
/// y·[ln(1 + rⁿ)/n² − rⁿ ln r/(n(1 + rⁿ))] (r = |i/I|), on both sides of the limit, at ratios
/// whose power overflows, and at rest (y = 0, ∂y/∂n = 0).
#[test]
fn a_limiter_with_a_knee_matches_its_closed_form() {
    use num_dual::Dual64;
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-12 * b.abs().max(1e-300);
    for (i, limit) in [(0.3f64, 1.0f64), (-0.9, 1.0), (1.1, 1.0), (-4.0, 2.5), (7.0, 1e-3), (0.0, 1.0)] {
        let r: f64 = (i / limit).abs();
        let soft = smooth_limit_with_knee(Dual64::new(i, 1.0), Dual64::from(limit), Dual64::from(2.0));
        let expected = i / (1.0 + r * r).sqrt();
        assert!(close(soft.re, expected), "n = 2 at ({i}, {limit}): {} vs {expected}", soft.re);
        let d_i = (1.0 + r * r).powf(-1.5);
        assert!(close(soft.eps, d_i), "∂/∂i at ({i}, {limit}): {} vs {d_i}", soft.eps);
        let eight = smooth_limit_with_knee(i, limit, 8.0);
        assert!(close(eight, smooth_limit(i, limit)), "n = 8 at ({i}, {limit}): {eight}");
        for n in [1.0f64, 2.7, 20.0] {
            let by_n = smooth_limit_with_knee(Dual64::from(i), Dual64::from(limit), Dual64::new(n, 1.0));
            let q = (n * r.ln()).exp();
            let y = i * (1.0 + q).powf(-1.0 / n);
            let d_n =
                if i == 0.0 { 0.0 } else { y * ((1.0 + q).ln() / (n * n) - q * r.ln() / (n * (1.0 + q))) };
            assert!(close(by_n.re, y), "value, n = {n} at ({i}, {limit}): {} vs {y}", by_n.re);
            assert!(
                // Against the value's scale: beyond the limit the reference's two terms cancel.
                (by_n.eps - d_n).abs() <= 1e-10 * (y.abs() + d_n.abs()),
                "∂/∂n, n = {n} at ({i}, {limit}): {} vs {d_n}",
                by_n.eps
            );
        }
    }
    // Far beyond the limit the power overflows; the value is the limit and stays finite.
    let far = smooth_limit_with_knee(Dual64::new(1e300, 1.0), Dual64::from(1e-10), Dual64::new(50.0, 1.0));
    assert!((far.re - 1e-10).abs() < 1e-22 && far.eps.is_finite(), "{far:?}");
}

/// A saturation's knee is a parameter of the model when given, and a file that states a knee of
/// zero is rejected with its place named.
#[test]
fn a_saturation_knee_is_a_parameter_when_given() {
    let m = with_effects("VoltageSaturation(voltage_limit: 6.0, knee: Some(2.5))");
    assert_eq!(m.parameter("voltage_knee").unwrap(), ParamId::VoltageKnee);
    let plain = with_effects("AmplifierSaturation(current_limit: 3.0)");
    assert!(plain.parameter("current_knee").is_err(), "not a parameter when absent");
    let zero = plant::PAPER_MODEL_RON.replace(
        "    bounds: {",
        "    effects: [AmplifierSaturation(current_limit: 3.0, knee: Some(0.0))],\n    bounds: {",
    );
    let msg = SlewingModel::from_ron(&zero, "zero.ron").unwrap_err().to_string();
    assert!(msg.contains("zero.ron") && msg.contains("knee") && msg.contains("> 0"), "{msg}");
}

#[test]
fn backlash_with_a_stiff_gear_and_a_closed_band_is_the_lumped_model() {
    // Adding the motor's row to the hub's gives the lumped hub row, so as the gear stiffens the
    // lumped model's eigenvalues reappear, with an error O((ω/ω_g)²); the gear adds its own.
    let lumped = eigenvalues(&SlewingModel::paper());
    let worst = |gear_hz: f64| {
        let m = with_effects(&format!("Backlash(dead_band: 1e-12, gear_frequency_hz: {gear_hz})"));
        assert_eq!(m.layout().n_dof, 5, "a motor degree of freedom");
        let split = eigenvalues(&m);
        lumped
            .iter()
            .map(|&(re, im)| {
                let size = (re * re + im * im).sqrt();
                split
                    .iter()
                    .map(|&(r, i)| ((r - re).powi(2) + (i - im).powi(2)).sqrt())
                    .fold(f64::INFINITY, f64::min)
                    / size
            })
            .fold(0.0, f64::max)
    };
    // (Beyond a few hundred Hz the eigensolver's rounding, ε‖A‖ with ‖A‖ ∝ f_g², takes over.)
    let (coarse, fine) = (worst(10.0), worst(100.0));
    println!("largest relative eigenvalue error: {coarse:.2e} at 10 Hz, {fine:.2e} at 100 Hz");
    assert!(fine < 1e-4, "100 Hz gear: {fine:.2e}");
    assert!(fine < coarse / 50.0, "second order in 1/f_g: {coarse:.2e} → {fine:.2e}");
}

#[test]
fn backlash_passes_no_torque_inside_its_band_and_the_gear_beyond_it() {
    // Band b = 10 mrad (half 5 mrad), hub at 0.1 rad, at rest. With the motor 20 mrad ahead the
    // gear passes k_g·(20 − 5) mrad: the dynamics are those of a closed band with the motor 15 mrad
    // ahead. With the motor 1 mrad ahead it passes nothing: those of a closed band with none.
    let f = |band: f64, ahead: f64| {
        let m = with_effects(&format!(
            "Backlash(dead_band: {band:e}, gear_frequency_hz: 12.0, tachometer_on_motor: false)"
        ));
        let layout = m.layout();
        let mut x = vec![0.0; layout.n_states];
        x[0] = 0.1;
        x[layout.motor.unwrap()] = 0.1 + ahead;
        let mut out = vec![0.0; layout.n_states];
        m.dynamics_with(|v| *v).unwrap().rhs(0.0, &x, &mut out);
        out
    };
    let close = |a: &[f64], b: &[f64], tolerance: f64| {
        let scale = b.iter().fold(0.0f64, |s, v| s.max(v.abs()));
        let err = a.iter().zip(b).fold(0.0f64, |s, (x, y)| s.max((x - y).abs()));
        assert!(err <= tolerance * scale, "{err:.3e} of {scale:.3e}");
    };
    close(&f(0.01, 0.02), &f(1e-12, 0.015), 1e-4);
    let gear_scale = f(1e-12, 0.001);
    let inside = f(0.01, 0.001);
    let rest = f(1e-12, 0.0);
    let err = inside.iter().zip(&rest).fold(0.0f64, |s, (x, y)| s.max((x - y).abs()));
    let scale = gear_scale.iter().zip(&rest).fold(0.0f64, |s, (x, y)| s.max((x - y).abs()));
    assert!(err < 1e-5 * scale, "inside the band: {err:.3e} against a closed band's {scale:.3e}");
}
