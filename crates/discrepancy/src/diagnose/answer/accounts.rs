//! A named effect's rivals as the answer reports them: the model's own parameters (or an added
//! linear term) refitted alone in its place ([`Rival`]), and what each account asks of the model
//! file ([`Departures`]).

use super::EffectParameter;
use serde::Serialize;

/// A linear term a rival adds to the model, which lacks it ([`Rival::adds`]).
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
#[non_exhaustive]
pub enum AddedTerm {
    /// A linear spring at the slewing rig's hub (`hub_stiffness`).
    HubSpring,
    /// A linear damper at a structure's coordinate (`drag_<coordinate>` with exponent 1): damping
    /// distributed otherwise than the model's (Rayleigh damping fixes every mode's ratio from
    /// two numbers).
    LinearDamper {
        /// The coordinate.
        coordinate: String,
    },
    /// Another output's signal picked up by one output's channel (`crosstalk_<output>_<from>`):
    /// it reads y + g·y_from, a wiring or amplifier fault.
    Crosstalk {
        /// The output whose reading carries the other's.
        output: String,
        /// The output picked up.
        from: String,
    },
    /// One output's channel read late (`lag_<output>`): it reads y(t − τ_s), a sampling skew
    /// or a filter's delay in the acquisition.
    Lag {
        /// The output read late.
        output: String,
    },
}

/// The in-sample evidence (nats) an effect needs over a rival of no more parameters to keep its
/// name. With equal parameter counts the gains' difference is the log Bayes factor (BIC's
/// penalties cancel), and ln B < 1 (2 ln B < 2) is evidence "not worth more than a bare mention"
/// on the scale of Kass & Raftery (1995, *Bayes factors*, JASA 90, §3.2); a gauge's calibration
/// and the beam's length differ by less than that on a record where either explains the one
/// strain gauge ([module `diagnose`](mod@crate::diagnose), step 7).
pub const RIVAL_MARGIN: f64 = 1.0;

/// A model parameter that, refitted alone in place of a named effect, explains the data as well
/// (its in-sample gain within the held-out threshold of the effect's, or more): a mismatch of it
/// is an answer these data do not rule out. It may also be a linear term the model lacks
/// ([`Rival::adds`]): a spring at the slewing rig's hub, a damper at a structure's coordinate.
#[derive(Clone, Debug, Serialize)]
pub struct Rival {
    /// Parameter name (`length`, …).
    pub name: String,
    /// Its value in the reference (the model file's, it was not refitted there; zero for an
    /// added term, absent there).
    pub reference_value: f64,
    /// Its value refitted in place of the effect.
    pub value: f64,
    /// Standard error of the refitted value.
    pub std_error: Option<f64>,
    /// In-sample gain of that refit over the reference (nats), to set against the effect's.
    pub in_sample: f64,
    /// Whether the parameter is not the model's own: the effect carrying it was added at zero
    /// to try it ([`Rival::adds`] says which).
    pub added: bool,
    /// The linear term added to try it, if the model lacked it.
    pub adds: Option<AddedTerm>,
    /// The nats its gain is charged before it is set against the effect: ln K for a term
    /// chosen as the best of K alternatives of one class (a crosstalk, of the p(p − 1) ordered
    /// pairs of p outputs; a lag, of the p outputs), which as a class weighs as one alternative; 0 for the model's own
    /// parameters and the other added terms, each an alternative of its own.
    pub penalty: f64,
    /// For a rival of a named sensor scale: how far each account moves the model file's values
    /// ([`Departures`]). `None` for the other effects and for an added term.
    pub departures: Option<Departures>,
}

/// What two accounts of the same record ask of the model file: a sensor's calibration error,
/// and one of the model's own parameters refitted in its place (step 7 of
/// [module `diagnose`](mod@crate::diagnose)). Each value of the file, and the sensor's
/// calibration (a gain of 1), is taken as known to a relative tolerance τ
/// ([`crate::DiagnoseOptions::file_tolerance`]), a log-normal prior; an account's refit is
/// charged Σ ln²(p̂/p_file)/(2(τ² + σ²)) nats over the reference's mismatch parameters, the
/// rival's own and the calibration's error, σ the relative standard error of p̂ in that refit
/// (the prior's part of the refit's log evidence by Laplace's approximation, one parameter at a
/// time: a value the record does not pin down costs little however far its estimate strays).
/// The rival's in-sample gain is set against the effect's less the difference of the two
/// charges ([`Departures::charge`]). One strain gauge read 4.6 % low, and a beam 5 % longer
/// whose EI/ρ and ρ move by a fifth to keep its modes and inertia where the record puts them,
/// explain the record alike; the file says which asks less.
#[derive(Clone, Debug, Serialize)]
pub struct Departures {
    /// What the rival's account asks of the file (nats).
    pub rival: f64,
    /// What the named effect's account asks of it, its calibration error included (nats).
    pub effect: f64,
    /// The relative tolerance τ the file's values are taken to be known to.
    pub tolerance: f64,
    /// The model file's values the two refits set more than 1 % apart, largest first.
    pub moved: Vec<Moved>,
}

impl Departures {
    /// The nats the rival's account is charged beyond the effect's: negative where the rival
    /// asks less of the file.
    pub fn charge(&self) -> f64 {
        self.rival - self.effect
    }
}

