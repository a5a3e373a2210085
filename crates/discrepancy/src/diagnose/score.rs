//! Steps 1–6 of the rule (the module's doc): every trial refitted on the whole record and
//! scored in sample under the measurement model ([`evidence`]), then the shortlist, best
//! in-sample evidence first, refitted on each fold and scored on the other.

use super::answer::last_error;
use super::catalog::Trial;
use super::evidence::{self, LikelihoodFit, NoiseModel, Predictor};
use super::force_noise;
use super::options::MIN_STRUCTURE;
use super::run::{self, Fitted, Folds};
use super::strength;
use super::{
    Candidate, DiagnoseOptions, Evidence, MIN_SENSOR_STRUCTURE_EXPLAINED, Observe, Verdict, failed, schedule,
    superficial,
};
use crate::WorkflowError;
use crate::frf::InputNoise;
use faer::Mat;
use mem::Measurement;
use models::{FitOutcome, Model};

/// Per-sample held-out log-likelihoods of one refit, or why it failed.
type Scored = Result<Vec<f64>, WorkflowError>;

/// The scoring of a catalog's trials against a reference: one problem, its parts named.
pub(super) struct Scoring<'a> {
    /// The reference's fitted model, to which each trial adds its effect.
    pub start: &'a Model,
    /// Where the reference ran far from the model file: the file's values, from which each
    /// trial is refitted too (the better refit is kept).
    pub restart: Option<&'a run::Restart>,
    /// The reference fit every candidate is compared with.
    pub reference: &'a Fitted,
    /// The reference's free parameters, refitted in every candidate too.
    pub free: &'a [String],
    /// The record as fitted (decimated if asked).
    pub data: &'a Measurement,
    /// Its two folds of alternate blocks.
    pub folds: &'a Folds,
    /// The bars a candidate must pass.
    pub options: &'a DiagnoseOptions,
    /// Told of every refit that finishes.
    pub observer: &'a dyn Observe,
}

/// The candidates as scored, and the measurement model they were scored under.
pub(super) struct Scores {
    /// One per trial, in the trials' order, each with its evidence and verdict so far.
    pub candidates: Vec<Candidate>,
    /// ρ per output, from the best-fitting model's residual.
    pub noise: NoiseModel,
    /// The reference's log-likelihood per output under `noise`.
    pub reference_likelihoods: Vec<f64>,
    /// The fit that maximises that likelihood where the noise is coloured beyond AR(1)
    /// ([`NoiseModel::coloured_fit`]): the form tests' refits.
    pub coloured: Option<LikelihoodFit>,
}

