//! The named effect: which candidate is named ([`choose`]), the refit that frees what only the
//! named effect determines ([`polish`]), the model parameters a named sensor scale cannot be
//! told from ([`scale_equivalents_of`]); those that explain the data as well are sought in
//! [`super::rivals`].
//! A named spring's form is tested beside it in [`super::spring`].

use super::answer::last_error;
use super::catalog::Trial;
use super::evidence::LikelihoodFit;
use super::{Candidate, Verdict, run, strength};
use mem::Measurement;
use models::FitOutcome;
use models::{Model, ModelEffect};
use plant::EffectKind;
use rayon::prelude::*;

/// The model's parameters (other than the refitted ones) whose only effect is to scale output
/// `output`: each sensitivity column confined to that output (the others' share below 10⁻⁹)
/// and proportional to it (cosine above 1 − 10⁻⁹). A named scale of that output is then exactly
/// a change of any of them (the slewing rig's beam thickness, which turns root curvature into
/// surface strain), and no record of these outputs tells a calibration error from that
/// parameter's. Empty if the sensitivities cannot be had (then nothing is claimed).
pub(super) fn scale_equivalents_of(
    model: &Model,
    data: &Measurement,
    output: usize,
    refitted: &[String],
) -> Vec<String> {
    let names: Vec<String> = model.parameter_names().into_iter().filter(|n| !refitted.contains(n)).collect();
    let refs: Vec<&str> = names.iter().map(|s| s.as_str()).collect();
    let Ok(values) = names.iter().map(|n| model.value(n)).collect::<Result<Vec<f64>, _>>() else {
        return Vec::new();
    };
    // The integrator every candidate was fitted with (a nonlinear model would otherwise get the
    // adaptive solver, with a sensitivity per parameter of the file).
    let integrator = models::Integrator::Exponential { max_step: run::max_step(model) };
    let Ok(r) = model.response_with(&refs, integrator).map_err(|e| e.to_string()).and_then(|response| {
        mem::sampled_response(response.as_ref(), data, &values).map_err(|e| e.to_string())
    }) else {
        return Vec::new();
    };
    let (k, n_out) = (r.outputs.nrows(), r.outputs.ncols());
    names
        .into_iter()
        .enumerate()
        .filter(|&(i, _)| {
            let (mut own, mut other, mut dot, mut power) = (0.0, 0.0, 0.0, 0.0);
            for t in 0..k {
                for o in 0..n_out {
                    let s = r.sensitivities[(t * n_out + o, i)];
                    if o == output {
                        let y = r.outputs[(t, o)];
                        (own, dot, power) = (own + s * s, dot + s * y, power + y * y);
                    } else {
                        other += s * s;
                    }
                }
            }
            own > 0.0 && other <= 1e-18 * own && dot * dot >= (1.0 - 1e-9) * own * power
        })
        .map(|(_, name)| name)
        .collect()
}

/// A named effect whose trial held a shape parameter that only the named effect can determine
/// (a backlash's gear frequency) is refitted with it free, from its fit, and reports those
/// estimates; the evidence that named it is unchanged. A failed or worse refit changes nothing.
pub(super) fn polish(candidate: &mut Candidate, trial: &Trial, free: &[String], data: &Measurement) {
    if candidate.kind != EffectKind::Backlash {
        return;
    }
    let gear = plant::ParamId::GearFrequency.name();
    let mut wider = trial.clone();
    wider.freed.push(gear);
    let Some(from) = candidate.model.as_ref() else { return };
    let all: Vec<String> = free.iter().chain(&wider.freed).cloned().collect();
    let Ok(outcome) = run::refit(from, data, &all, None, 60) else { return };
    let before = candidate.outcome.as_ref().map_or(f64::INFINITY, last_error);
    if last_error(&outcome) <= before {
        candidate.parameters = strength::effect_parameters(&outcome, &wider);
        candidate.model = Some(outcome.fitted.clone());
        candidate.outcome = Some(outcome);
    }
}

