//! The nonlinear effects as generalised forces: ẋ = A x + b_s Δτ_s(x) + b_h τ_h(x).
//!
//! * Amplifier limits: the amplifier's output voltage is e_a = G K_p(θ_ref − θ_c), limited to
//!   ±V with a voltage limit; the armature current i = (e_a − K_b θ̇)/R_a, limited to ±I with a
//!   current limit; the motor torque is K_t·i. The linear model's servo torque is
//!   −k_s θ_c − (K_bK_t/R_a) θ̇, so Δτ_s = K_t i − (−k_s θ_c − K_bK_t/R_a θ̇) enters through the
//!   servo direction [1, Γ_1, …] (θ_c is θ, or the delayed θ_d with a time delay).
//! * Dry friction, drag and a cubic stiffness are hub torques
//!   τ_h = −(F_c + ΔF e^{−(θ̇/v_st)²}) tanh(θ̇/v_s) − c_d|θ̇|ᵖ sign θ̇ − k₃θ³ − k₅θ⁵ − k₁′tθ (ΔF = 0 unless a
//!   static peak is given, the Stribeck form of Armstrong-Hélouvry, Dupont & Canudas de Wit,
//!   Automatica 30(7), 1994; a hub spring's linear part k₁θ is in A,
//!   [`crate::assemble::second_order`]).
//! * Backlash: the linear part holds the gear as a spring k_g(θ_m − θ) between motor and hub;
//!   the dead band takes back τ_c = k_g sat_{b/2}(θ_m − θ) (the smooth limiter), from the hub
//!   and to the motor, so that the gear passes k_g dz_b(θ_m − θ). The servo direction is then
//!   the motor's, so τ_c joins Δτ_s; the servo's back-EMF and its limits see the motor's rate.

use crate::assemble::{FirstOrder, Layout, Scalar, first_order, second_order};
use crate::output::output_matrix;
use crate::sensors::Sensor;
use crate::{Constants, Effect, PlantError};
use nalgebra::{DMatrix, DVector};
use num_dual::DualNum;

/// Everything needed to evaluate ẋ = f(x) and y = C x for a model with effects.
#[derive(Clone, Debug)]
pub struct Dynamics<D: Scalar> {
    /// The linear part, A (including delay and offset states).
    pub a: DMatrix<D>,
    /// Output matrix C.
    pub c: DMatrix<D>,
    /// Direction of a servo-torque change.
    pub servo_input: DVector<D>,
    /// Direction of a hub torque.
    pub hub_input: DVector<D>,
    /// State layout.
    pub layout: Layout,
    saturation: Option<Limiter<D>>,
    voltage: Option<Limiter<D>>,
    coulomb: Option<Friction<D>>,
    drag: Option<(D, Option<D>)>,
    /// k₃ of a hub spring (its linear part is in A).
    cubic: Option<D>,
    /// k₅ of a hub spring, when given (−k₅θ⁵).
    quintic: Option<D>,
    /// k₁′ of a hub spring, when given (−k₁′·t·θ).
    rate: Option<D>,
    /// Backlash: k_g and half the dead band.
    backlash: Option<(D, D)>,
    amplifier_voltage_gain: D,
    armature_resistance: D,
    back_emf_constant: D,
    torque_constant: D,
    servo_stiffness: D,
    emf_damping: D,
}

/// A limit on the amplifier's current or voltage: the level, an ideal clamp or not, and the
/// smooth limiter's knee when given.
#[derive(Clone, Copy, Debug)]
struct Limiter<D> {
    limit: D,
    sharp: bool,
    knee: Option<D>,
}

impl<D: Scalar> Limiter<D> {
    /// The limited value: the ideal clamp, or the smooth limiter with its knee.
    fn apply(&self, value: D) -> D {
        if self.sharp {
            return clamp(value, self.limit);
        }
        match self.knee {
            Some(knee) => smooth_limit_with_knee(value, self.limit, knee),
            None => smooth_limit(value, self.limit),
        }
    }
}

/// Dry friction at the hub: the Coulomb level, its smoothing velocity, and the static peak with
/// its Stribeck velocity when given.
#[derive(Clone, Copy, Debug)]
struct Friction<D> {
    torque: D,
    smoothing_velocity: f64,
    stribeck: Option<(D, D)>,
}

