//! The mismatch parameters the reference freed one at a time (step 4's secondary ones: a
//! structure's fixed parameters, its masses say), weighed against the effect the evidence chose.
//! (The slewing rig's mass per length is not weighed: tried there, it moved answers of the
//! slewing studies both ways and unsettled three of its tests; docs/diagnose.md.)
//!
//! A mismatch is absorbed before any effect is tried, so that a wrong parameter is not named a
//! missing effect. But a fixed parameter freed where the data determine it takes up part of
//! whatever is missing, and what it cannot take up is all that is left for the effect. On a
//! forced record with the force measured, a sensor that reads 3 % low is taken up by the masses
//! (the response's size and the mode shapes at the two sensors move with them): the three masses
//! gain 1,375 nats, the scale 34 on top of them — and a channel picking up another's signal then
//! explains those 34 as well. Refitted without the masses, the one scale explains more than the
//! three masses did (error 0.2622 against 0.2664), and the masses refitted beside it stay within
//! 1.5 standard errors of the file's values.
//!
//! So the reference is chosen with the effect, by the BIC of the whole account: the reference
//! with them and what the evidence chooses against it, or the reference without them and what
//! it chooses there (every candidate scored anew, so that the effect competes with every other
//! on the same terms). An account's value is its log-likelihood under one measurement model
//! (the first assessment's) less k ln(m)/2 for its k free parameters over m residuals, the
//! penalty of step 1 in nats. The diagnosis starts from the better of the two references alone;
//! the other is assessed too where its account could be the better — where the start's choice,
//! refitted against it, makes the better account, or where the start kept them and chose nothing
//! — and it is kept where its value is the higher and, if the start chose an effect, it chose the
//! same one ([`SecondaryMismatch`]).
//!
//! Where the held-out blocks do not tell the start's choice from another candidate ([`tied`]),
//! that candidate is refitted against the other reference too: the two may predict alike with the
//! secondary parameters free and not without them (a sensor scale on either gauge, with a
//! structure's masses free to take up their common part). Its account there is weighed against
//! the start's, and where it is the better the other reference is assessed, and kept where its
//! evidence chooses that candidate and its account is the better.

use super::answer::{RIVAL_MARGIN, ScaleInPlace, SecondaryMismatch};
use super::assess::Assessment;
use super::catalog::Trial;
use super::evidence::NoiseModel;
use super::run::{self, Fitted};
use super::strength;
use super::{Candidate, Verdict};
use crate::WorkflowError;
use mem::Measurement;
use models::FitOutcome;
use plant::EffectKind;

/// One account of the data: a reference, its free parameters' number, and what the evidence
/// chose against it.
pub(super) struct Account<'a> {
    /// The reference.
    pub reference: &'a Fitted,
    /// Its free parameters' number.
    pub free: usize,
    /// The candidate chosen against it, if any.
    pub chosen: Option<&'a Candidate>,
}

impl Account<'_> {
    /// Its log-likelihood under `noise` (nats), and its parameters' number; `None` for a
    /// quantization lattice, scored under a measurement model of its own, or a choice without a
    /// refit.
    fn value(&self, noise: &NoiseModel) -> Option<(f64, usize)> {
        let total = |o: &FitOutcome| noise.log_likelihoods(&o.first().residual(), None).iter().sum::<f64>();
        match self.chosen {
            None => Some((total(&self.reference.outcome), self.free)),
            Some(c) if c.kind == EffectKind::SensorQuantization => None,
            Some(c) => Some((total(c.outcome.as_ref()?), self.free + c.parameters.len())),
        }
    }

    fn label(&self) -> Option<String> {
        self.chosen.map(|c| c.label.clone())
    }
}

/// The two accounts weighed: `with` against `without`, both under `noise` over `m` residuals.
pub(super) fn weigh(
    parameters: &[String],
    with: &Account<'_>,
    without: &Account<'_>,
    noise: &NoiseModel,
    m: usize,
) -> Option<SecondaryMismatch> {
    let ((l_with, k_with), (l_without, k_without)) = (with.value(noise)?, without.value(noise)?);
    let gain = l_with - l_without;
    let charge = (k_with as f64 - k_without as f64) * (m as f64).ln() / 2.0;
    Some(SecondaryMismatch {
        parameters: parameters.to_vec(),
        with: with.label(),
        without: without.label(),
        gain,
        charge,
        earned: gain > charge,
        kept: gain > charge,
    })
}