/// What a test of a named effect's form refits against (the spring's form, module `spring`;
/// the friction's static peak, module `friction`; the saturation's knee, module `saturation`):
/// the reference's fitted model and free parameters, the record, the held-out threshold, and the
/// gain of a refit over the reference (nats, the likelihood every candidate is scored by).
#[derive(Clone, Copy)]
pub(super) struct FormTest<'a> {
    /// The reference's fitted model (which lacks the named effect).
    pub reference: &'a Model,
    /// The reference's free parameters.
    pub free: &'a [String],
    /// The record the candidates were fitted to.
    pub data: &'a Measurement,
    /// The held-out threshold (nats).
    pub threshold: f64,
    /// In-sample log-likelihood gain of a refit over the reference (nats).
    pub gain: &'a (dyn Fn(&FitOutcome) -> f64 + Sync),
    /// The likelihood's own fit where the noise is coloured beyond AR(1) (a forced record whose
    /// force is recorded with noise): the refits of a term judged by its standard error
    /// ([`super::spring::WALD_Z`]) are made by it, so that the error is the likelihood's. None:
    /// the RMS-weighted fit.
    pub under: Option<&'a LikelihoodFit>,
}

impl FormTest<'_> {
    /// The reference (which lacks the named effect) with `effect` added in its place, every
    /// value `fitted` (the candidate's model) has set on it, then `bounds`. `None` if the effect
    /// cannot be added or a value set.
    pub fn reference_with<'b>(
        &self,
        effect: ModelEffect,
        fitted: &Model,
        bounds: impl IntoIterator<Item = &'b (String, (f64, f64))>,
    ) -> Option<Model> {
        let mut model = self.reference.clone();
        model.add_effect(effect).ok()?;
        for name in fitted.parameter_names() {
            model.set(&name, fitted.value(&name).ok()?).ok()?;
        }
        for (name, range) in bounds {
            model.set_bounds(name, *range).ok()?;
        }
        Some(model)
    }

    /// The refits a test of a named effect's form compares, each to the fitter's own
    /// convergence: `fitted` (the candidate's model) as it is, with `named` free; and the
    /// richer form `with(start)` with `extra` freed beside them, from each of `starts` (the
    /// best kept), in parallel. `None` if a refit fails (or every start does).
    pub fn refit_pair(
        &self,
        fitted: &Model,
        named: &[String],
        extra: &[String],
        starts: &[f64],
        with: impl Fn(f64) -> Option<Model> + Sync,
    ) -> Option<(FitOutcome, FitOutcome)> {
        let refit = |model: &Model, free: &[String]| {
            run::refit_to(model, self.data, free, None, 60, run::Precision::Optimum).ok()
        };
        let richer: Vec<String> = named.iter().chain(extra).cloned().collect();
        let (as_named, best) = rayon::join(
            || refit(fitted, named),
            || {
                starts
                    .par_iter()
                    .filter_map(|&start| refit(&with(start)?, &richer))
                    .min_by(|a, b| last_error(a).total_cmp(&last_error(b)))
            },
        );
        Some((as_named?, best?))
    }
}

/// A parameter of a refit by name, with its standard error (`None` if the refit lacks it).
pub(super) fn parameter_of(outcome: &FitOutcome, name: &str) -> Option<super::EffectParameter> {
    let i = outcome.report.names.iter().position(|n| n == name)?;
    Some(super::EffectParameter {
        name: name.to_string(),
        value: outcome.report.parameters[i],
        std_error: outcome.report.std_error(i),
    })
}

/// The candidates (other than a lattice) that passed every test — `Outscored`, or the one
/// `Named` among them — whose held-out gains lie within `threshold` of the best of theirs: the
/// data do not tell them apart, and [`choose`] names one of them by its strength.
pub(super) fn not_told_apart(candidates: &[Candidate], threshold: f64) -> Vec<usize> {
    let passed = |c: &Candidate| {
        matches!(c.verdict, Verdict::Outscored | Verdict::Named) && c.kind != EffectKind::SensorQuantization
    };
    let held_out = |c: &Candidate| c.evidence.held_out.unwrap_or(f64::NEG_INFINITY);
    let best = candidates.iter().filter(|c| passed(c)).map(held_out).fold(f64::NEG_INFINITY, f64::max);
    (0..candidates.len())
        .filter(|&i| passed(&candidates[i]) && best - held_out(&candidates[i]) < threshold)
        .collect()
}

