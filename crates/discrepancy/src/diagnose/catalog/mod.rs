//! The candidates: each catalog effect where it can act on this model, with starting values
//! taken from the model and the data (never from a study's truth) and plausible bounds — for
//! the slewing rig (`slewing.rs`) and for any structure (`structure.rs`).

pub(super) mod slewing;
pub(super) mod structure;

use crate::localise::Localisation;
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

/// A resonance's frequency parameter and where the data may locate it.
///
/// The search range is a factor 2 about the seed. A refit that ends on one of the range's
/// bounds moves it a factor 2 further that way and refits from there (at most
/// [`Located::MAX_MOVES`] times, never past `limits`), kept while the error falls: a refit
/// pressing on a bound is following a mode the seeds missed. A heavily damped mode is seldom
/// seeded where it is (ERA on a short, noisy record sees a band, not a peak), and neither is a
/// lightly damped one whose coupling shifts the modelled modes more than it shows a peak of its
/// own (a mode at 0.52 Hz coupled through stiffness, seeded at the flexible mode's 1.7 Hz). A
/// stand-in found this way must still pass every test a seeded mode does: located, resolved,
/// removing half the residual's structure, unmatched by a rival.
#[derive(Clone, Debug, PartialEq)]
pub struct Located {
    /// The frequency parameter's name.
    pub name: String,
    /// How far the range may move: three cycles in the record, and clear of the frequencies the
    /// catalog avoids.
    pub limits: (f64, f64),
    /// The trial's label up to the frequency (`unmodeled_mode(damping, `): the label names the
    /// frequency where the refit located the mode, not its seed.
    pub prefix: String,
    /// The mode's damping-ratio parameter.
    pub damping: String,
}

impl Located {
    /// How many times a search range may move.
    pub const MAX_MOVES: usize = 2;

    /// The range after a refit ended at `f` on `side` of its range (None if it cannot move).
    pub fn moved(&self, range: (f64, f64), f: f64, side: mem::Side) -> Option<(f64, f64)> {
        let (low, high) = self.limits;
        let room = match side {
            mem::Side::Lower => range.0 > low * (1.0 + 1e-9),
            mem::Side::Upper => range.1 < high * (1.0 - 1e-9),
        };
        let next = about(f, self.limits);
        (room && next.0 < f && f < next.1).then_some(next)
    }

    /// The trial's label for a mode at `f` Hz.
    pub fn label(&self, f: f64) -> String {
        format!("{}{f:.2} Hz)", self.prefix)
    }
}

impl Seed {
    /// Where a mode's refit starts in the seed's range besides the seed itself: a factor √2
    /// either side of it, where the range reaches. Within a factor 2 of a closed-loop mode a
    /// coupled mode's error has more than one valley (an inertia-coupled mode at 1.2 Hz beside
    /// the flexible mode at 1.7 Hz has one at 1.5 Hz), and which one a refit from the seed alone
    /// falls into depends on where ERA put the seed, to the percent.
    fn other_starts(&self) -> impl Iterator<Item = f64> {
        let (low, high) = self.range;
        [std::f64::consts::FRAC_1_SQRT_2, std::f64::consts::SQRT_2]
            .map(|k| k * self.frequency)
            .into_iter()
            .filter(move |f| low < *f && *f < high)
    }
}

/// A search range: a factor 2 either side of `f`, within `limits`.
fn about(f: f64, limits: (f64, f64)) -> (f64, f64) {
    ((0.5 * f).max(limits.0), (2.0 * f).min(limits.1))
}

/// Where an unmodeled mode is looked for first.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Seed {
    /// Frequency \[Hz\].
    frequency: f64,
    /// Damping ratio.
    damping: f64,
    /// The search range: a factor 2 about the frequency, within `limits`.
    range: (f64, f64),
    /// How far the range may move ([`Located`]).
    limits: (f64, f64),
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

/// The catalog's candidates for `model` (which already carries the effects found so far), with
/// the residual modes of `localisation` for an unmodeled mode (and, for a structure, its
/// residual RMS per output for the mode's starting amplitudes). Effects the model has are not
/// tried again.
pub fn trials(model: &Model, localisation: &Localisation) -> Vec<Trial> {
    match model {
        Model::Slewing(m) => slewing::trials(m, localisation),
        Model::Structure(m) => structure::trials(m, localisation),
    }
}

/// The search for a named dry friction's static peak (module `friction` of
/// [`mod@crate::diagnose`]): the parameters' names and ranges, the Stribeck velocities the
/// refit starts from, and the friction's smoothing.
pub struct StaticPeakSearch {
    /// `static_peak…` and its range.
    pub peak: (String, (f64, f64)),
    /// `stribeck_velocity…` and its range.
    pub velocity: (String, (f64, f64)),
    /// The friction's sliding level (`coulomb_torque`, `friction_<c>`).
    pub coulomb: String,
    /// Starting Stribeck velocities (the refit keeps the best).
    pub velocity_starts: Vec<f64>,
    /// The named friction's fixed smoothing velocity.
    smoothing_velocity: f64,
}