impl<D: Scalar> Friction<D> {
    /// The friction's level at `rate`: F_c + ΔF e^{−(θ̇/v_st)²}.
    fn level(&self, rate: D) -> D {
        match self.stribeck {
            Some((peak, velocity)) => {
                let r = rate / velocity;
                self.torque + peak * DualNum::exp(&(-(r * r)))
            }
            None => self.torque,
        }
    }
}

/// Builds the dynamics of a model with its effects.
///
/// # Errors
/// As the linear assembly.
pub fn dynamics<D: Scalar>(c: &Constants<D>, sensors: &[Sensor]) -> Result<Dynamics<D>, PlantError> {
    let so = second_order(c)?;
    let FirstOrder { a, servo_input, hub_input, layout } = first_order(c, &so)?;
    let mut saturation = None;
    let mut voltage = None;
    let mut coulomb = None;
    let mut drag = None;
    let mut cubic = None;
    let (mut quintic, mut rate) = (None, None);
    let mut backlash = None;
    for e in &c.effects {
        match e {
            Effect::AmplifierSaturation { current_limit, sharp, knee } => {
                saturation = Some(Limiter { limit: *current_limit, sharp: *sharp, knee: *knee })
            }
            Effect::VoltageSaturation { voltage_limit, sharp, knee } => {
                voltage = Some(Limiter { limit: *voltage_limit, sharp: *sharp, knee: *knee })
            }
            Effect::CoulombFriction { torque, smoothing_velocity, static_peak, stribeck_velocity } => {
                let stribeck = static_peak.zip(*stribeck_velocity);
                coulomb =
                    Some(Friction { torque: *torque, smoothing_velocity: *smoothing_velocity, stribeck })
            }
            Effect::QuadraticDrag { hub, exponent } => drag = Some((*hub, *exponent)),
            Effect::CubicStiffness { coefficient, quintic: k5, rate: k1_rate, .. } => {
                cubic = Some(*coefficient);
                (quintic, rate) = (*k5, *k1_rate);
            }
            Effect::Backlash { dead_band, .. } => {
                let (kg, _) = crate::assemble::gear(c).expect("a backlash effect has a gear");
                backlash = Some((kg, *dead_band * D::from(0.5)));
            }
            _ => {}
        }
    }
    Ok(Dynamics {
        c: output_matrix(c, &so, sensors),
        a,
        servo_input,
        hub_input,
        layout,
        saturation,
        voltage,
        coulomb,
        drag,
        cubic,
        quintic,
        rate,
        backlash,
        amplifier_voltage_gain: c.amplifier_gain * c.position_gain,
        armature_resistance: c.armature_resistance,
        back_emf_constant: c.back_emf_constant,
        torque_constant: c.torque_constant,
        servo_stiffness: so.servo_stiffness,
        emf_damping: c.back_emf_constant * c.torque_constant / c.armature_resistance,
    })
}

/// The smooth current limiter i / (1 + (i/I)⁸)^{1/8}.
///
/// Beyond the limit it is evaluated as sign(i)·I / (1 + (I/i)⁸)^{1/8}, the same function: r⁸
/// never overflows, so value and derivatives stay finite for a limit however small against the
/// current (a dead band fitted down to nothing, a saturation far below the demand).
///
/// (The limiter with any other knee is [`smooth_limit_with_knee`].)
pub fn smooth_limit<D: Scalar>(current: D, limit: D) -> D {
    // (1 + r⁸)^{1/8} by three square roots: the same value, far cheaper than a power.
    two_sided(current, limit, |r: D| {
        DualNum::sqrt(&DualNum::sqrt(&DualNum::sqrt(&(D::from(1.0) + DualNum::powi(&r, 8)))))
    })
}