/// A candidate refitted against another reference (what the secondary parameters gain beside
/// it is then read from [`weigh`]); `None` when the refit fails.
///
/// It is refitted from two starts, and the smaller error kept: the other reference's fit with
/// the trial's effect added, and the candidate's own fit with the secondary parameters `joined`
/// at the other reference's values where it holds them fixed (freed from there where it frees
/// them). The two accounts are nested: where the other reference frees more, its account then
/// starts where the candidate's ends, and its refit's error is no larger. A strong roof
/// friction refitted from a reference with one floor's mass freed (forced draw 20261363) ran to
/// an error far above the friction's own fit, and the mass was charged −11,806 nats beside it.
fn refitted_from(
    chosen: &Candidate,
    trial: &Trial,
    reference: &Fitted,
    free: &[String],
    joined: &[String],
    data: &Measurement,
) -> Option<Candidate> {
    let from_reference =
        run::fit_trial(&reference.outcome.fitted, trial, free, data, None, 60).map(|f| f.outcome);
    let from_candidate = chosen.model.as_ref().and_then(|model| {
        let mut model = model.clone();
        for name in joined.iter().filter(|n| !free.contains(n)) {
            model.set(name, reference.outcome.fitted.value(name).ok()?).ok()?;
        }
        run::refit_with_effect(&model, trial, free, data, 60).ok()
    });
    let outcome = match from_candidate {
        Some(other) => run::better(from_reference, Ok(other)),
        None => from_reference,
    }
    .ok()?;
    let mut c = chosen.clone();
    c.parameters = strength::effect_parameters(&outcome, trial);
    c.model = Some(outcome.fitted.clone());
    c.outcome = Some(outcome);
    Some(c)
}

/// A reference and its free parameters.
pub(super) type Reference = (Fitted, Vec<String>);

/// The reference a diagnosis is made against, and what it finds there.
pub(super) struct Settled {
    /// The reference.
    pub reference: Reference,
    /// Its assessment.
    pub assessed: Assessment,
    /// The accounts weighed, if any were.
    pub weighed: Option<SecondaryMismatch>,
    /// Whether the reference is the full one (always, where no secondary parameter joined).
    pub kept: bool,
}

/// The problem of settling the reference: the two references, and how each is assessed and
/// its choice made.
pub(super) struct Settle<'a> {
    /// The reference with the secondary parameters.
    pub full: Reference,
    /// The reference without them.
    pub primary: Reference,
    /// The secondary parameters.
    pub joined: &'a [String],
    /// The record as fitted.
    pub data: &'a Measurement,
    /// Assesses a reference.
    pub assess: &'a dyn Fn(&Reference) -> Result<Assessment, WorkflowError>,
    /// The evidence's choice in an assessment, the secondary parameters in its reference or not.
    pub choose: &'a dyn Fn(&Assessment, bool) -> Option<usize>,
    /// The held-out gain (nats) within which two candidates are not told apart ([`tied`]).
    pub threshold: f64,
}

