//! The refits behind the evidence: a candidate's full refit, and the held-out refits of the
//! baseline and the shortlist on each fold, with and without the model's own parameters free.

use super::catalog::{Trial, freed};
use super::evidence::{block_length, folds, log_likelihoods};
use super::{Candidate, DiagnoseOptions, EffectParameter};
use crate::WorkflowError;
use crate::stats::ljung_box;
use mem::Measurement;
use models::{FitOutcome, FitRequest, Model};
use plant::{ParamId, SlewingModel};

/// The ODE tolerance of a diagnosis' refits: 10⁻⁷ of the states, far below the noise of any
/// record, and half the work of the fitting default.
const ODE_TOLERANCE: f64 = 1e-7;

/// Iterations of a held-out refit, which starts from the full refit's values.
const HELD_OUT_ITERATIONS: usize = 20;

/// A fit and its per-output log-likelihoods on every sample.
pub struct Fitted {
    /// The fit.
    pub outcome: FitOutcome,
    /// Per output, the profiled AR(1) log-likelihood of its residual.
    pub likelihoods: Vec<f64>,
}

impl Fitted {
    /// Fits `model` with `free` to every sample of `data`.
    pub fn full(
        model: &Model,
        data: &Measurement,
        free: &[String],
        iterations: usize,
    ) -> Result<Self, WorkflowError> {
        let outcome = refit(model, data, free, None, iterations)?;
        let likelihoods = log_likelihoods(&outcome.first().residual(), None);
        Ok(Self { outcome, likelihoods })
    }
}

/// The two folds of a record: alternate blocks of about a second.
pub struct Folds {
    weights: [Vec<f64>; 2],
}

impl Folds {
    /// The folds of `data`.
    pub fn new(data: &Measurement) -> Self {
        Self { weights: folds(data.n_samples(), block_length(data.n_samples(), data.interval())) }
    }
}

pub(super) fn refit(
    model: &Model,
    data: &Measurement,
    free: &[String],
    sample_weights: Option<&[f64]>,
    iterations: usize,
) -> Result<FitOutcome, WorkflowError> {
    let t0 = std::time::Instant::now();
    let refs: Vec<&str> = free.iter().map(|s| s.as_str()).collect();
    let mut request = FitRequest::new(&refs);
    request.max_iterations = iterations;
    request.derivative_check = mem::DerivativeCheck::Skip;
    request.ode_tolerance = Some(ODE_TOLERANCE);
    if let Some(w) = sample_weights {
        request.sample_weights = vec![w.to_vec()];
    }
    let r = models::fit(model, data, &request);
    if std::env::var("MEMID_DEBUG").is_ok() {
        let effects: Vec<String> = model
            .as_slewing()
            .map(|m| m.effects().iter().map(|e| e.kind().name().to_string()).collect())
            .unwrap_or_default();
        eprintln!(
            "fit {:?} free {:?} weights {} -> {:.2}s iters {:?}",
            effects,
            free,
            sample_weights.is_some(),
            t0.elapsed().as_secs_f64(),
            r.as_ref().map(|o| o.report.iterations).map_err(|e| e.to_string())
        );
    }
    Ok(r?)
}

/// The model of a trial: `start` with the effect and its bounds.
fn with_effect(start: &SlewingModel, trial: &Trial) -> Result<SlewingModel, WorkflowError> {
    let mut model = start.clone();
    model.add_effect(trial.effect.clone())?;
    for (id, b) in &trial.bounds {
        model.set_bounds(*id, *b);
    }
    Ok(model)
}

fn names(free: &[String], extra: impl IntoIterator<Item = String>) -> Vec<String> {
    let mut out = free.to_vec();
    for name in extra {
        if !out.contains(&name) {
            out.push(name);
        }
    }
    out
}

/// Refits `start` with the trial's effect on every sample (or on the weighted ones).
pub fn fit_trial(
    start: &SlewingModel,
    trial: &Trial,
    free: &[String],
    data: &Measurement,
    sample_weights: Option<&[f64]>,
    iterations: usize,
) -> Result<Fitted, WorkflowError> {
    let model = with_effect(start, trial)?;
    let free = names(free, freed(trial).into_iter().map(|id| id.name()));
    let outcome = refit(&Model::Slewing(model), data, &free, sample_weights, iterations)?;
    let likelihoods = log_likelihoods(&outcome.first().residual(), None);
    Ok(Fitted { outcome, likelihoods })
}

/// The effect's parameters as fitted.
pub fn effect_parameters(outcome: &FitOutcome, trial: &Trial) -> Vec<EffectParameter> {
    freed(trial)
        .into_iter()
        .filter_map(|id| {
            let name = id.name();
            let i = outcome.report.names.iter().position(|n| *n == name)?;
            Some(EffectParameter {
                name,
                value: outcome.report.parameters[i],
                std_error: outcome.report.std_error(i),
            })
        })
        .collect()
}

