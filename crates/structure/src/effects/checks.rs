//! Whether an effect can act on a model ([`Effect::invalid`]): its target exists there and its
//! values are possible.

use super::{Effect, Target};

impl Effect {
    /// Why the effect cannot act on a model with these outputs, coordinates and inputs (`None`
    /// if it can); `second_order` says whether the coordinates are a second-order model's.
    pub(crate) fn invalid(
        &self,
        outputs: &[String],
        coordinates: &[String],
        inputs: &[String],
        second_order: bool,
    ) -> Option<String> {
        let finite = |name: &str, v: f64| (!v.is_finite()).then(|| format!("{name} = {v} is not finite"));
        let problem = match self.target() {
            Target::Output(o) if !outputs.iter().any(|n| n == o) => {
                Some(format!("no output `{o}`; the outputs are {}", outputs.join(", ")))
            }
            Target::Coordinate(c) if !second_order => Some(format!(
                "{} at `{c}` needs a second-order model (its coordinates); this file is first order",
                if self.is_force() { "a force" } else { "an appendage" }
            )),
            Target::Coordinate(c) if !coordinates.iter().any(|n| n == c) => {
                Some(format!("no coordinate `{c}`; the coordinates are {}", coordinates.join(", ")))
            }
            _ => None,
        };
        problem.or_else(|| self.parameters(outputs).iter().find_map(|(n, v)| finite(n, *v))).or_else(|| {
            match self {
                Effect::SensorQuantization { step, .. } if !(step.is_finite() && *step > 0.0) => {
                    Some(format!("step = {step}: give a positive step"))
                }
                Effect::SensorCrosstalk { output, from, .. }
                    if from == output || !outputs.iter().any(|n| n == from) =>
                {
                    Some(format!(
                        "from = `{from}`: give another output than `{output}`; the outputs are {}",
                        outputs.join(", ")
                    ))
                }
                Effect::DryFriction { smoothing_velocity: v, .. } if !(v.is_finite() && *v > 0.0) => {
                    Some(format!("smoothing_velocity = {v}: give a positive velocity"))
                }
                Effect::DryFriction { static_peak, stribeck_velocity, .. }
                    if static_peak.is_some() != stribeck_velocity.is_some() =>
                {
                    Some("give `static_peak` and `stribeck_velocity` together (or neither)".into())
                }
                Effect::DryFriction { static_peak: Some(p), .. } if *p < 0.0 => {
                    Some(format!("static_peak = {p}: give a peak ≥ 0"))
                }
                Effect::DryFriction { stribeck_velocity: Some(v), .. } if *v <= 0.0 => {
                    Some(format!("stribeck_velocity = {v}: give a positive velocity"))
                }
                Effect::SensorDrift { time_constant: Some(tau), .. } if *tau <= 0.0 => {
                    Some(format!("time_constant = {tau}: give a positive time constant [s]"))
                }
                Effect::CubicStiffness { change: Some(change), .. }
                    if change.times.len() != change.values.len() =>
                {
                    Some(format!(
                        "change: {} times and {} values; give one value per time",
                        change.times.len(),
                        change.values.len()
                    ))
                }
                Effect::CubicStiffness { change: Some(change), .. }
                    if change.times.is_empty()
                        || change.times.iter().any(|t| !(t.is_finite() && *t > 0.0))
                        || change.times.windows(2).any(|w| w[1] <= w[0]) =>
                {
                    Some("change: give one or more positive times [s], each after the one before".into())
                }
                Effect::Drag { exponent, .. } if *exponent < 1.0 => {
                    Some(format!("exponent = {exponent}: give an exponent of at least 1"))
                }
                Effect::Appendage { mass, .. } if *mass <= 0.0 => {
                    Some(format!("mass = {mass}: give a positive mass [kg]"))
                }
                Effect::Appendage { frequency_hz, .. } if *frequency_hz <= 0.0 => {
                    Some(format!("frequency_hz = {frequency_hz}: give a positive frequency"))
                }
                Effect::Appendage { damping_ratio, .. } if *damping_ratio < 0.0 => {
                    Some(format!("damping_ratio = {damping_ratio}: give a ratio ≥ 0"))
                }
                Effect::Appendage { mass, frequency_hz, damping_ratio, .. }
                    if !spring_and_damper_finite(*mass, *frequency_hz, *damping_ratio) =>
                {
                    Some(format!(
                        "mass = {mass}, frequency_hz = {frequency_hz}, damping_ratio = {damping_ratio}: its stiffness \
                         m(2πf)² or damping 2ζm(2πf) overflows; give values of a physical appendage"
                    ))
                }
                Effect::UnmodeledMode { frequency_hz, damping_ratio, amplitudes, driven_by } => {
                    if *frequency_hz <= 0.0 {
                        Some(format!("frequency_hz = {frequency_hz}: give a positive frequency"))
                    } else if !spring_and_damper_finite(1.0, *frequency_hz, *damping_ratio) {
                        Some(format!(
                            "frequency_hz = {frequency_hz}, damping_ratio = {damping_ratio}: (2πf)² or 2ζ(2πf) overflows; \
                             give the frequency [Hz] and ratio of a physical mode"
                        ))
                    } else if *damping_ratio < 0.0 {
                        Some(format!("damping_ratio = {damping_ratio}: give a ratio ≥ 0"))
                    } else if amplitudes.len() != outputs.len() {
                        Some(format!(
                            "{} amplitude pairs for {} outputs; give one (cos, sin) pair per output",
                            amplitudes.len(),
                            outputs.len()
                        ))
                    } else {
                        driven_by.as_ref().filter(|i| !inputs.contains(i)).map(|input| {
                            if inputs.is_empty() {
                                format!("driven_by = `{input}`: the model has no inputs; leave it out for a free ringing")
                            } else {
                                format!("driven_by = `{input}`: no such input; the inputs are {}", inputs.join(", "))
                            }
                        })
                    }
                }
                _ => None,
            }
        })
    }
}

/// Whether a mass on a spring and damper tuned to `frequency_hz` with ratio `zeta` has a finite
/// stiffness m(2πf)² and damping 2ζm(2πf): values each finite alone can overflow in these.
fn spring_and_damper_finite(mass: f64, frequency_hz: f64, zeta: f64) -> bool {
    let omega = 2.0 * std::f64::consts::PI * frequency_hz;
    (mass * omega * omega).is_finite() && (2.0 * zeta * mass * omega).is_finite()
}
