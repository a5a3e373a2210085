//! Where a named effect's second-stage parameters are looked for: a dry friction's static peak
//! ([`StaticPeakSearch`]) and a saturation's knee ([`KneeSearch`]).

use models::{Model, ModelEffect};
use plant::EffectKind;

use super::slewing;

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
    pub(super) smoothing_velocity: f64,
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
    pub(super) kind: EffectKind,
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
