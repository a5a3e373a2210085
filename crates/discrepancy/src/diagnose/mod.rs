//! The discrepancy workflow: baseline fit → localise → refit with each candidate effect →
//! score every candidate by the same likelihood, in sample and on held-out blocks → name the
//! effect that earns its name, or say `none` and describe what remains.
//!
//! An effect is named only when all of these hold (each is a [`Verdict`] when it fails):
//! 1. its refit improves the in-sample likelihood beyond the BIC penalty of its parameters
//!    (ΔBIC < −10, "very strong" on the Kass–Raftery scale);
//! 2. its strength is resolved from "no effect" (|z| ≥ 3 with the fit's standard error, which
//!    carries the residual's correlation; for a limit, the standard error of its depth below
//!    the loop's demand, whose factor K_p is fitted too);
//! 3. fitted on alternate blocks of the record, it predicts the other blocks better than the
//!    baseline does, by more than the threshold (held-out log-likelihood, [`evidence`]);
//! 4. it still does so when the model's own linear parameters (modal damping, hub inertia,
//!    beam stiffness and mass) are freed as well: a parameter mismatch is not a missing effect;
//!    on a structure, those freed one at a time where the data determine them (its fixed
//!    parameters, such as its masses) are kept only where the account with them — the reference and what the evidence chooses against it — beats the
//!    account without them by the BIC ([`SecondaryMismatch`], module `secondary`): a fixed
//!    parameter freed takes up part of whatever is missing, and one effect that explains the
//!    record better than three masses is the simpler account;
//! 5. it removes at least a tenth of the structure the reference's residual holds beyond the
//!    measurement model (what an AR(20) predictor of the residual gains over the noise's own
//!    AR(1), [`evidence::structure`]): missing physics explains the structure it leaves, a
//!    stand-in only shaves it;
//! 6. a sensor effect removes at least half the structure on the one output it acts on
//!    ([`MIN_SENSOR_STRUCTURE_EXPLAINED`]): a sensor's error acts there alone; an unmodeled
//!    mode removes at least half of all of it ([`MIN_MODE_STRUCTURE_EXPLAINED`]): a mode is
//!    linear, as the model is, and where it is what is missing it leaves little but noise; a
//!    cubic stiffness removes at least half of it too ([`MIN_SPRING_STRUCTURE_EXPLAINED`]):
//!    within one record's amplitudes the cubic is the leading term of any smooth symmetric
//!    spring;
//!    - and no candidate set aside by 5 or 6 as a stand-in beats it on both counts, predicting
//!      the held-out blocks better by the threshold and removing at least as large a share of
//!      the structure ([`Verdict::Outpredicted`]): what is missing is then accounted for better
//!      than by the chosen effect, and what accounts for it better only stands in for it;
//! 7. it gains more in sample, by at least [`RIVAL_MARGIN`] = 1 nat (2 ln B ≥ 2, the lower
//!    edge of "positive" evidence on the Kass–Raftery scale), than each of the model's own
//!    parameters not refitted (for the slewing rig also the beam's length and the hub's
//!    radius, and a linear spring at the hub the model lacks), refitted alone in its place
//!    ([`Rival`], [`Verdict::MatchedByMismatch`]): a wrong parameter is not a missing effect,
//!    and one parameter that explains as much as an effect of one to three is the simpler
//!    answer. So is one sensor's channel picking up another's signal, y_i + g·y_j (a wiring
//!    fault; the pair that best explains the reference's residual, charged ln p(p − 1) nats
//!    for being the best of p(p − 1), module `crosstalk`), and, on the slewing rig, one
//!    sensor's channel read late, y_i(t − τ_s) (a sampling skew or a filter's delay; the output
//!    whose rate best explains the residual, charged ln p, module `lag`). (For a sensor scale, the parameters
//!    that scale its output alone are its exact equivalents and reported as such, not tried.)
//!    Set against a named sensor scale, a rival of the model's own is also charged what its
//!    account asks of the model file beyond the scale's ([`Departures`]): each file value, and
//!    the sensor's calibration, taken as known to a relative tolerance τ
//!    ([`DiagnoseOptions::file_tolerance`], 5 %), a refit is charged
//!    Σ ln²(p̂/p_file)/(2(τ² + σ²)) nats over the reference's mismatch parameters, the rival and
//!    the calibration error (σ the relative standard error of p̂ in the refit). A gauge read
//!    4.6 % low and a beam 5 % longer whose EI/ρ and ρ move by a fifth to keep its modes and
//!    inertia explain one strain gauge alike; a beam 3 % longer than the file says is the other
//!    way round (the scale's refit moves EI/ρ and ρ, the length's restores them).
//! 8. a symmetric spring (a structure's `cubic_stiffness` at coordinate c, or the slewing rig's
//!    at the hub) is demanded neither to be asymmetric nor to change with time: refitted with
//!    k₂q_c² or with k₁′·t·q_c beside its k₃q_c³ and a symmetric k₅q_c⁵, neither term is
//!    determined while gaining the threshold and a tenth of the spring's own gain in sample, or
//!    lying 5 standard errors from zero
//!    ([`SpringForm`], [`Verdict::Asymmetric`], [`Verdict::TimeVarying`], module `spring`; the
//!    hub spring, whose free decay stays on one side of zero, for a loss of stiffness with time
//!    only, the change a warming servo shows). A
//!    stop, a contact or a gap on one side is stiffer one way than the other; a storey that
//!    degrades, or a motor whose torque constant fades as it warms, changes its stiffness with
//!    time, which one free decay's falling amplitude lets a hardening spring absorb — physics
//!    outside the catalog that a symmetric cubic would otherwise stand in for; the quintic
//!    takes up what a symmetric spring of another form leaves, so that only asymmetry, or
//!    change with time, is left for the term.
//! 9. on a forced record, an effect that acts through the dynamics (not a sensor's) removes at
//!    least [`FORCE_NOISE_SHARE`] (half) of what the noise on the recorded force accounts for
//!    in the residual its own refit leaves ([`Verdict::WithinForceNoise`], module
//!    `force_noise`; the noise is read from the residual's spectra, [`crate::frf::input_noise`]).
//!    The model is driven by the recorded force, noise and all, and a dry friction or a drag at
//!    the driven floor damps the small, quick response to that noise more than the large one to
//!    the force: it gains on a record with nothing missing but a clean force. A missing effect
//!    removes what it put there itself; a stand-in for the noise removes part of what the noise
//!    put there and leaves the rest.
//!
//! A named dry friction on the slewing rig is first set against a servo whose stiffness falls
//! with time: refitted with −k₁′·t·θ at the hub beside it (the hub spring's rate, module
//! `friction`), where k₁′ is a loss, determined, gains the threshold or lies 5 standard errors
//! from zero, and gains a tenth of what the friction explains, the friction stands in for a
//! motor whose torque constant fades as it warms (outside the catalog), which also takes torque
//! away as the record goes on: its verdict is [`Verdict::TimeVarying`] and nothing is named. (True dry frictions that settle act on the
//! rate the other way, as a stiffness that grows as the motion dies.) On a structure a named
//! friction is set against a stiffness at its coordinate that changes with time, −k₁′·t·q_c:
//! where k₁′, determined, gains more beside the friction than the friction itself gained (and
//! the threshold), the friction stands in for a storey that degrades.
//!
//! A structure force that is named (a spring, a drag, a dry friction) must then explain the
//! record better, by the threshold in sample, than its rival account: no such force, but a
//! linear stiffness at one of the coordinates changing with time by a law of its own,
//! Δk(t)·q_j piecewise linear through (0, 0) and eight evenly spaced times, the best of every
//! coordinate's ([`TimeLaw`], module `time_law`; where it does not, [`Verdict::TimeVarying`]).
//! A storey that loses stiffness early and settles, or drops in a step, is not a rate k₁′·t,
//! and a spring's change with amplitude follows it as a free decay dies out; a drag at another
//! floor took up a storey degrading under a shaking. What only the force holds is what no law
//! in time makes: a spring's distortion within each cycle, a damping that changes with the
//! amplitude.
//!
//! A mode named on a structure (ringing in the outputs, or an appendage at a coordinate) must
//! likewise explain the record better, by the threshold in sample, than a linear damper at every
//! coordinate refitted at once ([`DampingRival`], module `damping`; where it does not,
//! [`Verdict::DampingDistribution`]): an appendage beside a modelled mode damps it as a tuned
//! mass does, and so stands in for damping distributed otherwise than the model's form gives.
//!
//! A named dry friction on the slewing rig is then refitted with a static peak beside it,
//! τ = −(F_c + ΔF e^{−(θ̇/v_st)²}) tanh(θ̇/v_s) (Stribeck; Armstrong-Hélouvry, Dupont & Canudas de
//! Wit, Automatica 30(7), 1994): where ΔF and v_st are determined and the peak gains at least
//! the threshold in sample, the named friction carries them ([`StaticPeak`], module
//! `friction`; F_c beside them must be determined too); otherwise it stays Coulomb's constant
//! level. The name does not change.
//!
//! A named saturation on the slewing rig is likewise refitted with the knee n of its limiter
//! x/(1 + |x/L|ⁿ)^{1/n} free (the catalog's is n = 8; n = 2 a soft limit, n → ∞ a clamp):
//! where L is determined, n is determined or at least 50 (a clamp), and the knee gains at least
//! the threshold in sample, the named saturation carries it ([`SaturationKnee`], module `saturation`). The name does not change.
//!
//! Of the candidates that pass, the one with the most held-out evidence is named; among those
//! whose held-out gains lie within the threshold of the best (not told apart), the one whose
//! strength is resolved by the most standard errors. A candidate that makes a further claim
//! than a passing sibling is named only where the data make it: a voltage limit, which says
//! which quantity the amplifier limits (so the back-EMF acts beyond it), only where its held-out
//! gain leads the current limit's by the threshold; otherwise the broader
//! `amplifier_saturation` (module `named`).
//!
//! Sensor quantization is a measurement model, not a force: it is named when the raw readings
//! of a sensor lie on a lattice while the signal moves, with a step comparable to the noise or
//! larger ([`crate::quantization`]).

