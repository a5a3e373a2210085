//! Effects added to a structure: what a linear model file leaves out, each where it acts.
//!
//! * **Sensor effects** on an output y (a CSV column): offset b, scale error s and drift d,
//!   read as y′ = (1 + s)·y + b + d·t; crosstalk g, another output's signal y_j picked up,
//!   y′ = y + g·y_j; and quantization to a step Δ (a reading model). They are
//!   measurement transforms: [`StructureModel::state_space`](crate::StructureModel::state_space)
//!   leaves them out and the adapter layer (`models`) applies them.
//! * **Local forces** at a coordinate q_j of a second-order model, entering as
//!   M q̈ + D q̇ + K q = F u − e_j f_j(q_j, q̇_j):
//!   dry friction f = (F_c + ΔF e^{−(v/v_st)²})·v/√(v² + v_s²) (a smooth sign of width v_s;
//!   the static peak ΔF over the Stribeck velocity v_st optional), drag
//!   f = c·v·|v|^(e−1) (velocity exponent e ≥ 1, quadratic for e = 2), and a hardening
//!   (k₃ > 0) or softening (k₃ < 0) spring f = k₃ q³ + k₂ q² + k₅ q⁵ + k₁′ t q + Δk(t) q (k₂,
//!   its asymmetric part, k₅, k₁′, a linear stiffness that changes over the record at time t
//!   since the release, and Δk(t), one that changes by a law of its own, piecewise linear
//!   through given times ([`StiffnessChange`]), optional). With x = [q; q̇] the state equation is
//!   ẋ = A x + B u + G f(t, x), G's column j = [0; −M⁻¹e_j], and an acceleration output reads
//!   its share of the force, y = C x + D u + H f(t, x) (H from the rows of G). A drag of
//!   exponent 1 held there is linear, a damper c·q̇_j: where no other force acts and its
//!   exponent is not freed, [`StructureModel::linear_state_space`](crate::StructureModel::linear_state_space)
//!   adds c to D_jj and the exact exponential path applies
//!   ([`StructureModel::is_linear_for`](crate::StructureModel::is_linear_for)).
//! * **An unmodeled mode**: a damped oscillation at f_e with damping ratio ζ_e that the model's
//!   modes do not contain — in free decay it adds to every output o its own amplitude,
//!   y_o += a_o η(t) + b_o η̇(t)/ω_e, with η̈ + 2ζ_eω_e η̇ + ω_e² η = 0, η(0) = 1, η̇(0) = 0. It
//!   is linear: two states appended to x, so the exact exponential path still applies. Driven
//!   by a measured input u_i instead (a forced record from rest), the same mode is its response
//!   to that input, η̈ + 2ζ_eω_e η̇ + ω_e² η = ω_e² u_i, η(0) = η̇(0) = 0: a static gain of 1, so
//!   a_o and b_o are the output's share per unit input.
//! * **An appendage** at a coordinate q_j of a second-order model: a mass m_a on a spring
//!   k_a = m_a ω_a² and damper c_a = 2ζ_a m_a ω_a (ω_a = 2π f_a), its displacement z two states
//!   appended to x, m_a z̈ = −k_a (z − q_j) − c_a (ż − q̇_j), the coordinate feeling the
//!   reaction through [0; M⁻¹e_j]; z(0) = q_j(0) + F_r/k_a with F_r its spring's force at the
//!   release (0: relaxed). Linear, so the exact exponential path still applies; an
//!   acceleration output reads the reaction through its rows of A.
//!
//! Every effect's parameters join the model's, after the file's, with names that say where they
//! act: `offset_<output>`, `scale_<output>`, `drift_<output>`, `crosstalk_<output>_<from>`,
//! `friction_<coordinate>`,
//! `static_peak_<coordinate>`, `stribeck_velocity_<coordinate>`,
//! `drag_<coordinate>`, `drag_exponent_<coordinate>`, `cubic_<coordinate>`, `quadratic_<coordinate>`, `quintic_<coordinate>`, `sided_<coordinate>`,
//! `stiffness_rate_<coordinate>`, `stiffness_change_<coordinate>_<i>`, `mode_frequency`,
//! `mode_damping`, `mode_cos_<output>`, `mode_sin_<output>`, `appendage_mass_<coordinate>`,
//! `appendage_frequency_<coordinate>`, `appendage_damping_<coordinate>`,
//! `appendage_release_<coordinate>`. A quantization step and a friction's
//! smoothing width are settings, not parameters.

