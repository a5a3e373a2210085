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
//!   (k₃ > 0) or softening (k₃ < 0) spring f = k₃ q³ + k₂ q² + k₅ q⁵ + k₁′ t q (k₂, its
//!   asymmetric part, k₅, and k₁′, a linear stiffness that changes over the record at time t
//!   since the release, optional). With x = [q; q̇] the state equation is
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
//!
//! Every effect's parameters join the model's, after the file's, with names that say where they
//! act: `offset_<output>`, `scale_<output>`, `drift_<output>`, `crosstalk_<output>_<from>`,
//! `friction_<coordinate>`,
//! `static_peak_<coordinate>`, `stribeck_velocity_<coordinate>`,
//! `drag_<coordinate>`, `drag_exponent_<coordinate>`, `cubic_<coordinate>`, `quadratic_<coordinate>`, `quintic_<coordinate>`,
//! `stiffness_rate_<coordinate>`, `mode_frequency`,
//! `mode_damping`, `mode_cos_<output>`, `mode_sin_<output>`. A quantization step and a friction's
//! smoothing width are settings, not parameters.

use mem::Scalar;
use mem::nalgebra::{DMatrix, DVector};
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
    /// A nonlinear spring k₃q³ + k₂q² + k₅q⁵ at a coordinate (hardening for k₃ > 0; k₂ makes it
    /// asymmetric, stiffer on one side than the other), with a linear stiffness k₁′·t that
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
        /// k₁′, a linear stiffness that grows at this rate over the record, f += k₁′·t·q with t
        /// the time since the release \[N/m/s\] (negative for a spring that degrades; 0 when
        /// absent); a parameter `stiffness_rate_<coordinate>` when given.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        rate: Option<f64>,
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
            | Effect::CubicStiffness { coordinate, .. } => Target::Coordinate(coordinate),
            Effect::UnmodeledMode { .. } => Target::Model,
        }
    }

    /// Whether it is a force at a coordinate (which makes the model nonlinear).
    pub fn is_force(&self) -> bool {
        matches!(self.target(), Target::Coordinate(_))
    }

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
            Effect::CubicStiffness { coordinate, coefficient, quadratic, quintic, rate } => {
                let mut out = vec![(format!("cubic_{coordinate}"), *coefficient)];
                out.extend(quadratic.map(|k2| (format!("quadratic_{coordinate}"), k2)));
                out.extend(quintic.map(|k5| (format!("quintic_{coordinate}"), k5)));
                out.extend(rate.map(|r| (format!("stiffness_rate_{coordinate}"), r)));
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
            Effect::CubicStiffness { coefficient, quadratic, quintic, rate, .. } => {
                let mut slots: Vec<&mut f64> = vec![coefficient];
                slots.extend(quadratic.as_mut());
                slots.extend(quintic.as_mut());
                slots.extend(rate.as_mut());
                *slots[k] = value;
            }
            Effect::Drag { coefficient, exponent, .. } => *[coefficient, exponent][k] = value,
            Effect::UnmodeledMode { frequency_hz, damping_ratio, amplitudes, .. } => match k {
                0 => *frequency_hz = value,
                1 => *damping_ratio = value,
                k if k % 2 == 0 => amplitudes[(k - 2) / 2].0 = value,
                k => amplitudes[(k - 2) / 2].1 = value,
            },
            Effect::SensorQuantization { .. } => {}
        }
    }

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
                "a force at `{c}` needs a second-order model (its coordinates); this file is first order"
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
                Effect::Drag { exponent, .. } if *exponent < 1.0 => {
                    Some(format!("exponent = {exponent}: give an exponent of at least 1"))
                }
                Effect::UnmodeledMode { frequency_hz, damping_ratio, amplitudes, driven_by } => {
                    if *frequency_hz <= 0.0 {
                        Some(format!("frequency_hz = {frequency_hz}: give a positive frequency"))
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

    /// The force f_j at time `t` since the release and a state x = [q; q̇] of `n` coordinates,
    /// with this effect's parameters `theta` (in the order of [`parameters`](Self::parameters))
    /// and its coordinate `j`; zero for an effect that is not a force.
    pub(crate) fn force<D: Scalar>(&self, t: f64, x: &[D], n: usize, j: usize, theta: &[D]) -> D {
        let (q, v) = (x[j], x[n + j]);
        match self {
            Effect::DryFriction { smoothing_velocity, static_peak, .. } => {
                let vs = D::from(*smoothing_velocity);
                let level = if static_peak.is_some() {
                    let r = v / theta[2];
                    theta[0] + theta[1] * (-(r * r)).exp()
                } else {
                    theta[0]
                };
                level * v / (v * v + vs * vs).sqrt()
            }
            Effect::Drag { .. } => {
                let (c, e) = (theta[0], theta[1]);
                if v.re() == 0.0 {
                    // f = c v |v|^(e−1): zero, with slope c only for a linear law.
                    if e.re() == 1.0 { c * v } else { v * D::from(0.0) }
                } else {
                    c * v * (v * v).powd((e - D::from(1.0)) * D::from(0.5))
                }
            }
            Effect::CubicStiffness { quadratic, quintic, rate, .. } => {
                let q3 = q * q * q;
                let mut f = theta[0] * q3;
                let mut k = 1;
                if quadratic.is_some() {
                    f += theta[k] * q * q;
                    k += 1;
                }
                if quintic.is_some() {
                    f += theta[k] * q3 * q * q;
                    k += 1;
                }
                if rate.is_some() {
                    f += theta[k] * D::from(t) * q;
                }
                f
            }
            _ => D::from(0.0),
        }
    }
}

/// Appends an unmodeled mode's two states to A, C, x(0) and B: `theta` is
/// (f_e, ζ_e, a_1, b_1, …, a_p, b_p). A free ringing starts from η(0) = 1 and B's new rows are
/// zero; a mode driven by input `driven_by` starts from rest with ω_e² in η̈'s row of that input.
pub(crate) fn append_mode<D: Scalar>(space: &mut mem::StateSpace<D>, theta: &[D], driven_by: Option<usize>) {
    let n = space.a.nrows();
    let omega = theta[0] * D::from(2.0 * std::f64::consts::PI);
    let zeta = theta[1];
    let mut a = DMatrix::from_element(n + 2, n + 2, D::from(0.0));
    a.view_mut((0, 0), (n, n)).copy_from(&space.a);
    a[(n, n + 1)] = D::from(1.0);
    a[(n + 1, n)] = -(omega * omega);
    a[(n + 1, n + 1)] = -(D::from(2.0) * zeta * omega);
    let p = space.c.nrows();
    let mut c = DMatrix::from_element(p, n + 2, D::from(0.0));
    c.view_mut((0, 0), (p, n)).copy_from(&space.c);
    for o in 0..p {
        c[(o, n)] = theta[2 + 2 * o];
        c[(o, n + 1)] = theta[3 + 2 * o] / omega;
    }
    let mut x0 = DVector::from_element(n + 2, D::from(0.0));
    x0.rows_mut(0, n).copy_from(&space.x0);
    if driven_by.is_none() {
        x0[n] = D::from(1.0);
    }
    if let Some(b) = &space.b {
        let mut wide = DMatrix::from_element(n + 2, b.ncols(), D::from(0.0));
        wide.view_mut((0, 0), (n, b.ncols())).copy_from(b);
        if let Some(i) = driven_by.filter(|&i| i < b.ncols()) {
            wide[(n + 1, i)] = omega * omega;
        }
        space.b = Some(wide);
    }
    space.a = a;
    space.c = c;
    space.x0 = x0;
}