/// The smooth limiter with knee n: x / (1 + |x/L|ⁿ)^{1/n} (n = 8 is [`smooth_limit`]).
///
/// |x/L|ⁿ = exp(n ln|x/L|), so the value's derivatives in x, L and n all exist; beyond the limit
/// it is evaluated as sign(x)·L / (1 + |L/x|ⁿ)^{1/n}, the same function with nothing that
/// overflows.
pub fn smooth_limit_with_knee<D: Scalar>(value: D, limit: D, knee: D) -> D {
    // (1 + |r|ⁿ)^{1/n}. |r|ⁿ below e^{−700} (10⁻³⁰⁴) changes nothing a double holds: 1, with no
    // derivative (r may be 0 — at rest — or have underflowed, and 0·ln 0 is no number).
    two_sided(value, limit, |r: D| {
        let log_power = knee * DualNum::ln(&abs(r));
        if log_power.re() < -700.0 {
            return D::from(1.0);
        }
        DualNum::exp(&(DualNum::ln(&(D::from(1.0) + DualNum::exp(&log_power))) / knee))
    })
}

/// A limiter x/ρ(x/L) with ρ(r) = (1 + |r|ⁿ)^{1/n} (`root`, called with |r| ≤ 1 only):
/// x/ρ(x/L) within the limit and sign(x)·L/ρ(L/x) beyond it — the same function, with no
/// power of a ratio above 1 that could overflow.
fn two_sided<D: Scalar>(value: D, limit: D, root: impl Fn(D) -> D) -> D {
    if value.re().abs() <= limit.re().abs() {
        value / root(value / limit)
    } else {
        let sign = if (value.re() < 0.0) == (limit.re() < 0.0) { 1.0 } else { -1.0 };
        limit * D::from(sign) / root(limit / value)
    }
}

impl<D: Scalar> Dynamics<D> {
    /// Whether f is linear (no nonlinear effect).
    pub fn is_linear(&self) -> bool {
        self.saturation.is_none()
            && self.voltage.is_none()
            && self.coulomb.is_none()
            && self.drag.is_none()
            && self.cubic.is_none()
            && self.backlash.is_none()
    }

    /// The states the torques depend on: θ, θ̇, the delay state if there is one, and the
    /// motor's angle and rate with backlash.
    pub fn torque_states(&self) -> Vec<usize> {
        let n = self.layout.n_dof;
        [0, n]
            .into_iter()
            .chain(self.layout.delay)
            .chain(self.layout.motor.into_iter().flat_map(|r| [r, n + r]))
            .collect()
    }

    /// The constants the torques depend on (limits, coefficients, gains): a parameter whose
    /// dual seed leaves all of them real does not change the torques.
    pub fn torque_constants(&self) -> Vec<D> {
        let mut out = vec![
            self.amplifier_voltage_gain,
            self.armature_resistance,
            self.back_emf_constant,
            self.torque_constant,
            self.servo_stiffness,
            self.emf_damping,
        ];
        for limiter in self.saturation.iter().chain(&self.voltage) {
            out.push(limiter.limit);
            out.extend(limiter.knee);
        }
        if let Some(f) = self.coulomb {
            out.push(f.torque);
            out.extend(f.stribeck.into_iter().flat_map(|(p, v)| [p, v]));
        }
        if let Some((c, p)) = self.drag {
            out.push(c);
            out.extend(p);
        }
        out.extend(self.cubic);
        out.extend(self.quintic);
        out.extend(self.rate);
        if let Some((kg, half)) = self.backlash {
            out.extend([kg, half]);
        }
        out
    }

