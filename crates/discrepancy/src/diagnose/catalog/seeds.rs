//! Where an unmodeled mode is looked for ([`Seed`], [`mode_seeds`]) and how its search range
//! moves ([`Located`]), and the range of a levelling drift's time constant.

use crate::localise::Localisation;

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
    /// What locates the resonance ([`Pole`]).
    pub pole: Pole,
}

/// What must locate a resonance for it to be named (`strength::strength_z`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Pole {
    /// A ringing added to the outputs: its frequency and its decay
    /// (`strength::pole_z`). Nothing else pins it, and an oscillation of unknown
    /// decay fitted over a few cycles can be any slow disturbance.
    Ringing,
    /// A body hung on the structure: its frequency alone
    /// (`strength::body_z`). It pushes back on its coordinate, and that reaction,
    /// resolved in its mass (the strength), shows it over the whole band; its damping ratio is
    /// read only from its own resonance, which may be weak, and a lightly damped body whose
    /// damping is not resolved from zero is still there (forced draw 20261360: a 50 kg body at
    /// 20.7 Hz, ζ 1.7 %, fitted at 49.5 ± 5.0 kg, 20.28 ± 0.36 Hz, ζ 0.025 ± 0.013).
    Body,
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
    pub(super) fn other_starts(&self) -> impl Iterator<Item = f64> {
        let (low, high) = self.range;
        [std::f64::consts::FRAC_1_SQRT_2, std::f64::consts::SQRT_2]
            .map(|k| k * self.frequency)
            .into_iter()
            .filter(move |f| low < *f && *f < high)
    }
}

/// A search range: a factor 2 either side of `f`, within `limits`.
pub(super) fn about(f: f64, limits: (f64, f64)) -> (f64, f64) {
    ((0.5 * f).max(limits.0), (2.0 * f).min(limits.1))
}

/// Where an unmodeled mode is looked for first.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Seed {
    /// Frequency \[Hz\].
    pub(super) frequency: f64,
    /// Damping ratio.
    pub(super) damping: f64,
    /// The search range: a factor 2 about the frequency, within `limits`.
    pub(super) range: (f64, f64),
    /// How far the range may move ([`Located`]).
    pub(super) limits: (f64, f64),
}

/// Where the time constant τ of a drift that levels off is looked for, on a record of
/// `record` seconds: from a third of the record (it levels off over the record, 95 % of its
/// level at the end) to three records (within 15 % of a constant rate at the end), started at
/// half and at the whole record (the refit keeps the better). The data must locate τ inside
/// that range and resolve it ([`super::Trial::interior`]): on its lower bound the drift is an offset
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
pub(super) const MIN_CYCLES: f64 = 3.0;

/// The damping ratio below which a mode ERA finds is taken as a seed for an unmodeled mode
/// coupled through inertia or stiffness (a mode coupled through damping allows more).
pub(super) const LIGHTLY_DAMPED: f64 = 0.2;

/// A frequency an unmodeled mode's seed and range are kept clear of (a modelled mode): by
/// `margin` (relative), or by `sharp.0` only for a seed damped less than `sharp.1`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Clear {
    /// The frequency \[Hz\].
    pub(super) frequency: f64,
    /// The relative clearance.
    pub(super) margin: f64,
    /// (clearance, damping ratio): the smaller clearance for a seed damped less than this.
    pub(super) sharp: Option<(f64, f64)>,
}

impl Clear {
    /// Kept clear by `margin` whatever the seed's damping.
    pub(super) fn by(frequency: f64, margin: f64) -> Self {
        Clear { frequency, margin, sharp: None }
    }

    /// The clearance for a seed of damping ratio `damping`.
    fn for_damping(&self, damping: f64) -> f64 {
        match self.sharp {
            Some((clearance, below)) if damping < below => clearance,
            _ => self.margin,
        }
    }
}

/// A seed at `f` Hz of damping ratio `damping`, unless it lies within the clearance of a
/// frequency in `avoid`: its range a factor 2 about it, stopping short of those frequencies (by
/// their clearance), three cycles in the record and the Nyquist frequency of the grid it is
/// simulated on (a mode needs three cycles to be told from a trend).
pub(super) fn seed_at(f: f64, damping: f64, avoid: &[Clear], localisation: &Localisation) -> Option<Seed> {
    if avoid.iter().any(|c| (f / c.frequency - 1.0).abs() < c.for_damping(damping)) {
        return None;
    }
    let mut limits = (MIN_CYCLES / record_length(localisation), localisation.nyquist_hz);
    for c in avoid {
        let (s, margin) = (c.frequency, c.for_damping(damping));
        if s < f {
            limits.0 = limits.0.max((1.0 + margin) * s);
        } else {
            limits.1 = limits.1.min(s / (1.0 + margin));
        }
    }
    let range = about(f, limits);
    (range.0 < f && f < range.1).then_some(Seed { frequency: f, damping, range, limits })
}

