//! `memid diagnose`: find where model and data disagree, name the missing effect, add it.

use crate::io::{Inputs, Outputs, Target, names, print, read_measurement};
use crate::output::fit_json;
use crate::progress::progress_bar;
use crate::report::Report;
use anyhow::{Result, bail};
use discrepancy::{DiagnoseOptions, Diagnosis, Observe, Verdict, diagnose_observed};
use serde_json::Value;
use std::path::PathBuf;

/// Find the physical effect a model is missing: baseline fit, localisation, candidate refits
/// scored by one likelihood in sample and on held-out blocks, and the augmented model.
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
    #[arg(long, value_name = "R", value_parser = super::at_least_one)]
    decimate: Option<usize>,
    /// Only try these catalog effects, comma-separated.
    #[arg(long)]
    only: Option<String>,
    /// Held-out log-likelihood gain (nats) an effect needs to be named (default: calibrated on
    /// the study's nulls, docs/diagnose.md).
    #[arg(long, default_value_t = discrepancy::diagnose::DEFAULT_THRESHOLD)]
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

/// The diagnosis as JSON (docs/json.md): the report, with the baseline fit's document.
pub fn diagnosis_json(d: &Diagnosis) -> Result<Value> {
    let mut document = serde_json::to_value(d.report())?;
    if let Value::Object(map) = &mut document {
        map.insert("baseline".into(), fit_json(&d.baseline));
    }
    Ok(document)
}

fn number(x: Option<f64>) -> String {
    x.map_or_else(|| "—".into(), |v| format!("{v:.1}"))
}

/// A fitted value to six significant digits: fixed-point between 10⁻³ and 10⁶, else in
/// exponent form (a driven mode's amplitude per newton, 10⁻⁹ m/N, would print as 0.00000).
fn value(v: f64) -> String {
    if v == 0.0 || !v.is_finite() || (1e-3..1e6).contains(&v.abs()) {
        format!("{v:.5}")
    } else {
        format!("{v:.5e}")
    }
}

/// The scores as a table.
pub fn diagnosis_table(d: &Diagnosis) -> String {
    let mut out = String::from("localisation:\n");
    for f in &d.localisation.findings {
        out += &format!("  - {f}\n");
    }
    out += &format!(
        "\n{:<34} {:>9} {:>9} {:>8}  {:<15} parameters\n",
        "candidate", "ΔBIC", "held-out", "z", "verdict"
    );
    for c in &d.candidates {
        let params = c
            .parameters
            .iter()
            .map(|p| match p.std_error {
                Some(se) => format!("{} = {} ± {:.2e}", p.name, value(p.value), se),
                None => format!("{} = {}", p.name, value(p.value)),
            })
            .collect::<Vec<_>>()
            .join(", ");
        let verdict = match &c.verdict {
            Verdict::Failed(why) => format!("failed: {why}"),
            other => format!("{other:?}"),
        };
        out += &format!(
            "{:<34} {:>9.1} {:>9} {:>8.1}  {:<15} {params}\n",
            c.label,
            c.evidence.delta_bic,
            number(c.evidence.held_out),
            c.evidence.strength_z,
            verdict
        );
    }
    out += &format!(
        "\nbaseline ‖Y_error‖ {:.5e} → augmented {:.5e} ({:.1} % smaller)\n",
        d.baseline_error(),
        d.augmented_error(),
        100.0 * (1.0 - d.augmented_error() / d.baseline_error()),
    );
    for line in d.answer() {
        out += &format!("{line}\n");
    }
    out
}

/// Runs the command.
pub fn run(args: Args) -> Result<()> {
    let mut inputs = Inputs::default();
    let model = args.model.load(&mut inputs)?;
    let data = read_measurement(&args.data, &mut inputs)?;
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
        // Checked here for a one-line error; diagnose decimates itself (the lattice of a
        // quantized sensor is looked for in the raw readings).
        data.decimate(r)?;
    }
    let free = names(&args.free);
    if free.is_empty() {
        bail!("--free needs at least one parameter name");
    }
    if !(args.threshold.is_finite() && args.threshold >= 0.0) {
        bail!("--threshold must be a finite number ≥ 0, got {}", args.threshold);
    }
    let mut options = DiagnoseOptions::new(&free.iter().map(|s| s.as_str()).collect::<Vec<_>>());
    options.threshold = args.threshold;
    options.decimate = args.decimate;
    let known = discrepancy::catalog_kinds();
    for name in args.only.as_deref().map(names).unwrap_or_default() {
        match plant::EffectKind::parse(&name).filter(|k| known.contains(k)) {
            Some(kind) => options.only.push(kind),
            None => bail!(
                "--only: unknown effect `{name}`; the catalog holds {}",
                known.iter().map(|k| k.name()).collect::<Vec<_>>().join(", ")
            ),
        }
    }
    let quiet = json_target == Some(Target::Stdout) || model_target == Some(Target::Stdout);
    let bar = Bar(progress_bar(quiet));
    let d = diagnose_observed(&model, &data, &options, &bar)?;
    bar.0.finish_and_clear();
    let json = diagnosis_json(&d)?;
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

/// The progress bar as a diagnosis observer.
struct Bar(indicatif::ProgressBar);

impl Observe for Bar {
    fn progress(&self, stage: &str, done: usize, total: usize) {
        self.0.set_length(total as u64);
        self.0.set_position(done as u64);
        self.0.set_message(stage.to_string());
    }
}
