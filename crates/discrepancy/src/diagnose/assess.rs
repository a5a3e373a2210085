//! Everything a diagnosis finds against one reference: where the reference disagrees with the
//! data, the catalog's trials at its fitted model, every candidate scored (steps 1–6 of the
//! module's rule), the force-noise screen (step 9) and the quantization lattices. A diagnosis
//! runs it once, or twice when the mismatch parameters the reference freed one at a time turn
//! out not to be earned beside the chosen effect (module `secondary`).

use super::catalog::{self, Trial};
use super::evidence::{LikelihoodFit, NoiseModel};
use super::quantized::quantization_candidates;
use super::run::{Fitted, Folds, RanOff, Restart};
use super::{Candidate, DiagnoseOptions, Observe, force_noise, score};
use crate::WorkflowError;
use crate::frf::{AppendageScan, InputNoise};
use crate::localise::{Localisation, localise_under};
use mem::Measurement;
use models::Model;
use plant::EffectKind;

/// One reference's assessment: the problem it was made from, its parts named.
pub(super) struct Assess<'a> {
    /// The model file as read: a second start for every trial where the reference ran far from
    /// its values ([`Restart`]).
    pub file: &'a Model,
    /// The reference every candidate is scored against.
    pub reference: &'a Fitted,
    /// Its free parameters, refitted in every candidate too.
    pub free: &'a [String],
    /// The record as read (for the quantization lattice).
    pub raw: &'a Measurement,
    /// The record as fitted (decimated if asked).
    pub data: &'a Measurement,
    /// Its two folds of alternate blocks.
    pub folds: &'a Folds,
    /// The bars a candidate must pass, and the kinds asked for.
    pub options: &'a DiagnoseOptions,
    /// Told of every refit that finishes.
    pub observer: &'a dyn Observe,
}

/// What [`Assess::run`] finds.
pub(super) struct Assessment {
    /// Where the reference disagrees with the data.
    pub localisation: Localisation,
    /// The catalog's trials, in the order of the first candidates.
    pub trials: Vec<Trial>,
    /// One per trial, then the quantization candidates, each with its evidence and verdict so far.
    pub candidates: Vec<Candidate>,
    /// The measurement model every candidate was scored under.
    pub noise: NoiseModel,
    /// The reference's log-likelihood per output under `noise`.
    pub reference_likelihoods: Vec<f64>,
    /// On a forced record, the noise on its recorded inputs.
    pub force_noise: Option<InputNoise>,
    /// The reference's free parameters that ran far from the model file's values, from which
    /// every trial was then refitted too.
    pub ran_off: Vec<RanOff>,
    /// The fit by the likelihood the candidates were scored under, where the noise is coloured
    /// beyond AR(1) (the form tests' refits).
    pub coloured: Option<LikelihoodFit>,
}

impl Assess<'_> {
    /// Localises, scores every trial and screens the candidates.
    ///
    /// # Errors
    /// A record too short for the largest refit, and failures of the lattice's reading.
    pub(super) fn run(&self) -> Result<Assessment, WorkflowError> {
        let Assess { file, reference, free, raw, data, folds, options, observer } = *self;
        // On a forced record, the residual's resonances are read under the noise the reference's
        // residual shows: where the force's noise colours it, its response at the modelled
        // modes is noise, not a mode the model lacks (the seeds of the unmodeled modes).
        let prior =
            data.inputs().map(|_| score::measurement_model(&reference.outcome, &reference.outcome, data));
        let whiten =
            prior.as_ref().map(|n| n.predictors.as_slice()).filter(|p| p.iter().any(Option::is_some));
        let mut localisation = localise_under(data, &reference.outcome, whiten);
        let wanted = |kind: EffectKind| options.only.is_empty() || options.only.contains(&kind);
        // On a forced structure's record, the bodies its residual shows hanging on a coordinate
        // (the appendages' own seeds), where a mode is asked for.
        let bodies = prior.as_ref().filter(|_| wanted(EffectKind::UnmodeledMode));
        if let (Some(noise), Some(model)) = (bodies, reference.outcome.fitted.as_structure()) {
            let first = reference.outcome.first();
            if let Some(predictors) = noise.whitening(noise.rho.len()) {
                localisation.appendages = AppendageScan {
                    model,
                    free,
                    data: &first.data,
                    residual: &first.residual(),
                    noise: &predictors,
                    margin: options.threshold,
                }
                .run();
            }
        }
        // The catalog's trials asked for, made at a model (their starts and bounds scaled by it).
        let trials_at = |model: &Model| -> Vec<Trial> {
            catalog::trials(model, data, &localisation).into_iter().filter(|t| wanted(t.kind)).collect()
        };
        let start = reference.outcome.fitted.clone();
        let trials = trials_at(&start);
        // Every candidate is refitted on half the record: it needs 10 readings a parameter there.
        let parameters = free.len() + trials.iter().map(|t| t.freed.len()).max().unwrap_or(0);
        let residuals = data.n_samples() * data.n_outputs();
        if residuals < 20 * parameters {
            return Err(WorkflowError::TooShort { residuals, parameters, needed: 20 * parameters });
        }
        let ran_off = Restart::ran_off(file, &reference.outcome);
        let restart = (!ran_off.is_empty())
            .then(|| Restart::model(file, &reference.outcome, free))
            .flatten()
            .map(|model| Restart { trials: trials_at(&model), model });
        let score::Scores { mut candidates, noise, reference_likelihoods, coloured } = score::Scoring {
            start: &start,
            restart: restart.as_ref(),
            reference,
            free,
            data,
            folds,
            options,
            observer,
        }
        .score(&trials);
        // On a forced record, an effect acting through the dynamics must remove more than the
        // recorded force's noise could let it take up.
        let force_noise = force_noise::screen(&mut candidates, &trials, &reference.outcome, data);
        // Quantization: a lattice in the raw readings.
        if wanted(EffectKind::SensorQuantization) {
            candidates.extend(quantization_candidates(&start, raw, data, reference, free)?);
        }
        Ok(Assessment {
            localisation,
            trials,
            candidates,
            noise,
            reference_likelihoods,
            force_noise,
            ran_off,
            coloured,
        })
    }
}