/// The candidates other than the chosen `i` that the held-out blocks do not tell from it — each
/// predicts them within `threshold` of `i`, or better — and that passed the tests of evidence
/// or were set aside as stand-ins against this reference ([`Verdict::LeavesItsOutput`],
/// [`Verdict::Superficial`]: tests of the structure its residual leaves, which the other
/// reference changes), best predictor first; not a lattice, scored under a measurement model of
/// its own.
///
/// Either may be the better account against the other reference. With a structure's masses
/// freed, a sensor scale common to every gauge is a change of the masses and stiffnesses
/// together, so the record sees only the ratio of the gauges' readings: a scale on q1 and one on
/// q3 predict alike, and the gauge chosen by a structure test may be the one the masses must
/// move for. The same scale on the true gauge needs no mass freed (forced draw 20261367,
/// `A_scale_medium_s0`: a −1 % scale on q1 named on q3 with the three masses freed, which gained
/// 251.9 nats beside the scale on q3; 24.3 nats held out on q1 against 23.9 on q3).
fn tied(candidates: &[Candidate], i: usize, threshold: f64) -> Vec<usize> {
    let Some(lead) = candidates[i].evidence.held_out else { return Vec::new() };
    let eligible = |c: &Candidate| {
        matches!(c.verdict, Verdict::Outscored | Verdict::LeavesItsOutput | Verdict::Superficial)
            && c.kind != EffectKind::SensorQuantization
            && c.outcome.is_some()
    };
    let mut found: Vec<(usize, f64)> = candidates
        .iter()
        .enumerate()
        .filter(|&(j, c)| j != i && eligible(c))
        .filter_map(|(j, c)| c.evidence.held_out.filter(|&y| lead - y < threshold).map(|y| (j, y)))
        .collect();
    found.sort_by(|a, b| b.1.total_cmp(&a.1));
    found.into_iter().map(|(j, _)| j).collect()
}

/// The account of reference `r` with `chosen`.
fn account<'a>(r: &'a Reference, chosen: Option<&'a Candidate>) -> Account<'a> {
    Account { reference: &r.0, free: r.1.len(), chosen }
}

impl Settle<'_> {
    /// Starts from the better reference alone by the BIC, and assesses the other only where its
    /// account could be the better: where the start's choice, refitted against it, is, or where
    /// the start kept the secondary parameters and chose nothing (an effect may explain what
    /// they took up). Of two assessments, the better account is kept — where the start chose an
    /// effect, only if the other chose the same one.
    ///
    /// # Errors
    /// Those of an assessment.
    pub(super) fn settle(self) -> Result<Settled, WorkflowError> {
        self.decide().map(|mut s| {
            if let Some(w) = s.weighed.as_mut() {
                w.kept = s.kept;
            }
            s
        })
    }

    fn decide(self) -> Result<Settled, WorkflowError> {
        let Settle { full, primary, joined, data, assess, choose, threshold } = self;
        let m = data.n_samples() * data.n_outputs();
        if joined.is_empty() {
            let assessed = assess(&full)?;
            return Ok(Settled { reference: full, assessed, weighed: None, kept: true });
        }
        let alone = {
            let noise = NoiseModel::of(&full.0.outcome.first().residual());
            weigh(joined, &account(&full, None), &account(&primary, None), &noise, m)
        };
        let with_first = alone.as_ref().is_none_or(|w| w.earned);
        let (start, other) = if with_first { (full, primary) } else { (primary, full) };
        let assessed = assess(&start)?;
        let first = choose(&assessed, with_first);
        // The two accounts, the one with the secondary parameters first.
        let pair = |a: &Account<'_>, b: &Account<'_>, noise: &NoiseModel| {
            if with_first { weigh(joined, a, b, noise, m) } else { weigh(joined, b, a, noise, m) }
        };
        let other_better = |w: &SecondaryMismatch| w.earned != with_first;
        // The start's account (its reference and choice) against candidate j refitted against
        // the other reference.
        let beside_of = |j: usize| {
            let c = refitted_from(
                &assessed.candidates[j],
                assessed.trials.get(j)?,
                &other.0,
                &other.1,
                joined,
                data,
            )?;
            let chosen = first.map(|i| &assessed.candidates[i]);
            pair(&account(&start, chosen), &account(&other, Some(&c)), &assessed.noise)
        };
        let beside = first.and_then(beside_of);
        // The effect the other reference's account is weighed beside: the start's choice, or a
        // candidate the held-out blocks do not tell from it whose account there is the better
        // ([`tied`]).
        let tie = match first {
            Some(i) if !beside.as_ref().is_some_and(other_better) => tied(&assessed.candidates, i, threshold)
                .into_iter()
                .find(|&j| beside_of(j).is_some_and(|w| other_better(&w))),
            _ => None,
        };
        let try_other = match first {
            None => with_first,
            Some(_) => beside.as_ref().is_some_and(other_better) || tie.is_some(),
        };
        let target = tie.or(first);
        let weighed = beside.or(alone);
        if !try_other {
            return Ok(Settled { reference: start, assessed, weighed, kept: with_first });
        }
        let other_assessed = assess(&other)?;
        let second = choose(&other_assessed, !with_first);
        // Where the start chose an effect, the other reference is weighed beside that effect
        // (or the one tied with it) only: an account with another effect was not chosen by the
        // evidence that decides between effects (held out, on one reference), and the likelihood
        // alone does not outrank it.
        let label = |a: &Assessment, i: Option<usize>| i.map(|i| a.candidates[i].label.clone());
        if first.is_some() && label(&assessed, target) != label(&other_assessed, second) {
            return Ok(Settled { reference: start, assessed, weighed, kept: with_first });
        }
        let both = pair(
            &account(&start, first.map(|i| &assessed.candidates[i])),
            &account(&other, second.map(|i| &other_assessed.candidates[i])),
            &assessed.noise,
        );
        Ok(match both {
            Some(w) if other_better(&w) => {
                Settled { reference: other, assessed: other_assessed, weighed: Some(w), kept: !with_first }
            }
            Some(w) => Settled { reference: start, assessed, weighed: Some(w), kept: with_first },
            None => Settled { reference: start, assessed, weighed, kept: with_first },
        })
    }
}