/// The candidate set aside as a stand-in ([`Verdict::Superficial`] or
/// [`Verdict::LeavesItsOutput`]: it predicts, but leaves too much of the residual's structure
/// for its kind) that beats the chosen one on both counts — it predicts the held-out blocks
/// better by at least `threshold` and removes at least as large a share of the residual's
/// structure — the best predictor among such, if any. The chosen effect is then not the best
/// account of what is missing by any measure the diagnosis has, and what accounts for more only
/// stands in for it: the physics is outside the catalog, and naming the chosen one would name a
/// lesser stand-in. (A one-sided stop read by accelerometers was named a dry friction at 228–1,054
/// nats held out, removing 10–16 % of the structure, while a symmetric spring set aside
/// predicted 1,005–1,319 and removed 23–31 %.) A stand-in that predicts better but explains less
/// of the structure does not unseat it: an excited appendage's mode (250 nats, 58 % of the
/// structure) stays named beside a sensor scale that takes up the appendage's added mass (317
/// nats, 5 %). A lattice is a measurement fact, scored by its own likelihood, and is neither
/// tested nor set against.
pub(super) fn outpredicted_by(candidates: &[Candidate], chosen: usize, threshold: f64) -> Option<usize> {
    let lead = candidates[chosen].evidence.held_out?;
    let structure = candidates[chosen].evidence.structure_explained;
    if candidates[chosen].kind == EffectKind::SensorQuantization {
        return None;
    }
    candidates
        .iter()
        .enumerate()
        .filter(|(_, c)| {
            matches!(c.verdict, Verdict::Superficial | Verdict::LeavesItsOutput)
                && c.kind != EffectKind::SensorQuantization
                && c.evidence.structure_explained >= structure
        })
        .filter_map(|(j, c)| c.evidence.held_out.map(|h| (j, h)))
        .filter(|&(_, h)| h - lead >= threshold)
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(j, _)| j)
}

/// The broader name of an effect that makes a further claim: a voltage limit is a saturation
/// of the amplifier that says, in addition, which quantity it limits (the output voltage, so
/// that the back-EMF still acts beyond it). `amplifier_saturation` names the amplifier's
/// saturation whichever it limits, refitted as its current limit (the paper's amplifier).
fn broader(kind: EffectKind) -> Option<EffectKind> {
    match kind {
        EffectKind::VoltageSaturation => Some(EffectKind::AmplifierSaturation),
        _ => None,
    }
}

/// The further claim is named only where the data make it: where the broader candidate passed
/// too and the chosen one's held-out gain leads it by less than the threshold, the broader one
/// is named instead (a current and a voltage limit differ only where the motor runs fast while
/// limited, and a record that barely reaches there does not tell them apart).
fn unless_told_apart(candidates: &[Candidate], chosen: usize, threshold: f64) -> usize {
    let Some(kind) = broader(candidates[chosen].kind) else { return chosen };
    let held_out = |c: &Candidate| c.evidence.held_out.unwrap_or(f64::NEG_INFINITY);
    let lead = held_out(&candidates[chosen]);
    candidates
        .iter()
        .enumerate()
        .filter(|(_, c)| c.kind == kind && matches!(c.verdict, Verdict::Outscored | Verdict::Named))
        .filter(|(_, c)| lead - held_out(c) < threshold)
        .max_by(|(_, a), (_, b)| held_out(a).total_cmp(&held_out(b)))
        .map_or(chosen, |(i, _)| i)
}

/// The named candidate: a proven lattice that matters first (a measurement fact), else the
/// candidate with the most held-out evidence beyond a mismatch among those that pass — among
/// those whose held-out gains are closer than the threshold (not told apart), the one whose
/// strength is resolved from "no effect" by the most standard errors, or its broader name
/// where that makes a further claim the data do not decide ([`unless_told_apart`]); for a
/// sensor's zero, the law the held-out blocks decide ([`zeros_law`]).
pub(super) fn choose(candidates: &[Candidate], threshold: f64) -> Option<usize> {
    let lattice = candidates
        .iter()
        .enumerate()
        .filter(|(_, c)| c.kind == EffectKind::SensorQuantization && c.verdict == Verdict::Outscored)
        .max_by(|(_, a), (_, b)| {
            let ratio = |c: &Candidate| c.lattice.map_or(0.0, |l| l.step / l.noise.max(f64::MIN_POSITIVE));
            ratio(a).total_cmp(&ratio(b))
        })
        .map(|(i, _)| i);
    lattice.or_else(|| {
        // Held-out gains closer than the threshold are not told apart; among those, the one
        // whose strength the data resolve most surely decides (the largest z). The likelihood's
        // ΔBIC trusts the measurement model's AR(1) correlation, fixed from the best-fitting
        // residual; the strength's standard error is a sandwich over each refit's own residual
        // variance and correlation (White 1982), so a candidate that gains by bending into
        // structure it leaves has a wide one. Strengths within [`STRENGTH_TIE`] of the largest
        // are not told apart either, and among them the fewest parameters decide, between
        // bodies at floors the better fit ([`most_resolved`]).
        most_resolved(candidates, &not_told_apart(candidates, threshold))
            .map(|i| zeros_law(candidates, unless_told_apart(candidates, i, threshold), threshold))
    })
}

