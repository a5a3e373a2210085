//! The catalog of physical effects a model file may add to the paper's linear model.
//!
//! Linear effects are exact augmentations of the state space (they keep the
//! matrix-exponential path); nonlinear ones add generalised forces (see [`crate::nonlinear`]);
//! sensor effects act on the readings only and are applied by the adapter layer (`models`),
//! which applies them to any model kind.
//!
//! | effect | parameters (names) | form |
//! | --- | --- | --- |
//! | `AmplifierSaturation` | `current_limit` \[A\], optional `current_knee` n | armature current i = sat((e_a − K_bθ̇)/R_a) |
//! | `VoltageSaturation` | `voltage_limit` \[V\], optional `voltage_knee` n | amplifier output e_a = sat(G K_p(θ_ref − θ)); the back-EMF still acts |
//! | `CoulombFriction` | `coulomb_torque` \[N·m\], optional `static_peak` ΔF \[N·m\] and `stribeck_velocity` v_st \[rad/s\] | τ = −(F_c + ΔF e^{−(θ̇/v_st)²}) tanh(θ̇/v_s), v_s fixed smoothing velocity: dry friction, with a static peak that falls to the Coulomb level over v_st (Stribeck; Armstrong-Hélouvry, Dupont & Canudas de Wit 1994) when given |
//! | `QuadraticDrag` | `drag_hub` \[N·m·(s/rad)ᵖ\], optional `drag_exponent` p | τ = −c_d \|θ̇\|ᵖ sign θ̇ (p = 2 unless given: air drag, the paper's ref. 10) |
//! | `CubicStiffness` | `cubic_stiffness` \[N·m/rad³\], optional `hub_stiffness` k₁ \[N·m/rad\], `quintic_stiffness` k₅ \[N·m/rad⁵\] and `stiffness_rate` k₁′ \[N·m/(rad·s)\] | τ = −(k₁ + k₁′t)θ − k₃θ³ − k₅θ⁵ on the hub (hardening for k₃ > 0, softening for k₃ < 0; k₁, k₁′, k₅ = 0 unless given; k₅ and k₁′ are the terms the diagnosis tests a named spring's form with) |
//! | `TimeDelay` | `delay` \[s\] | feedback sees θ(t − τ), Padé(1,1): θ_d = −θ + w, ẇ = (2/τ)(2θ − w) |
//! | `UnmodeledMode` | `extra_mode_frequency` \[Hz\], `extra_mode_damping`, `extra_mode_coupling` \[√kg·m\], optional `extra_mode_stiffness_coupling` \[N·m/√kg\], optional `extra_mode_damping_coupling` \[N·m·s/√kg\] | a mass-normalised mode η: η̈ + 2ζωη̇ + ω²η coupled to the hub through M (and K, and D) |
//! | `Backlash` | `backlash` \[rad\], `gear_frequency` \[Hz\] | the motor is a body of its own (I_m), joined to the hub by a gear of stiffness k_g = I_m(2πf_g)² and damping 2ζ_g I_m 2πf_g with a dead band of total width b: τ_g = k_g dz_b(θ_m − θ) + c_g(θ̇_m − θ̇); the servo, C_v and the back-EMF act on the motor, the potentiometer reads the hub, the tachometer the motor (or the hub) |
//! | `SensorQuantization` | — (measurement only) | y ← Δ·round(y/Δ) on one sensor |
//! | `OutputOffset` | `offset_<output>` | y ← y + b on one sensor |
//! | `SensorScale` | `scale_<output>` | y ← (1 + s)·y on one sensor (a calibration error) |
//! | `SensorCrosstalk` | `crosstalk_<output>_<from>` | y ← y + g·y_from on one sensor: another sensor's signal picked up by its channel (a wiring or amplifier fault; a measurement fact the diagnosis sets against a named effect, not a catalog candidate) |
//! | `SensorLag` | `lag_<output>` \[s\] | y ← y(t − τ_s) on one sensor, Padé(1,1): y_read = −y + w, ẇ = (2/τ_s)(2y − w) — its channel read late (a multiplexed converter's sampling skew, an anti-alias filter's group delay; a measurement fact the diagnosis sets against a named effect, not a catalog candidate) |
//! | `SensorDrift` | `drift_<output>` \[unit/s\], optional `drift_time_<output>` τ \[s\] | y ← y + d·t on one sensor (a slow drift); with τ, y ← y + d·τ(1 − e^{−t/τ}): a drift at rate d that levels off at d·τ (a sensor warming up) |