mod checks;
mod dynamics;
mod parameters;

pub(crate) use dynamics::{append_appendage, append_mode};
use serde::{Deserialize, Serialize};

/// An effect added to a structure model (the `effects:` list of its model file).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum Effect {
    /// A constant bias b on an output \[output's unit\].
    OutputOffset {
        /// The output's column.
        output: String,
        /// b.
        offset: f64,
    },
    /// A scale-factor error s: the sensor reads (1 + s)·y.
    SensorScale {
        /// The output's column.
        output: String,
        /// s.
        scale: f64,
    },
    /// A drift d·t of an output \[unit/s\]; with a time constant τ \[s\] it levels off,
    /// d·τ(1 − e^{−t/τ}) (`drift_time_<output>`).
    SensorDrift {
        /// The output's column.
        output: String,
        /// d.
        rate: f64,
        /// τ (absent: the drift goes on, d·t).
        #[serde(default)]
        time_constant: Option<f64>,
    },
    /// Another output's signal picked up by this output's channel: it reads y + g·y_from.
    SensorCrosstalk {
        /// The output's column.
        output: String,
        /// The output whose signal it picks up (as the dynamics give it).
        from: String,
        /// g.
        gain: f64,
    },
    /// Readings rounded to multiples of `step`.
    SensorQuantization {
        /// The output's column.
        output: String,
        /// The step Δ > 0.
        step: f64,
    },
    /// Dry friction (F_c + ΔF e^{−(v/v_st)²})·v/√(v² + v_s²) at a coordinate \[N\]: Coulomb's
    /// level F_c, with a static peak ΔF over the Stribeck velocity v_st if given.
    DryFriction {
        /// The coordinate.
        coordinate: String,
        /// F_c ≥ 0.
        force: f64,
        /// v_s > 0, the velocity over which the force reverses.
        smoothing_velocity: f64,
        /// ΔF = F_s − F_c ≥ 0, how far the friction at rest exceeds the sliding level (0 when
        /// absent); a parameter `static_peak_<coordinate>` when given, with `stribeck_velocity`.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        static_peak: Option<f64>,
        /// v_st > 0, the velocity over which the peak falls, as e^{−(v/v_st)²}; a parameter
        /// `stribeck_velocity_<coordinate>` when given.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        stribeck_velocity: Option<f64>,
    },
    /// Drag c·v·|v|^(e−1) at a coordinate.
    Drag {
        /// The coordinate.
        coordinate: String,
        /// c.
        coefficient: f64,
        /// e ≥ 1.
        exponent: f64,
    },
    /// A nonlinear spring k₃q³ + k₂q² + k₅q⁵ + kₛq⁴|q| at a coordinate (hardening for k₃ > 0;
    /// k₂ and kₛ make it asymmetric, stiffer on one side than the other), with a linear stiffness k₁′·t that
    /// changes over the record if `rate` is given.
    CubicStiffness {
        /// The coordinate.
        coordinate: String,
        /// k₃.
        coefficient: f64,
        /// k₂, the spring's quadratic (asymmetric) part (0 when absent); a parameter
        /// `quadratic_<coordinate>` when given.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        quadratic: Option<f64>,
        /// k₅, a quintic part k₅q⁵ (symmetric, as k₃q³; 0 when absent); a parameter
        /// `quintic_<coordinate>` when given.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        quintic: Option<f64>,
        /// kₛ, a one-sided part at the quintic's power, kₛq⁴|q| (even: it adds to k₅q⁵ on one
        /// side and takes from it on the other, so the spring is stiffer one way at large
        /// amplitude, as a stop or a contact that closes beyond a gap; 0 when absent); a
        /// parameter `sided_<coordinate>` when given.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        sided: Option<f64>,
        /// k₁′, a linear stiffness that grows at this rate over the record, f += k₁′·t·q with t
        /// the time since the release \[N/m/s\] (negative for a spring that degrades; 0 when
        /// absent); a parameter `stiffness_rate_<coordinate>` when given.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        rate: Option<f64>,
        /// Δk(t), a linear stiffness that changes over the record by a law of its own, piecewise
        /// linear in t through (0, 0) and the given (tᵢ, Δkᵢ), constant after the last time:
        /// f += Δk(t)·q (0 when absent); parameters `stiffness_change_<coordinate>_<i>`, i from 1.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        change: Option<StiffnessChange>,
    },
    /// A mode the model lacks, seen in every output with its own amplitude.
    UnmodeledMode {
        /// f_e > 0 \[Hz\].
        frequency_hz: f64,
        /// ζ_e ≥ 0.
        damping_ratio: f64,
        /// (a_o, b_o) per output, in the outputs' order.
        amplitudes: Vec<(f64, f64)>,
        /// The measured input that drives the mode (from rest, with a static gain of 1); none
        /// for a free ringing from η(0) = 1.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        driven_by: Option<String>,
    },
    /// A mass the model lacks on a spring and damper at a coordinate (a second-order file's): an
    /// appendage, equipment on a floor, a tuned mass. Its displacement z joins the state, and
    /// with k_a = m_a ω_a², c_a = 2ζ_a m_a ω_a (ω_a = 2π f_a, the appendage's frequency on a
    /// fixed base) m_a z̈ = −k_a (z − q_j) − c_a (ż − q̇_j), while the coordinate feels the
    /// reaction k_a (z − q_j) + c_a (ż − q̇_j). Linear: the exact exponential path still applies.
    /// It starts from z(0) = q_j(0) + F_r/k_a and ż(0) = q̇_j(0): F_r is its spring's force at
    /// the release (0 when absent: it moves with the coordinate, relaxed). The force, not the
    /// displacement F_r/k_a, is the parameter: the ringing it starts pushes on the coordinate
    /// with F_r whatever the mass, so a record determines it where it leaves m_a loose.
    Appendage {
        /// The coordinate it hangs on.
        coordinate: String,
        /// m_a > 0 \[kg\] (`appendage_mass_<coordinate>`).
        mass: f64,
        /// f_a > 0 \[Hz\] (`appendage_frequency_<coordinate>`).
        frequency_hz: f64,
        /// ζ_a ≥ 0 (`appendage_damping_<coordinate>`).
        damping_ratio: f64,
        /// F_r, its spring's force at the release \[N\]; a parameter
        /// `appendage_release_<coordinate>` when given.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        release_force: Option<f64>,
    },
}