/// How far apart (in standard errors) two candidates' strengths must lie to be told apart: a
/// strength z = estimate / standard error scatters by about one from record to record.
pub const STRENGTH_TIE: f64 = 1.0;

/// Among `tied` (held-out gains the data do not tell apart), the candidate whose strength is
/// resolved from "no effect" by the most standard errors; where others lie within
/// [`STRENGTH_TIE`] of it, the one of those with the fewest parameters (then the largest z, then
/// the better ΔBIC): the same fit for fewer parameters. On the forced draw 20261362 a 3 % scale on q1
/// (`A_scale_strong_s1`) predicted the held-out blocks within 4.3 nats of a 12.8 kg body at
/// 7.35 Hz on floor 3, their strengths 18.2 and 18.4 σ: the body, three parameters for the
/// scale's one, was named. Between accounts of as many parameters (one effect at two floors)
/// parsimony says nothing, and the larger z decides as before: ranking those by ΔBIC named a
/// cubic spring at the roof for a storey that lost stiffness (20261356 `C_loss_step_strong_s0`,
/// z 60.6 against floor 2's 61.5, ΔBIC −2,468.2 against −2,456.5), where the spring the larger
/// z names is then matched by a stiffness changing in time and nothing is named.
///
/// Where that is a body at a floor, the body among `tied` of as many parameters, its strength
/// within [`STRENGTH_TIE`] of the chosen one's, that fits the record best in sample (the
/// smallest ΔBIC) is chosen instead: the mode is what the record shows, and which floor it hangs
/// at is a claim [`floor_untold`] withholds where it is not told; the larger z there is no
/// choice between two fits of one mode, and the better fit gives the mode's frequency and mass
/// and is what rival accounts are weighed against. On the free-decay draw 20261377
/// (`A_appendage_strong_s0`, 50 kg at 18.8 Hz on floor 1) a body on floor 2 at 14.78 Hz (z 12.7,
/// 81.8 nats in sample) was chosen over floor 1's at 18.33 Hz (z 12.0, 91.9 nats, 3.9 nats ahead
/// held out): that account fell 2.0 nats short of `m1` and `m2` freed, which were kept, and
/// nothing was named; the floor-1 body's beats them ([`super::secondary`]). Springs at two
/// floors stay the larger z's.
pub(super) fn most_resolved(candidates: &[Candidate], tied: &[usize]) -> Option<usize> {
    let z = |i: usize| candidates[i].evidence.strength_z;
    let size = |i: usize| candidates[i].parameters.len();
    let bic = |i: usize| candidates[i].evidence.delta_bic;
    let body = |i: usize| appendage_at(&candidates[i]).is_some();
    let best = tied.iter().map(|&i| z(i)).fold(f64::NEG_INFINITY, f64::max);
    let chosen =
        tied.iter().copied().filter(|&i| best - z(i) < STRENGTH_TIE).min_by(|&a, &b| {
            size(a).cmp(&size(b)).then(z(b).total_cmp(&z(a))).then(bic(a).total_cmp(&bic(b)))
        })?;
    if !body(chosen) {
        return Some(chosen);
    }
    tied.iter()
        .copied()
        .filter(|&j| body(j) && size(j) == size(chosen) && (z(j) - z(chosen)).abs() < STRENGTH_TIE)
        .min_by(|&a, &b| bic(a).total_cmp(&bic(b)))
        .or(Some(chosen))
}

/// Whether `kind` is a law in time of a sensor's zero: an offset or a drift ([`zeros_law`]).
pub(super) fn is_zero_law(kind: EffectKind) -> bool {
    matches!(kind, EffectKind::OutputOffset | EffectKind::SensorDrift)
}

