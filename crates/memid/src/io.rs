//! Reading and writing files: CSV data, model files, outputs written whole or not at all.

use anyhow::{Context, Result, anyhow, bail};
use faer::Mat;
use mem::{Measurement, MemError};
use plant::SlewingModel;
use std::path::{Path, PathBuf};

/// Reads a CSV with header `t,<output names>` into a measurement. Errors name the file and line.
pub fn read_measurement(path: &Path) -> Result<Measurement> {
    let text =
        std::fs::read_to_string(path).with_context(|| format!("cannot read data file {}", path.display()))?;
    parse_measurement(&text, &path.display().to_string())
}

/// Parses CSV text (see [`read_measurement`]); `shown` names it in errors.
pub fn parse_measurement(text: &str, shown: &str) -> Result<Measurement> {
    let mut reader = csv::ReaderBuilder::new().trim(csv::Trim::All).from_reader(text.as_bytes());
    let headers = reader.headers().with_context(|| format!("{shown}: cannot read the CSV header"))?.clone();
    if headers.len() < 2 || !matches!(&headers[0], "t" | "time") {
        bail!(
            "{shown}:1: the header must be `t,<output names>` (found `{}`)",
            headers.iter().collect::<Vec<_>>().join(",")
        );
    }
    let names: Vec<String> = headers.iter().skip(1).map(|s| s.to_string()).collect();
    let mut times = Vec::new();
    let mut rows: Vec<Vec<f64>> = Vec::new();
    for (index, record) in reader.records().enumerate() {
        let line = index + 2;
        let record = record.map_err(|e| anyhow!("{shown}:{line}: malformed CSV: {e}"))?;
        if record.len() != headers.len() {
            bail!("{shown}:{line}: {} fields where the header has {}", record.len(), headers.len());
        }
        let mut values = Vec::with_capacity(record.len());
        for (column, field) in record.iter().enumerate() {
            let v: f64 = field
                .parse()
                .map_err(|_| anyhow!("{shown}:{line}:{}: `{field}` is not a number", column + 1))?;
            if !v.is_finite() {
                bail!(
                    "{shown}:{line}:{}: `{field}` is not a finite number; remove or repair the sample",
                    column + 1
                );
            }
            values.push(v);
        }
        times.push(values[0]);
        rows.push(values[1..].to_vec());
    }
    let values = Mat::from_fn(rows.len(), names.len(), |k, o| rows[k][o]);
    Measurement::from_times(&times, names, values).map_err(|e| match e {
        MemError::Sample { sample, message } => anyhow!("{shown}:{}: {message}", sample + 2),
        other => anyhow!("{shown}: {other}"),
    })
}

/// CSV text for a measurement-like table.
pub fn csv_text(names: &[String], times: &[f64], values: &Mat<f64>) -> String {
    let mut out = String::from("t");
    for n in names {
        out.push(',');
        out.push_str(n);
    }
    out.push('\n');
    for (k, t) in times.iter().enumerate() {
        out.push_str(&format!("{t}"));
        for o in 0..values.ncols() {
            out.push_str(&format!(",{:e}", values[(k, o)]));
        }
        out.push('\n');
    }
    out
}

/// The files a command reads, so that no output overwrites them.
#[derive(Default)]
pub struct Inputs(Vec<PathBuf>);

impl Inputs {
    /// Records an input.
    pub fn add(&mut self, path: &Path) {
        self.0.push(std::fs::canonicalize(path).unwrap_or_else(|_| path.to_path_buf()));
    }

    /// Fails if `output` is one of the inputs.
    pub fn guard(&self, output: &Path) -> Result<()> {
        let canonical = std::fs::canonicalize(output).unwrap_or_else(|_| output.to_path_buf());
        if self.0.contains(&canonical) {
            bail!("refusing to overwrite the input file {}; choose another output path", output.display());
        }
        Ok(())
    }
}

/// Writes `contents` to `path` whole or not at all (a temporary file, then a rename).
pub fn write_atomic(path: &Path, contents: &[u8]) -> Result<()> {
    let dir = path.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create directory {}", dir.display()))?;
    let name = path.file_name().ok_or_else(|| anyhow!("{} is not a file path", path.display()))?;
    let tmp = dir.join(format!(".{}.tmp-{}", name.to_string_lossy(), std::process::id()));
    std::fs::write(&tmp, contents).with_context(|| format!("cannot write {}", tmp.display()))?;
    std::fs::rename(&tmp, path).with_context(|| format!("cannot move the result into {}", path.display()))?;
    Ok(())
}

/// Loads a model file and applies `--set NAME=VALUE` assignments.
pub fn load_model(path: &Path, sets: &[String], inputs: &mut Inputs) -> Result<SlewingModel> {
    inputs.add(path);
    let mut model = SlewingModel::load(path)?;
    apply_sets(&mut model, sets)?;
    Ok(model)
}

/// Applies `NAME=VALUE` assignments.
pub fn apply_sets(model: &mut SlewingModel, sets: &[String]) -> Result<()> {
    for set in sets {
        let (name, value) = set
            .split_once('=')
            .ok_or_else(|| anyhow!("--set `{set}`: expected NAME=VALUE, e.g. --set cv=0.2"))?;
        let id = model.parameter(name.trim())?;
        let value: f64 =
            value.trim().parse().map_err(|_| anyhow!("--set `{set}`: `{value}` is not a number"))?;
        model.set(id, value)?;
    }
    Ok(())
}

/// Splits a comma-separated list of names.
pub fn names(list: &str) -> Vec<String> {
    list.split(',').map(|s| s.trim().to_string()).filter(|s| !s.is_empty()).collect()
}
