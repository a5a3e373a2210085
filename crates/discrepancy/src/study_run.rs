//! Running the hidden-effect study: one diagnose per (case, seed), scored against the truth.

use crate::study::{baseline, measurement, truth_effect};
use crate::{DiagnoseOptions, diagnose};

/// The outcome of one (case, seed).
#[derive(Clone, Debug)]
pub struct StudyResult {
    /// The hidden effect (or "none").
    pub case: String,
    /// The seed of the noise.
    pub seed: u64,
    /// What diagnose named.
    pub named: String,
    /// 1 − augmented error / baseline error.
    pub shrink: f64,
    /// Relative error of the recovered parameter (None for "none" or a wrong name).
    pub parameter_error: Option<f64>,
}

/// Runs one case with one seed (baseline free parameters C_v and K_p).
pub fn run_case(case: &str, seed: u64) -> StudyResult {
    let data = measurement(case, seed);
    let d = diagnose(&baseline(), &data, &DiagnoseOptions::new(&["cv", "kp"])).expect("the study's fits run");
    let named = d.effect().to_string();
    let parameter_error = truth_effect(case).and_then(|(_, name, value)| {
        let chosen = &d.candidates[d.chosen?];
        (chosen.effect == case).then(|| {
            let p = chosen
                .parameters
                .iter()
                .find(|p| p.name == name)
                .expect("the effect's parameter is reported");
            (p.value / value - 1.0).abs()
        })
    });
    StudyResult {
        case: case.into(),
        seed,
        named,
        shrink: 1.0 - d.augmented_error() / d.baseline_error(),
        parameter_error,
    }
}
