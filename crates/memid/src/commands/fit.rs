//! `memid fit`: the MEM fit of a model to measured data.

use crate::io::{Inputs, Outputs, Target, names, print, read_measurement};
use crate::output::{fit_json, fit_table};
use crate::progress::spinner;
use crate::report::Report;
use anyhow::{Result, bail};
use mem::{Measurement, Safeguard};
use models::{FitRequest, Model, fit_experiments};
use std::path::PathBuf;

/// Fit the free parameters of a model to one or more measured records (free decays, or forced
/// responses whose CSV also holds the model's input columns).
#[derive(clap::Args)]
#[command(allow_negative_numbers = true)]
pub struct Args {
    #[command(flatten)]
    model: super::model_args::ModelArgs,
    /// Measured data (CSV with header t,<outputs>[,<inputs>]); repeat for several experiments
    /// of the same structure, each with its own rate, length and initial state.
    #[arg(long, required = true)]
    data: Vec<PathBuf>,
    /// Parameters to tune, shared by every experiment, comma-separated (default: the model
    /// file's free parameters).
    #[arg(long)]
    free: Option<String>,
    /// Parameters estimated once per experiment (e.g. initial displacements), comma-separated;
    /// reported as NAME@k for experiment k.
    #[arg(long, value_name = "NAMES")]
    per_experiment: Option<String>,
    /// Use only these outputs, comma-separated (e.g. `theta`, as the paper did).
    #[arg(long)]
    outputs: Option<String>,
    /// Keep every R-th sample after an anti-aliasing filter (the paper: 128 Hz → 12.8 Hz is 10).
    #[arg(long, value_name = "R", value_parser = super::at_least_one)]
    decimate: Option<usize>,
    /// The paper's plain Gauss–Newton step, without the Levenberg–Marquardt safeguard.
    #[arg(long)]
    plain: bool,
    /// Unit output weights (Eq. 22 exactly) instead of 1/RMS per output.
    #[arg(long)]
    unweighted: bool,
    /// Skip the check of the sensitivities against central differences at the start.
    #[arg(long)]
    no_derivative_check: bool,
    /// The covariance of the intervals: `auto` (white noise unless the residuals are
    /// correlated, then AR(1)), `white`, or `ar1`.
    #[arg(long, value_enum, default_value_t = CovarianceArg::Auto)]
    covariance: CovarianceArg,
    /// Iteration cap.
    #[arg(long, default_value_t = 100)]
    max_iterations: usize,
    /// Write the fit as JSON to FILE (`-` for standard output; suppresses the table).
    #[arg(long, value_name = "FILE")]
    json: Option<PathBuf>,
    /// Write a report (figures, report.md, fit.json) into DIR.
    #[arg(long, value_name = "DIR")]
    report: Option<PathBuf>,
    /// Write the fitted model as a new RON file.
    #[arg(short = 'o', long = "output")]
    output: Option<PathBuf>,
}

/// `--covariance`.
#[derive(Clone, Copy, Debug, clap::ValueEnum)]
pub enum CovarianceArg {
    /// White noise per output unless the residuals fail a whiteness test, then AR(1).
    Auto,
    /// Independent errors, one variance per output.
    White,
    /// An AR(1) sandwich per output.
    Ar1,
}

impl From<CovarianceArg> for mem::Covariance {
    fn from(c: CovarianceArg) -> Self {
        match c {
            CovarianceArg::Auto => mem::Covariance::Auto,
            CovarianceArg::White => mem::Covariance::White,
            CovarianceArg::Ar1 => mem::Covariance::Ar1,
        }
    }
}

