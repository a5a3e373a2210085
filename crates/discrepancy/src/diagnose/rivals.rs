//! The rivals of a named effect ([`Rivals`]): the model's own parameters, each refitted alone
//! in its place, that explain the record as well (step 7 of [module `diagnose`](super)); and,
//! for a named sensor scale, how far each account moves the model file's values ([`Account`],
//! [`Departures`]).

use super::answer::{Departures, Moved, ScaleChoice};
use super::{Candidate, Rival, mismatch, run};
use mem::Measurement;
use models::{FitOutcome, Model};
use plant::EffectKind;
use rayon::prelude::*;

/// The search for [`Rival`]s of a named effect: each of the model's own parameters the
/// reference did not refit ([`mismatch::rival_parameters`]) is refitted alone beside the reference's,
/// from the reference, in its range, to the fitter's own convergence
/// ([`run::Precision::Optimum`]); those whose gain reaches `to_match` (the effect's in-sample
/// gain less the held-out threshold; set against a sensor scale, with what the scale's account
/// asks of the model file beyond theirs added, [`Departures`]) and that the data determine inside
/// their range explain the record as well as the effect. A sensor's calibration and the structure's geometry can act
/// alike on one output (the slewing rig's beam length on its one strain gauge), and a wrong
/// length or density moves the modes as an unmodeled mode coupled to them does: the answer then
/// says which mismatch the data do not rule out and what it would be.
pub(super) struct Rivals<'a> {
    /// The reference's fitted model.
    pub reference: &'a Model,
    /// The reference's free parameters.
    pub free: &'a [String],
    /// Parameters not tried (the scale's exact equivalents, reported as such).
    pub exclude: &'a [String],
    /// Terms tried beside the model's own parameters (a sensor's crosstalk, module `crosstalk`).
    pub also: Vec<mismatch::RivalTrial>,
    /// The gain a rival must reach (nats).
    pub to_match: f64,
    /// The model file as given, whose values a rival's refit and the effect's move.
    pub file: &'a Model,
    /// The reference's mismatch parameters, whose moves each account is charged with.
    pub mismatch: &'a [String],
    /// The named effect's account, for a sensor scale ([`Account::of_scale`]): each rival of the
    /// model's own is then charged its own departure from the file ([`Departures`]).
    pub effect: Option<Account<'a>>,
    /// The relative tolerance τ the file's values are known to ([`super::DiagnoseOptions::file_tolerance`]).
    pub tolerance: f64,
}

/// A named sensor scale's account of the record, against which a rival's is set
/// ([`Departures`]).
#[derive(Clone, Copy)]
pub(super) struct Account<'a> {
    /// What it asks of the model file (nats, [`charge`]): its calibration error and the
    /// reference's mismatch parameters in its refit.
    pub charge: f64,
    /// Its refit.
    pub outcome: &'a FitOutcome,
}

impl<'a> Account<'a> {
    /// The account of a named sensor scale; `None` for another effect, or where a value is
    /// missing or not positive ([`charge`]).
    pub fn of_scale(
        candidate: &'a Candidate,
        file: &Model,
        mismatch: &[String],
        tolerance: f64,
    ) -> Option<Self> {
        if candidate.kind != EffectKind::SensorScale {
            return None;
        }
        let [scale] = candidate.parameters.as_slice() else { return None };
        let outcome = candidate.outcome.as_ref()?;
        let gain = 1.0 + scale.value;
        // Its gain of 1 is the calibration's stated value; the standard error of ln(1 + s).
        let relative = scale.std_error.map_or(f64::INFINITY, |se| se / gain);
        let own = (gain > 0.0).then(|| gain.ln().powi(2) / (2.0 * (tolerance.powi(2) + relative.powi(2))))?;
        Some(Self { charge: own + charge(outcome, file, mismatch, tolerance)?, outcome })
    }
}