/// The law of a sensor's zero the held-out blocks decide. An offset and a drift are two laws in
/// time of one error, the sensor's zero; where the chosen candidate is one of them, another law
/// of the same output's zero that predicts the held-out blocks better by at least `threshold`,
/// and was set aside only because it leaves more than half its output's structure
/// ([`Verdict::LeavesItsOutput`]: it passed every other test), is named in its place: the law
/// that passed that test shows the output's structure is its zero's, and which law the zero
/// follows is the likelihood's to say. On the forced draw 20261356 a medium drift on floor 1
/// gained 164 nats held out and an offset 122, while the drift removed 48 % of its output's
/// structure and the offset 62 %: the offset was named. On 20261354 a medium offset (133 nats,
/// 44 %) was named a drift (97 nats, 58 %). Any other candidate, or a law the threshold does
/// not tell apart, leaves the choice as it is.
fn zeros_law(candidates: &[Candidate], chosen: usize, threshold: f64) -> usize {
    let zero = |c: &Candidate| is_zero_law(c.kind);
    let named = &candidates[chosen];
    let Some(lead) = named.evidence.held_out.filter(|_| zero(named) && named.output.is_some()) else {
        return chosen;
    };
    candidates
        .iter()
        .enumerate()
        .filter(|(_, c)| zero(c) && c.output == named.output && c.verdict == Verdict::LeavesItsOutput)
        .filter_map(|(j, c)| c.evidence.held_out.map(|h| (j, h)))
        .filter(|&(_, h)| h - lead >= threshold)
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .map_or(chosen, |(j, _)| j)
}

/// The coordinate of an appendage candidate (`appendage_frequency_<c>` among its parameters)
/// and its frequency.
pub(in crate::diagnose) fn appendage_at(candidate: &Candidate) -> Option<(&str, f64)> {
    candidate.parameters.iter().find_map(|p| Some((p.name.strip_prefix("appendage_frequency_")?, p.value)))
}

