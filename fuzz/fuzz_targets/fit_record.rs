//! A fit of a fixture model (free decay or forced) to a short record of arbitrary numbers
//! (constant, tiny, huge, spiky, quantized): it must answer Ok or an error, never panic, and an
//! answer that is Ok holds finite parameters and a finite error — never a silent NaN.
#![no_main]

use faer::Mat;
use libfuzzer_sys::fuzz_target;
use mem::Measurement;
use models::{FitRequest, Model};
use std::sync::OnceLock;

/// The fixtures: free decays of displacements (two outputs) and accelerations (three), and the
/// forced building (a force in, three accelerations out; and with quantized sensors), each with
/// the free parameters its file names.
fn models() -> &'static [Model] {
    static MODELS: OnceLock<Vec<Model>> = OnceLock::new();
    MODELS.get_or_init(|| {
        [
            include_str!("../../fixtures/shear_building.ron"),
            include_str!("../../fixtures/shear_building_acc.ron"),
        ]
        .iter()
        .map(|text| Model::from_ron(text, "fixture").expect("a fixture parses"))
        .collect()
    })
}

fuzz_target!(|data: &[u8]| {
    let [which, scale, interval, rest @ ..] = data else { return };
    let model = &models()[usize::from(*which) % models().len()];
    // The record's columns: the model's inputs (if any), then its outputs.
    let names: Vec<String> = model.input_names().into_iter().chain(model.output_names()).collect();
    let p = names.len();
    let k = (rest.len() / (2 * p)).min(64);
    if k < 2 {
        return;
    }
    // Each sample an i16 times 10^(scale mod 24 − 12): constant runs, tiny and huge magnitudes.
    let factor = 10f64.powi(i32::from(*scale % 24) - 12);
    let values = Mat::from_fn(k, p, |t, o| {
        let at = 2 * (t * p + o);
        f64::from(i16::from_le_bytes([rest[at], rest[at + 1]])) * factor
    });
    let h = [0.001, 0.005, 0.01, 0.05, 0.2][usize::from(*interval % 5)];
    let Ok(record) = Measurement::new(names.clone(), 0.0, h, values) else { return };
    let free: Vec<String> = model.file_free();
    let free: Vec<&str> = free.iter().map(String::as_str).collect();
    let mut request = FitRequest::new(&free);
    request.max_iterations = 8;
    request.derivative_check = mem::DerivativeCheck::Skip;
    let Ok(outcome) = models::fit(model, &record, &request) else { return };
    let report = &outcome.report;
    assert!(report.parameters.iter().all(|v| v.is_finite()), "parameters {:?}", report.parameters);
    assert!(report.error_history.iter().all(|e| e.is_finite()), "errors {:?}", report.error_history);
});