/// Restricts model and data to `outputs` (if given), aligns the data with the model (outputs in
/// its order, its inputs attached) and decimates it.
pub fn prepare(
    model: Model,
    data: Vec<Measurement>,
    outputs: Option<&str>,
    decimate: Option<usize>,
) -> Result<(Model, Vec<Measurement>)> {
    let model = match (outputs, &model) {
        (Some(list), Model::Slewing(m)) => {
            let chosen = names(list);
            let refs: Vec<&str> = chosen.iter().map(|s| s.as_str()).collect();
            Model::Slewing(m.select_outputs(&refs)?)
        }
        (Some(_), Model::Structure(_)) => {
            bail!(
                "--outputs selects sensors of the slewing rig; a structure file measures what its `outputs` list"
            )
        }
        (None, _) => model,
    };
    let data = data
        .iter()
        .map(|d| {
            let aligned = models::align(&model, d)?;
            Ok(match decimate {
                Some(r) => aligned.decimate(r)?,
                None => aligned,
            })
        })
        .collect::<Result<Vec<_>>>()?;
    Ok((model, data))
}

/// Runs the command.
pub fn run(args: Args) -> Result<()> {
    let mut inputs = Inputs::default();
    let model = args.model.load(&mut inputs)?;
    let data = args.data.iter().map(|d| read_measurement(d, &mut inputs)).collect::<Result<Vec<_>>>()?;
    let mut outputs = Outputs::new(&inputs);
    let json_target = args.json.as_deref().map(Target::from_arg);
    let model_target = args.output.as_deref().map(Target::from_arg);
    for target in json_target.iter().chain(&model_target) {
        outputs.check(target)?;
    }
    if let Some(dir) = &args.report {
        outputs.check_directory(dir)?;
    }
    let (model, data) = prepare(model, data, args.outputs.as_deref(), args.decimate)?;
    let free = match &args.free {
        Some(list) => names(list),
        None => model.file_free(),
    };
    let per_experiment = args.per_experiment.as_deref().map(names).unwrap_or_default();
    if free.is_empty() && per_experiment.is_empty() {
        bail!("no parameters to fit: give --free NAME[,NAME...] or mark parameters free in the model file");
    }
    let mut request = FitRequest::new(&free.iter().map(|s| s.as_str()).collect::<Vec<_>>());
    request.per_experiment = per_experiment;
    request.normalize = !args.unweighted;
    request.safeguard = if args.plain { Safeguard::None } else { Safeguard::LevenbergMarquardt };
    if args.no_derivative_check {
        request.derivative_check = mem::DerivativeCheck::Skip;
    }
    request.max_iterations = args.max_iterations;
    request.covariance = args.covariance.into();
    let quiet = json_target.is_some();
    let bar = spinner(&format!("fitting {}", free.join(", ")), quiet);
    let outcome = fit_experiments(&model, &data, &request)?;
    bar.finish_and_clear();
    let json = fit_json(&outcome);
    let mut messages = String::new();
    match &json_target {
        Some(target) => outputs.stage(target, (serde_json::to_string_pretty(&json)? + "\n").into_bytes())?,
        None => {
            for (path, record) in args.data.iter().zip(&data) {
                messages += &format!(
                    "MEM fit of `{}` to {} ({} samples at {:.4} s, outputs {})\n",
                    model.name(),
                    path.display(),
                    record.n_samples(),
                    record.interval(),
                    model.output_names().join(", ")
                );
            }
            messages += &fit_table(&outcome.report);
        }
    }
    if let Some(target) = &model_target {
        outputs.stage(target, outcome.fitted.to_ron().into_bytes())?;
        if let (Target::File(path), false) = (target, quiet) {
            messages += &format!("fitted model written to {}\n", path.display());
        }
    }
    if let Some(dir) = &args.report {
        let mut report = Report::new(dir, "memid fit");
        report.text(&format!("```text\n{}```\n", fit_table(&outcome.report)));
        for (e, experiment) in outcome.experiments.iter().enumerate() {
            let suffix = if outcome.experiments.len() > 1 { format!("_{}", e + 1) } else { String::new() };
            report.measured(&format!("measured{suffix}"), "Measured time histories", &experiment.data);
            report.fit(&format!("fit{suffix}"), "Fit", &outcome, e);
        }
        report.json("fit.json", &json)?;
        let path = report.stage(&mut outputs)?;
        if !quiet {
            messages += &format!("report written to {}\n", path.display());
        }
    }
    outputs.commit()?;
    print(&messages)
}
