//! The discrepancy workflow: baseline fit → localise → refit with each candidate effect →
//! score every candidate by the same likelihood, in sample and on held-out blocks → name the
//! effect that earns its name, or say `none` and describe what remains.
//!
//! Every candidate is refitted from where the reference ends, its effect sized by that model;
//! where a free parameter of the reference ran more than a decade from the model file's value
//! (a linear fit driven off by a strong nonlinearity), from the file's values too, and the
//! better refit is kept (`run::Restart`; the parameters are reported as [`RanOff`]).
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
//!    record better than three masses is the simpler account — a candidate the held-out
//!    blocks do not tell from the choice is weighed without them too (a scale on either gauge,
//!    when the masses take up their common part); on the slewing rig the beam's mass per length
//!    stays as it joined, and where nothing is named a sensor scale that explains the record as
//!    well in its place is reported ([`ScaleInPlace`]);
//! 5. it removes at least a tenth of the structure the reference's residual holds beyond the
//!    measurement model (what an AR(20) predictor of the residual gains over the noise's own
//!    AR(1), [`evidence::structure`]): missing physics explains the structure it leaves, a
//!    stand-in only shaves it — unless what it leaves is less than it gains in sample, where the
//!    residual holds too little structure to judge it by ([`superficial`]);
//! 6. a sensor effect removes at least half the structure on the one output it acts on
//!    ([`MIN_SENSOR_STRUCTURE_EXPLAINED`]; on a record whose recorded force has noise, beyond
//!    the better of the measurement model and the force's noise read from each residual
//!    itself): a sensor's error acts there alone; an unmodeled
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
//!    lying 5 standard errors from zero (refitted by the scored likelihood itself where the
//!    noise is coloured beyond AR(1), so that the standard error is that likelihood's)
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
//!    put there and leaves the rest. An effect that gains more than [`FORCE_NOISE_EXEMPT`] nats
//!    held out is not screened: the screen weighs powers, the evidence likelihoods, and a narrow
//!    band the noise leaves quiet can hold a strong effect whose power is small beside the
//!    noise's response at the modelled modes.
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
//! A mode named on a structure (ringing in the outputs, or an appendage at a coordinate), and a
//! drag or a dry friction named there, must likewise explain the record better, by the
//! threshold in sample, than a linear damper at every coordinate refitted at once
//! ([`DampingRival`], module `damping`; where it does not, [`Verdict::DampingDistribution`]):
//! an appendage beside a modelled mode damps it as a tuned mass does, and a drag's exponent
//! bends the damping with the response's amplitude, so either can stand in for damping
//! distributed otherwise than the model's form gives.
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
//! strength is resolved by the most standard errors — within a standard error of it, the one
//! of fewest parameters, and between bodies hung at different floors the one that fits the
//! record best in sample (its floor a claim the label withholds where it is not told). A
//! sensor's offset and its drift are two laws of one error, its zero: where one is chosen and
//! the other, set aside only by step 6, predicts the held-out blocks better by the threshold,
//! the other is named (module `named`).
//! A candidate that makes a further claim
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
mod checks;
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
mod reference;
mod report;
mod residual;
mod rivals;
mod run;
mod saturation;
mod schedule;
mod score;
mod secondary;
mod spring;
mod strength;
mod time_law;

pub use answer::{
    AddedTerm, Candidate, DampingRival, Departures, Diagnosis, EffectParameter, Evidence, Moved,
    RIVAL_MARGIN, Rival, SaturationKnee, ScaleChoice, ScaleInPlace, SecondaryMismatch, SpringForm,
    SpringTerm, StaticPeak, TimeLaw, Verdict,
};
pub use force_noise::{
    FORCE_NOISE_EXEMPT, FORCE_NOISE_SHARE, MAX_PREDICTOR_ORDER, PREDICTOR_CONVERGED, PREDICTOR_ORDER,
};
pub use options::{
    DEFAULT_FILE_TOLERANCE, DEFAULT_THRESHOLD, DiagnoseOptions, MIN_MODE_STRUCTURE_EXPLAINED,
    MIN_SENSOR_STRUCTURE_EXPLAINED, MIN_SPRING_STRUCTURE_EXPLAINED, MIN_STRUCTURE_EXPLAINED,
    min_structure_explained, superficial,
};
pub use report::DiagnosisReport;
pub use rivals::SAME_FIT;
pub use run::RanOff;