impl StaticPeakSearch {
    /// The slewing rig's hub friction at Coulomb level `torque` with a static peak `peak`
    /// falling over `velocity`.
    pub fn friction_with(&self, torque: f64, peak: f64, velocity: f64) -> ModelEffect {
        ModelEffect::Slewing(plant::Effect::CoulombFriction {
            torque,
            smoothing_velocity: self.smoothing_velocity,
            static_peak: Some(peak),
            stribeck_velocity: Some(velocity),
        })
    }
}

/// Where the static peak of the dry friction `effect` (a trial's, without a peak) is looked for
/// on `model`: the slewing rig's hub friction. `None` for any other effect, and for a
/// structure's friction: the catalog smooths it over 1 % of the coordinate's peak rate (what the
/// integrator's substep allows at the largest force of its range), and a peak over a few
/// smoothing velocities cannot be told from a sharper switch — on the structure study's plain
/// tanh frictions (18 records of its development, held-out and fresh sets) a peak gained 34–240
/// nats with its Stribeck velocity on a bound of its range. A structure file may still
/// state a peak (`DryFriction(…, static_peak: Some(ΔF), stribeck_velocity: Some(v_st))`).
pub fn static_peak(model: &Model, effect: &ModelEffect) -> Option<StaticPeakSearch> {
    match (model, effect) {
        (
            Model::Slewing(m),
            ModelEffect::Slewing(plant::Effect::CoulombFriction {
                static_peak: None,
                smoothing_velocity,
                ..
            }),
        ) => Some(slewing::static_peak(m, *smoothing_velocity)),
        _ => None,
    }
}

/// The search for a named saturation's knee (module `saturation` of
/// [`mod@crate::diagnose`]): the knee's and the limit's names and ranges, the knees the refit
/// starts from, and the limiter it refines.
pub struct KneeSearch {
    /// `current_knee` or `voltage_knee`, and its range.
    pub knee: (String, (f64, f64)),
    /// The limit (`current_limit`, `voltage_limit`) and its range beside a knee: a soft limiter
    /// bends the output well below its level, which may then lie above the demand.
    pub limit: (String, (f64, f64)),
    /// Starting knees (the refit keeps the best).
    pub knee_starts: Vec<f64>,
    /// The named limiter (its kind; its level is the refit's).
    kind: EffectKind,
}

impl KneeSearch {
    /// The named limiter at level `limit` with knee `knee`.
    pub fn limiter_with(&self, limit: f64, knee: f64) -> ModelEffect {
        let knee = Some(knee);
        ModelEffect::Slewing(match self.kind {
            EffectKind::VoltageSaturation => {
                plant::Effect::VoltageSaturation { voltage_limit: limit, sharp: false, knee }
            }
            _ => plant::Effect::AmplifierSaturation { current_limit: limit, sharp: false, knee },
        })
    }
}

/// Where the knee of the saturation `effect` (a trial's smooth limiter, without a knee of its
/// own) is looked for on `model`: the slewing rig's amplifier. `None` for any other effect.
pub fn knee(model: &Model, effect: &ModelEffect) -> Option<KneeSearch> {
    match (model, effect) {
        (
            Model::Slewing(m),
            ModelEffect::Slewing(
                e @ (plant::Effect::AmplifierSaturation { sharp: false, knee: None, .. }
                | plant::Effect::VoltageSaturation { sharp: false, knee: None, .. }),
            ),
        ) => Some(slewing::knee(m, e.kind())),
        _ => None,
    }
}

/// Where the time constant τ of a drift that levels off is looked for, on a record of
/// `record` seconds: from a third of the record (it levels off over the record, 95 % of its
/// level at the end) to three records (within 15 % of a constant rate at the end), started at
/// half and at the whole record (the refit keeps the better). The data must locate τ inside
/// that range and resolve it ([`Trial::interior`]): on its lower bound the drift is an offset
/// but for the record's first seconds — where the motion is largest, so that its rise stands
/// in for a misfit of the dynamics there (a delay's) as much as for a sensor; on its upper one
/// it is a constant rate. `None` for a record of no known length.
pub(super) fn drift_time_range(record: f64) -> Option<((f64, f64), [f64; 2])> {
    (record.is_finite() && record > 0.0).then(|| ((record / 3.0, 3.0 * record), [record / 2.0, record]))
}

/// The record's length as localisation measured it (the end of its last window).
pub(super) fn record_length(localisation: &Localisation) -> f64 {
    localisation.windows.last().map_or(f64::INFINITY, |w| w.1)
}

/// Cycles an unmodeled mode must complete within the record.
const MIN_CYCLES: f64 = 3.0;

/// The damping ratio below which a mode ERA finds is taken as a seed for an unmodeled mode
/// coupled through inertia or stiffness (a mode coupled through damping allows more).
const LIGHTLY_DAMPED: f64 = 0.2;

