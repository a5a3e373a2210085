//! Reading inputs (CSV records, model files, `--set` assignments) and writing outputs safely
//! ([`files`]).

mod files;

pub use files::{BrokenPipe, Inputs, Outputs, Target, install_signal_cleanup, print};

use anyhow::{Result, anyhow, bail};
use mem::Measurement;
use models::Model;
use std::path::Path;

/// Reads a CSV with header `t,<columns>` into a measurement; errors name the file, line and column.
///
/// A record is read on the model's clock: its initial state holds at t = 0, and a record whose
/// first sample is later is fitted from there (docs/fitting.md). A record that starts more than
/// half a sample after t = 0 is noted on stderr, since time stamps read off a clock that did not
/// start at the release put the model's decay before the record.
pub fn read_measurement(path: &Path, inputs: &mut Inputs) -> Result<Measurement> {
    inputs.add(path);
    let data = Measurement::read_csv(path)?;
    if let Some(note) = late_start(path, &data) {
        use std::io::Write;
        let _ = writeln!(std::io::stderr(), "{note}");
    }
    Ok(data)
}

/// The note for a record whose first sample is more than half a sample after the model's t = 0.
fn late_start(path: &Path, data: &Measurement) -> Option<String> {
    (data.start() > 0.5 * data.interval()).then(|| {
        format!(
            "memid: note: {} starts at t = {} s; the model's initial state holds at t = 0 and is carried \
             to the first sample (if the first sample is the release, shift the time column to start at 0)",
            path.display(),
            data.start()
        )
    })
}

/// Loads a model file of either kind and applies `--set NAME=VALUE` assignments.
pub fn load_model(path: &Path, sets: &[String], inputs: &mut Inputs) -> Result<Model> {
    inputs.add(path);
    let mut model = Model::load(path)?;
    apply_sets(&mut model, sets)?;
    Ok(model)
}

/// Parses one `--set NAME=VALUE` into its name and a finite value.
pub fn parse_set(set: &str) -> Result<(&str, f64)> {
    let (name, value) = set
        .split_once('=')
        .ok_or_else(|| anyhow!("--set `{set}`: expected NAME=VALUE, e.g. --set cv=0.2"))?;
    let v: f64 =
        value.trim().parse().map_err(|_| anyhow!("--set {set}: `{}` is not a number", value.trim()))?;
    if !v.is_finite() {
        bail!("--set {set}: `{}` is not a finite number", value.trim());
    }
    Ok((name.trim(), v))
}

/// Applies `NAME=VALUE` assignments; errors name the assignment.
pub fn apply_sets(model: &mut Model, sets: &[String]) -> Result<()> {
    for set in sets {
        let (name, value) = parse_set(set)?;
        model.set(name, value).map_err(|e| anyhow!("--set {set}: {e}"))?;
    }
    if !sets.is_empty() {
        model.check_values().map_err(|e| anyhow!("--set {}: {e}", sets.join(" --set ")))?;
    }
    Ok(())
}

/// Splits a comma-separated list of names.
pub fn names(list: &str) -> Vec<String> {
    list.split(',').map(|s| s.trim().to_string()).filter(|s| !s.is_empty()).collect()
}