use crate::sensors::Sensor;
use serde::{Deserialize, Serialize};

/// The kinds of effect in the catalog (the JSON `effect` names of `memid diagnose`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum EffectKind {
    /// A limit on the armature current; in diagnosis also the amplifier's saturation where the
    /// data do not say which quantity it limits.
    AmplifierSaturation,
    /// A limit on the amplifier's output voltage (the back-EMF still acts beyond it).
    VoltageSaturation,
    /// Dry friction at the hub.
    CoulombFriction,
    /// Drag at the hub (exponent 2 unless given).
    QuadraticDrag,
    /// Hardening or softening stiffness at the hub.
    CubicStiffness,
    /// A dead band between motor and hub.
    Backlash,
    /// A quantized sensor.
    SensorQuantization,
    /// A constant bias on a sensor.
    OutputOffset,
    /// A scale-factor error of a sensor.
    SensorScale,
    /// A slow drift of a sensor.
    SensorDrift,
    /// A transport delay in the feedback loop.
    TimeDelay,
    /// A structural mode the model lacks.
    UnmodeledMode,
    /// Another sensor's signal picked up by one sensor's channel. Not a candidate of the
    /// diagnosis: it is set against a named effect (a wiring fault is not physics).
    SensorCrosstalk,
    /// One sensor's channel read late (a sampling skew, a filter's delay). Not a candidate of
    /// the diagnosis: it is set against a named effect (an acquisition's timing is not physics).
    SensorLag,
}

impl EffectKind {
    /// Every kind, in catalog order.
    pub const ALL: [EffectKind; 14] = [
        EffectKind::AmplifierSaturation,
        EffectKind::VoltageSaturation,
        EffectKind::CoulombFriction,
        EffectKind::QuadraticDrag,
        EffectKind::CubicStiffness,
        EffectKind::Backlash,
        EffectKind::SensorQuantization,
        EffectKind::OutputOffset,
        EffectKind::SensorScale,
        EffectKind::SensorDrift,
        EffectKind::TimeDelay,
        EffectKind::UnmodeledMode,
        EffectKind::SensorCrosstalk,
        EffectKind::SensorLag,
    ];

    /// The catalog name (snake case), as `memid diagnose` reports it.
    pub fn name(self) -> &'static str {
        match self {
            EffectKind::AmplifierSaturation => "amplifier_saturation",
            EffectKind::VoltageSaturation => "voltage_saturation",
            EffectKind::CoulombFriction => "coulomb_friction",
            EffectKind::QuadraticDrag => "quadratic_drag",
            EffectKind::CubicStiffness => "cubic_stiffness",
            EffectKind::Backlash => "backlash",
            EffectKind::SensorQuantization => "sensor_quantization",
            EffectKind::OutputOffset => "output_offset",
            EffectKind::SensorScale => "sensor_scale",
            EffectKind::SensorDrift => "sensor_drift",
            EffectKind::TimeDelay => "time_delay",
            EffectKind::UnmodeledMode => "unmodeled_mode",
            EffectKind::SensorCrosstalk => "sensor_crosstalk",
            EffectKind::SensorLag => "sensor_lag",
        }
    }

    /// The kind of a catalog name.
    pub fn parse(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|k| k.name() == name)
    }

    /// Whether the effect acts on one sensor's readings only, applied to the readings (a
    /// [`EffectKind::SensorLag`] acts on one sensor's readings too, but through a state of the
    /// dynamics: it is not one of these).
    pub fn is_sensor_effect(self) -> bool {
        matches!(
            self,
            EffectKind::SensorQuantization
                | EffectKind::OutputOffset
                | EffectKind::SensorScale
                | EffectKind::SensorDrift
                | EffectKind::SensorCrosstalk
        )
    }
}