    /// The nonlinear torques (Δτ_s, τ_h) at state x and time t from the release (only a hub
    /// spring's `stiffness_rate` depends on t).
    pub fn torques(&self, t: f64, x: &[D]) -> (D, D) {
        let zero = D::from(0.0);
        let theta = x[0];
        let rate = x[self.layout.n_dof];
        // The servo's back-EMF and C_v act on the motor's rate (the hub's without backlash).
        let motor_rate = self.layout.motor.map_or(rate, |r| x[self.layout.n_dof + r]);
        let controlled = match self.layout.delay {
            Some(w) => -theta + x[w],
            None => theta,
        };
        let servo = if self.saturation.is_some() || self.voltage.is_some() {
            // e_a = G K_p (θ_ref − θ_c) with θ_ref = 0, limited; i = (e_a − K_b θ̇)/R_a, limited.
            let mut volts = -self.amplifier_voltage_gain * controlled;
            if let Some(limiter) = self.voltage {
                volts = limiter.apply(volts);
            }
            let mut current = (volts - self.back_emf_constant * motor_rate) / self.armature_resistance;
            if let Some(limiter) = self.saturation {
                current = limiter.apply(current);
            }
            self.torque_constant * current + self.servo_stiffness * controlled + self.emf_damping * motor_rate
        } else {
            zero
        };
        let mut servo = servo;
        let mut hub = zero;
        if let (Some((kg, half)), Some(r)) = (self.backlash, self.layout.motor) {
            let taken = kg * dead_band_limit(x[r] - theta, half);
            servo += taken;
            hub -= taken;
        }
        if let Some(f) = self.coulomb {
            hub -= f.level(rate) * tanh(rate / D::from(f.smoothing_velocity));
        }
        if let Some((c_d, exponent)) = self.drag {
            hub -= match exponent {
                // |v|^p sign v, with |v|^p = exp(p ln|v|) (0 at rest).
                Some(p) if rate.re() != 0.0 => {
                    c_d * DualNum::exp(&(p * DualNum::ln(&abs(rate)))) * signum(rate)
                }
                Some(_) => zero,
                None => c_d * abs(rate) * rate,
            };
        }
        if let Some(k3) = self.cubic {
            hub -= k3 * theta * theta * theta;
        }
        if let Some(k5) = self.quintic {
            let square = theta * theta;
            hub -= k5 * square * square * theta;
        }
        if let Some(rate) = self.rate {
            hub -= rate * D::from(t) * theta;
        }
        (servo, hub)
    }

    /// ẋ = f(t, x) into `out`.
    pub fn rhs(&self, t: f64, x: &[D], out: &mut [D]) {
        let n = self.layout.n_states;
        for i in 0..n {
            let mut acc = D::from(0.0);
            for j in 0..n {
                acc += self.a[(i, j)] * x[j];
            }
            out[i] = acc;
        }
        if !self.is_linear() {
            let (servo, hub) = self.torques(t, x);
            for i in 0..n {
                out[i] += self.servo_input[i] * servo + self.hub_input[i] * hub;
            }
        }
    }
}

/// sat_h(δ) by the smooth limiter (0 for a closed band, h = 0).
fn dead_band_limit<D: Scalar>(delta: D, half: D) -> D {
    if half.re() <= 0.0 { D::from(0.0) } else { smooth_limit(delta, half) }
}

/// The ideal clamp (not differentiable at the corner; truth data only).
fn clamp<D: Scalar>(value: D, limit: D) -> D {
    if value.re() > limit.re() {
        limit
    } else if value.re() < -limit.re() {
        -limit
    } else {
        value
    }
}

/// tanh x as s(1 − e)/(1 + e) with e = exp(−2|x|) ≤ 1 and s = sign x: finite value and
/// derivative for every x (num-dual's sinh/cosh quotient overflows to NaN beyond |x| ≈ 355,
/// which a sharp friction law reaches at ordinary speeds).
pub fn tanh<D: Scalar>(x: D) -> D {
    let s = if x.re() < 0.0 { -1.0 } else { 1.0 };
    let e = DualNum::exp(&(x * D::from(-2.0 * s)));
    (D::from(1.0) - e) / (D::from(1.0) + e) * D::from(s)
}

/// sign(x) as a scalar (0 at 0).
fn signum<D: Scalar>(x: D) -> D {
    D::from(if x.re() > 0.0 {
        1.0
    } else if x.re() < 0.0 {
        -1.0
    } else {
        0.0
    })
}

/// |x| for any scalar (via its sign, so dual parts get sign(x)·ẋ).
fn abs<D: Scalar>(x: D) -> D {
    if x.re() < 0.0 { -x } else { x }
}

#[cfg(test)]
mod tests {
    use super::*;
    use num_dual::Dual64;

    #[test]
    fn tanh_is_finite_with_its_derivative_at_any_argument() {
        for x in [-1e6, -400.0, -20.0, -0.3, 0.0, 1e-9, 0.7, 35.0, 400.0, 1e6] {
            let t = tanh(Dual64::new(x, 1.0));
            assert!((t.re - f64::tanh(x)).abs() < 1e-15, "{x}");
            // sech²x, written without cancellation.
            let e = (-2.0 * x.abs()).exp();
            let exact = 4.0 * e / (1.0 + e).powi(2);
            assert!((t.eps - exact).abs() <= 1e-14 * exact.max(1e-300) + 1e-300, "{x}: {} vs {exact}", t.eps);
        }
    }
}
