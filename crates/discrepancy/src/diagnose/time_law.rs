//! The rival of a named structure force (a `cubic_stiffness`, `quadratic_drag` or
//! `coulomb_friction` at coordinate c): no such force, but a linear stiffness that changes with
//! time by a law of its own at one of the structure's coordinates, Δk(t)·q_j, Δk piecewise
//! linear through (0, 0) and [`LAW_TIMES`] evenly spaced times to the record's end (the
//! `change` of [`structure::Effect::CubicStiffness`] with k₃ = 0).
//!
//! A storey whose stiffness changes during the record — it degrades, settles after a loss,
//! drops in a step — is outside the catalog, and in one record a force of the catalog can stand
//! for it: in a free decay the amplitude falls as time passes, so a hardening spring's change
//! with amplitude follows a stiffness lost early; on a forced record a drag at another floor
//! took up a storey losing 5 % of its stiffness over the record (the forced draw 20261305). The
//! spring's test for a rate k₁′·t beside it ([`super::spring`]) sees a change that goes on
//! through the record at its own coordinate; it misses one that settles or steps, and one at
//! another storey. Here the named force is set against the law at every coordinate, each
//! refitted from the reference's fit with its values within ±k_jj/2 (at most half the
//! coordinate's stiffness gained or lost), in parallel; the best is the rival. The named force
//! keeps its name only where it explains the record better than the rival by the held-out
//! threshold in sample ([`TimeLaw::as_well`]; a spring counted with its quintic, the form the
//! spring test refits it to). The law is not charged for its parameters: it is the account
//! outside the catalog, and the catalog's name must be earned against it. What only the named
//! force holds is what no law in time makes: a spring's distortion within each cycle, a drag's
//! or a friction's damping that changes with the amplitude.

use super::answer::TimeLaw;
use super::catalog::Trial;
use super::named::{FormTest, parameter_of};
use super::run;
use super::spring::{record_end, symmetric};

use models::{FitOutcome, ModelEffect};
use rayon::prelude::*;

/// The law's times: it changes from the release, piecewise linear through this many evenly
/// spaced times to the record's end (1.25 s apart on a 10 s record: a few cycles of a
/// building's lowest mode, so that it follows a change over the record, not one within a cycle).
pub(super) const LAW_TIMES: usize = 8;

/// `stiffness_change_<c>_<i>`, i = 1 … n.
fn law_names(coordinate: &str, n: usize) -> Vec<String> {
    (1..=n).map(|i| format!("stiffness_change_{coordinate}_{i}")).collect()
}

/// The rival law in time to a named force of `trial` on a structure, whose own account gains
/// `effect_gain` nats in sample over the reference: `None` where the trial is not a force at a
/// coordinate of a structure, or every law's refit fails.
pub(super) fn rival(trial: &Trial, test: &FormTest, effect_gain: f64) -> Option<TimeLaw> {
    let ModelEffect::Structure(effect) = &trial.effect else { return None };
    if !effect.is_force() {
        return None;
    }
    let end = record_end(test.data)?;
    let scales = super::catalog::structure::scales(test.reference.as_structure()?, Some(test.data));
    let (coordinate, times, outcome, gain) = scales
        .par_iter()
        .filter_map(|s| {
            let (times, outcome) = law_fit(test, &s.coordinate, s.k, end)?;
            let gain = (test.gain)(&outcome);
            gain.is_finite().then(|| (s.coordinate.clone(), times, outcome, gain))
        })
        .max_by(|a, b| a.3.total_cmp(&b.3))?;
    let values =
        law_names(&coordinate, times.len()).iter().filter_map(|name| parameter_of(&outcome, name)).collect();
    Some(TimeLaw {
        coordinate,
        times,
        values,
        gain,
        effect_gain,
        as_well: effect_gain - gain < test.threshold,
    })
}

/// The reference with a linear stiffness at `coordinate` that changes with time by a law of its
/// own (its values within ±k/2), refitted from the reference's own fit: the law's times and the
/// outcome. `None` if the refit fails.
fn law_fit(test: &FormTest, coordinate: &str, k: f64, end: f64) -> Option<(Vec<f64>, FitOutcome)> {
    let times: Vec<f64> = (1..=LAW_TIMES).map(|i| end * i as f64 / LAW_TIMES as f64).collect();
    let effect = structure::Effect::CubicStiffness {
        coordinate: coordinate.to_string(),
        coefficient: 0.0,
        quadratic: None,
        quintic: None,
        sided: None,
        rate: None,
        change: Some(structure::StiffnessChange::zero(times.clone())),
    };
    let mut model = test.reference.clone();
    model.add_effect(effect.into()).ok()?;
    let names = law_names(coordinate, times.len());
    for name in &names {
        model.set_bounds(name, symmetric(0.5 * k)).ok()?;
    }
    let free: Vec<String> = test.free.iter().chain(&names).cloned().collect();
    let outcome = run::refit_to(&model, test.data, &free, None, 60, run::Precision::Optimum).ok()?;
    Some((times, outcome))
}
