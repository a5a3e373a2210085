//! The answer of a diagnosis: each candidate with its evidence and [`Verdict`], and the
//! [`Diagnosis`] that holds them, the named one first.

use super::ResidualStructure;
use super::evidence::NoiseModel;
use crate::localise::Localisation;
use crate::quantization::Lattice;
use models::{FitOutcome, Model};
use plant::{EffectKind, Sensor};
use serde::Serialize;

mod accounts;
mod forms;

pub use accounts::{AddedTerm, Departures, Moved, RIVAL_MARGIN, Rival, ScaleInPlace};
pub use forms::{DampingRival, SaturationKnee, SpringForm, SpringTerm, StaticPeak, TimeLaw};

/// A parameter of an effect, as fitted.
#[derive(Clone, Debug, Serialize)]
pub struct EffectParameter {
    /// Parameter name (`current_limit`, `offset_theta`, …).
    pub name: String,
    /// Fitted value.
    pub value: f64,
    /// Standard error, where the data determine it.
    pub std_error: Option<f64>,
}

/// The evidence for one candidate, every figure a difference of the same log-likelihood
/// ([`super::evidence`]) to the reference's (the baseline with the model's own parameters free).
#[derive(Clone, Debug, Default, Serialize)]
pub struct Evidence {
    /// In-sample log-likelihood gain (nats).
    pub in_sample: f64,
    /// ΔBIC = −2·in_sample + k ln m (negative is better).
    pub delta_bic: f64,
    /// Held-out log-likelihood gain over both folds (nats), if scored.
    pub held_out: Option<f64>,
    /// The strength's distance from "no effect" in standard errors (smallest over its strength
    /// parameters).
    pub strength_z: f64,
    /// 1 − ‖Y_error‖/baseline ‖Y_error‖.
    pub reduction: f64,
    /// Smallest Ljung–Box p-value of the refit's residuals over the outputs.
    pub whiteness_p: f64,
    /// The share of the reference residual's predictable structure ([`super::evidence::structure`])
    /// that the refit removes: 1 − structure(refit)/structure(reference).
    pub structure_explained: f64,
    /// The structure (nats, [`super::evidence::structure`]) the reference's residual holds
    /// beyond the measurement model, of which `structure_explained` is the share removed.
    pub structure_held: f64,
    /// The structure (nats) the refit's residual leaves.
    pub structure_left: f64,
    /// For a sensor effect, the same share on the one output it acts on (1 where the
    /// reference holds less than 10 nats of structure there); below
    /// [`super::MIN_SENSOR_STRUCTURE_EXPLAINED`] the effect is not named
    /// ([`Verdict::LeavesItsOutput`]).
    pub sensor_structure_explained: Option<f64>,
}

