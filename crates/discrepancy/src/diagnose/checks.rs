//! The named effect set against what else could explain it (steps 5–8 of the module's list):
//! the stand-ins that predict better, the model's own parameters, the spring's form terms, a
//! friction's static peak and a fading servo, a law in time, a damping distributed otherwise, a
//! saturation's knee and an appendage's floor. Each test that the effect fails names nothing.

use super::catalog::Trial;
use super::evidence::{self, LikelihoodFit, NoiseModel};
use super::named::{self, choose, polish, scale_equivalents_of};
use super::run::Fitted;
use super::{
    Candidate, DampingRival, DiagnoseOptions, Rival, SaturationKnee, ScaleChoice, SpringForm, SpringTerm,
    StaticPeak, TimeLaw, Verdict,
};
use super::{crosstalk, damping, friction, lag, rivals, saturation, spring, time_law};
use mem::Measurement;
use models::{FitOutcome, Model};
use plant::EffectKind;

/// The problem: a reference, its candidates' trials, and what the named effect is weighed by.
pub(super) struct Checks<'a> {
    /// The user's model file.
    pub model: &'a Model,
    /// The bars.
    pub options: &'a DiagnoseOptions,
    /// The mismatch parameters in the reference.
    pub mismatch: &'a [String],
    /// The reference.
    pub reference: &'a Fitted,
    /// Its free parameters.
    pub free: &'a [String],
    /// The trials, in the candidates' order.
    pub trials: &'a [Trial],
    /// The record as fitted.
    pub data: &'a Measurement,
    /// The measurement model.
    pub noise: &'a NoiseModel,
    /// The reference's log-likelihood per output under `noise`.
    pub reference_likelihoods: &'a [f64],
    /// The fit by that likelihood where the noise is coloured beyond AR(1)
    /// ([`NoiseModel::coloured_fit`]).
    pub coloured: Option<&'a LikelihoodFit>,
}

/// What the checks found, each where it was made.
#[derive(Default)]
pub(super) struct Found {
    /// The named candidate's index, if one stands.
    pub chosen: Option<usize>,
    /// A named scale's exact equivalents.
    pub scale_equivalents: Vec<String>,
    /// Between two scales that fit alike, the one chosen.
    pub scale_choice: Option<ScaleChoice>,
    /// The model's parameters set against the named effect.
    pub rivals: Vec<Rival>,
    /// A named spring's form terms.
    pub spring: Option<SpringForm>,
    /// A law in time set against a structure's force.
    pub time_law: Option<TimeLaw>,
    /// Linear dampers set against a structure's mode.
    pub damping: Option<DampingRival>,
    /// A named friction's static peak.
    pub static_peak: Option<StaticPeak>,
    /// A servo that fades beside a named friction.
    pub fading: Option<SpringTerm>,
    /// A named saturation's knee.
    pub saturation_knee: Option<SaturationKnee>,
}

