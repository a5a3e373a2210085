//! The catalog of physical effects a model file may add to the paper's linear model.
//!
//! Linear effects are exact augmentations of the state space (they keep the
//! matrix-exponential path); nonlinear ones add generalised forces (see [`crate::nonlinear`]).
//!
//! | effect | parameters (names) | form |
//! | --- | --- | --- |
//! | `AmplifierSaturation` | `current_limit` \[A\] | armature current i = sat((e_a − K_bθ̇)/R_a) |
//! | `CoulombFriction` | `coulomb_torque` \[N·m\] | τ = −F_c tanh(θ̇/v_s), v_s fixed smoothing velocity |
//! | `QuadraticDrag` | `drag_hub` \[N·m·s²/rad²\] | τ = −c_d \|θ̇\| θ̇ (air drag, the paper's ref. 10) |
//! | `SensorQuantization` | — (measurement only) | y ← Δ·round(y/Δ) on one sensor |
//! | `OutputOffset` | `offset_<output>` | y ← y + b (a constant state) |
//! | `TimeDelay` | `delay` \[s\] | feedback sees θ(t − τ), Padé(1,1): θ_d = −θ + w, ẇ = (2/τ)(2θ − w) |
//! | `UnmodeledMode` | `extra_mode_frequency` \[Hz\], `extra_mode_damping`, `extra_mode_coupling` \[√kg·m\] | a mass-normalised mode η: η̈ + 2ζωη̇ + ω²η coupled to the hub through M |

use crate::sensors::Sensor;
use serde::{Deserialize, Serialize};

/// One effect and its parameter values.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum Effect<D = f64> {
    /// Armature current limit of the power amplifier.
    AmplifierSaturation {
        /// Current limit \[A\].
        current_limit: D,
        /// `true`: an ideal clamp (for truth data; not differentiable at the corner).
        /// `false` (default): the smooth limiter i/(1 + (i/I)⁸)^{1/8}, within 1 % of linear
        /// below 0.6·I and of the clamp above 2·I.
        #[serde(default)]
        sharp: bool,
    },
    /// Dry friction at the hub, smoothed by tanh so that sensitivities exist.
    CoulombFriction {
        /// Friction torque \[N·m\].
        torque: D,
        /// Smoothing velocity v_s \[rad/s\] (fixed; the friction is within 1 − tanh(3) ≈ 0.5 % of
        /// its full value above 3·v_s).
        smoothing_velocity: f64,
    },
    /// Air drag on the hub and beam, lumped as a torque ∝ |θ̇|θ̇.
    QuadraticDrag {
        /// Coefficient c_d \[N·m·s²/rad²\].
        hub: D,
    },
    /// Quantization of one sensor (the potentiometer's windings); measurement-only.
    SensorQuantization {
        /// Which sensor.
        sensor: Sensor,
        /// Step Δ, in the output's unit.
        step: f64,
    },
    /// A constant bias on one sensor.
    OutputOffset {
        /// Which sensor.
        sensor: Sensor,
        /// Bias, in the output's unit.
        offset: D,
    },
    /// A delay in the position feedback.
    TimeDelay {
        /// Delay τ \[s\].
        delay: D,
    },
    /// An extra structural mode that the beam model lacks.
    UnmodeledMode {
        /// Natural frequency \[Hz\].
        frequency_hz: D,
        /// Damping ratio.
        damping_ratio: D,
        /// Coupling to the hub (a participation integral) \[√kg·m\].
        coupling: D,
    },
}

impl<D> Effect<D> {
    /// The catalog name (snake case), as used by `memid diagnose`.
    pub fn kind(&self) -> &'static str {
        match self {
            Effect::AmplifierSaturation { .. } => "amplifier_saturation",
            Effect::CoulombFriction { .. } => "coulomb_friction",
            Effect::QuadraticDrag { .. } => "quadratic_drag",
            Effect::SensorQuantization { .. } => "sensor_quantization",
            Effect::OutputOffset { .. } => "output_offset",
            Effect::TimeDelay { .. } => "time_delay",
            Effect::UnmodeledMode { .. } => "unmodeled_mode",
        }
    }

    /// Whether the effect makes the dynamics nonlinear.
    pub fn is_nonlinear(&self) -> bool {
        matches!(
            self,
            Effect::AmplifierSaturation { .. }
                | Effect::CoulombFriction { .. }
                | Effect::QuadraticDrag { .. }
        )
    }

    /// Converts the parameter values with `f`.
    pub fn map<E>(&self, f: impl Fn(&D) -> E) -> Effect<E> {
        match self {
            Effect::AmplifierSaturation { current_limit, sharp } => {
                Effect::AmplifierSaturation { current_limit: f(current_limit), sharp: *sharp }
            }
            Effect::CoulombFriction { torque, smoothing_velocity } => {
                Effect::CoulombFriction { torque: f(torque), smoothing_velocity: *smoothing_velocity }
            }
            Effect::QuadraticDrag { hub } => Effect::QuadraticDrag { hub: f(hub) },
            Effect::SensorQuantization { sensor, step } => {
                Effect::SensorQuantization { sensor: *sensor, step: *step }
            }
            Effect::OutputOffset { sensor, offset } => {
                Effect::OutputOffset { sensor: *sensor, offset: f(offset) }
            }
            Effect::TimeDelay { delay } => Effect::TimeDelay { delay: f(delay) },
            Effect::UnmodeledMode { frequency_hz, damping_ratio, coupling } => Effect::UnmodeledMode {
                frequency_hz: f(frequency_hz),
                damping_ratio: f(damping_ratio),
                coupling: f(coupling),
            },
        }
    }
}
