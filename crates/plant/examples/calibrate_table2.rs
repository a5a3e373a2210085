//! Calibrates the constants the paper does not print (ρ and the amplifier gain G) so that the
//! model's closed-loop modes match the three model rows of the paper's Table 2.
//!
//! `cargo run --release -p plant --example calibrate_table2 -- fixtures/slewing.ron`
//!
//! Levenberg–Marquardt on the relative errors of the servo frequency (weight 5), servo damping
//! ratio (weight 1) and first flexible frequency (weight 1) of the three rows, with a
//! central-difference Jacobian (a two-parameter calibration script, not production code).

use plant::{ModeKind, ParamId, SlewingModel};

/// (C_v, K_p, servo Hz, servo ζ, flexible-1 Hz, flexible-1 ζ) from Table 2's model rows.
pub const TABLE2_MODEL_ROWS: [(&str, f64, f64, f64, f64, f64, f64); 3] = [
    ("Initial", 0.0528, 8.0, 0.1520, 0.0632, 1.72, 0.0231),
    ("Run 1 final", 0.2048, 8.0, 0.1519, 0.2448, 1.724, 0.0246),
    ("Run 2 final", 0.1299, 6.5753, 0.1377, 0.1773, 1.7249, 0.0242),
];

fn table(model: &SlewingModel, cv: f64, kp: f64) -> (f64, f64, f64, f64) {
    let mut m = model.clone();
    m.set(ParamId::ViscousDamping, cv).unwrap();
    m.set(ParamId::PositionGain, kp).unwrap();
    let rows = m.modal().unwrap();
    let servo = rows.iter().find(|r| r.kind == ModeKind::Servo).unwrap();
    let flex = rows.iter().find(|r| r.kind == ModeKind::Flexible(1)).unwrap();
    (servo.frequency_hz, servo.damping_ratio, flex.frequency_hz, flex.damping_ratio)
}

fn residuals(model: &SlewingModel, rho: f64, gain: f64) -> Vec<f64> {
    let mut m = model.clone();
    m.set(ParamId::MassPerLength, rho).unwrap();
    m.set(ParamId::AmplifierGain, gain).unwrap();
    TABLE2_MODEL_ROWS
        .iter()
        .flat_map(|&(_, cv, kp, f1, z1, f2, _)| {
            let (mf1, mz1, mf2, _) = table(&m, cv, kp);
            [5.0 * (mf1 / f1 - 1.0), mz1 / z1 - 1.0, mf2 / f2 - 1.0]
        })
        .collect()
}

fn main() {
    let path = std::env::args().nth(1).unwrap_or_else(|| "fixtures/slewing.ron".into());
    let model = SlewingModel::load(std::path::Path::new(&path)).expect("model file loads");
    let mut p = [0.475, 1.0]; // a bare 3 in × 1/32 in steel strip, unity amplifier gain
    let mut mu = 1e-2;
    let cost = |r: &[f64]| r.iter().map(|v| v * v).sum::<f64>();
    let mut r = residuals(&model, p[0], p[1]);
    for iteration in 0..50 {
        let mut jac = vec![[0.0; 2]; r.len()];
        for k in 0..2 {
            let h = 1e-6 * p[k];
            let mut plus = p;
            plus[k] += h;
            let mut minus = p;
            minus[k] -= h;
            let (rp, rm) = (residuals(&model, plus[0], plus[1]), residuals(&model, minus[0], minus[1]));
            for i in 0..r.len() {
                jac[i][k] = (rp[i] - rm[i]) / (2.0 * h);
            }
        }
        // (JᵀJ + μ diag(JᵀJ)) δ = −Jᵀr, 2×2 by Cramer's rule
        let mut jtj = [[0.0; 2]; 2];
        let mut jtr = [0.0; 2];
        for i in 0..r.len() {
            for a in 0..2 {
                jtr[a] += jac[i][a] * r[i];
                for b in 0..2 {
                    jtj[a][b] += jac[i][a] * jac[i][b];
                }
            }
        }
        let m00 = jtj[0][0] * (1.0 + mu);
        let m11 = jtj[1][1] * (1.0 + mu);
        let det = m00 * m11 - jtj[0][1] * jtj[1][0];
        let step = [(-jtr[0] * m11 + jtr[1] * jtj[0][1]) / det, (-jtr[1] * m00 + jtr[0] * jtj[1][0]) / det];
        let trial = [p[0] + step[0], p[1] + step[1]];
        let rt = residuals(&model, trial[0], trial[1]);
        if cost(&rt) < cost(&r) {
            let small = step[0].abs() < 1e-9 * p[0] && step[1].abs() < 1e-9 * p[1];
            p = trial;
            r = rt;
            mu *= 0.3;
            if small {
                eprintln!("converged after {iteration} iterations");
                break;
            }
        } else {
            mu *= 10.0;
        }
    }
    println!("calibrated: mass_per_length = {:.4} kg/m, amplifier_gain = {:.4}", p[0], p[1]);
    let mut m = model.clone();
    m.set(ParamId::MassPerLength, p[0]).unwrap();
    m.set(ParamId::AmplifierGain, p[1]).unwrap();
    println!(
        "| row | servo Hz paper / model | servo ζ paper / model | flex-1 Hz paper / model | flex-1 ζ paper / model |"
    );
    println!("|---|---|---|---|---|");
    for &(name, cv, kp, f1, z1, f2, z2) in &TABLE2_MODEL_ROWS {
        let (mf1, mz1, mf2, mz2) = table(&m, cv, kp);
        println!(
            "| {name} | {f1:.4} / {mf1:.4} ({:+.2} %) | {:.2} % / {:.2} % ({:+.1} %) | {f2:.4} / {mf2:.4} ({:+.2} %) | {:.2} % / {:.2} % |",
            100.0 * (mf1 / f1 - 1.0),
            100.0 * z1,
            100.0 * mz1,
            100.0 * (mz1 / z1 - 1.0),
            100.0 * (mf2 / f2 - 1.0),
            100.0 * z2,
            100.0 * mz2
        );
    }
}
