//! A named effect's rivals as the answer reports them: the model's own parameters (or an added
//! linear term) refitted alone in its place ([`Rival`]), and what each account asks of the model
//! file ([`Departures`]).

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