/// The problem of a sensor's scale set in place of the secondary mismatch parameters that
/// joined a slewing reference ([`ScaleInPlace`]), where nothing was named.
pub(super) struct InPlace<'a> {
    /// The candidates scored against the reference with them.
    pub candidates: &'a [Candidate],
    /// Their trials, in the candidates' order.
    pub trials: &'a [Trial],
    /// The reference with them.
    pub full: &'a Fitted,
    /// Its free parameters.
    pub full_free: &'a [String],
    /// The reference without them, and its free parameters.
    pub primary: &'a Reference,
    /// The secondary parameters that joined.
    pub joined: &'a [String],
    /// The measurement model every candidate was scored under.
    pub noise: &'a NoiseModel,
    /// The record as fitted.
    pub data: &'a Measurement,
    /// The strength (standard errors) a scale must be resolved by.
    pub min_strength_z: f64,
}

impl InPlace<'_> {
    /// The sensor scale that, refitted against the reference without the secondary parameters,
    /// explains the record best, if it explains it as well as they do (to within
    /// [`RIVAL_MARGIN`] by the BIC) and is resolved from zero; `None` where none does.
    pub(super) fn find(&self) -> Option<ScaleInPlace> {
        use rayon::prelude::*;
        let InPlace { candidates, trials, full, full_free, primary, joined, noise, data, min_strength_z } =
            *self;
        if joined.is_empty() {
            return None;
        }
        let m = data.n_samples() * data.n_outputs();
        let scales: Vec<usize> = (0..candidates.len().min(trials.len()))
            .filter(|&i| candidates[i].kind == EffectKind::SensorScale && candidates[i].model.is_some())
            .collect();
        scales
            .par_iter()
            .filter_map(|&i| {
                let c = refitted_from(&candidates[i], &trials[i], &primary.0, &primary.1, joined, data)?;
                let value = c.parameters.first()?.clone();
                let resolved =
                    value.std_error.is_some_and(|s| s > 0.0 && value.value.abs() >= min_strength_z * s);
                // The two accounts weighed as the secondary parameters are: the scale's account
                // over the reference's is what the joined parameters fall short of their charge.
                let with = Account { reference: full, free: full_free.len(), chosen: None };
                let w = weigh(joined, &with, &account(primary, Some(&c)), noise, m)?;
                let gain = w.charge - w.gain;
                (resolved && gain >= -RIVAL_MARGIN).then(|| ScaleInPlace {
                    parameters: joined.to_vec(),
                    scale: c.label.clone(),
                    value,
                    gain,
                })
            })
            .collect::<Vec<_>>()
            .into_iter()
            .max_by(|a, b| a.gain.total_cmp(&b.gain))
    }
}