/// For a named appendage at coordinate c: its label without the floor, where the same mode
/// hung at another coordinate fits the record within `threshold` of it in sample (refitted, with
/// whatever verdict) — the record shows the mode but does not say where it hangs, and the floor
/// is a further claim the data do not make (the forced draw 20261308: a weak appendage on floor 2,
/// 9.4 resonance nats, named at floor 1, 27.7 nats in sample against floor 2's 28.0, not resolved
/// at 2.93 σ). The label then lists the floors not told apart, the named one first:
/// `unmodeled_mode(15.81 Hz; at q1 or q2)`. `None` for another effect, or a floor told apart.
pub(super) fn floor_untold(candidates: &[Candidate], chosen: usize, threshold: f64) -> Option<String> {
    let named = &candidates[chosen];
    let (floor, f) = appendage_at(named)?;
    let mut floors = vec![floor.to_string()];
    for c in candidates.iter().filter(|c| !matches!(c.verdict, Verdict::Failed(_))) {
        if let Some((other, _)) = appendage_at(c)
            && !floors.iter().any(|f| f == other)
            && c.evidence.in_sample > named.evidence.in_sample - threshold
        {
            floors.push(other.to_string());
        }
    }
    (floors.len() > 1).then(|| {
        let (last, rest) = floors.split_last().expect("two or more");
        format!("unmodeled_mode({f:.2} Hz; at {} or {last})", rest.join(", "))
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::diagnose::{EffectParameter, Evidence};
    use plant::Sensor;

    fn passing(kind: EffectKind, held_out: f64, delta_bic: f64, strength_z: f64) -> Candidate {
        Candidate {
            kind,
            sensor: Some(Sensor::StrainGauge),
            output: Some(2),
            label: kind.name().to_string(),
            replaces: None,
            parameters: Vec::new(),
            evidence: Evidence { held_out: Some(held_out), delta_bic, strength_z, ..Evidence::default() },
            lattice: None,
            verdict: Verdict::Outscored,
            model: None,
            outcome: None,
        }
    }

    /// The blind set's strain-gauge offset behind a delay (docs/diagnose.md, "Other acquisition
    /// conditions"): a drift 6.5 nats ahead held out and 46 ahead in ΔBIC, resolved at 3.8 σ,
    /// against the offset at 25.8 σ. Held-out gains within the threshold are not told apart, and
    /// the better-resolved strength decides; a gain beyond the threshold still decides alone.
    #[test]
    fn among_held_out_gains_not_told_apart_the_better_resolved_strength_is_named() {
        let drift = passing(EffectKind::SensorDrift, 271.9, -445.1, 3.8);
        let offset = passing(EffectKind::OutputOffset, 265.4, -398.7, 25.8);
        assert_eq!(choose(&[drift.clone(), offset.clone()], 10.0), Some(1));
        assert_eq!(choose(&[offset.clone(), drift.clone()], 10.0), Some(0));
        // Told apart: 12 nats ahead held out is named whatever its z.
        let ahead = passing(EffectKind::SensorDrift, 277.5, -445.1, 3.8);
        assert_eq!(choose(&[ahead, offset.clone()], 10.0), Some(0));
        // Equal strengths: the smaller ΔBIC.
        let twin = passing(EffectKind::SensorScale, 266.0, -420.0, 25.8);
        assert_eq!(choose(&[offset.clone(), twin.clone()], 10.0), Some(1));
        // A candidate that did not pass is never named.
        let mut failed = offset;
        failed.verdict = Verdict::Superficial;
        assert_eq!(choose(&[drift, failed], 10.0), Some(0));
        // The ties are counted from the best gain, not from the one named: 83 lies within the
        // threshold of the named 91 but 17 nats behind the best, so it was not among them.
        let (best, named, behind) = (
            passing(EffectKind::CubicStiffness, 100.0, -150.0, 1.0),
            passing(EffectKind::QuadraticDrag, 91.0, -140.0, 20.0),
            passing(EffectKind::CoulombFriction, 83.0, -130.0, 30.0),
        );
        let all = [best, named, behind];
        assert_eq!(choose(&all, 10.0), Some(1));
        assert_eq!(not_told_apart(&all, 10.0), vec![0, 1]);
    }

    /// Strengths within a standard error of each other are not told apart either, and the fewer
    /// parameters decide (the forced draw 20261362's 3 % scale against a body at 7.35 Hz: held
    /// out 143.7 and 139.4 nats, z 18.2 and 18.4); a strength more than one standard error
    /// ahead still decides alone, and so does the larger z between as many parameters.
    #[test]
    fn among_strengths_within_a_standard_error_the_fewer_parameters_are_named() {
        let with = |kind: EffectKind, held_out: f64, delta_bic: f64, z: f64, n: usize| {
            let mut c = passing(kind, held_out, delta_bic, z);
            c.parameters = (0..n)
                .map(|i| EffectParameter { name: format!("p{i}"), value: 1.0, std_error: Some(0.1) })
                .collect();
            c
        };
        let scale = with(EffectKind::SensorScale, 143.7, -262.8, 18.2, 1);
        let body = with(EffectKind::UnmodeledMode, 139.4, -256.5, 18.4, 3);
        assert_eq!(choose(&[body.clone(), scale.clone()], 10.0), Some(1));
        assert_eq!(choose(&[scale.clone(), body.clone()], 10.0), Some(0));
        let surer = with(EffectKind::UnmodeledMode, 139.4, -256.5, 19.3, 3);
        assert_eq!(choose(&[surer, scale], 10.0), Some(0));
        // 20261356: two floors' cubic springs, one parameter each, held out 1,570.9 and 1,562.1
        // nats, z 60.6 and 61.5: the larger z, not the better ΔBIC (−2,468.2 and −2,456.5).
        let roof = with(EffectKind::CubicStiffness, 1570.9, -2468.2, 60.6, 1);
        let second = with(EffectKind::CubicStiffness, 1562.1, -2456.5, 61.5, 1);
        assert_eq!(choose(&[roof.clone(), second.clone()], 10.0), Some(1));
        assert_eq!(choose(&[second, roof], 10.0), Some(0));
    }

    /// Between bodies at two floors whose held-out gains and strengths are not told apart, the
    /// one that fits the record better in sample is chosen, not the larger z (the free-decay draw
    /// 20261377: floor 2 at 14.78 Hz, 82.4 nats held out, z 12.7, ΔBIC −138.8; floor 1 at
    /// 18.33 Hz, 86.3 nats, z 12.0, ΔBIC −158.9). A body whose z is a standard error ahead, or
    /// one of another size, is not moved; a body is not traded for another kind.
    #[test]
    fn between_floors_not_told_apart_the_body_that_fits_better_is_chosen() {
        let body = |floor: &str, held_out: f64, delta_bic: f64, z: f64, n: usize| {
            let mut c = passing(EffectKind::UnmodeledMode, held_out, delta_bic, z);
            c.parameters = [format!("appendage_mass_{floor}"), format!("appendage_frequency_{floor}")]
                .into_iter()
                .chain((2..n).map(|i| format!("p{i}")))
                .map(|name| EffectParameter { name, value: 1.0, std_error: Some(0.1) })
                .collect();
            c
        };
        let second = body("q2", 82.4, -138.8, 12.7, 3);
        let first = body("q1", 86.3, -158.9, 12.0, 3);
        assert_eq!(choose(&[second.clone(), first.clone()], 10.0), Some(1));
        assert_eq!(choose(&[first.clone(), second.clone()], 10.0), Some(0));
        // A strength more than a standard error ahead still decides.
        let surer = body("q2", 82.4, -138.8, 13.1, 3);
        assert_eq!(choose(&[surer.clone(), first.clone()], 10.0), Some(0));
        // A body of another size is not moved to: the fewer parameters decided.
        let released = body("q1", 86.3, -160.0, 12.0, 4);
        assert_eq!(choose(&[second.clone(), released], 10.0), Some(0));
        // Nor is a spring traded for a body.
        let mut spring = passing(EffectKind::CubicStiffness, 82.4, -138.8, 12.7);
        spring.parameters = vec![EffectParameter { name: "k3".into(), value: 1.0, std_error: Some(0.1) }; 3];
        assert_eq!(choose(&[spring, first], 10.0), Some(0));
    }

    /// The law of a sensor's zero is the held-out blocks' to decide, once a law of it has shown
    /// the output's structure is the sensor's (the forced draws 20261356 and 20261354: a
    /// medium drift named an offset, and a medium offset named a drift).
    #[test]
    fn the_held_out_blocks_decide_the_law_of_a_sensors_zero() {
        let law = |kind: EffectKind, held_out: f64, z: f64, verdict: Verdict| {
            let mut c = passing(kind, held_out, -2.0 * held_out, z);
            c.verdict = verdict;
            c
        };
        // 20261356: the offset passed (62 % of its output's structure), the drift 41.4 nats
        // ahead did not (48 %): the drift is named.
        let offset = law(EffectKind::OutputOffset, 122.5, 12.4, Verdict::Outscored);
        let drift = law(EffectKind::SensorDrift, 163.9, 15.2, Verdict::LeavesItsOutput);
        assert_eq!(choose(&[offset.clone(), drift.clone()], 10.0), Some(1));
        // 20261354 the other way round.
        let offset = law(EffectKind::OutputOffset, 132.6, 16.1, Verdict::LeavesItsOutput);
        let drift = law(EffectKind::SensorDrift, 96.6, 13.3, Verdict::Outscored);
        assert_eq!(choose(&[drift.clone(), offset.clone()], 10.0), Some(1));
        // Within the threshold the law that passed stays named.
        let close = law(EffectKind::OutputOffset, 105.0, 16.1, Verdict::LeavesItsOutput);
        assert_eq!(choose(&[drift.clone(), close], 10.0), Some(0));
        // Another output's zero, a law set aside for another reason, or another kind: no change.
        let mut elsewhere = offset.clone();
        elsewhere.output = Some(0);
        assert_eq!(choose(&[drift.clone(), elsewhere], 10.0), Some(0));
        let superficial = law(EffectKind::OutputOffset, 132.6, 16.1, Verdict::Superficial);
        assert_eq!(choose(&[drift.clone(), superficial], 10.0), Some(0));
        let scale = law(EffectKind::SensorScale, 132.6, 16.1, Verdict::LeavesItsOutput);
        assert_eq!(choose(&[drift.clone(), scale], 10.0), Some(0));
        // A chosen effect that is not a sensor's zero keeps its name.
        let mode = law(EffectKind::UnmodeledMode, 96.6, 13.3, Verdict::Outscored);
        assert_eq!(choose(&[mode, offset], 10.0), Some(0));
    }

    /// The blind set's strong current clamp s2 under AR(1) noise on every sensor (docs/diagnose.md,
    /// "Other acquisition conditions"): the voltage limit 0.6 nats ahead held out and 0.4 σ
    /// better resolved. The data do not say which quantity the amplifier limits, so the
    /// amplifier's saturation is named; the demo's voltage limit, 18.8 nats ahead, is named.
    #[test]
    fn a_voltage_limit_is_named_only_where_it_is_told_from_a_current_limit() {
        let current = passing(EffectKind::AmplifierSaturation, 955.33, -2000.0, 153.84);
        let voltage = passing(EffectKind::VoltageSaturation, 955.95, -2001.0, 154.27);
        assert_eq!(choose(&[current.clone(), voltage.clone()], 10.0), Some(0));
        assert_eq!(choose(&[voltage.clone(), current.clone()], 10.0), Some(1));
        // Told apart: the demo's first step.
        let (current, voltage) = (
            passing(EffectKind::AmplifierSaturation, 3226.05, -6000.0, 4269.8),
            passing(EffectKind::VoltageSaturation, 3244.85, -6040.0, 4659.1),
        );
        assert_eq!(choose(&[current.clone(), voltage.clone()], 10.0), Some(1));
        // The broader name must have passed itself.
        let mut failed = passing(EffectKind::AmplifierSaturation, 955.33, -2000.0, 153.84);
        failed.verdict = Verdict::Superficial;
        let voltage = passing(EffectKind::VoltageSaturation, 955.95, -2001.0, 154.27);
        assert_eq!(choose(&[failed, voltage.clone()], 10.0), Some(1));
        // A current limit ahead is named as before, and a narrower name is never put for it.
        let ahead = passing(EffectKind::AmplifierSaturation, 960.0, -2003.0, 160.0);
        assert_eq!(choose(&[voltage, ahead], 10.0), Some(1));
    }
    /// A stand-in unseats the chosen effect only when it beats it on both counts: held out by
    /// the threshold and in the share of the residual's structure it removes (the numbers of the
    /// stop read by accelerometers, and of the excited roof appendage beside a sensor scale).
    #[test]
    fn a_stand_in_unseats_the_chosen_effect_only_by_predicting_and_explaining_more() {
        let with = |mut c: Candidate, verdict: Verdict, structure: f64| {
            c.verdict = verdict;
            c.evidence.structure_explained = structure;
            c
        };
        let friction =
            with(passing(EffectKind::CoulombFriction, 1054.4, -2000.0, 17.3), Verdict::Named, 0.16);
        let spring =
            with(passing(EffectKind::CubicStiffness, 1256.9, -3000.0, 44.8), Verdict::Superficial, 0.233);
        assert_eq!(outpredicted_by(&[friction.clone(), spring.clone()], 0, 10.0), Some(1));
        // Within the threshold held out: not told apart, no unseating.
        let close =
            with(passing(EffectKind::CubicStiffness, 1060.0, -3000.0, 44.8), Verdict::Superficial, 0.3);
        assert_eq!(outpredicted_by(&[friction.clone(), close], 0, 10.0), None);
        // Predicting better but explaining less of the structure: no unseating.
        let mode = with(passing(EffectKind::UnmodeledMode, 250.1, -475.8, 12.3), Verdict::Named, 0.579);
        let scale = with(passing(EffectKind::SensorScale, 317.2, -455.6, 22.7), Verdict::Superficial, 0.053);
        assert_eq!(outpredicted_by(&[mode, scale], 0, 10.0), None);
        // Only candidates set aside as stand-ins count: one outscored, not predictive or weak does not.
        for verdict in [Verdict::Outscored, Verdict::NotPredictive, Verdict::Weak] {
            let other = with(spring.clone(), verdict, 0.233);
            assert_eq!(outpredicted_by(&[friction.clone(), other], 0, 10.0), None);
        }
        let leaves = with(spring, Verdict::LeavesItsOutput, 0.233);
        assert_eq!(outpredicted_by(&[friction.clone(), leaves.clone()], 0, 10.0), Some(1));
        // A lattice is neither tested nor set against.
        let lattice = with(passing(EffectKind::SensorQuantization, 0.0, -9000.0, 50.0), Verdict::Named, 0.0);
        assert_eq!(outpredicted_by(&[lattice, leaves], 0, 10.0), None);
    }

    /// A named appendage's floor is dropped from its label where the same mode at another
    /// floor fits within the threshold in sample, whatever that one's verdict; told apart, the
    /// label keeps it.
    #[test]
    fn an_appendage_floor_not_told_apart_is_not_claimed() {
        let at = |floor: &str, in_sample: f64, verdict: Verdict| {
            let mut c = passing(EffectKind::UnmodeledMode, 20.0, -20.0, 3.1);
            c.label = format!("unmodeled_mode({floor}, 15.81 Hz)");
            c.parameters = vec![EffectParameter {
                name: format!("appendage_frequency_{floor}"),
                value: 15.81,
                std_error: Some(0.1),
            }];
            c.evidence.in_sample = in_sample;
            c.verdict = verdict;
            c
        };
        let named = at("q1", 27.7, Verdict::Named);
        let close = at("q2", 28.0, Verdict::Unresolved);
        let far = at("q3", 12.0, Verdict::Weak);
        let label = floor_untold(&[named.clone(), close.clone(), far.clone()], 0, 10.0);
        assert_eq!(label.as_deref(), Some("unmodeled_mode(15.81 Hz; at q1 or q2)"));
        // The floor told apart: kept. A failed refit does not count.
        assert_eq!(floor_untold(&[named.clone(), far], 0, 10.0), None);
        let failed = Candidate { verdict: Verdict::Failed("no".into()), ..close };
        assert_eq!(floor_untold(&[named, failed], 0, 10.0), None);
        // Not an appendage: nothing to drop.
        let ringing = passing(EffectKind::UnmodeledMode, 20.0, -20.0, 3.1);
        assert_eq!(floor_untold(&[ringing], 0, 10.0), None);
    }
}
