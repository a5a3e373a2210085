//! The candidates: each catalog effect where it can act on this model, with starting values
//! taken from the model and the data (never from a study's truth) and plausible bounds — for
//! the slewing rig (`slewing.rs`) and for any structure (`structure.rs`); where a mode is looked
//! for (`seeds.rs`) and a named effect's second-stage parameters (`searches.rs`).

mod searches;
mod seeds;
pub(super) mod slewing;
pub(super) mod structure;

pub use searches::{KneeSearch, StaticPeakSearch, knee, static_peak};
use seeds::{Clear, LIGHTLY_DAMPED, Seed, drift_time_range, mode_seeds, record_length, seed_at};
pub use seeds::{Located, Pole};

use crate::localise::Localisation;
use mem::Measurement;
use models::{Model, ModelEffect};
use plant::{EffectKind, Sensor, SlewingModel};

/// A candidate to try: the effect with its starting values, the bounds of its parameters, and
/// which parameters measure its strength (0 means "no effect").
#[derive(Clone, Debug)]
pub struct Trial {
    /// The effect as it is added to the model.
    pub effect: ModelEffect,
    /// Its kind (the catalog's closed set, shared by both kinds of model).
    pub kind: EffectKind,
    /// The slewing rig's sensor it acts on, for a sensor effect there.
    pub sensor: Option<Sensor>,
    /// The output (column) a sensor effect acts on, on either kind of model.
    pub output: Option<usize>,
    /// The catalog name with its target, e.g. `output_offset(theta)`.
    pub label: String,
    /// Bounds of the effect's parameters, by name.
    pub bounds: Vec<(String, (f64, f64))>,
    /// How far from "no effect" the fitted effect is.
    pub strength: Vec<Strength>,
    /// The parameters the trial frees besides the baseline's.
    pub freed: Vec<String>,
    /// A resonance's frequency, which the data must locate inside its search range (a refit
    /// that still ends on a bound of it, once the range has moved as far as it may, found no
    /// mode there).
    pub located: Option<Located>,
    /// Other starting values of the same effect: a nonlinear effect's error surface can hold
    /// a local minimum in which the free parameters partly stand in for it, and the refit keeps
    /// the best of its starts.
    pub alternatives: Vec<ModelEffect>,
    /// The effect of the model it takes the place of: a sibling already named (a current limit
    /// for a voltage limit, or back), which an earlier run could not tell from this one.
    pub replaces: Option<EffectKind>,
    /// Shape parameters the data must locate inside their range: a refit that ends with one on
    /// a bound, or with its standard error half its value or more, found no such form there,
    /// and the effect's strength is then none (a drift's time constant, looked for from a third of
    /// the record to three records).
    pub interior: Vec<String>,
}

impl Trial {
    /// A trial of `effect`, freeing `freed`.
    fn new(
        effect: ModelEffect,
        kind: EffectKind,
        label: String,
        bounds: Vec<(String, (f64, f64))>,
        strength: Vec<Strength>,
        freed: Vec<String>,
    ) -> Self {
        Trial {
            effect,
            kind,
            sensor: None,
            output: None,
            label,
            bounds,
            strength,
            freed,
            located: None,
            alternatives: Vec::new(),
            replaces: None,
            interior: Vec::new(),
        }
    }

    /// The label of the trial as fitted in `outcome`: a resonance is named at the frequency
    /// the refit located it at.
    pub fn label_at(&self, outcome: &models::FitOutcome) -> String {
        let report = &outcome.report;
        self.located
            .as_ref()
            .and_then(|l| {
                let i = report.names.iter().position(|n| *n == l.name)?;
                Some(l.label(report.parameters[i]))
            })
            .unwrap_or_else(|| self.label.clone())
    }

    /// The trial of a sensor effect on output `o`.
    fn on_output(mut self, o: usize) -> Self {
        self.output = Some(o);
        self
    }

    /// Requires the data to locate `name` inside its range ([`Trial::interior`]).
    fn located_inside(mut self, name: String) -> Self {
        self.interior.push(name);
        self
    }

    /// Adds another starting point.
    fn or_from(mut self, effect: impl Into<ModelEffect>) -> Self {
        self.alternatives.push(effect.into());
        self
    }

    /// Adds a mode's other starts in `seed`'s range ([`Seed::other_starts`]), the mode at
    /// frequency f being `at(f)`.
    fn or_from_other_starts<E: Into<ModelEffect>>(self, seed: &Seed, at: impl Fn(f64) -> E) -> Self {
        seed.other_starts().fold(self, |t, f| t.or_from(at(f)))
    }
}

/// A parameter that measures an effect's strength, and where the effect vanishes.
#[derive(Clone, Debug, PartialEq)]
pub enum Strength {
    /// The effect vanishes at 0 (either sign acts).
    Nonzero(String),
    /// A limit on the loop's current or voltage: it vanishes once the limit is well above the
    /// largest demand on it (1.5× the demand at the start, where the smooth limiter's
    /// compression is below 0.05 %); the demand is the fitted model's.
    Limit(String, Demand),
    /// Several parameters of which any one acts (an unmodeled mode's amplitude in each
    /// output): the effect is resolved when the best resolved of them is.
    Largest(Vec<String>),
}

/// What a limit limits.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Demand {
    /// The armature current G K_p θ(0)/R_a at the start.
    Current,
    /// The amplifier's output G K_p θ(0) at the start.
    Voltage,
}

impl Demand {
    /// Its value for `model`.
    pub fn of(self, model: &SlewingModel) -> f64 {
        let c = model.constants();
        let volts = c.amplifier_gain * c.position_gain * model.initial_state()[0].abs();
        match self {
            Demand::Current => volts / c.armature_resistance,
            Demand::Voltage => volts,
        }
    }
}

impl Strength {
    /// The parameters it is measured by.
    pub fn names(&self) -> Vec<&str> {
        match self {
            Strength::Nonzero(n) | Strength::Limit(n, _) => vec![n.as_str()],
            Strength::Largest(names) => names.iter().map(String::as_str).collect(),
        }
    }

    /// The distance of `value` (of parameter `name`) from "no effect" in units of `std_error`
    /// for the fitted `model` (negative for a limit above where it acts).
    pub fn z(&self, value: f64, std_error: f64, model: &Model) -> f64 {
        match self {
            Strength::Nonzero(_) | Strength::Largest(_) => value.abs() / std_error,
            Strength::Limit(_, demand) => match model.as_slewing() {
                Some(m) => (1.5 * demand.of(m) - value) / std_error,
                None => 0.0,
            },
        }
    }
}

/// The catalog's candidates for `model` (which already carries the effects found so far) on
/// `record` (a structure's force scales are its response to the record's inputs), with
/// the residual modes of `localisation` for an unmodeled mode (and, for a structure, its
/// residual RMS per output for the mode's starting amplitudes). Effects the model has are not
/// tried again.
pub fn trials(model: &Model, record: &Measurement, localisation: &Localisation) -> Vec<Trial> {
    match model {
        Model::Slewing(m) => slewing::trials(m, localisation),
        Model::Structure(m) => structure::trials(m, record, localisation),
    }
}