/// Where an unmodeled mode may be: physical modes of the baseline's residual and of the data
/// itself damped less than `max_damping`, at most two, more than `margin` (relative) from each frequency in `avoid`
/// and 10 % from each other, with the frequency within a factor 2 of the seed and `margin` clear
/// of the frequencies to avoid. The slewing rig avoids only its servo mode (25 %): a mode near a
/// modelled flexible mode is allowed there, because coupled to the hub a new mode and a modelled
/// one beat (two peaks where the model has one), which no retuning of the modelled mode
/// reproduces, while near the servo a heavily coupled "mode" would only reshape the servo's own
/// response. A structure's extra mode adds to the outputs without coupling, so near any of the
/// modelled modes it would only stand in for a change of that mode: it avoids them all (15 %).
///
/// Where neither record shows a mode to seed from, the modes in `fallback` (frequency, damping
/// ratio) are taken under the same rules: for the slewing rig its first flexible mode, which
/// every free decay of the rig holds and a mode coupled to it shifts. ERA misses it where the
/// servo's two overdamped poles carry all but a few percent of the record (a heavily damped mode
/// coupled through damping takes the flexible mode's motion away), and then no mode was tried.
fn mode_seeds(
    avoid: &[f64],
    margin: f64,
    max_damping: f64,
    localisation: &Localisation,
    fallback: &[(f64, f64)],
) -> Vec<Seed> {
    let record = record_length(localisation);
    let found: Vec<(f64, f64)> = localisation
        .residual_modes
        .iter()
        .chain(&localisation.data_modes)
        .filter(|m| m.physical)
        .map(|m| (m.frequency_hz, m.damping_ratio))
        .collect();
    let seeded = |modes: &[(f64, f64)]| {
        let mut seeds: Vec<Seed> = Vec::new();
        for &(f, damping) in modes {
            let near_servo = avoid.iter().any(|s| (f / s - 1.0).abs() < margin);
            // (A NaN damping ratio is no seed either.)
            let damped_enough = damping < max_damping;
            if !damped_enough || near_servo || seeds.iter().any(|s| (s.frequency / f - 1.0).abs() < 0.1) {
                continue;
            }
            // A mode needs three cycles in the record to be told from a trend.
            let mut limits = (MIN_CYCLES / record, f64::INFINITY);
            for &s in avoid {
                if s < f {
                    limits.0 = limits.0.max((1.0 + margin) * s);
                } else {
                    limits.1 = limits.1.min(s / (1.0 + margin));
                }
            }
            let range = about(f, limits);
            if range.0 < f && f < range.1 {
                seeds.push(Seed { frequency: f, damping, range, limits });
            }
            if seeds.len() == 2 {
                break;
            }
        }
        seeds
    };
    let seeds = seeded(&found);
    if seeds.is_empty() { seeded(fallback) } else { seeds }
}

#[cfg(test)]
mod tests {
    use super::*;
    use mem::Side;

    #[test]
    fn a_range_moves_a_factor_two_past_the_bound_reached_and_stops_at_its_limits() {
        let located =
            Located { name: "f".into(), limits: (0.3, 10.0), prefix: "m(".into(), damping: "z".into() };
        // Seeded at 1.6 Hz: (0.8, 3.2); the refit ends on the lower bound.
        assert_eq!(located.moved((0.8, 3.2), 0.8, Side::Lower), Some((0.4, 1.6)));
        // Next time the limit cuts the range; once on the limit it cannot move.
        assert_eq!(located.moved((0.4, 1.6), 0.4, Side::Lower), Some((0.3, 0.8)));
        assert_eq!(located.moved((0.3, 0.8), 0.3, Side::Lower), None);
        // Upwards alike.
        assert_eq!(located.moved((0.8, 3.2), 3.2, Side::Upper), Some((1.6, 6.4)));
        assert_eq!(located.moved((3.2, 10.0), 10.0, Side::Upper), None);
    }

    /// The fallback seeds only where neither record shows a mode, under the same rules.
    #[test]
    fn the_models_mode_is_seeded_only_where_the_record_shows_none() {
        let mode = |f: f64| era::EraMode {
            frequency_hz: f,
            damping_ratio: 0.03,
            consistency: 1.0,
            mpc: Some(1.0),
            contribution: 0.5,
            physical: true,
        };
        let record = |modes: Vec<era::EraMode>| Localisation {
            outputs: Vec::new(),
            windows: vec![(0.0, 30.0, 1.0)],
            decrement_vs_amplitude: Vec::new(),
            decrement_trend: 0.0,
            residual_modes: Vec::new(),
            data_modes: modes,
            findings: Vec::new(),
        };
        let fallback = [(1.7, 0.01)];
        let frequencies = |l: &Localisation| -> Vec<f64> {
            mode_seeds(&[0.15], 0.25, LIGHTLY_DAMPED, l, &fallback).iter().map(|s| s.frequency).collect()
        };
        assert_eq!(frequencies(&record(Vec::new())), [1.7]);
        assert_eq!(frequencies(&record(vec![mode(5.3)])), [5.3]);
        // A mode near the servo is no seed, and then neither record shows one.
        assert_eq!(frequencies(&record(vec![mode(0.16)])), [1.7]);
        let seeds = mode_seeds(&[0.15], 0.25, LIGHTLY_DAMPED, &record(Vec::new()), &fallback);
        assert_eq!((seeds[0].range, seeds[0].damping), ((0.85, 3.4), 0.01));
    }
}