/// Why a candidate was or was not named.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(rename_all = "snake_case", tag = "verdict", content = "detail")]
pub enum Verdict {
    /// It earns its name: the answer.
    Named,
    /// It passed every test, but another candidate has more held-out evidence.
    Outscored,
    /// Its in-sample gain does not pay for its parameters (ΔBIC ≥ −bic_threshold).
    Weak,
    /// Its strength is not resolved from "no effect".
    Unresolved,
    /// It was not among the best candidates scored out of sample.
    NotShortlisted,
    /// Fitted on half the record, it does not predict the other half better by the threshold.
    NotPredictive,
    /// It predicts better, but leaves the reference residual's predictable structure nearly as
    /// it was (it removes less than [`super::min_structure_explained`] of its kind: a tenth, a
    /// cubic stiffness less than [`super::MIN_SPRING_STRUCTURE_EXPLAINED`] and an unmodeled
    /// mode less than [`super::MIN_MODE_STRUCTURE_EXPLAINED`], half): it shaves a misfit rather
    /// than explaining it.
    Superficial,
    /// A sensor effect that predicts better but leaves most of the structure on the one output
    /// it acts on (it removes less than [`super::MIN_SENSOR_STRUCTURE_EXPLAINED`] of it): what
    /// is missing acts on that output through the dynamics, and the sensor's error only shaves it.
    LeavesItsOutput,
    /// An effect that a mismatch of one of the model's own parameters (or a linear spring at
    /// the slewing rig's hub), refitted alone in its place, explains as well, to within
    /// [`RIVAL_MARGIN`] ([`Rival`]): one wrong parameter is the simpler answer than a missing
    /// effect, so nothing is named.
    MatchedByMismatch,
    /// A symmetric spring whose data demand an asymmetric part beside it ([`SpringForm`]): the
    /// missing restoring force is one-sided, outside the catalog, so nothing is named.
    Asymmetric,
    /// A symmetric spring whose data demand a stiffness that changes with time beside it
    /// ([`SpringForm`]): the stiffness changes during the record, not with amplitude — outside
    /// the catalog, so nothing is named.
    TimeVarying,
    /// Chosen by its held-out evidence, but a candidate set aside as a stand-in
    /// ([`Verdict::Superficial`], [`Verdict::LeavesItsOutput`]) predicts the held-out blocks
    /// better by the threshold and removes at least as much of the residual's structure: what
    /// is missing is accounted for better than by this effect, and what accounts for it better
    /// only stands in for it — physics outside the catalog, so nothing is named.
    Outpredicted,
    /// A mode the model lacks, or a drag or dry friction at a coordinate, that a linear damper
    /// at every coordinate, refitted at once, explains as well ([`DampingRival`]): the
    /// structure's damping is distributed otherwise than the model's form gives — a mismatch of
    /// its own damping, not a missing effect — so nothing is named.
    DampingDistribution,
    /// An effect acting through the dynamics, on a forced record whose recorded force is noisy,
    /// that removes less of the residual than [`super::FORCE_NOISE_SHARE`] of what the force's
    /// noise puts there ([`crate::frf::InputNoise`]): it may only take up the model's response to
    /// that noise, so nothing is named for it.
    WithinForceNoise,
    /// A lattice that is not there, or a step far below the noise.
    NoLattice,
    /// The refit failed (the message says why).
    Failed(String),
}

/// One candidate effect and its evidence.
#[derive(Clone, Debug, Serialize)]
pub struct Candidate {
    /// Its kind.
    #[serde(rename = "effect")]
    pub kind: EffectKind,
    /// The sensor, for a sensor effect.
    pub sensor: Option<Sensor>,
    /// The record's output (its column among the outputs) a sensor effect acts on.
    #[serde(skip)]
    pub output: Option<usize>,
    /// Catalog name with its target, e.g. `output_offset(theta)`.
    pub label: String,
    /// The effect of the model it takes the place of, for a swap of siblings.
    pub replaces: Option<EffectKind>,
    /// The effect's parameters.
    pub parameters: Vec<EffectParameter>,
    /// Its evidence.
    pub evidence: Evidence,
    /// The lattice, for sensor quantization.
    pub lattice: Option<Lattice>,
    /// The outcome.
    #[serde(flatten)]
    pub verdict: Verdict,
    /// The refitted model.
    #[serde(skip)]
    pub model: Option<Model>,
    /// The refit.
    #[serde(skip)]
    pub outcome: Option<FitOutcome>,
}

/// Where two sensor scales fit a record alike (in sample to within
/// [`SAME_FIT`](super::SAME_FIT), held out within the threshold): the record sees only the ratio
/// of the two sensors' readings when the model's own parameters that set the response's size are
/// refitted beside each (with a measured force, every mass and stiffness scaled together scales
/// every output), and one sensor reading high is the other reading low with the structure moved
/// to match. The data leave the two accounts equal, so what each asks of the model file decides
/// (its calibration error and its moves of the file's values, a log-normal prior of width τ on
/// each: the charge of a named scale's account, step 7) — the Bayesian choice between two models
/// of equal likelihood.
#[derive(Clone, Debug, Serialize)]
pub struct ScaleChoice {
    /// The scale named.
    pub named: String,
    /// What its account asks of the file (nats).
    pub named_charge: f64,
    /// The scale that fits alike.
    pub other: String,
    /// What that account asks of the file (nats).
    pub other_charge: f64,
}

