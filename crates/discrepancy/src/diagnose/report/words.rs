//! The answer in words: why this effect, or why none and what remains (the sentences on a
//! named effect's form, and on the rivals a candidate was set aside for, are in `forms.rs`).

use super::super::{
    Candidate, Diagnosis, MIN_SENSOR_STRUCTURE_EXPLAINED, SaturationKnee, StaticPeak, Verdict,
};
use super::charges::{asks_less, asks_more};
use crate::quantization;
use plant::EffectKind;

impl Diagnosis {
    /// Where the named law of a sensor's zero leaves more than half its output's structure and
    /// another law of the same zero removed enough of it (module `named`, `zeros_law`): why the
    /// law named is this one.
    fn zeros_law_sentence(&self, c: &Candidate) -> Option<String> {
        let zero = super::super::named::is_zero_law;
        let share = c.evidence.sensor_structure_explained?;
        if !zero(c.kind) || share >= MIN_SENSOR_STRUCTURE_EXPLAINED {
            return None;
        }
        let other = self
            .candidates
            .iter()
            .filter(|o| zero(o.kind) && o.output == c.output && o.verdict == Verdict::Outscored)
            .filter(|o| {
                o.evidence.sensor_structure_explained.is_some_and(|s| s >= MIN_SENSOR_STRUCTURE_EXPLAINED)
            })
            .max_by(|a, b| {
                a.evidence.held_out.unwrap_or(0.0).total_cmp(&b.evidence.held_out.unwrap_or(0.0))
            })?;
        Some(format!(
            "it removes {:.0} % of its output's structure, under the {:.0} % a sensor's error is asked to; {} on \
             the same output removes {:.0} %, so the error is the sensor's zero, and {} predicts the held-out blocks \
             {:.1} nats better, so its law is named",
            100.0 * share,
            100.0 * MIN_SENSOR_STRUCTURE_EXPLAINED,
            other.label,
            100.0 * other.evidence.sensor_structure_explained.unwrap_or(0.0),
            c.label,
            c.evidence.held_out.unwrap_or(0.0) - other.evidence.held_out.unwrap_or(0.0)
        ))
    }

    /// Where a sensor scale `c` (held out `x` nats) is named with the model's own parameters
    /// refitted beside it, and the scale of another gauge predicts the held-out blocks as well
    /// (within the threshold) but was set aside as leaving its own output's structure: with
    /// those parameters free, a scale common to every gauge is theirs (masses and stiffnesses
    /// scaled together scale the response), so the record sees only the ratio of the gauges'
    /// readings, and which gauge is off is not told by it (the structure study's −1 % and −3 %
    /// scales on q1 named on q3, draws 20261366–67).
    fn other_gauge_sentence(&self, c: &Candidate, x: f64) -> Option<String> {
        if c.kind != EffectKind::SensorScale || self.mismatch_parameters.is_empty() {
            return None;
        }
        let other = self
            .candidates
            .iter()
            .filter(|o| o.kind == EffectKind::SensorScale && o.output != c.output)
            .filter(|o| o.verdict == Verdict::LeavesItsOutput)
            .filter(|o| o.evidence.held_out.is_some_and(|y| (x - y).abs() < self.threshold))
            .max_by(|a, b| {
                a.evidence.held_out.unwrap_or(0.0).total_cmp(&b.evidence.held_out.unwrap_or(0.0))
            })?;
        Some(format!(
            "{} predicts as well ({:.1} nats held out against {x:.1}) but was set aside as leaving its own \
             output's structure: with {} refitted, a scale common to every gauge is a change of the model's own \
             parameters, so these data see only the ratio of the gauges' readings; check the calibration of both",
            other.label,
            other.evidence.held_out.unwrap_or(0.0),
            self.mismatch_parameters.join(", ")
        ))
    }