/// The smallest distance of the effect's strength parameters from "no effect", in standard
/// errors (0 where a standard error is not determined).
pub fn strength_z(outcome: &FitOutcome, trial: &Trial) -> f64 {
    let model = outcome.fitted.as_slewing().expect("diagnose fits slewing models");
    trial
        .strength
        .iter()
        .map(|s| {
            let name = s.id().name();
            outcome.report.names.iter().position(|n| *n == name).map_or(0.0, |i| {
                match outcome.report.std_error(i) {
                    Some(se) if se > 0.0 => s.z(outcome.report.parameters[i], se, model),
                    _ => 0.0,
                }
            })
        })
        .fold(f64::INFINITY, f64::min)
        .min(1e6)
}

/// The smallest Ljung–Box p-value (lags 1–20) of the fit's residuals over the outputs.
pub fn whiteness(outcome: &FitOutcome) -> f64 {
    let residual = outcome.first().residual();
    (0..residual.ncols())
        .map(|o| ljung_box(&(0..residual.nrows()).map(|k| residual[(k, o)]).collect::<Vec<_>>(), 20).1)
        .fold(1.0, f64::min)
}

/// The model's own linear parameters a mismatch would live in, that the user did not free:
/// the modal damping of every flexible mode, the hub inertia and the beam's stiffness.
pub fn mismatch_parameters(model: &SlewingModel, free: &[String]) -> Vec<String> {
    mismatch_ids(model).into_iter().map(|(id, _)| id.name()).filter(|n| !free.contains(n)).collect()
}

/// The mismatch parameters with the range a mismatch is looked for in: a fifth to five times a
/// modal damping, half to twice the hub inertia, ±30 % of the beam's stiffness (wider ranges
/// only let a refit wander into stiff, slow and implausible models).
fn mismatch_ids(model: &SlewingModel) -> Vec<(ParamId, (f64, f64))> {
    let around = |id: ParamId, low: f64, high: f64| {
        let v = model.get(id);
        (id, if v > 0.0 { (low * v, high * v) } else { (0.0, 1.0) })
    };
    (1..=model.n_modes())
        .map(|i| around(ParamId::ModalDamping(i), 0.2, 5.0))
        .chain([around(ParamId::HubInertia, 0.5, 2.0), around(ParamId::EiOverRho, 0.7, 1.3)])
        .collect()
}

/// `model` with the mismatch parameters' ranges.
fn with_mismatch_bounds(mut model: SlewingModel) -> SlewingModel {
    for (id, b) in mismatch_ids(&model) {
        model.set_bounds(id, b);
    }
    model
}

/// A held-out refit to run.
#[derive(Clone, Debug, PartialEq)]
pub enum Job {
    /// The baseline (with the mismatch parameters free if `extended`).
    Baseline {
        /// Mismatch parameters free.
        extended: bool,
    },
    /// Candidate `index` (likewise).
    Candidate {
        /// Index into the candidates (and trials).
        index: usize,
        /// Mismatch parameters free.
        extended: bool,
    },
}

/// Fits a job on fold `fold` and returns the per-output log-likelihoods of its prediction of
/// the other fold.
#[allow(clippy::too_many_arguments)]
pub fn held_out(
    job: &Job,
    fold: usize,
    folds: &Folds,
    trials: &[Trial],
    candidates: &[Candidate],
    start: &SlewingModel,
    options: &DiagnoseOptions,
    mismatch: &[String],
    data: &Measurement,
) -> Result<Vec<f64>, WorkflowError> {
    let train = &folds.weights[fold];
    let test = &folds.weights[1 - fold];
    let extra = |extended: bool| if extended { mismatch.to_vec() } else { Vec::new() };
    let outcome = match job {
        Job::Baseline { extended } => {
            let free = names(&options.free, extra(*extended));
            refit(
                &Model::Slewing(with_mismatch_bounds(start.clone())),
                data,
                &free,
                Some(train),
                HELD_OUT_ITERATIONS,
            )?
        }
        Job::Candidate { index, extended } => {
            let trial = &trials[*index];
            // Start from the candidate's full refit (its effect in place, bounds kept).
            let from = candidates[*index].model.as_ref().map_or_else(
                || with_effect(start, trial),
                |m| {
                    let mut m = m.clone();
                    for (id, b) in &trial.bounds {
                        m.set_bounds(*id, *b);
                    }
                    Ok(m)
                },
            )?;
            let free =
                names(&options.free, freed(trial).into_iter().map(|id| id.name()).chain(extra(*extended)));
            refit(&Model::Slewing(with_mismatch_bounds(from)), data, &free, Some(train), HELD_OUT_ITERATIONS)?
        }
    };
    Ok(log_likelihoods(&outcome.first().residual(), Some(test)))
}
