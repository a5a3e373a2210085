//! A named effect's form in words (a friction's static peak, a saturation's knee), and the
//! rival accounts a structure's force or mode was set aside for (a law in time, dampers
//! distributed otherwise).

use super::super::{DampingRival, EffectParameter, SaturationKnee, StaticPeak, TimeLaw};

impl TimeLaw {
    /// Why the named force, whose own in-sample gain over the reference was `in_sample`, was set
    /// aside for this law (the threshold it had to beat the law by).
    pub(super) fn sentence(&self, in_sample: f64, threshold: f64) -> String {
        format!(
            "predictive on held-out blocks ({in_sample:.1} nats in sample), but a linear stiffness at `{}` that \
             changes with time by a law of its own ({} values, piecewise linear to {:.2} s), in its place, explains \
             the record as well ({:.1} nats in sample against {:.1}; the named force must explain {threshold:.0} \
             more) — a stiffness lost or gained during the record (a storey that degrades, settles after a loss or \
             drops in a step), outside the catalog, for which it only stands in",
            self.coordinate,
            self.values.len(),
            self.times.last().copied().unwrap_or(0.0),
            self.gain,
            self.effect_gain,
        )
    }
}

impl DampingRival {
    /// Why the named effect of this kind (a mode, a drag or a dry friction), whose own in-sample
    /// gain over the reference was `in_sample`, was set aside for these dampers (the threshold
    /// it had to beat them by).
    pub(super) fn sentence(&self, kind: plant::EffectKind, in_sample: f64, threshold: f64) -> String {
        let what = match kind {
            plant::EffectKind::QuadraticDrag => "drag",
            plant::EffectKind::CoulombFriction => "friction",
            _ => "mode",
        };
        format!(
            "predictive on held-out blocks ({in_sample:.1} nats in sample), but a linear damper at every coordinate \
             ({}), in its place, explains the record as well ({:.1} nats in sample against {:.1}; the named {what} must \
             explain {threshold:.0} more) — the structure's damping is distributed otherwise than the model's form \
             gives (its modes' ratios), a mismatch of the model's own damping, for which the {what} only stands in",
            self.dampers
                .iter()
                .map(|d| with_se(d, format!("`{}` = {:.3e}", d.name, d.value)))
                .collect::<Vec<_>>()
                .join(", "),
            self.gain,
            self.effect_gain,
        )
    }
}

impl StaticPeak {
    /// The friction's form in words: the peak the data demand, or how far it got.
    pub(super) fn sentence(&self) -> String {
        // The slewing rig's hub friction (the only one tested): a torque against a rate.
        let (force, rate) = (" N·m", " rad/s");
        let with_se = |p: &EffectParameter| with_se(p, format!("{:.3e}", p.value));
        if self.demanded {
            format!(
                "the friction has a static peak: it breaks away at F_c + ΔF = {:.3e}{force} and slides at F_c = \
                 {}{force}, the peak ΔF = {}{force} falling over the Stribeck velocity {}{rate} (gains {:.1} nats over \
                 a constant level); the named friction carries it. Its height and width are those of this form, \
                 e^{{−(v/v_st)²}}: the standard errors do not include what another form of the peak would move them",
                self.coulomb_torque.value + self.peak.value,
                with_se(&self.coulomb_torque),
                with_se(&self.peak),
                with_se(&self.stribeck_velocity),
                self.gain
            )
        } else {
            format!(
                "no static peak is resolved beside it (ΔF = {}{force} over {}{rate} gains {:.1} nats): the friction \
                 stays Coulomb's constant level",
                with_se(&self.peak),
                with_se(&self.stribeck_velocity),
                self.gain
            )
        }
    }
}

impl SaturationKnee {
    /// The limiter's form in words: the knee the data demand, or how far it got.
    pub(super) fn sentence(&self) -> String {
        let with_se = |p: &EffectParameter| with_se(p, format!("{:.3}", p.value));
        let unit = if self.limit.name == plant::ParamId::CurrentLimit.name() { " A" } else { " V" };
        if self.demanded && self.clamp {
            format!(
                "the limit is a clamp: the limiter's knee comes out at n = {:.0} (50 or more is within 1.4 % of a clamp; \
                 it gains {:.1} nats over the catalog's n = 8), with the limit L = {}{unit}; the named saturation \
                 carries it",
                self.knee.value,
                self.gain,
                with_se(&self.limit)
            )
        } else if self.demanded {
            let shape = if self.knee.value < 8.0 { "softer" } else { "sharper" };
            format!(
                "the limit is {shape} than the catalog's limiter x/(1 + |x/L|⁸)^{{1/8}}: its knee n = {} with the limit \
                 L = {}{unit} (gains {:.1} nats over n = 8; n → ∞ is a clamp, n = 2 the soft x/√(1 + (x/L)²)); the \
                 named saturation carries it. L is the level of this family, which a soft limiter reaches only \
                 slowly: the standard errors do not include what another form of the knee would move them",
                with_se(&self.knee),
                with_se(&self.limit),
                self.gain
            )
        } else {
            format!(
                "no knee other than the catalog's is resolved (n = {} gains {:.1} nats over n = 8): the limiter \
                 stays x/(1 + |x/L|⁸)^{{1/8}}",
                with_se(&self.knee),
                self.gain
            )
        }
    }
}

/// A form parameter's value (as `value` writes it) with its standard error, or "(not
/// determined)".
fn with_se(p: &EffectParameter, value: String) -> String {
    match p.std_error {
        Some(se) => format!("{value} ± {se:.1e}"),
        None => format!("{value} (not determined)"),
    }
}