/// A law of change with time, piecewise linear through (0, 0) and (tᵢ, vᵢ) and constant after the
/// last time (the `change` of [`Effect::CubicStiffness`]): the times are settings, the values
/// parameters.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StiffnessChange {
    /// t₁ < t₂ < … \[s\], positive, from the release.
    pub times: Vec<f64>,
    /// vᵢ = Δk(tᵢ), one per time \[N/m\].
    pub values: Vec<f64>,
}

impl StiffnessChange {
    /// The law at zero at `times`.
    pub fn zero(times: Vec<f64>) -> Self {
        let values = vec![0.0; times.len()];
        StiffnessChange { times, values }
    }

    /// The weights (wᵢ, w_{i+1}) of the two values at time `t` and the index i of the first, so
    /// that Δk(t) = wᵢvᵢ + w_{i+1}v_{i+1} (the value before the first time is 0 at t = 0):
    /// `None` for the first interval's zero end, and for t beyond the last time the last value
    /// alone.
    pub(crate) fn weights(&self, t: f64) -> [(Option<usize>, f64); 2] {
        let n = self.times.len();
        let i = self.times.partition_point(|&ti| ti <= t);
        if i >= n {
            return [(n.checked_sub(1), 1.0), (None, 0.0)];
        }
        let (t0, first) = if i == 0 { (0.0, None) } else { (self.times[i - 1], Some(i - 1)) };
        let w = ((t - t0) / (self.times[i] - t0)).clamp(0.0, 1.0);
        [(first, 1.0 - w), (Some(i), w)]
    }
}