impl Scoring<'_> {
    /// Refits and scores every trial.
    pub(super) fn score(&self, trials: &[Trial]) -> Scores {
        let Scoring { start, restart, reference, free: reference_free, data, folds, options, observer } =
            *self;
        let total = trials.len();
        let again: Vec<Option<usize>> =
            restart.map_or_else(|| vec![None; trials.len()], |r| r.matching(trials));
        let done = std::sync::atomic::AtomicUsize::new(0);
        // The costliest refits start first, so that the workers finish together.
        // One refit of each trial's model; the full refit makes one per start, a held-out refit one.
        let refit: Vec<usize> = trials.iter().map(|trial| schedule::trial_refit_cost(start, trial)).collect();
        let indices: Vec<usize> = (0..trials.len()).collect();
        let fits: Vec<Result<Fitted, WorkflowError>> = schedule::largest_first(
            &indices,
            |&i| refit[i] * (1 + trials[i].alternatives.len()) * (1 + usize::from(again[i].is_some())),
            |&i| {
                let trial = &trials[i];
                let mut result = run::fit_trial(start, trial, reference_free, data, None, 60);
                if let (Some(r), Some(j)) = (restart, again[i]) {
                    let other = run::fit_trial(&r.model, &r.trials[j], reference_free, data, None, 60);
                    result = run::better(result.map(|f| f.outcome), other.map(|f| f.outcome))
                        .map(|outcome| Fitted { outcome });
                }
                observer.progress(
                    "candidates",
                    done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1,
                    total,
                );
                result
            },
        );
        // The measurement model: ρ per output from the best-fitting model's residual.
        let best = fits
            .iter()
            .filter_map(|f| f.as_ref().ok())
            .map(|f| &f.outcome)
            .chain(std::iter::once(&reference.outcome))
            .min_by(|a, b| last_error(a).total_cmp(&last_error(b)))
            .expect("the reference is there");
        let (mut best, mut noise) = (best, measurement_model(best, &reference.outcome, data));
        // On a forced record the noise is read again from the model its own likelihood puts
        // first, if that is another: the best-fitting refit may be one that matched part of the
        // force's noise, and read from it that noise looks smaller than it is.
        if !noise.predictors.is_empty() {
            let outcomes: Vec<&FitOutcome> =
                fits.iter().filter_map(|f| f.as_ref().ok()).map(|f| &f.outcome).collect();
            let total =
                |o: &FitOutcome| noise.log_likelihoods(&o.first().residual(), None).iter().sum::<f64>();
            let first = outcomes
                .iter()
                .copied()
                .chain(std::iter::once(&reference.outcome))
                .max_by(|a, b| total(a).total_cmp(&total(b)))
                .expect("the reference is there");
            if !std::ptr::eq(first, best) {
                (best, noise) = (first, measurement_model(first, &reference.outcome, data));
            }
        }
        let under = noise.fit_weights(&best.first().residual());
        let coloured = noise.coloured_fit(&best.first().residual());
        let likelihoods = |outcome: &FitOutcome| noise.log_likelihoods(&outcome.first().residual(), None);
        let reference_likelihoods = likelihoods(&reference.outcome);
        let m = (data.n_samples() * data.n_outputs()) as f64;
        // The structure beyond the measurement model's own prediction.
        let beyond = |residual: &Mat<f64>| evidence::structure_per_output(residual, &noise);
        let reference_per_output = beyond(&reference.outcome.first().residual());
        let reference_structure: f64 = reference_per_output.iter().sum();
        // Under MIN_STRUCTURE a residual is noise, the reference's or the refit's: a refit that
        // leaves no more than that explains all the structure there is.
        let share = |left: f64, held: f64| {
            if held > MIN_STRUCTURE && left > MIN_STRUCTURE { 1.0 - left / held } else { 1.0 }
        };
        // On a forced record with noise on its force, a sensor effect's share on its own output
        // is of the structure beyond the better of that noise model and the one read again from
        // each residual itself, the reference's and the refit's ([`own_structure`]).
        let reference_on_output =
            own_structure(&noise, &reference.outcome, &reference.outcome, data, &reference_per_output);
        // The share of the structure a refit removes, in all and on a sensor effect's own output
        // (one AR fit per output serves both).
        let explained = |outcome: &FitOutcome, output: Option<usize>| {
            let left = beyond(&outcome.first().residual());
            let on = |o: usize| {
                share(
                    own_structure(&noise, outcome, &reference.outcome, data, &left)
                        .get(o)
                        .copied()
                        .unwrap_or(0.0),
                    reference_on_output.get(o).copied().unwrap_or(0.0),
                )
            };
            (share(left.iter().sum(), reference_structure), output.map(on), left.iter().sum::<f64>())
        };
        let mut candidates: Vec<Candidate> = trials
            .iter()
            .zip(fits)
            .map(|(trial, fit)| match fit {
                Ok(fit) => {
                    let in_sample = evidence::gain(&likelihoods(&fit.outcome), &reference_likelihoods);
                    let parameters = strength::effect_parameters(&fit.outcome, trial);
                    // A swap trades the replaced effect's parameters for its own.
                    let added =
                        parameters.len() - usize::from(trial.replaces.is_some()).min(parameters.len());
                    let (structure_explained, sensor_structure_explained, structure_left) =
                        explained(&fit.outcome, trial.output);
                    let evidence = Evidence {
                        in_sample,
                        delta_bic: -2.0 * in_sample + added as f64 * m.ln(),
                        held_out: None,
                        strength_z: strength::strength_z(&fit.outcome, trial),
                        reduction: 1.0 - last_error(&fit.outcome) / last_error(&reference.outcome),
                        whiteness_p: strength::whiteness(&fit.outcome),
                        structure_explained,
                        structure_held: reference_structure,
                        structure_left,
                        sensor_structure_explained,
                    };
                    let verdict = if evidence.delta_bic >= -options.bic_threshold {
                        Verdict::Weak
                    } else if evidence.strength_z < options.min_strength_z {
                        Verdict::Unresolved
                    } else {
                        Verdict::NotShortlisted
                    };
                    Candidate {
                        kind: trial.kind,
                        sensor: trial.sensor,
                        output: trial.output,
                        label: trial.label_at(&fit.outcome),
                        replaces: trial.replaces,
                        parameters,
                        evidence,
                        lattice: None,
                        verdict,
                        model: Some(fit.outcome.fitted.clone()),
                        outcome: Some(fit.outcome),
                    }
                }
                Err(e) => failed(trial, e.to_string()),
            })
            .collect();
        // The shortlist, best in-sample evidence first, is scored out of sample.
        let mut order: Vec<usize> =
            (0..candidates.len()).filter(|&i| candidates[i].verdict == Verdict::NotShortlisted).collect();
        order.sort_by(|&a, &b| candidates[a].evidence.delta_bic.total_cmp(&candidates[b].evidence.delta_bic));
        order.truncate(options.shortlist);
        if !order.is_empty() {
            let jobs: Vec<(Option<usize>, usize)> = std::iter::once(None)
                .chain(order.iter().map(|&i| Some(i)))
                .flat_map(|job| [0, 1].map(|fold| (job, fold)))
                .collect();
            let total = jobs.len();
            let done = std::sync::atomic::AtomicUsize::new(0);
            let reference_cost = schedule::refit_cost(start);
            let scores: Vec<(Option<usize>, Scored)> = schedule::largest_first(
                &jobs,
                |(job, _)| job.map_or(reference_cost, |i| refit[i]),
                |&(job, fold)| {
                    let from = match job {
                        None => run::HeldOut::Reference(start),
                        Some(i) => run::HeldOut::Candidate(&trials[i], candidates[i].model.as_ref()),
                    };
                    let test = &folds.weights[1 - fold];
                    let result = run::held_out(from, fold, folds, reference_free, data, &under)
                        .map(|residual| noise.log_likelihoods(&residual, Some(test)));
                    observer.progress(
                        "held-out",
                        done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1,
                        total,
                    );
                    (job, result)
                },
            );
            let sum = |wanted: Option<usize>| -> Option<Vec<f64>> {
                let parts: Vec<&Vec<f64>> = scores
                    .iter()
                    .filter(|(job, _)| *job == wanted)
                    .map(|(_, r)| r.as_ref().ok())
                    .collect::<Option<Vec<_>>>()?;
                (parts.len() == 2).then(|| parts[0].iter().zip(parts[1]).map(|(a, b)| a + b).collect())
            };
            let base = sum(None);
            for &i in &order {
                let c = &mut candidates[i];
                c.evidence.held_out =
                    sum(Some(i)).as_ref().zip(base.as_ref()).map(|(c, b)| evidence::gain(c, b));
                c.verdict = match c.evidence.held_out {
                    None => Verdict::Failed("a held-out refit failed".into()),
                    Some(h) if h < options.threshold => Verdict::NotPredictive,
                    _ if superficial(c.kind, &c.evidence) => Verdict::Superficial,
                    _ if c
                        .evidence
                        .sensor_structure_explained
                        .is_some_and(|s| s < MIN_SENSOR_STRUCTURE_EXPLAINED) =>
                    {
                        Verdict::LeavesItsOutput
                    }
                    _ => Verdict::Outscored,
                };
            }
        }
        Scores { candidates, noise, reference_likelihoods, coloured }
    }
}