/// Where an unmodeled mode may be: physical modes of the baseline's residual and of the data
/// itself damped less than `max_damping`, at most two, clear of each frequency in `avoid` (by
/// its [`Clear`]) and 10 % from each other, with the frequency within a factor 2 of the seed and
/// as clear of the frequencies to avoid. The slewing rig avoids only its servo mode (25 %): a
/// mode near a modelled flexible mode is allowed there, because coupled to the hub a new mode
/// and a modelled one beat (two peaks where the model has one), which no retuning of the
/// modelled mode reproduces, while near the servo a heavily coupled "mode" would only reshape
/// the servo's own response. A structure's extra mode adds to the outputs without coupling, so
/// near any of the modelled modes it would only stand in for a change of that mode: it avoids
/// them all (15 %) — on a forced record, where the measured input shows each resonance's width,
/// a seed far lighter damped than a modelled mode only by a few of that mode's bandwidths
/// (module `structure`).
///
/// Where neither record shows a mode to seed from, the modes in `fallback` (frequency, damping
/// ratio) are taken under the same rules: for the slewing rig its first flexible mode, which
/// every free decay of the rig holds and a mode coupled to it shifts. ERA misses it where the
/// servo's two overdamped poles carry all but a few percent of the record (a heavily damped mode
/// coupled through damping takes the flexible mode's motion away), and then no mode was tried.
pub(super) fn mode_seeds(
    avoid: &[Clear],
    max_damping: f64,
    localisation: &Localisation,
    fallback: &[(f64, f64)],
) -> Vec<Seed> {
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
            // (A NaN damping ratio is no seed either.)
            let damped_enough = damping < max_damping;
            if !damped_enough || seeds.iter().any(|s| (s.frequency / f - 1.0).abs() < 0.1) {
                continue;
            }
            seeds.extend(seed_at(f, damping, avoid, localisation));
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
        let located = Located {
            name: "f".into(),
            limits: (0.3, 10.0),
            prefix: "m(".into(),
            damping: "z".into(),
            pole: Pole::Ringing,
        };
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
            nyquist_hz: 64.0,
            outputs: Vec::new(),
            windows: vec![(0.0, 30.0, 1.0)],
            decrement_vs_amplitude: Vec::new(),
            decrement_trend: 0.0,
            residual_modes: Vec::new(),
            data_modes: modes,
            appendages: Vec::new(),
            findings: Vec::new(),
        };
        let fallback = [(1.7, 0.01)];
        let frequencies = |l: &Localisation| -> Vec<f64> {
            mode_seeds(&[Clear::by(0.15, 0.25)], LIGHTLY_DAMPED, l, &fallback)
                .iter()
                .map(|s| s.frequency)
                .collect()
        };
        assert_eq!(frequencies(&record(Vec::new())), [1.7]);
        assert_eq!(frequencies(&record(vec![mode(5.3)])), [5.3]);
        // A mode near the servo is no seed, and then neither record shows one.
        assert_eq!(frequencies(&record(vec![mode(0.16)])), [1.7]);
        let seeds = mode_seeds(&[Clear::by(0.15, 0.25)], LIGHTLY_DAMPED, &record(Vec::new()), &fallback);
        assert_eq!((seeds[0].range, seeds[0].damping), ((0.85, 3.4), 0.01));
    }

    /// A modelled mode at 13.7 Hz, ζ 5.6 %, kept clear by 15 %, or by 1.5 ζ for a seed damped
    /// less than ζ/2 (a forced record's sharp peak on the mode's flank).
    #[test]
    fn a_sharp_seed_needs_only_the_smaller_clearance_and_its_range_stops_there() {
        let residual = |f: f64, zeta: f64| era::EraMode {
            frequency_hz: f,
            damping_ratio: zeta,
            consistency: 1.0,
            mpc: Some(1.0),
            contribution: 0.5,
            physical: true,
        };
        let record = |mode: era::EraMode| Localisation {
            nyquist_hz: 100.0,
            outputs: Vec::new(),
            windows: vec![(0.0, 10.0, 1.0)],
            decrement_vs_amplitude: Vec::new(),
            decrement_trend: 0.0,
            residual_modes: vec![mode],
            data_modes: Vec::new(),
            appendages: Vec::new(),
            findings: Vec::new(),
        };
        let (f, zeta) = (13.7, 0.056);
        let broad = Clear::by(f, 0.15);
        let sharp = Clear { sharp: Some((1.5 * zeta, 0.5 * zeta)), ..broad };
        // 13 % above the mode: too near for the broad rule, clear for a sharp seed.
        let light = record(residual(15.48, 0.01));
        assert!(mode_seeds(&[broad], LIGHTLY_DAMPED, &light, &[]).is_empty());
        let seeds = mode_seeds(&[sharp], LIGHTLY_DAMPED, &light, &[]);
        assert_eq!(seeds.len(), 1);
        assert!((seeds[0].limits.0 - (1.0 + 1.5 * zeta) * f).abs() < 1e-12, "{:?}", seeds[0]);
        // A seed as damped as the mode (a change of the mode itself) keeps the broad rule.
        assert!(mode_seeds(&[sharp], LIGHTLY_DAMPED, &record(residual(15.48, 0.04)), &[]).is_empty());
        // And a sharp one within 1.5 ζ of the mode is no seed either.
        assert!(mode_seeds(&[sharp], LIGHTLY_DAMPED, &record(residual(14.5, 0.01)), &[]).is_empty());
    }
}