    /// Why this effect, or why none and what remains.
    pub(super) fn verdict_sentences(&self) -> Vec<String> {
        match self.named() {
            Some(c) => {
                let why = match (&c.lattice, c.evidence.held_out) {
                    (Some(l), _) => format!(
                        "{}: the raw readings lie on a lattice of step {:.4e} ({}), {:.1}× the noise σ",
                        c.label,
                        l.step,
                        match l.form {
                            quantization::LatticeForm::Exact { levels } =>
                                format!("exactly, {levels} levels"),
                            quantization::LatticeForm::Blurred { z, .. } =>
                                format!("blurred by noise, its phase held by {z:.0} standard errors"),
                            quantization::LatticeForm::Sawtooth { z, amplitude_ratio, .. } => format!(
                                "noise after the rounding: the residual is the rounding's sawtooth of the fitted \
                                 response, held by {z:.0} standard errors at {amplitude_ratio:.2}× a rounding's amplitude"
                            ),
                        },
                        l.step / l.noise.max(f64::MIN_POSITIVE)
                    ),
                    (None, Some(x)) => format!(
                        "{}: fitted on alternate blocks it predicts the others better by {:.1} nats, ΔBIC {:.1}, \
                         strength {:.1} σ from none{}",
                        c.label,
                        x,
                        c.evidence.delta_bic,
                        c.evidence.strength_z,
                        if self.mismatch_parameters.is_empty() {
                            String::new()
                        } else {
                            format!(
                                " (the model's own parameters {} refitted alongside)",
                                self.mismatch_parameters.join(", ")
                            )
                        }
                    ),
                    (None, None) => c.label.clone(),
                };
                let mut out = vec![why];
                if !self.scale_equivalents.is_empty() {
                    out.push(format!(
                        "the model's {} scale{} that output alone: these data cannot tell a sensor calibration error \
                         from an error in {}; measure {} to tell them apart",
                        self.scale_equivalents.iter().map(|n| format!("`{n}`")).collect::<Vec<_>>().join(", "),
                        if self.scale_equivalents.len() == 1 { "s" } else { "" },
                        if self.scale_equivalents.len() == 1 { "it" } else { "them" },
                        if self.scale_equivalents.len() == 1 { "it" } else { "them" },
                    ));
                }
                for r in &self.rivals {
                    let fit = format!(
                        "a mismatch of {} explains these data as well: refitted alone in place of the effect it \
                         moves from {:.5} to {:.5}{} and gains {:.1} nats (the effect {:.1})",
                        r.described(),
                        r.reference_value,
                        r.value,
                        r.std_error.map_or(String::new(), |se| format!(" ± {se:.5}")),
                        r.in_sample,
                        c.evidence.in_sample,
                    );
                    out.push(match r.departures.as_ref().filter(|d| d.charge() > 0.0) {
                        Some(d) => format!("{fit}, but {}", asks_more(d, &r.name)),
                        None => format!(
                            "{fit}; one record of these outputs does not tell them apart, so check `{}` before adding \
                             the effect",
                            r.name
                        ),
                    });
                }
                out.extend(self.zeros_law_sentence(c));
                out.extend(self.static_peak.as_ref().map(StaticPeak::sentence));
                out.extend(self.saturation_knee.as_ref().map(SaturationKnee::sentence));
                // The rivals the named one was chosen among: not told apart by these data.
                if let Some(x) = c.evidence.held_out {
                    let tied = super::super::named::not_told_apart(&self.candidates, self.threshold);
                    for r in tied
                        .into_iter()
                        .map(|i| &self.candidates[i])
                        .filter(|r| r.verdict == Verdict::Outscored)
                    {
                        if let Some(choice) = self.scale_choice.as_ref().filter(|s| s.other == r.label) {
                            out.push(format!(
                                "{} fits as well (within {:.1} nats held out, {:.1} in sample): the record sees \
                                 the ratio of the two sensors' readings, the model's own parameters moved to \
                                 match either, so what each asks of the model file decided ({:.2} nats for \
                                 {}, {:.2} for {})",
                                r.label,
                                r.evidence.held_out.map_or(0.0, |y| (x - y).abs()),
                                (c.evidence.in_sample - r.evidence.in_sample).abs(),
                                choice.named_charge,
                                choice.named,
                                choice.other_charge,
                                choice.other
                            ));
                        } else if let Some(y) = r.evidence.held_out {
                            // Strengths within a standard error of each other: the fewer
                            // parameters decided, where the two differ in number.
                            let z_tied = (r.evidence.strength_z - c.evidence.strength_z).abs()
                                < super::super::named::STRENGTH_TIE;
                            let by_size = z_tied && r.parameters.len() != c.parameters.len();
                            // Two bodies of as many parameters: the better fit decided.
                            let body = |c: &Candidate| super::super::named::appendage_at(c).is_some();
                            let by_fit = z_tied && !by_size && body(c) && body(r);
                            out.push(format!(
                                "{} predicts within {:.1} nats of it (ΔBIC {:.1} against {:.1}, strength {:.1} σ \
                                 against {:.1}): these data barely tell the two apart, and {}",
                                r.label,
                                (x - y).abs(),
                                r.evidence.delta_bic,
                                c.evidence.delta_bic,
                                r.evidence.strength_z,
                                c.evidence.strength_z,
                                if by_size {
                                    "with strengths within a standard error of each other the account with fewer \
                                     parameters decided"
                                } else if by_fit {
                                    "with strengths within a standard error of each other the body that fits the \
                                     record better in sample gives the mode"
                                } else {
                                    "the strength resolved by more standard errors decided"
                                }
                            ));
                        }
                    }
                    out.extend(self.other_gauge_sentence(c, x));
                }
                out
            }
            None => {
                let mut out = vec!["none: no candidate of the catalog earns its name".to_string()];
                if self.mismatch_gain > 10.0 {
                    out.push(format!(
                        "refitting the model's own parameters ({}) gains {:.0} nats: a parameter mismatch, not a \
                         missing effect",
                        self.mismatch_parameters.join(", "),
                        self.mismatch_gain
                    ));
                }
                // The effect a mismatch unseated or the spring-form test set aside, if one was; else
                // the best predictor held out.
                let unseated = self.candidates.iter().find(|c| {
                    matches!(
                        c.verdict,
                        Verdict::MatchedByMismatch
                            | Verdict::Asymmetric
                            | Verdict::TimeVarying
                            | Verdict::DampingDistribution
                            | Verdict::Outpredicted
                    )
                });
                if let Some(best) =
                    unseated.or_else(|| self.candidates.iter().find(|c| c.evidence.held_out.is_some()))
                {
                    let law_aside = self.time_law.as_ref().filter(|law| law.as_well);
                    out.push(format!(
                        "{}, {}, was {}",
                        if unseated.is_some() { "the candidate the evidence chose" } else { "the strongest candidate" },
                        best.label,
                        match &best.verdict {
                            Verdict::NotPredictive => "not predictive on held-out blocks".to_string(),
                            Verdict::WithinForceNoise => format!(
                                "predictive on held-out blocks, but it removes less than {:.0} % of what the \
                                 noise on the recorded force accounts for in the residual it leaves, and gains \
                                 at most {:.0} nats held out: it may only take up the model's response to that \
                                 noise",
                                100.0 * super::super::FORCE_NOISE_SHARE,
                                super::super::FORCE_NOISE_EXEMPT
                            ),
                            Verdict::Superficial => format!(
                                "predictive on held-out blocks but it removes only {:.0} % of the residual's \
                                 structure: a stand-in, not the missing physics",
                                100.0 * best.evidence.structure_explained.max(0.0)
                            ),
                            Verdict::LeavesItsOutput => format!(
                                "predictive on held-out blocks but it leaves {:.0} % of the structure on the output \
                                 it acts on: what is missing there acts through the dynamics",
                                100.0 * (1.0 - best.evidence.sensor_structure_explained.unwrap_or(0.0)).clamp(0.0, 1.0)
                            ),
                            Verdict::MatchedByMismatch => {
                                let unseating: Vec<String> = self
                                    .rivals
                                    .iter()
                                    .filter(|r| r.unseats(best.evidence.in_sample))
                                    .map(|r| {
                                        format!(
                                            "{} {:.5} → {:.5}{} ({:.1} nats{})",
                                            r.described(),
                                            r.reference_value,
                                            r.value,
                                            r.std_error.map_or(String::new(), |se| format!(" ± {se:.5}")),
                                            r.in_sample,
                                            r.departures
                                                .as_ref()
                                                .filter(|d| d.charge() < 0.0)
                                                .map_or(String::new(), |d| format!("; {}", asks_less(d, &r.name)))
                                        )
                                    })
                                    .collect();
                                let one = unseating.len() == 1;
                                format!(
                                    "predictive on held-out blocks ({:.1} nats in sample), but {} parameter{}, {}refitted \
                                     alone in its place, explain{} the data as well (to within a nat): \
                                     {}; check {} before adding the effect",
                                    best.evidence.in_sample,
                                    if one { "one".to_string() } else { unseating.len().to_string() },
                                    if one { "" } else { "s" },
                                    if one { "" } else { "each " },
                                    if one { "s" } else { "" },
                                    unseating.join(", "),
                                    if one { "it" } else { "them" }
                                )
                            }
                            Verdict::Outpredicted => {
                                let chosen = self.candidates.iter().position(|c| std::ptr::eq(c, best));
                                match chosen.and_then(|i| super::super::named::outpredicted_by(&self.candidates, i, self.threshold)) {
                                    Some(j) => {
                                        let stand_in = &self.candidates[j];
                                        format!(
                                            "predictive on held-out blocks ({:.1} nats, {:.0} % of the residual's \
                                             structure removed), but {}, set aside as a stand-in, predicts them better \
                                             ({:.1} nats) and removes more of the structure ({:.0} %): what is missing \
                                             is accounted for better than by {}, and what accounts for it better only \
                                             stands in for it — physics outside the catalog",
                                            best.evidence.held_out.unwrap_or(0.0),
                                            100.0 * best.evidence.structure_explained.max(0.0),
                                            stand_in.label,
                                            stand_in.evidence.held_out.unwrap_or(0.0),
                                            100.0 * stand_in.evidence.structure_explained.max(0.0),
                                            best.label
                                        )
                                    }
                                    None => format!("{:?}", best.verdict),
                                }
                            }
                            // A structure's mode set aside for its damping distributed otherwise.
                            Verdict::DampingDistribution => match &self.damping {
                                Some(rival) => rival.sentence(best.kind, best.evidence.in_sample, self.threshold),
                                None => format!("{:?}", best.verdict),
                            },
                            // A structure force set aside for a stiffness that changes with time.
                            Verdict::TimeVarying if law_aside.is_some() => law_aside
                                .map_or_else(String::new, |law| law.sentence(best.evidence.in_sample, self.threshold)),
                            Verdict::TimeVarying if best.kind == plant::EffectKind::CoulombFriction => {
                                // The rig's servo, or a structure's storey.
                                let (change, physics) = if self.reference.fitted.as_structure().is_some() {
                                    (
                                        "a stiffness that changes with time",
                                        "a storey that degrades or a joint that loosens during the record",
                                    )
                                } else {
                                    ("the servo's stiffness falls with time", "a motor whose torque constant fades as it warms")
                                };
                                match &self.fading {
                                    Some(term) => format!(
                                        "predictive on held-out blocks ({:.1} nats in sample), but beside it {change}: \
                                         `{}` = {:.4e}{} adds {:.1} nats — {physics}, outside the catalog, for which a \
                                         constant friction only stands in",
                                        best.evidence.in_sample,
                                        term.parameter.name,
                                        term.parameter.value,
                                        term.parameter.std_error.map_or(String::new(), |se| format!(" ± {se:.2e}")),
                                        term.gain
                                    ),
                                    None => format!("{:?}", best.verdict),
                                }
                            }
                            Verdict::Asymmetric | Verdict::TimeVarying => match &self.spring {
                                Some(form) => {
                                    let asymmetric =
                                        form.asymmetric.as_ref().filter(|_| best.verdict == Verdict::Asymmetric);
                                    let (term, what, kind) = if let Some(asymmetric) = asymmetric {
                                        (
                                            asymmetric,
                                            "the restoring force is stiffer on one side than the other: its \
                                             asymmetric part",
                                            "a stop, a contact or a gap that closes one way, which the catalog's \
                                             symmetric spring does not hold",
                                        )
                                    } else {
                                        (
                                            &form.changing,
                                            "its stiffness changes with time in a way a symmetric spring's change \
                                             with amplitude does not follow: a rate",
                                            "a stiffness that degrades or recovers during the record (a joint that \
                                             loosens, a motor whose torque constant fades as it warms), or another \
                                             change the catalog's symmetric spring does not hold",
                                        )
                                    };
                                    format!(
                                        "predictive on held-out blocks ({:.1} nats in sample), but {what} `{}` = \
                                         {:.4e}{} adds {:.1} nats beside it and a symmetric quintic term (which adds \
                                         {:.1}) — {kind}",
                                        best.evidence.in_sample,
                                        term.parameter.name,
                                        term.parameter.value,
                                        term.parameter.std_error.map_or(String::new(), |se| format!(" ± {se:.2e}")),
                                        term.gain,
                                        term.symmetric_gain
                                    )
                                }
                                None => format!("{:?}", best.verdict),
                            },
                            other => format!("{other:?}"),
                        }
                    ));
                }
                out.extend(self.residual.sentences());
                out
            }
        }
    }
}