/// What a refit asks of the model file over `names` (nats): Σ ln²(p̂/p_file)/(2(τ² + σ²)), with
/// σ the relative standard error of p̂ in the refit (0 for a value it holds fixed, none — no
/// charge — for one the data leave undetermined). With each file value known to τ in its
/// logarithm (a log-normal prior), this is the prior's part of the refit's log evidence, the
/// likelihood taken as Gaussian about p̂ (Laplace's approximation, one parameter at a time): a
/// value the record pins down far from the file costs much, one the record hardly sees costs
/// little however far its estimate strays. `None` where a value is missing or not positive in
/// either (its relative move is not defined).
pub(super) fn charge(outcome: &FitOutcome, file: &Model, names: &[String], tolerance: f64) -> Option<f64> {
    let report = &outcome.report;
    names.iter().try_fold(0.0, |total, name| {
        let (at_file, value) = (file.value(name).ok()?, outcome.fitted.value(name).ok()?);
        if !(at_file > 0.0 && value > 0.0 && value.is_finite()) {
            return None;
        }
        let relative = match report.names.iter().position(|n| n == name) {
            Some(i) => report.std_error(i).map_or(f64::INFINITY, |se| se / value),
            None => 0.0,
        };
        Some(total + (value / at_file).ln().powi(2) / (2.0 * (tolerance.powi(2) + relative.powi(2))))
    })
}

/// A rival's account set against the effect's ([`Departures`]): each one's [`charge`], and the
/// values of `names` the two refits set more than 1 % apart, each given against the file,
/// largest first.
fn departures(
    rival: &FitOutcome,
    effect: Account<'_>,
    file: &Model,
    names: &[String],
    tolerance: f64,
) -> Option<Departures> {
    let mut moved = Vec::new();
    for name in names {
        let value = rival.fitted.value(name).ok()?;
        let there = effect.outcome.fitted.value(name).ok()?;
        let apart = (value / there).ln().abs();
        if apart > 0.01f64.ln_1p() {
            moved.push((
                apart,
                Moved { name: name.clone(), file: file.value(name).ok()?, rival: value, effect: there },
            ));
        }
    }
    moved.sort_by(|a, b| b.0.total_cmp(&a.0));
    Some(Departures {
        rival: charge(rival, file, names, tolerance)?,
        effect: effect.charge,
        tolerance,
        moved: moved.into_iter().map(|(_, m)| m).collect(),
    })
}

impl Rivals<'_> {
    pub(super) fn find(&self, data: &Measurement, gain: impl Fn(&FitOutcome) -> f64 + Sync) -> Vec<Rival> {
        let tried: Vec<mismatch::RivalTrial> =
            mismatch::rival_parameters(self.reference, Some(data), self.free)
                .into_iter()
                .chain(self.also.iter().cloned())
                .filter(|t| !self.exclude.contains(&t.name))
                .collect();
        let mut found = tried
            .par_iter()
            .filter_map(|t| {
                let name = &t.name;
                let mut from = self.reference.clone();
                if let Some((effect, _)) = &t.adds {
                    from.add_effect(effect.clone()).ok()?;
                }
                // An added term is absent from the reference: its value there is zero (a lag's
                // limit), whatever value the refit starts from.
                let reference_value = if t.adds.is_some() { 0.0 } else { from.value(name).ok()? };
                from.set_bounds(name, t.bounds).ok()?;
                let free: Vec<String> = self.free.iter().chain([name]).cloned().collect();
                let outcome = run::refit_to(&from, data, &free, None, 60, run::Precision::Optimum).ok()?;
                let in_sample = gain(&outcome);
                let i = outcome.report.names.iter().position(|n| n == name)?;
                let departures = self.effect.filter(|_| t.adds.is_none()).and_then(|effect| {
                    let charged: Vec<String> = self.mismatch.iter().chain([name]).cloned().collect();
                    departures(&outcome, effect, self.file, &charged, self.tolerance)
                });
                // Listed where the likelihood alone reaches the bar (the user is told of the tie
                // and of what the rival would ask of the file), or with what the effect asks.
                let credit = departures.as_ref().map_or(0.0, |d| d.charge().min(0.0));
                (in_sample - credit >= self.to_match && mismatch::determined(&outcome, name)).then(|| Rival {
                    name: name.clone(),
                    reference_value,
                    value: outcome.report.parameters[i],
                    std_error: outcome.report.std_error(i),
                    in_sample,
                    added: t.adds.is_some(),
                    adds: t.adds.as_ref().map(|(_, term)| term.clone()),
                    penalty: t.penalty,
                    departures,
                })
            })
            .collect::<Vec<_>>();
        // The best first; a stable sort keeps the order tried among equal gains.
        found.sort_by(|a, b| b.in_sample.total_cmp(&a.in_sample));
        found
    }
}