impl std::fmt::Display for EffectKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// One effect and its parameter values.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum Effect<D = f64> {
    /// Armature current limit of the power amplifier.
    AmplifierSaturation {
        /// Current limit \[A\].
        current_limit: D,
        /// `true`: an ideal clamp (for truth data; not differentiable at the corner).
        /// `false` (default): the smooth limiter i/(1 + |i/I|ⁿ)^{1/n} with n = 8 (or `knee`),
        /// within 1 % of linear below 0.6·I and of the clamp above 2·I.
        #[serde(default)]
        sharp: bool,
        /// The limiter's knee n (`current_knee`), 8 when absent: how sharply the output turns from
        /// linear to the limit. Large n approaches the clamp; n = 2 is the soft limit
        /// i/√(1 + (i/I)²), below the linear law by 1 % already at 0.14·I. A parameter when
        /// given; ignored by a sharp clamp.
        #[serde(default)]
        knee: Option<D>,
    },
    /// Output voltage limit of the power amplifier.
    VoltageSaturation {
        /// Voltage limit \[V\].
        voltage_limit: D,
        /// An ideal clamp (`true`) or the smooth limiter of [`Effect::AmplifierSaturation`].
        #[serde(default)]
        sharp: bool,
        /// The smooth limiter's knee n (`voltage_knee`), 8 when absent (as
        /// [`Effect::AmplifierSaturation`]'s).
        #[serde(default)]
        knee: Option<D>,
    },
    /// Dry friction at the hub, smoothed by tanh so that sensitivities exist.
    CoulombFriction {
        /// Friction torque \[N·m\].
        torque: D,
        /// Smoothing velocity v_s \[rad/s\] (fixed; the friction is within 1 − tanh(3) ≈ 0.5 % of
        /// its full value above 3·v_s).
        smoothing_velocity: f64,
        /// ΔF = F_s − F_c \[N·m\] (`static_peak`): how far the friction at rest (the static,
        /// breakaway level F_s) exceeds the sliding one. Given together with
        /// `stribeck_velocity`; absent, the friction is Coulomb's alone.
        #[serde(default)]
        static_peak: Option<D>,
        /// v_st \[rad/s\] (`stribeck_velocity`): the rate over which the peak falls, as
        /// e^{−(θ̇/v_st)²}.
        #[serde(default)]
        stribeck_velocity: Option<D>,
    },
    /// Air drag on the hub and beam, lumped as a torque ∝ |θ̇|ᵖ sign θ̇.
    QuadraticDrag {
        /// Coefficient c_d \[N·m·(s/rad)ᵖ\].
        hub: D,
        /// The exponent p (2 when absent); a parameter (`drag_exponent`) when given.
        #[serde(default)]
        exponent: Option<D>,
    },
    /// A nonlinear restoring torque at the hub: a spring there, hardening or softening.
    CubicStiffness {
        /// k₃ \[N·m/rad³\]: τ = −k₁θ − k₃θ³.
        coefficient: D,
        /// k₁ \[N·m/rad\], the spring's linear part (0 when absent); a parameter
        /// (`hub_stiffness`) when given. Acting on the hub alone, it is not the servo's
        /// stiffness: the servo's torque reaches the flexible modes through the hub's geometry
        /// (Γ), a hub spring's does not.
        #[serde(default)]
        linear: Option<D>,
        /// k₅ \[N·m/rad⁵\]: a symmetric refinement of the spring's form, −k₅θ⁵ (0 when absent);
        /// a parameter (`quintic_stiffness`) when given.
        #[serde(default)]
        quintic: Option<D>,
        /// k₁′ \[N·m/(rad·s)\]: a linear stiffness that grows at this rate over the record,
        /// −k₁′·t·θ with t from the release (0 when absent): a stiffness that changes with time,
        /// not with amplitude; a parameter (`stiffness_rate`) when given.
        #[serde(default)]
        rate: Option<D>,
    },
    /// A dead band in the gear between the motor and the hub (backlash).
    ///
    /// The motor becomes a degree of freedom θ_m of its own with inertia I_m (taken out of the
    /// hub's); the servo torque, C_v and the back-EMF act on it, with the potentiometer's θ (the
    /// hub) fed back. The gear passes τ_g = k_g dz_b(θ_m − θ) + c_g(θ̇_m − θ̇) to the hub, where
    /// dz_b(δ) = δ − sat_{b/2}(δ) is zero inside the band (the smooth limiter of
    /// [`Effect::AmplifierSaturation`] for sat). With the band closed and the gear rigid it is
    /// the lumped model exactly.
    Backlash {
        /// Total width b of the dead band \[rad\] (`backlash`).
        dead_band: D,
        /// f_g = √(k_g/I_m)/2π \[Hz\] (`gear_frequency`): the motor against the gear's stiffness.
        gear_frequency_hz: D,
        /// Damping ratio ζ_g of the gear, c_g = 2ζ_g I_m 2πf_g (fixed; 0.05 when absent).
        #[serde(default = "default_gear_damping")]
        gear_damping_ratio: f64,
        /// The tachometer reads the motor shaft (`true`, the default) or the hub.
        #[serde(default = "default_true")]
        tachometer_on_motor: bool,
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
    /// A scale-factor error of one sensor.
    SensorScale {
        /// Which sensor.
        sensor: Sensor,
        /// s: the reading is (1 + s)·y.
        scale: D,
    },
    /// A slow drift of one sensor.
    SensorDrift {
        /// Which sensor.
        sensor: Sensor,
        /// d: the reading is y + d·t, in the output's unit per second (its rate at t = 0 when
        /// it levels off).
        rate: D,
        /// τ \[s\] (`drift_time_<output>`, absent: none): the drift levels off, the reading is
        /// y + d·τ(1 − e^{−t/τ}) — a sensor or its amplifier warming up — and d·t as τ → ∞.
        #[serde(default)]
        time_constant: Option<D>,
    },
    /// Another sensor's signal picked up by one sensor's channel.
    SensorCrosstalk {
        /// The sensor whose reading carries the other's.
        sensor: Sensor,
        /// The sensor whose signal it picks up.
        from: Sensor,
        /// g: the reading is y + g·y_from (y_from as the dynamics give it, before the other
        /// sensor's own effects), in the ratio of the two outputs' units.
        gain: D,
    },
    /// One sensor's channel read late: the reading is y(t − τ_s), by Padé(1,1) (a state w,
    /// ẇ = (2/τ_s)(2y − w), read as −y + w), which keeps the exponential path. A multiplexed
    /// converter that samples its channels in turn, or an anti-alias filter of one channel
    /// (group delay ≈ its phase slope), reads one sensor late against the others.
    SensorLag {
        /// Which sensor.
        sensor: Sensor,
        /// τ_s \[s\] (`lag_<output>`), > 0.
        lag: D,
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
        /// Coupling to the hub through the mass matrix (a participation integral) \[√kg·m\].
        coupling: D,
        /// Coupling to the hub through the stiffness matrix \[N·m/√kg\] (absent: none).
        #[serde(default)]
        stiffness_coupling: Option<D>,
        /// Coupling to the hub through the damping matrix \[N·m·s/√kg\] (absent: none): a
        /// damper between the hub and the mode's coordinate.
        #[serde(default)]
        damping_coupling: Option<D>,
    },
}