pub use residual::{Band, ResidualStructure};

use crate::WorkflowError;
use catalog::Trial;
use evidence::NoiseModel;
use mem::Measurement;
use models::{FitOutcome, Model, align};
use named::choose;
use run::Folds;

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
    // A spike or a dropout in one reading is neither physics nor the measurement model's noise.
    let (raw, glitches) = crate::glitch::set_aside(align(model, raw)?)?;
    let data = match options.decimate {
        Some(r) if r > 1 => raw.decimate(r)?,
        _ => raw.clone(),
    };
    let folds = Folds::new(&data);
    let reference::References { baseline, reference, free: reference_free, mismatch, primary, joined } =
        reference::fit(model, &data, options, observer)?;
    // The secondary mismatch parameters weighed by the BIC of the whole account: with them and
    // what the evidence chooses against them, or without them (module `secondary`).
    let primary_mismatch: Vec<String> = mismatch.iter().filter(|n| !joined.contains(n)).cloned().collect();
    let assess = |r: &secondary::Reference| {
        assess::Assess {
            file: model,
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
    // too, it moved answers both ways on the slewing studies; docs/diagnose.md). Where nothing
    // is named there, a sensor's scale set in its place is reported ([`ScaleInPlace`]).
    let (joined, kept_as_joined) = if model.as_structure().is_some() {
        (joined, None)
    } else {
        let copy = || (run::Fitted { outcome: primary.0.outcome.clone() }, primary.1.clone());
        (Vec::new(), (!joined.is_empty()).then(|| (copy(), joined)))
    };
    let settled = secondary::Settle {
        full: (reference, reference_free),
        primary,
        joined: &joined,
        data: &data,
        assess: &assess,
        choose: &first_choice,
        threshold: options.threshold,
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
        ran_off,
        coloured,
    } = assessed;
    let likelihoods = |outcome: &FitOutcome| noise.log_likelihoods(&outcome.first().residual(), None);
    let mismatch_gain = evidence::gain(&reference_likelihoods, &likelihoods(&baseline.outcome));
    // The named effect, set against every rival account (module `checks`). The other
    // candidates are not named in its place where it falls: they were scored against a
    // reference without the rival, which may explain what they do. A lattice is a measurement
    // fact, not set against a mismatch.
    let found = checks::Checks {
        model,
        options,
        mismatch: &mismatch,
        reference: &reference,
        free: &reference_free,
        trials: &trials,
        data: &data,
        noise: &noise,
        reference_likelihoods: &reference_likelihoods,
        coloured: coloured.as_ref(),
    }
    .run(&mut candidates);
    // On the slewing rig, where nothing is named: a sensor's scale set in place of the
    // secondary parameters that joined ([`ScaleInPlace`]), reported, not named.
    let scale_in_place = kept_as_joined.filter(|_| found.chosen.is_none()).and_then(|(primary, joined)| {
        secondary::InPlace {
            candidates: &candidates,
            trials: &trials,
            full: &reference,
            full_free: &reference_free,
            primary: &primary,
            joined: &joined,
            noise: &noise,
            data: &data,
            min_strength_z: options.min_strength_z,
        }
        .find()
    });
    let chosen = found.chosen;
    // Named first, then by held-out evidence, then in-sample.
    let mut indexed: Vec<(usize, Candidate)> = candidates.into_iter().enumerate().collect();
    indexed.sort_by(|(i, a), (j, b)| {
        (Some(*j) == chosen).cmp(&(Some(*i) == chosen)).then_with(|| {
            let key = |c: &Candidate| c.evidence.held_out.unwrap_or(f64::NEG_INFINITY);
            key(b).total_cmp(&key(a)).then(a.evidence.delta_bic.total_cmp(&b.evidence.delta_bic))
        })
    });
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
        scale_in_place,
        noise,
        candidates,
        chosen: chosen.map(|_| 0),
        threshold: options.threshold,
        scale_equivalents: found.scale_equivalents,
        scale_choice: found.scale_choice,
        force_noise,
        ran_off,
        rivals: found.rivals,
        spring: found.spring,
        time_law: found.time_law,
        damping: found.damping,
        static_peak: found.static_peak,
        fading: found.fading,
        saturation_knee: found.saturation_knee,
        glitches,
    })
}

fn failed(trial: &Trial, why: String) -> Candidate {
    Candidate {
        kind: trial.kind,
        sensor: trial.sensor,
        output: trial.output,
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
