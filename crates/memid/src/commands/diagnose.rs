//! `memid diagnose`: find where model and data disagree, name the missing effect, add it.

use crate::io::{Inputs, Outputs, Target, names, print, read_measurement};
use crate::output::fit_json;
use crate::progress::spinner;
use crate::report::Report;
use anyhow::{Result, bail};
use discrepancy::{DiagnoseOptions, Diagnosis, diagnose};
use serde_json::{Value, json};
use std::path::PathBuf;

/// Find the physical effect a model is missing: baseline fit, localisation, candidate refits
/// scored by BIC, and the augmented model.
#[derive(clap::Args)]
#[command(allow_negative_numbers = true)]
pub struct Args {
    #[command(flatten)]
    model: super::model_args::ModelArgs,
    /// Measured data (CSV with header t,<outputs>).
    #[arg(long)]
    data: PathBuf,
    /// Parameters refitted in the baseline and in every candidate, comma-separated.
    #[arg(long)]
    free: String,
    /// Keep every R-th sample after an anti-aliasing filter.
    #[arg(long, value_name = "R")]
    decimate: Option<usize>,
    /// Only try these catalog effects, comma-separated.
    #[arg(long)]
    only: Option<String>,
    /// Evidence needed to name an effect: ΔBIC below −THRESHOLD.
    #[arg(long, default_value_t = 10.0)]
    threshold: f64,
    /// Write the augmented model as a new RON file.
    #[arg(short = 'o', long = "output")]
    output: Option<PathBuf>,
    /// Write the diagnosis as JSON to FILE (`-` for standard output; suppresses the table).
    #[arg(long, value_name = "FILE")]
    json: Option<PathBuf>,
    /// Write a report (residual plots before and after, scores) into DIR.
    #[arg(long, value_name = "DIR")]
    report: Option<PathBuf>,
}

/// The diagnosis as JSON (docs/json.md).
pub fn diagnosis_json(d: &Diagnosis) -> Value {
    let chosen = d.chosen.map(|i| &d.candidates[i]);
    json!({
        "effect": d.effect(),
        "label": chosen.map(|c| c.label.clone()),
        "parameters": chosen.map_or(Vec::new(), |c| c.parameters.iter().map(|p| json!({
            "name": p.name, "value": p.value, "std_error": p.std_error,
        })).collect()),
        "baseline_error": d.baseline_error(),
        "augmented_error": d.augmented_error(),
        "candidates": d.candidates.iter().map(|c| json!({
            "effect": c.effect,
            "label": c.label,
            "error": if c.error.is_finite() { json!(c.error) } else { Value::Null },
            "score": if c.score.is_finite() { json!(c.score) } else { Value::Null },
            "delta_bic": if c.delta_bic.is_finite() { json!(c.delta_bic) } else { Value::Null },
            "reduction": if c.reduction.is_finite() { json!(c.reduction) } else { Value::Null },
            "whiteness_p": if c.whiteness_p.is_finite() { json!(c.whiteness_p) } else { Value::Null },
            "parameters": c.parameters.iter().map(|p| json!({"name": p.name, "value": p.value, "std_error": p.std_error})).collect::<Vec<_>>(),
            "failure": c.failure,
        })).collect::<Vec<_>>(),
        "localisation": {
            "findings": d.localisation.findings,
            "outputs": d.localisation.outputs.iter().map(|o| json!({
                "name": o.name, "share": o.share, "rms": o.rms, "early_to_late": o.early_to_late, "whiteness_p": o.whiteness_p,
            })).collect::<Vec<_>>(),
            "windows": d.localisation.windows.iter().map(|(a, b, s)| json!({"start": a, "end": b, "share": s})).collect::<Vec<_>>(),
            "decrement_vs_amplitude": d.localisation.decrement_vs_amplitude,
            "decrement_trend": d.localisation.decrement_trend,
            "residual_modes": d.localisation.residual_modes.iter().map(|m| json!({
                "frequency_hz": m.frequency_hz, "damping_ratio": m.damping_ratio, "contribution": m.contribution,
            })).collect::<Vec<_>>(),
        },
        "baseline": fit_json(&d.baseline),
    })
}