mod answer;
mod assess;
pub mod catalog;
mod crosstalk;
mod damping;
pub mod evidence;
mod force_noise;
mod friction;
mod lag;
mod mismatch;
mod named;
mod options;
mod quantized;
mod report;
mod residual;
mod rivals;
mod run;
mod saturation;
mod schedule;
mod score;
mod secondary;
mod spring;
mod time_law;

pub use answer::{
    AddedTerm, Candidate, DampingRival, Departures, Diagnosis, EffectParameter, Evidence, Moved,
    RIVAL_MARGIN, Rival, SaturationKnee, ScaleChoice, SecondaryMismatch, SpringForm, SpringTerm, StaticPeak,
    TimeLaw, Verdict,
};
pub use force_noise::FORCE_NOISE_SHARE;
pub use options::{
    DEFAULT_FILE_TOLERANCE, DEFAULT_THRESHOLD, DiagnoseOptions, MIN_MODE_STRUCTURE_EXPLAINED,
    MIN_SENSOR_STRUCTURE_EXPLAINED, MIN_SPRING_STRUCTURE_EXPLAINED, MIN_STRUCTURE_EXPLAINED,
    min_structure_explained,
};
pub use report::DiagnosisReport;
pub use rivals::SAME_FIT;

pub use residual::{Band, ResidualStructure};

