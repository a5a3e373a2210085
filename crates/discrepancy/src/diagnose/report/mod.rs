//! The diagnosis in words and as the JSON document of `memid diagnose --json` (docs/json.md).
//! The sentences are in `words.rs` and `forms.rs`.

mod charges;
mod forms;
mod words;

use super::{Diagnosis, EffectParameter, NoiseModel, ResidualStructure, SaturationKnee};
use crate::localise::Localisation;
use serde::Serialize;

/// The diagnosis as the JSON document of `memid diagnose --json` (docs/json.md).
#[derive(Debug, Serialize)]
pub struct DiagnosisReport<'a> {
    /// The named effect's catalog name, or `none`.
    pub effect: &'a str,
    /// The named candidate's label (with its sensor), if one is named.
    pub label: Option<&'a str>,
    /// The named effect's parameters.
    pub parameters: &'a [EffectParameter],
    /// The answer in words: why this effect, or why none and what remains.
    pub answer: Vec<String>,
    /// ‖Y_error‖ of the baseline.
    pub baseline_error: f64,
    /// ‖Y_error‖ of the augmented model.
    pub augmented_error: f64,
    /// The model's own parameters freed to tell a mismatch from a missing effect.
    pub mismatch_parameters: &'a [String],
    /// In-sample gain of freeing them (nats).
    pub mismatch_gain: f64,
    /// The mismatch parameters freed one at a time, weighed against the effect first chosen
    /// ([`super::SecondaryMismatch`]); absent where there were none or nothing was chosen.
    pub secondary_mismatch: Option<&'a super::SecondaryMismatch>,
    /// On the slewing rig, where nothing is named: a sensor's scale that explains the record as
    /// well as the secondary mismatch parameters that joined the reference
    /// ([`super::ScaleInPlace`]); absent otherwise.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub scale_in_place: Option<&'a super::ScaleInPlace>,
    /// What the baseline's residual holds.
    pub residual: &'a ResidualStructure,
    /// The measurement model every candidate was scored under.
    pub noise: &'a NoiseModel,
    /// Every candidate with its evidence and verdict.
    pub candidates: &'a [super::Candidate],
    /// Where the baseline disagrees with the data.
    pub localisation: &'a Localisation,
    /// For a named sensor scale: the model's parameters that scale that output alone, which the
    /// data cannot tell from the named calibration error (empty otherwise).
    pub equivalent_parameters: &'a [String],
    /// For a named sensor scale chosen between two that fit alike: what each account asks of the
    /// model file ([`super::ScaleChoice`]); absent otherwise.
    pub scale_choice: Option<&'a super::ScaleChoice>,
    /// On a forced record: the noise estimated on its recorded inputs, and the share of the
    /// best-fitting residual it accounts for ([`crate::frf::InputNoise`]); absent otherwise.
    pub force_noise: Option<&'a crate::frf::InputNoise>,
    /// The reference's free parameters that ran more than a decade from the model file's values,
    /// from which every candidate was then refitted too ([`super::RanOff`]); absent if none.
    #[serde(skip_serializing_if = "<[_]>::is_empty")]
    pub ran_off: &'a [super::RanOff],
    /// For a named effect: the model's parameters that, refitted alone instead, explain the
    /// data as well — mismatches these data do not rule out; for an effect they unseated
    /// ([`super::Verdict::MatchedByMismatch`]), those that explain them as well, to within a nat (empty
    /// otherwise).
    pub rival_mismatches: &'a [super::Rival],
    /// For a structure `cubic_stiffness` that was named, or set aside as
    /// [`super::Verdict::Asymmetric`] or [`super::Verdict::TimeVarying`]: its asymmetric part k₂q² refitted
    /// beside it, and whether the data demand it; absent otherwise (and for the slewing rig's
    /// hub spring, which is tested for change with time only).
    pub asymmetric_spring: Option<&'a super::SpringTerm>,
    /// For the same spring, and for the slewing rig's hub spring likewise: a linear stiffness
    /// that changes with time, k₁′·t·q, refitted beside it, and whether the data demand it;
    /// absent otherwise.
    pub changing_spring: Option<&'a super::SpringTerm>,
    /// For a structure force named (or set aside for it): the rival account of a linear
    /// stiffness at a coordinate that changes with time by a law of its own, in place of the
    /// force, and whether it explains the record as well; absent otherwise.
    pub time_law: Option<&'a super::TimeLaw>,
    /// The rival of a named mode on a structure: a linear damper at every coordinate; where it
    /// explains the record as well, the mode was set aside ([`super::Verdict::DampingDistribution`]).
    pub damping: Option<&'a super::DampingRival>,
    /// For a named `coulomb_friction` on the slewing rig: its static (Stribeck) peak refitted
    /// beside it, and whether the data demand it — demanded, the named friction carries it;
    /// absent otherwise.
    pub static_friction_peak: Option<&'a super::StaticPeak>,
    /// For a `coulomb_friction` on the slewing rig, named or set aside as `time_varying`: a
    /// servo stiffness that falls with time, k₁′·t·θ at the hub, refitted beside it, and whether
    /// the data demand it (then the friction stands in for a fading torque constant and nothing
    /// is named); absent otherwise.
    pub fading_servo: Option<&'a super::SpringTerm>,
    /// The knee of a named saturation ([`SaturationKnee`]), when one was tested.
    pub saturation_knee: Option<&'a SaturationKnee>,
    /// Readings set aside as glitches before anything was fitted, each replaced by the line
    /// through the readings that bound its run (empty if none).
    pub glitches: &'a [crate::glitch::Glitch],
}

