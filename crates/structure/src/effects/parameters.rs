//! An effect's parameters: their names (which say where each acts) and values, in one order
//! that [`Effect::parameters`] lists and [`Effect::set`] writes.

use super::Effect;

impl Effect {
    /// Its parameters' names and values, given the outputs' names (for a mode's amplitudes).
    pub fn parameters(&self, outputs: &[String]) -> Vec<(String, f64)> {
        match self {
            Effect::OutputOffset { output, offset } => vec![(format!("offset_{output}"), *offset)],
            Effect::SensorScale { output, scale } => vec![(format!("scale_{output}"), *scale)],
            Effect::SensorDrift { output, rate, time_constant } => {
                let mut out = vec![(format!("drift_{output}"), *rate)];
                out.extend(time_constant.map(|tau| (format!("drift_time_{output}"), tau)));
                out
            }
            Effect::SensorQuantization { .. } => Vec::new(),
            Effect::SensorCrosstalk { output, from, gain } => {
                vec![(format!("crosstalk_{output}_{from}"), *gain)]
            }
            Effect::DryFriction { coordinate, force, static_peak, stribeck_velocity, .. } => {
                let mut out = vec![(format!("friction_{coordinate}"), *force)];
                out.extend(static_peak.map(|p| (format!("static_peak_{coordinate}"), p)));
                out.extend(stribeck_velocity.map(|v| (format!("stribeck_velocity_{coordinate}"), v)));
                out
            }
            Effect::Drag { coordinate, coefficient, exponent } => vec![
                (format!("drag_{coordinate}"), *coefficient),
                (format!("drag_exponent_{coordinate}"), *exponent),
            ],
            Effect::CubicStiffness { coordinate, coefficient, quadratic, quintic, sided, rate, change } => {
                let mut out = vec![(format!("cubic_{coordinate}"), *coefficient)];
                out.extend(quadratic.map(|k2| (format!("quadratic_{coordinate}"), k2)));
                out.extend(quintic.map(|k5| (format!("quintic_{coordinate}"), k5)));
                out.extend(sided.map(|ks| (format!("sided_{coordinate}"), ks)));
                out.extend(rate.map(|r| (format!("stiffness_rate_{coordinate}"), r)));
                for (i, v) in change.iter().flat_map(|c| &c.values).enumerate() {
                    out.push((format!("stiffness_change_{coordinate}_{}", i + 1), *v));
                }
                out
            }
            Effect::UnmodeledMode { frequency_hz, damping_ratio, amplitudes, .. } => {
                let mut out = vec![
                    ("mode_frequency".to_string(), *frequency_hz),
                    ("mode_damping".into(), *damping_ratio),
                ];
                for (name, (a, b)) in outputs.iter().zip(amplitudes) {
                    out.push((format!("mode_cos_{name}"), *a));
                    out.push((format!("mode_sin_{name}"), *b));
                }
                out
            }
            Effect::Appendage { coordinate, mass, frequency_hz, damping_ratio, release_force } => {
                let mut out = vec![
                    (format!("appendage_mass_{coordinate}"), *mass),
                    (format!("appendage_frequency_{coordinate}"), *frequency_hz),
                    (format!("appendage_damping_{coordinate}"), *damping_ratio),
                ];
                out.extend(release_force.map(|f| (format!("appendage_release_{coordinate}"), f)));
                out
            }
        }
    }

    /// Sets its k-th parameter (in the order of [`parameters`](Self::parameters)).
    pub(crate) fn set(&mut self, k: usize, value: f64) {
        match self {
            Effect::OutputOffset { offset: v, .. }
            | Effect::SensorScale { scale: v, .. }
            | Effect::SensorCrosstalk { gain: v, .. } => *v = value,
            Effect::SensorDrift { rate, time_constant, .. } => {
                let mut slots: Vec<&mut f64> = vec![rate];
                slots.extend(time_constant.as_mut());
                *slots[k] = value;
            }
            Effect::DryFriction { force, static_peak, stribeck_velocity, .. } => {
                let mut slots: Vec<&mut f64> = vec![force];
                slots.extend(static_peak.as_mut());
                slots.extend(stribeck_velocity.as_mut());
                *slots[k] = value;
            }
            Effect::CubicStiffness { coefficient, quadratic, quintic, sided, rate, change, .. } => {
                let mut slots: Vec<&mut f64> = vec![coefficient];
                slots.extend(quadratic.as_mut());
                slots.extend(quintic.as_mut());
                slots.extend(sided.as_mut());
                slots.extend(rate.as_mut());
                slots.extend(change.iter_mut().flat_map(|c| c.values.iter_mut()));
                *slots[k] = value;
            }
            Effect::Drag { coefficient, exponent, .. } => *[coefficient, exponent][k] = value,
            Effect::UnmodeledMode { frequency_hz, damping_ratio, amplitudes, .. } => match k {
                0 => *frequency_hz = value,
                1 => *damping_ratio = value,
                k if k % 2 == 0 => amplitudes[(k - 2) / 2].0 = value,
                k => amplitudes[(k - 2) / 2].1 = value,
            },
            Effect::Appendage { mass, frequency_hz, damping_ratio, release_force, .. } => {
                let mut slots: Vec<&mut f64> = vec![mass, frequency_hz, damping_ratio];
                slots.extend(release_force.as_mut());
                *slots[k] = value;
            }
            Effect::SensorQuantization { .. } => {}
        }
    }
}
