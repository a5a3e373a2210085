//! The nonlinear effects as generalised forces: ẋ = A x + b_s Δτ_s(x) + b_h τ_h(x).
//!
//! * Amplifier current limit: the armature current is i = (G K_p(θ_ref − θ_c) − K_b θ̇)/R_a and
//!   the motor torque K_t·sat(i); the linear model's servo torque is −k_s θ_c − (K_bK_t/R_a) θ̇,
//!   so Δτ_s = K_t sat(i) − (−k_s θ_c − K_bK_t/R_a θ̇) enters through the servo direction
//!   [1, Γ_1, …] (θ_c is θ, or the delayed θ_d with a time delay).
//! * Coulomb friction and quadratic drag are hub torques τ_h = −F_c tanh(θ̇/v_s) − c_d|θ̇|θ̇.

use crate::assemble::{FirstOrder, Layout, Scalar, first_order, second_order};
use crate::sensors::{Sensor, output_matrix};
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
    saturation: Option<(D, bool)>,
    coulomb: Option<(D, f64)>,
    drag: Option<D>,
    position_current_gain: D,
    emf_current_gain: D,
    torque_constant: D,
    servo_stiffness: D,
    emf_damping: D,
}

/// Builds the dynamics of a model with its effects.
///
/// # Errors
/// As the linear assembly.
pub fn dynamics<D: Scalar>(c: &Constants<D>, sensors: &[Sensor]) -> Result<Dynamics<D>, PlantError> {
    let so = second_order(c)?;
    let FirstOrder { a, servo_input, hub_input, layout } = first_order(c, &so)?;
    let mut saturation = None;
    let mut coulomb = None;
    let mut drag = None;
    for e in &c.effects {
        match e {
            Effect::AmplifierSaturation { current_limit, sharp } => {
                saturation = Some((*current_limit, *sharp))
            }
            Effect::CoulombFriction { torque, smoothing_velocity } => {
                coulomb = Some((*torque, *smoothing_velocity))
            }
            Effect::QuadraticDrag { hub } => drag = Some(*hub),
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
        coulomb,
        drag,
        position_current_gain: c.amplifier_gain * c.position_gain / c.armature_resistance,
        emf_current_gain: c.back_emf_constant / c.armature_resistance,
        torque_constant: c.torque_constant,
        servo_stiffness: so.servo_stiffness,
        emf_damping: c.back_emf_constant * c.torque_constant / c.armature_resistance,
    })
}

/// The smooth current limiter i / (1 + (i/I)⁸)^{1/8}.
pub fn smooth_limit<D: Scalar>(current: D, limit: D) -> D {
    let r = current / limit;
    current * DualNum::powf(&(D::from(1.0) + DualNum::powi(&r, 8)), -0.125)
}

impl<D: Scalar> Dynamics<D> {
    /// Whether f is linear (no nonlinear effect).
    pub fn is_linear(&self) -> bool {
        self.saturation.is_none() && self.coulomb.is_none() && self.drag.is_none()
    }

    /// The nonlinear torques (Δτ_s, τ_h) at state x.
    pub fn torques(&self, x: &[D]) -> (D, D) {
        let zero = D::from(0.0);
        let theta = x[0];
        let rate = x[self.layout.n_dof];
        let controlled = match self.layout.delay {
            Some(w) => -theta + x[w],
            None => theta,
        };
        let servo = match self.saturation {
            Some((limit, sharp)) => {
                let current = -self.position_current_gain * controlled - self.emf_current_gain * rate;
                let limited = if sharp {
                    if current.re() > limit.re() {
                        limit
                    } else if current.re() < -limit.re() {
                        -limit
                    } else {
                        current
                    }
                } else {
                    smooth_limit(current, limit)
                };
                self.torque_constant * limited + self.servo_stiffness * controlled + self.emf_damping * rate
            }
            None => zero,
        };
        let mut hub = zero;
        if let Some((torque, v_s)) = self.coulomb {
            hub -= torque * DualNum::tanh(&(rate / D::from(v_s)));
        }
        if let Some(c_d) = self.drag {
            hub -= c_d * abs(rate) * rate;
        }
        (servo, hub)
    }

    /// ẋ = f(x) into `out`.
    pub fn rhs(&self, x: &[D], out: &mut [D]) {
        let n = self.layout.n_states;
        for i in 0..n {
            let mut acc = D::from(0.0);
            for j in 0..n {
                acc += self.a[(i, j)] * x[j];
            }
            out[i] = acc;
        }
        if !self.is_linear() {
            let (servo, hub) = self.torques(x);
            for i in 0..n {
                out[i] += self.servo_input[i] * servo + self.hub_input[i] * hub;
            }
        }
    }
}

/// |x| for any scalar (via its sign, so dual parts get sign(x)·ẋ).
fn abs<D: Scalar>(x: D) -> D {
    if x.re() < 0.0 { -x } else { x }
}