/// The mismatch parameters the reference freed one at a time on a structure (its fixed
/// parameters), weighed by the BIC (module `secondary`): the account of
/// the data with them — the reference and what the evidence chose against it — against the
/// account without them. Not earned, the account without them was kept: every candidate was
/// scored against the reference without them.
#[derive(Clone, Debug, Serialize)]
pub struct SecondaryMismatch {
    /// The parameters.
    pub parameters: Vec<String>,
    /// The effect chosen against the reference with them (its label), if any.
    pub with: Option<String>,
    /// The effect of the account without them, if any: the same effect refitted, or what the
    /// evidence chose against that reference.
    pub without: Option<String>,
    /// The account with them less the one without, in sample (nats).
    pub gain: f64,
    /// The charge of the parameters the account with them has beyond the other's, k ln(m)/2
    /// over m residuals (nats; negative where it has fewer).
    pub charge: f64,
    /// Whether they gain more than their charge.
    pub earned: bool,
    /// Whether the reference kept them: where they are not earned, unless the account without
    /// them chose another effect than the one chosen with them (module `secondary`).
    pub kept: bool,
}

impl SecondaryMismatch {
    /// In words (the answer says it where they were left out).
    pub fn sentence(&self) -> String {
        let one = self.parameters.len() == 1;
        let account = |e: &Option<String>| e.clone().unwrap_or_else(|| "no effect".into());
        let why = if self.earned {
            // Earned, and left out all the same: the evidence, against the reference with them,
            // did not choose the effect it chose without them (module `secondary`).
            format!(
                "more than the {:.1} their charge asks, but against the reference with {} the evidence did not \
                 choose {}",
                self.charge,
                if one { "it" } else { "them" },
                account(&self.with)
            )
        } else {
            format!("less than the {:.1} their charge asks", self.charge)
        };
        format!(
            "the model's fixed {} freed with {} gain{} {:.1} nats over {} without {}, {why}: {} kept at the \
             file's value{}, and every candidate was scored against that model",
            self.parameters.join(", "),
            account(&self.with),
            if one { "s" } else { "" },
            self.gain,
            account(&self.without),
            if one { "it" } else { "them" },
            if one { "it is" } else { "they are" },
            if one { "" } else { "s" },
        )
    }
}

