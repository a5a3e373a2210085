//! The form of a named saturation (`amplifier_saturation` or `voltage_saturation` on the
//! slewing rig): the catalog's limiter turns from linear to the limit within a narrow knee, as
//! a clamp does; is this amplifier's limit softer?
//!
//! The catalog scores a saturation with the smooth limiter x/(1 + |x/L|⁸)^{1/8}, within 1 % of
//! linear below 0.6·L and of the clamp above 2·L. Amplifiers limit in other ways too: an
//! output stage whose gain falls as it nears its rail, a current loop with a tanh-like limit,
//! a supply that sags with the load — a soft limit bends the output long before the level and
//! reaches it only slowly. The knee n of the family x/(1 + |x/L|ⁿ)^{1/n} measures that (n → ∞
//! the clamp; n = 2 the soft limit x/√(1 + (x/L)²); n ≈ 2.7 within 0.022·L of L·tanh(x/L)
//! everywhere).
//! Once the saturation is named, it is refitted with n free beside its level
//! ([`crate::diagnose::catalog::KneeSearch`] gives the ranges and starts).
//!
//! From the candidate's fit the saturation is refitted to the fitter's own convergence, first
//! as it is, then with its knee (from each start; the best is kept). The knee's gain is the
//! difference of their in-sample log-likelihoods; the data demand it when it gains at least the
//! held-out threshold, the limit beside it is determined inside its range (standard error below
//! half the value, off the bounds), and the knee is too — or is [`CLAMP_KNEE`] or more, a
//! clamp: an amplifier that limits right below the demand (a clamp at 0.97 of it)
//! leaves the catalog's n = 8 hundreds of nats short. Demanded, the named effect carries it
//! (its parameters, the augmented model); otherwise the limiter stays the catalog's and the
//! report says how far the knee got. The name does not change.

use super::answer::SaturationKnee;
use super::catalog::Trial;
use super::named::{FormTest, parameter_of};
use super::{Candidate, mismatch, strength};

use plant::EffectKind;

/// The knee at and beyond which a limiter is taken for a clamp: x/(1 + |x/L|ⁿ)^{1/n} is within
/// 2^{−1/n} of the clamp at the limit, 1.4 % for n = 50, and closer elsewhere.
pub(super) const CLAMP_KNEE: f64 = 50.0;

/// The knee of the catalog's limiter, x/(1 + |x/L|⁸)^{1/8} ([`plant::nonlinear::smooth_limit`]).
const CATALOG_KNEE: f64 = 8.0;

/// The knee test of a named saturation ([`SaturationKnee`]), refitted from the test's reference
/// (which lacks the saturation) with the candidate's values; when the data demand the knee, the
/// candidate's model, refit and parameters become those with it. Where the trial's clamp start
/// fitted best and the knee is not demanded, they become the catalog's limiter's, refitted from
/// the clamp's level. `None` for any other candidate, a trial whose limiter has a knee of its
/// own, or when a refit fails.
pub(super) fn knee(candidate: &mut Candidate, trial: &Trial, test: &FormTest) -> Option<SaturationKnee> {
    let FormTest { free, threshold, gain, .. } = *test;
    if !matches!(candidate.kind, EffectKind::AmplifierSaturation | EffectKind::VoltageSaturation) {
        return None;
    }
    let fitted = candidate.model.as_ref()?;
    let search = super::catalog::knee(fitted, &trial.effect)?;
    let (knee_name, knee_range) = search.knee.clone();
    let (limit_name, limit_range) = search.limit.clone();
    let limit = fitted.value(&limit_name).ok()?.clamp(limit_range.0, limit_range.1);
    // The reference (which lacks the saturation) with the limiter and its knee added, every
    // other value the candidate's fit, in the candidate's ranges, the limit's wider one beside a
    // knee, and the knee's.
    let knee_bounds = [(limit_name.clone(), limit_range), (knee_name.clone(), knee_range)];
    // The limiter at `knee` (set after the candidate's values are copied: a candidate refitted
    // from the trial's clamp start carries a knee of its own).
    let at = |knee: f64, bounds: &mut dyn Iterator<Item = &(String, (f64, f64))>| {
        let mut model = test.reference_with(search.limiter_with(limit, knee), fitted, bounds)?;
        model.set(&knee_name, knee).ok()?;
        Some(model)
    };
    let with_knee = |knee: f64| {
        let knee = knee.clamp(knee_range.0, knee_range.1);
        at(knee, &mut trial.bounds.iter().filter(|(name, _)| *name != limit_name).chain(&knee_bounds))
    };
    // The form the knee is measured against is the catalog's limiter: the candidate as it is,
    // or, where the trial's clamp start fitted best, the catalog's limiter refitted from the
    // clamp's level in the trial's ranges.
    let from_clamp = fitted.value(&knee_name).is_ok();
    let catalog_form = if from_clamp { Some(at(CATALOG_KNEE, &mut trial.bounds.iter())?) } else { None };
    // From a clamp, the sharp start is the clamp itself (its refit is already there).
    let starts: Vec<f64> = match from_clamp {
        true => search.knee_starts.iter().take(1).copied().chain([knee_range.1]).collect(),
        false => search.knee_starts.clone(),
    };
    let named: Vec<String> = free.iter().chain(&trial.freed).cloned().collect();
    let (as_named, best) = test.refit_pair(
        catalog_form.as_ref().unwrap_or(fitted),
        &named,
        std::slice::from_ref(&knee_name),
        &starts,
        with_knee,
    )?;
    let added = gain(&best) - gain(&as_named);
    // A knee of CLAMP_KNEE or more is a clamp: the data ask for a limiter at least that sharp,
    // and sharper ones are barely told apart (the knee's standard error grows without bound
    // towards the clamp, where it may also stop short of its range's end).
    let knee = parameter_of(&best, &knee_name)?;
    let clamp = knee.value >= CLAMP_KNEE;
    let demanded = added >= threshold
        && mismatch::determined(&best, &limit_name)
        && (clamp || mismatch::determined(&best, &knee_name));
    let result =
        SaturationKnee { knee, limit: parameter_of(&best, &limit_name)?, gain: added, clamp, demanded };
    if demanded {
        let mut wider = trial.clone();
        wider.freed.push(knee_name);
        candidate.parameters = strength::effect_parameters(&best, &wider);
        candidate.model = Some(best.fitted.clone());
        candidate.outcome = Some(best);
    } else if from_clamp {
        // Not demanded: the named saturation is the catalog's limiter, as the report says.
        candidate.parameters = strength::effect_parameters(&as_named, trial);
        candidate.model = Some(as_named.fitted.clone());
        candidate.outcome = Some(as_named);
    }
    Some(result)
}