/// The gear's damping ratio when a file gives none.
pub const DEFAULT_GEAR_DAMPING: f64 = 0.05;

fn default_gear_damping() -> f64 {
    DEFAULT_GEAR_DAMPING
}

fn default_true() -> bool {
    true
}

impl<D> Effect<D> {
    /// The effect's kind.
    pub fn kind(&self) -> EffectKind {
        match self {
            Effect::AmplifierSaturation { .. } => EffectKind::AmplifierSaturation,
            Effect::VoltageSaturation { .. } => EffectKind::VoltageSaturation,
            Effect::CoulombFriction { .. } => EffectKind::CoulombFriction,
            Effect::QuadraticDrag { .. } => EffectKind::QuadraticDrag,
            Effect::CubicStiffness { .. } => EffectKind::CubicStiffness,
            Effect::Backlash { .. } => EffectKind::Backlash,
            Effect::SensorQuantization { .. } => EffectKind::SensorQuantization,
            Effect::OutputOffset { .. } => EffectKind::OutputOffset,
            Effect::SensorScale { .. } => EffectKind::SensorScale,
            Effect::SensorDrift { .. } => EffectKind::SensorDrift,
            Effect::TimeDelay { .. } => EffectKind::TimeDelay,
            Effect::UnmodeledMode { .. } => EffectKind::UnmodeledMode,
            Effect::SensorCrosstalk { .. } => EffectKind::SensorCrosstalk,
            Effect::SensorLag { .. } => EffectKind::SensorLag,
        }
    }