/// The scores as a table.
pub fn diagnosis_table(d: &Diagnosis) -> String {
    let mut out = String::from("localisation:\n");
    for f in &d.localisation.findings {
        out += &format!("  - {f}\n");
    }
    out += &format!(
        "\n{:<34} {:>12} {:>10} {:>11}  parameters\n",
        "candidate", "‖Y_error‖", "reduction", "ΔBIC"
    );
    for c in &d.candidates {
        let params = c
            .parameters
            .iter()
            .map(|p| format!("{} = {:.5} ± {:.2e}", p.name, p.value, p.std_error))
            .collect::<Vec<_>>()
            .join(", ");
        match &c.failure {
            Some(why) => out += &format!("{:<34} failed: {why}\n", c.label),
            None => {
                out += &format!(
                    "{:<34} {:>12.5e} {:>9.1}% {:>11.1}  {params}\n",
                    c.label,
                    c.error,
                    100.0 * c.reduction,
                    c.delta_bic
                )
            }
        }
    }
    out += &format!(
        "\nbaseline ‖Y_error‖ {:.5e} → augmented {:.5e} ({:.1} % smaller)\nnamed effect: {}\n",
        d.baseline_error(),
        d.augmented_error(),
        100.0 * (1.0 - d.augmented_error() / d.baseline_error()),
        d.chosen.map_or(
            "none (no candidate passes ΔBIC < −threshold with its strength resolved from zero)".to_string(),
            |i| d.candidates[i].label.clone()
        )
    );
    out
}

/// Runs the command.
pub fn run(args: Args) -> Result<()> {
    let mut inputs = Inputs::default();
    let model = args.model.load(&mut inputs)?;
    let Some(model) = model.as_slewing().cloned() else {
        bail!("diagnose works on the slewing rig's model files; structure files are fitted with `memid fit`")
    };
    let mut data = read_measurement(&args.data, &mut inputs)?;
    let mut outputs = Outputs::new(&inputs);
    let json_target = args.json.as_deref().map(Target::from_arg);
    let model_target = args.output.as_deref().map(Target::from_arg);
    for target in json_target.iter().chain(&model_target) {
        outputs.check(target)?;
    }
    if let Some(dir) = &args.report {
        outputs.check_directory(dir)?;
    }
    if let Some(r) = args.decimate {
        data = data.decimate(r)?;
    }
    let free = names(&args.free);
    if free.is_empty() {
        bail!("--free needs at least one parameter name");
    }
    if !(args.threshold.is_finite() && args.threshold >= 0.0) {
        bail!("--threshold must be a finite number ≥ 0, got {}", args.threshold);
    }
    let mut options = DiagnoseOptions::new(&free.iter().map(|s| s.as_str()).collect::<Vec<_>>());
    options.bic_threshold = args.threshold;
    options.only = args.only.as_deref().map(names).unwrap_or_default();
    let known = discrepancy::catalog_names();
    if let Some(unknown) = options.only.iter().find(|o| !known.contains(&o.as_str())) {
        bail!("--only: unknown effect `{unknown}`; the catalog holds {}", known.join(", "));
    }
    let quiet = json_target == Some(Target::Stdout) || model_target == Some(Target::Stdout);
    let bar = spinner("diagnosing: baseline fit, localisation, candidate refits", quiet);
    let d = diagnose(&model, &data, &options)?;
    bar.finish_and_clear();
    let json = diagnosis_json(&d);
    let mut messages = String::new();
    match &json_target {
        Some(target) => outputs.stage(target, (serde_json::to_string_pretty(&json)? + "\n").into_bytes())?,
        None => messages += &diagnosis_table(&d),
    }
    if let Some(target) = &model_target {
        outputs.stage(target, d.augmented().to_ron().into_bytes())?;
        if let (Target::File(path), None) = (target, &json_target) {
            messages += &format!("augmented model written to {}\n", path.display());
        }
    }
    if let Some(dir) = &args.report {
        let mut report = Report::new(dir, "memid diagnose");
        report.text(&format!("```text\n{}```\n", diagnosis_table(&d)));
        report.fit("baseline", "Baseline model", &d.baseline, 0);
        if let Some(outcome) = d.chosen.and_then(|i| d.candidates[i].outcome.as_ref()) {
            report.fit(
                "augmented",
                &format!("With {}", d.candidates[d.chosen.unwrap_or(0)].label),
                outcome,
                0,
            );
        }
        report.json("diagnosis.json", &json)?;
        let path = report.stage(&mut outputs)?;
        if json_target.is_none() {
            messages += &format!("report written to {}\n", path.display());
        }
    }
    outputs.commit()?;
    print(&messages)
}
