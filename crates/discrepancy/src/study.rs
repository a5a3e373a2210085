//! The hidden-effect study: truth models with one catalog effect at a moderate strength, data
//! with 1 % sensor noise, shared by the tests and by the long study that writes
//! docs/diagnose.md.

use faer::Mat;
use mem::Measurement;
use plant::SlewingModel;
use rand::{Rng, SeedableRng};

/// The catalog effects the study hides, and `"none"` (noise only).
pub const CASES: [&str; 8] = [
    "amplifier_saturation",
    "coulomb_friction",
    "quadratic_drag",
    "sensor_quantization",
    "output_offset",
    "time_delay",
    "unmodeled_mode",
    "none",
];

/// The truth's effect (RON) and the parameter to recover with its true value.
pub fn truth_effect(case: &str) -> Option<(&'static str, &'static str, f64)> {
    Some(match case {
        "amplifier_saturation" => {
            ("AmplifierSaturation(current_limit: 1.3, sharp: true)", "current_limit", 1.3)
        }
        "coulomb_friction" => {
            ("CoulombFriction(torque: 0.01, smoothing_velocity: 0.005)", "coulomb_torque", 0.01)
        }
        "quadratic_drag" => ("QuadraticDrag(hub: 0.06)", "drag_hub", 0.06),
        "sensor_quantization" => {
            ("SensorQuantization(sensor: Potentiometer, step: 0.015)", "quantization_step_theta", 0.015)
        }
        "output_offset" => ("OutputOffset(sensor: Potentiometer, offset: 0.01)", "offset_theta", 0.01),
        "time_delay" => ("TimeDelay(delay: 0.1)", "delay", 0.1),
        "unmodeled_mode" => (
            "UnmodeledMode(frequency_hz: 0.6, damping_ratio: 0.03, coupling: 0.25)",
            "extra_mode_frequency",
            0.6,
        ),
        _ => return None,
    })
}

/// The baseline model every case is fitted with: the paper's model (C_v, K_p free).
pub fn baseline() -> SlewingModel {
    SlewingModel::paper()
}

/// The truth model of a case: the paper's model with C_v = 0.08 (the baseline starts at the
/// paper's 0.0528) and the hidden effect.
pub fn truth(case: &str) -> SlewingModel {
    let effects = truth_effect(case).map_or(String::new(), |(e, _, _)| e.to_string());
    let text = plant::PAPER_MODEL_RON
        .replace("viscous_damping: 0.0528,", "viscous_damping: 0.08,")
        .replace("    bounds: {", &format!("    effects: [{effects}],\n    bounds: {{"));
    SlewingModel::from_ron(&text, "study-truth").expect("the study's truth models are valid")
}

/// 12.8 Hz for 30 s of all three sensors, with white noise of 1 % of each output's RMS.
pub fn measurement(case: &str, seed: u64) -> Measurement {
    let model = truth(case);
    let h = 1.0 / 12.8;
    let n = 385;
    let clean = models::simulate_model(&model, h, n).expect("the study's truth models simulate");
    let mut rng = rand::rngs::StdRng::seed_from_u64(seed);
    let mut noisy = Mat::zeros(n, clean.ncols());
    for o in 0..clean.ncols() {
        let rms = ((0..n).map(|k| clean[(k, o)].powi(2)).sum::<f64>() / n as f64).sqrt();
        for k in 0..n {
            noisy[(k, o)] = clean[(k, o)] + 0.01 * rms * rng.sample::<f64, _>(rand_distr::StandardNormal);
        }
    }
    let names = model.output_names().iter().map(|s| s.to_string()).collect();
    Measurement::new(names, 0.0, h, noisy).expect("finite data")
}