/// The answer of [`super::diagnose`].
#[derive(Clone, Debug)]
pub struct Diagnosis {
    /// The baseline fit (the parameters the user freed).
    pub baseline: FitOutcome,
    /// The reference: the baseline with the model's own parameters free too, what every
    /// candidate is scored against.
    pub reference: FitOutcome,
    /// Where it disagrees with the data.
    pub localisation: Localisation,
    /// What the baseline's residual holds beyond noise, and where.
    pub residual: ResidualStructure,
    /// The model's own parameters freed to tell a mismatch from a missing effect.
    pub mismatch_parameters: Vec<String>,
    /// In-sample gain of freeing them (nats): the reference's log-likelihood less the baseline's.
    pub mismatch_gain: f64,
    /// The mismatch parameters freed one at a time, weighed against the effect first chosen
    /// ([`SecondaryMismatch`]); `None` where there were none or nothing was chosen.
    pub secondary: Option<SecondaryMismatch>,
    /// On the slewing rig, where nothing is named and a secondary mismatch parameter joined the
    /// reference: a sensor's scale that explains the record as well in its place, if one does.
    pub scale_in_place: Option<ScaleInPlace>,
    /// The measurement model every candidate was scored under.
    pub noise: NoiseModel,
    /// All candidates, named first, then by evidence.
    pub candidates: Vec<Candidate>,
    /// Index of the named candidate.
    pub chosen: Option<usize>,
    /// The held-out gain an effect needed (nats).
    pub threshold: f64,
    /// For a named sensor scale: the model's parameters (not refitted) that scale that output
    /// alone, so that the data cannot tell the named calibration error from an error in them.
    pub scale_equivalents: Vec<String>,
    /// For a named sensor scale chosen between two that fit alike: what each asks of the model
    /// file ([`ScaleChoice`]).
    pub scale_choice: Option<ScaleChoice>,
    /// On a forced record, the noise estimated on its recorded inputs and what it accounts for
    /// in the best-fitting residual ([`crate::frf::input_noise`]).
    pub force_noise: Option<crate::frf::InputNoise>,
    /// The reference's free parameters that ended more than a decade from the model file's
    /// values (off their bounds): every candidate was then refitted from the file's values too,
    /// and the better refit kept ([`super::RanOff`]).
    pub ran_off: Vec<super::RanOff>,
    /// For a named effect, or the one they unseated: the model's parameters that, refitted
    /// alone instead, explain the data as well ([`Rival`]).
    pub rivals: Vec<Rival>,
    /// For a `cubic_stiffness` (a structure's, or the slewing rig's hub spring) that was named,
    /// or set aside as [`Verdict::Asymmetric`] or [`Verdict::TimeVarying`]: its form tested
    /// beside it ([`SpringForm`]). `None` otherwise,
    /// also when a rival unseated the spring first (the test is not run then).
    pub spring: Option<SpringForm>,
    /// For a structure force (`cubic_stiffness`, `quadratic_drag`, `coulomb_friction`) named, or
    /// set aside for it as [`Verdict::TimeVarying`]: the rival of a linear stiffness that changes
    /// with time by a law of its own ([`TimeLaw`]). `None` otherwise, also where a test before
    /// it set the force aside.
    pub time_law: Option<TimeLaw>,
    /// The rival of a named mode, drag or dry friction on a structure, if one was named: a
    /// linear damper at every coordinate ([`DampingRival`]); where it explains the record as
    /// well, the effect was set aside as [`Verdict::DampingDistribution`].
    pub damping: Option<DampingRival>,
    /// For a named `coulomb_friction` on the slewing rig: its static peak refitted beside it
    /// ([`StaticPeak`]); `None` otherwise, or when a refit failed.
    pub static_peak: Option<StaticPeak>,
    /// For a `coulomb_friction` on the slewing rig that was named, or set aside as
    /// [`Verdict::TimeVarying`]: a servo stiffness that falls with time, k₁′·t·θ at the hub,
    /// refitted beside it (module `friction`); `None` otherwise, or when a refit failed.
    pub fading: Option<SpringTerm>,
    /// The knee of a named saturation on the slewing rig ([`SaturationKnee`]); `None`
    /// otherwise, or when a refit failed.
    pub saturation_knee: Option<SaturationKnee>,
    /// Readings set aside as glitches before anything was fitted (module [`crate::glitch`]).
    pub glitches: Vec<crate::glitch::Glitch>,
}

impl Diagnosis {
    /// The named effect's catalog name, or `"none"`.
    pub fn effect(&self) -> &str {
        self.chosen.map_or("none", |i| self.candidates[i].kind.name())
    }
    /// The named candidate.
    pub fn named(&self) -> Option<&Candidate> {
        self.chosen.map(|i| &self.candidates[i])
    }
    /// The augmented model (the reference's fitted model if none is named).
    pub fn augmented(&self) -> &Model {
        self.named().and_then(|c| c.model.as_ref()).unwrap_or(&self.reference.fitted)
    }
    /// The augmented model's error (the reference's if none is named).
    pub fn augmented_error(&self) -> f64 {
        self.named().and_then(|c| c.outcome.as_ref()).map_or_else(|| last_error(&self.reference), last_error)
    }
    /// The baseline's error.
    pub fn baseline_error(&self) -> f64 {
        last_error(&self.baseline)
    }
}

/// The last error of a fit's history (its ‖Y_error‖ at the estimate).
pub(super) fn last_error(outcome: &FitOutcome) -> f64 {
    *outcome.report.error_history.last().expect("a history has its start")
}