/// The in-sample gap (nats) within which two sensor scales fit alike ([`ScaleChoice`]).
pub const SAME_FIT: f64 = 1.0;

/// For a chosen sensor scale `i`: the sensor scale among those not told apart from it that fits
/// alike and asks least of the file ([`ScaleChoice`]), with the choice; `None` when no other
/// scale fits alike, or a charge is not defined.
pub(super) fn closer_to_file(
    candidates: &[Candidate],
    i: usize,
    file: &Model,
    mismatch: &[String],
    tolerance: f64,
    threshold: f64,
) -> Option<(usize, ScaleChoice)> {
    let chosen = &candidates[i];
    if chosen.kind != EffectKind::SensorScale {
        return None;
    }
    let charge = |c: &Candidate| Account::of_scale(c, file, mismatch, tolerance).map(|a| a.charge);
    let alike: Vec<usize> = super::named::not_told_apart(candidates, threshold)
        .into_iter()
        .filter(|&j| {
            j != i
                && candidates[j].kind == EffectKind::SensorScale
                && (candidates[j].evidence.in_sample - chosen.evidence.in_sample).abs() < SAME_FIT
        })
        .collect();
    let (j, other_charge) = alike
        .into_iter()
        .filter_map(|j| Some((j, charge(&candidates[j])?)))
        .min_by(|a, b| a.1.total_cmp(&b.1))?;
    let own = charge(chosen)?;
    let (named, other, named_charge, other_charge) =
        if other_charge < own { (j, i, other_charge, own) } else { (i, j, own, other_charge) };
    Some((
        named,
        ScaleChoice {
            named: candidates[named].label.clone(),
            named_charge,
            other: candidates[other].label.clone(),
            other_charge,
        },
    ))
}

#[cfg(test)]
mod tests {
    use super::super::answer::{Departures, Rival};

    fn rival(in_sample: f64, departures: Option<Departures>) -> Rival {
        Rival {
            name: "length".into(),
            reference_value: 1.19,
            value: 1.22,
            std_error: Some(0.003),
            in_sample,
            added: false,
            adds: None,
            penalty: 0.0,
            departures,
        }
    }

    fn asks(rival: f64, effect: f64) -> Option<Departures> {
        Some(Departures { rival, effect, tolerance: 0.05, moved: Vec::new() })
    }

    /// The likelihood's tie is broken by what each account asks of the model file: a rival
    /// that asks more keeps its hands off an effect it ties with, one that asks less unseats an
    /// effect that leads it by more than the margin; without departures the margin alone rules.
    #[test]
    fn what_each_account_asks_of_the_file_breaks_the_tie() {
        // The scale leads by half a nat: alone, the margin lets the length unseat it.
        assert!(rival(10.0, None).unseats(10.5));
        // The length's account asks 4 nats more of the file: the scale keeps its name.
        assert!(!rival(10.0, asks(30.0, 26.0)).unseats(10.5));
        // The scale leads by 3 nats, but its refit moves the file 6 nats further: the length.
        assert!(!rival(10.0, None).unseats(13.0));
        assert!(rival(10.0, asks(20.0, 26.0)).unseats(13.0));
        assert_eq!(asks(20.0, 26.0).unwrap().charge(), -6.0);
    }
}