/// The kinds of [`Effect`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum EffectKind {
    /// [`Effect::OutputOffset`].
    OutputOffset,
    /// [`Effect::SensorScale`].
    SensorScale,
    /// [`Effect::SensorDrift`].
    SensorDrift,
    /// [`Effect::SensorQuantization`].
    SensorQuantization,
    /// [`Effect::SensorCrosstalk`].
    SensorCrosstalk,
    /// [`Effect::DryFriction`].
    DryFriction,
    /// [`Effect::Drag`].
    Drag,
    /// [`Effect::CubicStiffness`].
    CubicStiffness,
    /// [`Effect::UnmodeledMode`].
    UnmodeledMode,
    /// [`Effect::Appendage`].
    Appendage,
}

/// Where an effect acts.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Target<'a> {
    /// An output column.
    Output(&'a str),
    /// A coordinate.
    Coordinate(&'a str),
    /// The whole model (an unmodeled mode).
    Model,
}

impl Effect {
    /// Its kind.
    pub fn kind(&self) -> EffectKind {
        match self {
            Effect::OutputOffset { .. } => EffectKind::OutputOffset,
            Effect::SensorScale { .. } => EffectKind::SensorScale,
            Effect::SensorDrift { .. } => EffectKind::SensorDrift,
            Effect::SensorQuantization { .. } => EffectKind::SensorQuantization,
            Effect::SensorCrosstalk { .. } => EffectKind::SensorCrosstalk,
            Effect::DryFriction { .. } => EffectKind::DryFriction,
            Effect::Drag { .. } => EffectKind::Drag,
            Effect::CubicStiffness { .. } => EffectKind::CubicStiffness,
            Effect::UnmodeledMode { .. } => EffectKind::UnmodeledMode,
            Effect::Appendage { .. } => EffectKind::Appendage,
        }
    }

    /// Where it acts.
    pub fn target(&self) -> Target<'_> {
        match self {
            Effect::OutputOffset { output, .. }
            | Effect::SensorScale { output, .. }
            | Effect::SensorDrift { output, .. }
            | Effect::SensorQuantization { output, .. }
            | Effect::SensorCrosstalk { output, .. } => Target::Output(output),
            Effect::DryFriction { coordinate, .. }
            | Effect::Drag { coordinate, .. }
            | Effect::CubicStiffness { coordinate, .. }
            | Effect::Appendage { coordinate, .. } => Target::Coordinate(coordinate),
            Effect::UnmodeledMode { .. } => Target::Model,
        }
    }

    /// Whether it is a force at a coordinate (which makes the model nonlinear); an appendage
    /// acts at a coordinate too, but through two states of its own in the linear model.
    pub fn is_force(&self) -> bool {
        matches!(self.target(), Target::Coordinate(_)) && !matches!(self, Effect::Appendage { .. })
    }

    /// How many states it adds to the linear model: two for an unmodeled mode or an appendage.
    pub fn added_states(&self) -> usize {
        match self {
            Effect::UnmodeledMode { .. } | Effect::Appendage { .. } => 2,
            _ => 0,
        }
    }
}