/// Per output, the structure in `outcome`'s residual beyond the better, for that output, of the
/// measurement model `noise` (whose structure is `shared`) and the same model with its
/// force-noise predictors read again from this residual ([`force_noise::read`]); `shared` where
/// `noise` has no predictors (no noise on a recorded force) or the read fails.
///
/// A sensor's offset or drift adds to its readings what the response does not, and where it is
/// what is missing it leaves its output unstructured but for the noise
/// ([`MIN_SENSOR_STRUCTURE_EXPLAINED`]). The force's noise is read once, from the model the
/// likelihood puts first, and that read can fall short of what another residual holds (chirps
/// read 0.11–0.6 % against a truth of 1 % on draw 20261316): the noise's response the read
/// misses is then counted as structure the sensor effect leaves. Read from the residual the
/// effect leaves — as the force-noise screen reads it ([`force_noise::screen`]) — it is not.
fn own_structure(
    noise: &NoiseModel,
    outcome: &FitOutcome,
    reference: &FitOutcome,
    data: &Measurement,
    shared: &[f64],
) -> Vec<f64> {
    let read = (!noise.predictors.is_empty()).then(|| force_noise::read(outcome, reference, data)).flatten();
    let Some(read) = read else { return shared.to_vec() };
    let residual = outcome.first().residual();
    let own = with_force_noise(noise.clone(), &read, &residual);
    let again = evidence::structure_per_output(&residual, &own);
    shared.iter().enumerate().map(|(o, &here)| again.get(o).map_or(here, |&s| s.min(here))).collect()
}

/// The measurement model read from one fit's residual: ρ per output, and on a forced record the
/// predictors of the noise its recorded force's noise leaves ([`force_noise::predictors`]).
pub(super) fn measurement_model(best: &FitOutcome, reference: &FitOutcome, data: &Measurement) -> NoiseModel {
    let residual = best.first().residual();
    let noise = NoiseModel::of(&residual);
    match force_noise::read(best, reference, data) {
        Some(read) => with_force_noise(noise, &read, &residual),
        None => noise,
    }
}

/// `noise` (its ρ_o kept) with the predictors of the noise the force's noise `read` leaves in
/// `residual` ([`force_noise::predictors`]) and their orders.
fn with_force_noise(mut noise: NoiseModel, read: &InputNoise, residual: &Mat<f64>) -> NoiseModel {
    noise.predictors = force_noise::predictors(read, &noise, residual);
    noise.predictor_order = noise.predictors.iter().map(|p| p.as_ref().map_or(0, Predictor::order)).collect();
    noise
}