impl Checks<'_> {
    /// Chooses the effect the evidence names among `candidates`, sets it against every rival
    /// account, and records each verdict on the candidates.
    pub(super) fn run(&self, candidates: &mut [Candidate]) -> Found {
        let mut found = Found::default();
        found.chosen = self.chosen(candidates, &mut found);
        // The equivalents belong to a named scale only.
        if found.chosen.is_none_or(|i| candidates[i].kind != EffectKind::SensorScale) {
            found.scale_equivalents.clear();
            found.scale_choice = None;
        }
        found
    }

    fn chosen(&self, candidates: &mut [Candidate], found: &mut Found) -> Option<usize> {
        let Checks {
            model,
            options,
            mismatch,
            reference,
            free,
            trials,
            data,
            noise,
            reference_likelihoods,
            coloured,
        } = *self;
        let tolerance = options.file_tolerance;
        let likelihoods = |outcome: &FitOutcome| noise.log_likelihoods(&outcome.first().residual(), None);
        let mut i = choose(candidates, options.threshold)?;
        // Two sensor scales that fit alike: the one that asks less of the model file.
        if let Some((j, choice)) =
            rivals::closer_to_file(candidates, i, model, mismatch, tolerance, options.threshold)
        {
            i = j;
            found.scale_choice = Some(choice);
        }
        candidates[i].verdict = Verdict::Named;
        // The named effect must predict what is missing at least as well as any stand-in does.
        if named::outpredicted_by(candidates, i, options.threshold).is_some() {
            candidates[i].verdict = Verdict::Outpredicted;
            return None;
        }
        let Some(trial) = trials.get(i) else { return Some(i) };
        polish(&mut candidates[i], trial, free, data);
        if let (EffectKind::SensorScale, Some(output), Some(fitted)) =
            (trial.kind, trial.output, candidates[i].model.as_ref())
        {
            let refitted: Vec<String> = free.iter().chain(&trial.freed).cloned().collect();
            found.scale_equivalents = scale_equivalents_of(fitted, data, output, &refitted);
        }
        // A named effect is set against the model's own parameters it could stand for: if one
        // of them, refitted alone, explains the data as well (in sample, to within a nat), a
        // parameter mismatch is the simpler answer and nothing is named. A sensor scale's exact
        // equivalents (the parameters that scale its output alone) are reported as such and not
        // tried.
        let search = rivals::Rivals {
            reference: &reference.outcome.fitted,
            free,
            exclude: &found.scale_equivalents,
            also: crosstalk::screened(&reference.outcome, noise, trial.output)
                .into_iter()
                .chain(lag::screened(&reference.outcome, noise, data.interval()))
                .collect(),
            to_match: candidates[i].evidence.in_sample - options.threshold,
            file: model,
            mismatch,
            effect: rivals::Account::of_scale(&candidates[i], model, mismatch, tolerance),
            tolerance,
        };
        found.rivals = search.find(data, |o| evidence::gain(&likelihoods(o), reference_likelihoods));
        if found.rivals.iter().any(|r| r.unseats(candidates[i].evidence.in_sample)) {
            candidates[i].verdict = Verdict::MatchedByMismatch;
            return None;
        }
        // A symmetric spring whose data demand an asymmetric part (a one-sided force) or a
        // stiffness that changes with time (a degradation): physics outside the catalog.
        let gain = |o: &FitOutcome| evidence::gain(&likelihoods(o), reference_likelihoods);
        let test = named::FormTest {
            reference: &reference.outcome.fitted,
            free,
            data,
            threshold: options.threshold,
            gain: &gain,
            under: coloured,
        };
        found.spring = spring::form(&candidates[i], trial, &test);
        if let Some(form) = &found.spring {
            let demanded = [
                (form.asymmetric.as_ref(), Verdict::Asymmetric),
                (Some(&form.changing), Verdict::TimeVarying),
            ]
            .into_iter()
            .filter_map(|(term, verdict)| term.filter(|t| t.demanded).map(|t| (t, verdict)))
            .max_by(|(a, _), (b, _)| a.gain.total_cmp(&b.gain));
            if let Some((_, verdict)) = demanded {
                candidates[i].verdict = verdict;
                return None;
            }
        }
        // A named dry friction: does it stick (a static peak above its sliding level)?
        found.static_peak = friction::static_peak(&mut candidates[i], trial, &test);
        // And, in that form, does a servo that loses stiffness with time explain it (a torque
        // constant that fades, outside the catalog)?
        found.fading = friction::fading(&candidates[i], trial, &test);
        if found.fading.as_ref().is_some_and(|t| t.demanded) {
            candidates[i].verdict = Verdict::TimeVarying;
            return None;
        }
        // A structure force set against a stiffness that changes with time by a law of its
        // own, at any coordinate: it must explain the record better (module `time_law`).
        let effect_gain = match &found.spring {
            Some(form) => Some(form.gain),
            None => candidates[i].outcome.as_ref().map(&gain),
        };
        found.time_law = effect_gain.and_then(|g| time_law::rival(trial, &test, g));
        if found.time_law.as_ref().is_some_and(|law| law.as_well) {
            candidates[i].verdict = Verdict::TimeVarying;
            return None;
        }
        // A structure's mode set against the model's damping distributed otherwise: a linear
        // damper at every coordinate (module `damping`).
        found.damping = effect_gain.and_then(|g| damping::rival(trial, &test, g));
        if found.damping.as_ref().is_some_and(|d| d.as_well) {
            candidates[i].verdict = Verdict::DampingDistribution;
            return None;
        }
        // A named saturation: is its limit softer than the catalog's limiter?
        found.saturation_knee = saturation::knee(&mut candidates[i], trial, &test);
        // A named appendage's floor is claimed only where the data tell it from the same mode
        // at another floor.
        if let Some(label) = named::floor_untold(candidates, i, options.threshold) {
            candidates[i].label = label;
        }
        Some(i)
    }
}