impl Diagnosis {
    /// The answer in words.
    pub fn answer(&self) -> Vec<String> {
        let mut out = self.verdict_sentences();
        out.extend(self.secondary.as_ref().filter(|s| !s.kept).map(super::SecondaryMismatch::sentence));
        out.extend(self.scale_in_place.as_ref().map(super::ScaleInPlace::sentence));
        out.extend(self.ran_off_sentence());
        out.extend(self.force_noise_sentence());
        out.extend(self.glitch_sentence());
        out
    }

    /// The reference's parameters that ran far from the model file, in words (`None` where
    /// none did).
    fn ran_off_sentence(&self) -> Option<String> {
        if self.ran_off.is_empty() {
            return None;
        }
        let moved: Vec<String> = self
            .ran_off
            .iter()
            .map(|r| {
                format!(
                    "`{}` {:.6e} against the file's {:.6e} ({:.3}×)",
                    r.name,
                    r.fitted,
                    r.file,
                    r.fitted / r.file
                )
            })
            .collect();
        Some(format!(
            "the reference fit ran far from the model file ({}): every candidate was refitted from the file's values \
             too, and the better of its two refits kept",
            moved.join(", ")
        ))
    }

    /// The noise estimated on a forced record's recorded inputs, in words (`None` for a free
    /// decay, or where none is seen).
    fn force_noise_sentence(&self) -> Option<String> {
        let noise = self.force_noise.as_ref().filter(|n| n.inputs.iter().any(|i| i.rms > 0.0))?;
        let levels: Vec<String> = noise
            .inputs
            .iter()
            .map(|i| format!("`{}` about {:.3e} ({:.2} % of its RMS)", i.input, i.rms, 100.0 * i.share))
            .collect();
        // Its response through the model, part of the measurement model.
        let orders: Vec<String> =
            self.noise.predictor_order.iter().filter(|&&q| q > 0).map(usize::to_string).collect();
        let coloured = if orders.is_empty() {
            String::new()
        } else {
            format!(
                "; its response through the model is part of the noise every candidate is scored under (the \
                 spectrum it and the sensor's noise leave, predicted to order {}), so matching it earns nothing",
                orders.join(" and ")
            )
        };
        Some(format!(
            "noise on the recorded input{}: {}; it accounts for {:.0} % of the best-fitting residual, and an \
             effect acting through the dynamics must remove at least {:.0} % \
             of what it accounts for in the residual its refit leaves, unless it gains more than {:.0} nats held \
             out{coloured}",
            if levels.len() == 1 { "" } else { "s" },
            levels.join(", "),
            100.0 * noise.share,
            100.0 * super::FORCE_NOISE_SHARE,
            super::FORCE_NOISE_EXEMPT
        ))
    }

    /// The readings set aside as glitches, in words (`None` if there were none).
    fn glitch_sentence(&self) -> Option<String> {
        const SHOWN: usize = 3;
        let (first, more) = (self.glitches.iter().take(SHOWN), self.glitches.len().saturating_sub(SHOWN));
        let listed: Vec<String> = first
            .map(|g| {
                format!(
                    "`{}` at {:.4} s ({:.4e}, replaced by {:.4e})",
                    g.output, g.time, g.reading, g.replaced_by
                )
            })
            .collect();
        (!listed.is_empty()).then(|| {
            format!(
                "{} reading{} set aside as glitch{} before fitting (far from the readings on both sides, beyond \
                 {}× the record's 95th-percentile change from one sample to the next): {}{}",
                self.glitches.len(),
                if self.glitches.len() == 1 { "" } else { "s" },
                if self.glitches.len() == 1 { "" } else { "es" },
                crate::glitch::GLITCH_FACTOR,
                listed.join(", "),
                if more > 0 { format!(" and {more} more") } else { String::new() }
            )
        })
    }

    /// The JSON document.
    pub fn report(&self) -> DiagnosisReport<'_> {
        let named = self.named();
        DiagnosisReport {
            effect: self.effect(),
            label: named.map(|c| c.label.as_str()),
            parameters: named.map_or(&[], |c| c.parameters.as_slice()),
            answer: self.answer(),
            baseline_error: self.baseline_error(),
            augmented_error: self.augmented_error(),
            mismatch_parameters: &self.mismatch_parameters,
            mismatch_gain: self.mismatch_gain,
            secondary_mismatch: self.secondary.as_ref(),
            scale_in_place: self.scale_in_place.as_ref(),
            residual: &self.residual,
            noise: &self.noise,
            candidates: &self.candidates,
            localisation: &self.localisation,
            equivalent_parameters: &self.scale_equivalents,
            scale_choice: self.scale_choice.as_ref(),
            force_noise: self.force_noise.as_ref(),
            ran_off: &self.ran_off,
            rival_mismatches: &self.rivals,
            asymmetric_spring: self.spring.as_ref().and_then(|f| f.asymmetric.as_ref()),
            changing_spring: self.spring.as_ref().map(|f| &f.changing),
            time_law: self.time_law.as_ref(),
            damping: self.damping.as_ref(),
            static_friction_peak: self.static_peak.as_ref(),
            fading_servo: self.fading.as_ref(),
            saturation_knee: self.saturation_knee.as_ref(),
            glitches: &self.glitches,
        }
    }
}
