//! `diagnose` end to end through the library: a parameter mismatch is not a missing effect, a
//! sensor effect is named on its sensor, and (ignored, long) the blind development set made by a
//! simulator that shares no code with memid meets its rules.

use discrepancy::{DiagnoseOptions, RIVAL_MARGIN, Verdict, diagnose};
use models::Model;
use plant::SlewingModel;

/// The paper's model file with `edit` applied to its text.
fn edited(edit: impl Fn(String) -> String) -> SlewingModel {
    SlewingModel::from_ron(&edit(plant::PAPER_MODEL_RON.to_string()), "truth.ron").unwrap()
}

/// 30 s at 12.8 Hz of `truth` with 1 % noise of each output's RMS.
fn record(truth: &SlewingModel, seed: u64) -> mem::Measurement {
    let response = Model::Slewing(truth.clone()).response(&[]).unwrap();
    test_problems::simulate_measurement(response.as_ref(), &[], 1.0 / 12.8, 385, 0.01, seed)
}

fn options() -> DiagnoseOptions {
    DiagnoseOptions::new(&["cv", "kp"])
}

/// The diagnosis of `fixtures/independent/effects/<name>.csv` (128 Hz, from the study's
/// independent truth plant) with the paper's model file, decimated to 12.8 Hz.
fn decimated_fixture(name: &str) -> discrepancy::Diagnosis {
    decimated_fixture_from(name, |t| t)
}

/// The same, with `edit` applied to the model file's text (the record's own θ(0), say).
fn decimated_fixture_from(name: &str, edit: impl Fn(String) -> String) -> discrepancy::Diagnosis {
    fixture_at(name, Some(10), edit)
}

/// The diagnosis of `fixtures/independent/effects/<name>.csv` with the paper's model file
/// edited by `edit`, decimated by `decimate` if given.
fn fixture_at(
    name: &str,
    decimate: Option<usize>,
    edit: impl Fn(String) -> String,
) -> discrepancy::Diagnosis {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../../fixtures");
    let text = std::fs::read_to_string(format!("{root}/slewing.ron")).unwrap();
    let model = Model::from_ron(&edit(text), "slewing.ron").unwrap();
    let data =
        mem::Measurement::read_csv(std::path::Path::new(&format!("{root}/independent/effects/{name}.csv")))
            .unwrap();
    let mut options = options();
    options.decimate = decimate;
    diagnose(&model, &data, &options).unwrap()
}

/// A held-out case of the study kept as a fixture (`fixtures/independent/study_cases.py`), as
/// the study runs it: released from its θ(0), C_v and K_p free, decimated by 10.
fn held_out_case(name: &str, theta0: f64) -> discrepancy::Diagnosis {
    fixture_at(name, Some(10), |t| {
        t.replace("hub_angle: 0.5,", &format!("hub_angle: {theta0},"))
            .replace("free: [\"cv\"],", "free: [\"cv\", \"kp\"],")
    })
}

mod beyond_catalog;
mod blind;
mod mismatch;
mod modes;
mod named;