    /// The sensor a measurement-side effect acts on.
    pub fn sensor(&self) -> Option<Sensor> {
        match self {
            Effect::SensorQuantization { sensor, .. }
            | Effect::OutputOffset { sensor, .. }
            | Effect::SensorScale { sensor, .. }
            | Effect::SensorDrift { sensor, .. }
            | Effect::SensorCrosstalk { sensor, .. }
            | Effect::SensorLag { sensor, .. } => Some(*sensor),
            _ => None,
        }
    }

    /// Whether the effect makes the dynamics nonlinear.
    pub fn is_nonlinear(&self) -> bool {
        matches!(
            self,
            Effect::AmplifierSaturation { .. }
                | Effect::VoltageSaturation { .. }
                | Effect::CoulombFriction { .. }
                | Effect::QuadraticDrag { .. }
                | Effect::CubicStiffness { .. }
                | Effect::Backlash { .. }
        )
    }

    /// Converts the parameter values with `f`.
    pub fn map<E>(&self, f: impl Fn(&D) -> E) -> Effect<E> {
        match self {
            Effect::AmplifierSaturation { current_limit, sharp, knee } => Effect::AmplifierSaturation {
                current_limit: f(current_limit),
                sharp: *sharp,
                knee: knee.as_ref().map(&f),
            },
            Effect::VoltageSaturation { voltage_limit, sharp, knee } => Effect::VoltageSaturation {
                voltage_limit: f(voltage_limit),
                sharp: *sharp,
                knee: knee.as_ref().map(&f),
            },
            Effect::CoulombFriction { torque, smoothing_velocity, static_peak, stribeck_velocity } => {
                Effect::CoulombFriction {
                    torque: f(torque),
                    smoothing_velocity: *smoothing_velocity,
                    static_peak: static_peak.as_ref().map(&f),
                    stribeck_velocity: stribeck_velocity.as_ref().map(&f),
                }
            }
            Effect::QuadraticDrag { hub, exponent } => {
                Effect::QuadraticDrag { hub: f(hub), exponent: exponent.as_ref().map(&f) }
            }
            Effect::CubicStiffness { coefficient, linear, quintic, rate } => Effect::CubicStiffness {
                coefficient: f(coefficient),
                linear: linear.as_ref().map(&f),
                quintic: quintic.as_ref().map(&f),
                rate: rate.as_ref().map(&f),
            },
            Effect::Backlash { dead_band, gear_frequency_hz, gear_damping_ratio, tachometer_on_motor } => {
                Effect::Backlash {
                    dead_band: f(dead_band),
                    gear_frequency_hz: f(gear_frequency_hz),
                    gear_damping_ratio: *gear_damping_ratio,
                    tachometer_on_motor: *tachometer_on_motor,
                }
            }
            Effect::SensorQuantization { sensor, step } => {
                Effect::SensorQuantization { sensor: *sensor, step: *step }
            }
            Effect::OutputOffset { sensor, offset } => {
                Effect::OutputOffset { sensor: *sensor, offset: f(offset) }
            }
            Effect::SensorScale { sensor, scale } => Effect::SensorScale { sensor: *sensor, scale: f(scale) },
            Effect::SensorDrift { sensor, rate, time_constant } => Effect::SensorDrift {
                sensor: *sensor,
                rate: f(rate),
                time_constant: time_constant.as_ref().map(&f),
            },
            Effect::TimeDelay { delay } => Effect::TimeDelay { delay: f(delay) },
            Effect::SensorCrosstalk { sensor, from, gain } => {
                Effect::SensorCrosstalk { sensor: *sensor, from: *from, gain: f(gain) }
            }
            Effect::SensorLag { sensor, lag } => Effect::SensorLag { sensor: *sensor, lag: f(lag) },
            Effect::UnmodeledMode {
                frequency_hz,
                damping_ratio,
                coupling,
                stiffness_coupling,
                damping_coupling,
            } => Effect::UnmodeledMode {
                frequency_hz: f(frequency_hz),
                damping_ratio: f(damping_ratio),
                coupling: f(coupling),
                stiffness_coupling: stiffness_coupling.as_ref().map(&f),
                damping_coupling: damping_coupling.as_ref().map(&f),
            },
        }
    }
}