use crate::WorkflowError;
use answer::last_error;
use catalog::Trial;
use evidence::NoiseModel;
use mem::Measurement;
use models::{FitOutcome, Model, align};
use named::{choose, polish, scale_equivalents_of};
use plant::EffectKind;
use run::{Fitted, Folds};

/// Progress of a diagnosis (argmin's `Observe`): the CLI draws a bar from it.
pub trait Observe: Sync {
    /// `done` of `total` fits of the current `stage` are finished.
    fn progress(&self, _stage: &str, _done: usize, _total: usize) {}
}

/// An observer that ignores progress.
pub struct Quiet;
impl Observe for Quiet {}

/// Runs the workflow without progress reports.
///
/// # Errors
/// As [`diagnose_observed`].
pub fn diagnose(
    model: &Model,
    data: &Measurement,
    options: &DiagnoseOptions,
) -> Result<Diagnosis, WorkflowError> {
    diagnose_observed(model, data, options, &Quiet)
}

/// Runs the workflow on a raw record (decimated here if the options say so), reporting progress.
///
/// # Errors
/// Column mismatches and failures of the baseline fit (candidates that fail are reported, not
/// fatal).
pub fn diagnose_observed(
    model: &Model,
    raw: &Measurement,
    options: &DiagnoseOptions,
    observer: &dyn Observe,
) -> Result<Diagnosis, WorkflowError> {
    if model.as_slewing().is_some() && !model.input_names().is_empty() {
        return Err(WorkflowError::Driven { inputs: model.input_names().join(", ") });
    }
    let tolerance = options.file_tolerance;
    if !(tolerance.is_finite() && tolerance > 0.0) {
        return Err(WorkflowError::Setting {
            field: "file_tolerance",
            value: tolerance,
            need: "a positive relative tolerance (0.05 for 5 %)",
        });
    }
    let wrapped = model;
    // A spike or a dropout in one reading is neither physics nor the measurement model's noise.
    let (raw, glitches) = crate::glitch::set_aside(align(wrapped, raw)?)?;
    let data = match options.decimate {
        Some(r) if r > 1 => raw.decimate(r)?,
        _ => raw.clone(),
    };
    let folds = Folds::new(&data);
    observer.progress("baseline", 0, 2);
    let baseline = Fitted::converged(wrapped, &data, &options.free, 100)?;
    observer.progress("baseline", 1, 2);
    // The reference every candidate is scored against: the baseline with the model's own
    // linear parameters free too, so that a mismatch is absorbed before any effect is tried.
    let mismatch = mismatch::mismatch_parameters(model, &options.free);
    let from = mismatch::with_mismatch_bounds(baseline.outcome.fitted.clone());
    let all_free: Vec<String> = options.free.iter().chain(&mismatch).cloned().collect();
    let trial_reference = Fitted::full(&from, &data, &all_free, 100)?;
    // The mismatch parameters the data determine stay free; the others keep the model file's
    // values (a flat direction, or one run to its bound, only misleads every refit after it),
    // and the reference is refitted with the determined ones from the baseline.
    let mut mismatch: Vec<String> =
        mismatch.into_iter().filter(|name| mismatch::determined(&trial_reference.outcome, name)).collect();
    let mut reference_free: Vec<String> = options.free.iter().chain(&mismatch).cloned().collect();
    let mut reference = if reference_free.len() == all_free.len() {
        trial_reference
    } else {
        Fitted::full(&from, &data, &reference_free, 100)?
    };
    // The secondary ones join one at a time, only where the data determine them and they leave
    // the others determined (a mass per length freed beside two inertias can make all three
    // undetermined, and then none would absorb an inertia mismatch).
    let primary = (Fitted { outcome: reference.outcome.clone() }, reference_free.clone());
    let mut secondary_joined: Vec<String> = Vec::new();
    for name in mismatch::secondary_mismatch_parameters(model, &options.free) {
        let mut free = reference_free.clone();
        free.push(name.clone());
        if let Ok(fit) = Fitted::full(&from, &data, &free, 100)
            && mismatch.iter().chain([&name]).all(|n| mismatch::determined(&fit.outcome, n))
            && last_error(&fit.outcome) <= last_error(&reference.outcome)
        {
            reference = fit;
            reference_free = free;
            mismatch.push(name.clone());
            secondary_joined.push(name);
        }
    }
    observer.progress("baseline", 2, 2);
    // The secondary mismatch parameters weighed by the BIC of the whole account: with them and
    // what the evidence chooses against them, or without them (module `secondary`).
    let primary_mismatch: Vec<String> =
        mismatch.iter().filter(|n| !secondary_joined.contains(n)).cloned().collect();
    let assess = |r: &secondary::Reference| {
        assess::Assess {
            reference: &r.0,
            free: &r.1,
            raw: &raw,
            data: &data,
            folds: &folds,
            options,
            observer,
        }
        .run()
    };
    // The evidence's choice, and between two sensor scales that fit alike the one that asks
    // less of the file, as the named effect is chosen below.
    let first_choice = |a: &assess::Assessment, with: bool| {
        let listed = if with { &mismatch } else { &primary_mismatch };
        choose(&a.candidates, options.threshold).map(|i| {
            rivals::closer_to_file(&a.candidates, i, model, listed, tolerance, options.threshold)
                .map_or(i, |(j, _)| j)
        })
    };
    // On a structure only: the slewing rig's mass per length stays as it joined (weighed there
    // too, it moved answers both ways on the slewing studies; docs/diagnose.md).
    let joined = if model.as_structure().is_some() { secondary_joined.clone() } else { Vec::new() };
    let settled = secondary::Settle {
        full: (reference, reference_free),
        primary,
        joined: &joined,
        data: &data,
        assess: &assess,
        choose: &first_choice,
    }
    .settle()?;
    let ((reference, reference_free), assessed, secondary) =
        (settled.reference, settled.assessed, settled.weighed);
    let mismatch = if settled.kept { mismatch } else { primary_mismatch };
    let assess::Assessment {
        localisation,
        trials,
        mut candidates,
        noise,
        reference_likelihoods,
        force_noise,
    } = assessed;
    let likelihoods = |outcome: &FitOutcome| noise.log_likelihoods(&outcome.first().residual(), None);
    let mismatch_gain = evidence::gain(&reference_likelihoods, &likelihoods(&baseline.outcome));
    // A named effect is set against the model's own parameters it could stand for: if one of
    // them, refitted alone, explains the data as well (in sample, to within a nat), a parameter
    // mismatch is the simpler answer and nothing is named. The other candidates are not named
    // in its place: they were scored against a reference without that mismatch, which may
    // explain what they do. A sensor scale's exact equivalents (the parameters that scale its
    // output alone) are reported as such and not tried. A lattice is a measurement fact, not
    // set against a mismatch.
    let mut scale_equivalents = Vec::new();
    let mut rivals = Vec::new();
    let mut spring = None;
    let mut time_law = None;
    let mut damping = None;
    let mut static_peak = None;
    let mut fading = None;
    let mut saturation_knee = None;
    let mut scale_choice = None;
    let chosen = (|| {
        let mut i = choose(&candidates, options.threshold)?;
        // Two sensor scales that fit alike: the one that asks less of the model file.
        if let Some((j, choice)) =
            rivals::closer_to_file(&candidates, i, model, &mismatch, tolerance, options.threshold)
        {
            i = j;
            scale_choice = Some(choice);
        }
        candidates[i].verdict = Verdict::Named;
        // The named effect must predict what is missing at least as well as any stand-in does.
        if named::outpredicted_by(&candidates, i, options.threshold).is_some() {
            candidates[i].verdict = Verdict::Outpredicted;
            return None;
        }
        let Some(trial) = trials.get(i) else { return Some(i) };
        polish(&mut candidates[i], trial, &reference_free, &data);
        if let (EffectKind::SensorScale, Some(output), Some(fitted)) =
            (trial.kind, trial.output, candidates[i].model.as_ref())
        {
            let refitted: Vec<String> = reference_free.iter().chain(&trial.freed).cloned().collect();
            scale_equivalents = scale_equivalents_of(fitted, &data, output, &refitted);
        }
        let search = rivals::Rivals {
            reference: &reference.outcome.fitted,
            free: &reference_free,
            exclude: &scale_equivalents,
            also: crosstalk::screened(&reference.outcome, &noise, trial.output)
                .into_iter()
                .chain(lag::screened(&reference.outcome, &noise, data.interval()))
                .collect(),
            to_match: candidates[i].evidence.in_sample - options.threshold,
            file: model,
            mismatch: &mismatch,
            effect: rivals::Account::of_scale(&candidates[i], model, &mismatch, tolerance),
            tolerance,
        };
        rivals = search.find(&data, |o| evidence::gain(&likelihoods(o), &reference_likelihoods));
        if rivals.iter().any(|r| r.unseats(candidates[i].evidence.in_sample)) {
            candidates[i].verdict = Verdict::MatchedByMismatch;
            return None;
        }
        // A symmetric spring whose data demand an asymmetric part (a one-sided force) or a
        // stiffness that changes with time (a degradation): physics outside the catalog.
        let gain = |o: &FitOutcome| evidence::gain(&likelihoods(o), &reference_likelihoods);
        let test = named::FormTest {
            reference: &reference.outcome.fitted,
            free: &reference_free,
            data: &data,
            threshold: options.threshold,
            gain: &gain,
        };
        spring = spring::form(&candidates[i], trial, &test);
        if let Some(form) = &spring {
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
        static_peak = friction::static_peak(&mut candidates[i], trial, &test);
        // And, in that form, does a servo that loses stiffness with time explain it (a torque
        // constant that fades, outside the catalog)?
        fading = friction::fading(&candidates[i], trial, &test);
        if fading.as_ref().is_some_and(|t| t.demanded) {
            candidates[i].verdict = Verdict::TimeVarying;
            return None;
        }
        // A structure force set against a stiffness that changes with time by a law of its own,
        // at any coordinate: it must explain the record better (module `time_law`).
        let effect_gain = match &spring {
            Some(form) => Some(form.gain),
            None => candidates[i].outcome.as_ref().map(&gain),
        };
        time_law = effect_gain.and_then(|g| time_law::rival(trial, &test, g));
        if time_law.as_ref().is_some_and(|law| law.as_well) {
            candidates[i].verdict = Verdict::TimeVarying;
            return None;
        }
        // A structure's mode set against the model's damping distributed otherwise: a linear
        // damper at every coordinate (module `damping`).
        damping = effect_gain.and_then(|g| damping::rival(trial, &test, g));
        if damping.as_ref().is_some_and(|d| d.as_well) {
            candidates[i].verdict = Verdict::DampingDistribution;
            return None;
        }
        // A named saturation: is its limit softer than the catalog's limiter?
        saturation_knee = saturation::knee(&mut candidates[i], trial, &test);
        // A named appendage's floor is claimed only where the data tell it from the same mode
        // at another floor.
        if let Some(label) = named::floor_untold(&candidates, i, options.threshold) {
            candidates[i].label = label;
        }
        Some(i)
    })();
    // The equivalents belong to a named scale only; the rivals to a named effect or to the one
    // they unseated.
    if chosen.is_none_or(|i| candidates[i].kind != EffectKind::SensorScale) {
        scale_equivalents.clear();
        scale_choice = None;
    }
    // Named first, then by held-out evidence, then in-sample.
    let mut indexed: Vec<(usize, Candidate)> = candidates.into_iter().enumerate().collect();
    indexed.sort_by(|(i, a), (j, b)| {
        (Some(*j) == chosen).cmp(&(Some(*i) == chosen)).then_with(|| {
            let key = |c: &Candidate| c.evidence.held_out.unwrap_or(f64::NEG_INFINITY);
            key(b).total_cmp(&key(a)).then(a.evidence.delta_bic.total_cmp(&b.evidence.delta_bic))
        })
    });
    let chosen = chosen.map(|_| 0);
    let candidates: Vec<Candidate> = indexed.into_iter().map(|(_, c)| c).collect();
    let residual = ResidualStructure::of(&reference.outcome);
    Ok(Diagnosis {
        baseline: baseline.outcome,
        reference: reference.outcome,
        localisation,
        residual,
        mismatch_parameters: mismatch,
        mismatch_gain,
        secondary,
        noise,
        candidates,
        chosen,
        threshold: options.threshold,
        scale_equivalents,
        scale_choice,
        force_noise,
        rivals,
        spring,
        time_law,
        damping,
        static_peak,
        fading,
        saturation_knee,
        glitches,
    })
}

fn failed(trial: &Trial, why: String) -> Candidate {
    Candidate {
        kind: trial.kind,
        sensor: trial.sensor,
        label: trial.label.clone(),
        replaces: trial.replaces,
        parameters: Vec::new(),
        evidence: Evidence::default(),
        lattice: None,
        verdict: Verdict::Failed(why),
        model: None,
        outcome: None,
    }
}

/// The parameter names of a trial's strength (for tests and reports).
pub fn strength_parameters(trial: &Trial) -> Vec<String> {
    trial.strength.iter().flat_map(|s| s.names()).map(str::to_string).collect()
}