/// A value of the model file that two accounts set apart ([`Departures::moved`]).
#[derive(Clone, Debug, Serialize)]
pub struct Moved {
    /// Parameter name.
    pub name: String,
    /// The model file's value.
    pub file: f64,
    /// The rival's refit's value.
    pub rival: f64,
    /// The named effect's refit's value.
    pub effect: f64,
}

impl Moved {
    /// `name` +5.0 % in the rival's refit (`rival` true) or the effect's.
    pub(in crate::diagnose) fn described(&self, rival: bool) -> String {
        let value = if rival { self.rival } else { self.effect };
        format!("`{}` {:+.1} %", self.name, 100.0 * (value / self.file - 1.0))
    }
}

impl Rival {
    /// `name`, and for an added parameter what it is.
    pub(in crate::diagnose) fn described(&self) -> String {
        match &self.adds {
            Some(AddedTerm::HubSpring) => {
                format!("`{}` (a linear spring at the hub, absent from the model)", self.name)
            }
            Some(AddedTerm::LinearDamper { coordinate }) => {
                format!("`{}` (a linear damper at {coordinate}, absent from the model)", self.name)
            }
            Some(AddedTerm::Crosstalk { output, from }) => format!(
                "`{}` (`{from}`'s signal picked up by the `{output}` channel, y + g·{from}: a wiring fault, not physics)",
                self.name
            ),
            Some(AddedTerm::Lag { output }) => format!(
                "`{}` (the `{output}` channel read late, y(t − τ_s): a sampling skew or a filter's delay in the acquisition, not physics)",
                self.name
            ),
            None => format!("`{}`", self.name),
        }
    }

    /// Whether this mismatch explains the data as well as an effect of in-sample gain
    /// `effect_in_sample` (with no more parameters), to within [`RIVAL_MARGIN`], once charged
    /// its [`penalty`](Self::penalty): then the effect is not named
    /// ([`super::Verdict::MatchedByMismatch`]).
    ///
    /// Set against a named sensor scale, the rival is also charged what its account asks of the
    /// model file beyond the scale's ([`Departures::charge`], negative where it asks less).
    pub fn unseats(&self, effect_in_sample: f64) -> bool {
        let charge = self.departures.as_ref().map_or(0.0, Departures::charge);
        self.in_sample - self.penalty - charge + RIVAL_MARGIN > effect_in_sample
    }
}

/// A sensor's scale that explains a slewing record as well as the secondary mismatch parameters
/// that joined its reference (the beam's mass per length): refitted against the reference
/// without them, at the model file's values, its account is within [`RIVAL_MARGIN`] of theirs
/// or better, the accounts' parameter counts charged by the BIC, and the scale is resolved from
/// zero. Looked for, and reported, where nothing is named against the reference with them; the
/// reference keeps them (the slewing rig's mass per length is not weighed against effects,
/// module `secondary`), and the answer says that the record does not tell them from the gauge's
/// calibration.
///
/// A strain gauge read 2 % high (held-out draw 20261406, `A_scale_strain_medium_s1`) is taken up
/// by ρ freed beside EI/ρ (the scale is left 4.5 nats against that reference); the scale in ρ's
/// place is 3.9 nats the better, at +2.05 ± 0.05 %. Naming it there was tried and not kept: on
/// the demo's record, whose truth has ρ off, the fourth run then named a −0.95 % strain scale
/// that is 15.8 nats the better in ρ's place (docs/diagnose.md).
#[derive(Clone, Debug, Serialize)]
pub struct ScaleInPlace {
    /// The secondary mismatch parameters the scale stands in for.
    pub parameters: Vec<String>,
    /// The scale's label, `sensor_scale(<output>)`.
    pub scale: String,
    /// The scale's parameter as refitted in their place.
    pub value: EffectParameter,
    /// The account with the scale less the reference's, in sample, less the charge of the
    /// scale's parameter beyond theirs, k ln(m)/2 (nats; at least −[`RIVAL_MARGIN`]).
    pub gain: f64,
}

impl ScaleInPlace {
    /// In words.
    pub fn sentence(&self) -> String {
        let names: Vec<String> = self.parameters.iter().map(|n| format!("`{n}`")).collect();
        let (names, one) = (names.join(", "), self.parameters.len() == 1);
        let se = self
            .value
            .std_error
            .map_or_else(|| " (not determined)".to_string(), |s| format!(" ± {:.2} %", 100.0 * s));
        let scale = format!("{} of {:+.2} %{se}", self.scale, 100.0 * self.value.value);
        let how = if self.gain > RIVAL_MARGIN {
            format!(
                "explains these data better than {names} freed in the reference ({:.1} nats by the BIC)",
                self.gain
            )
        } else {
            format!(
                "explains these data as well as {names} freed in the reference ({:+.1} nats by the BIC)",
                self.gain
            )
        };
        format!(
            "with {names} at the file's value, {scale} {how}: the reference keeps {} (a mismatch of the model's \
             own parameters), and one record of these outputs does not tell {} from the gauge's calibration, so \
             check the gauge as well as {names}",
            if one { "it" } else { "them" },
            if one { "that parameter" } else { "those parameters" },
        )
    }
}
