//! What an effect does to the dynamics: a force's value at a state ([`Effect::force`]), an
//! unmodeled mode's two states appended to the linear model ([`append_mode`]) and an
//! appendage's ([`append_appendage`]).

use super::Effect;
use mem::Scalar;
use mem::nalgebra::{DMatrix, DVector};

impl Effect {
    /// For a dry friction, its level at rest — the sliding level plus any static peak, with its
    /// parameters `theta` as [`force`](Self::force) reads them — and its smoothing velocity v_s;
    /// `None` for another effect. Below v_s it acts as a damper of level/v_s.
    pub(crate) fn friction_at_rest(&self, theta: &[f64]) -> Option<(f64, f64)> {
        match self {
            Effect::DryFriction { smoothing_velocity, static_peak, .. } => {
                let peak = if static_peak.is_some() { theta.get(1)?.abs() } else { 0.0 };
                Some((theta.first()?.abs() + peak, *smoothing_velocity))
            }
            _ => None,
        }
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
            Effect::CubicStiffness { quadratic, quintic, sided, rate, change, .. } => {
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
                if sided.is_some() {
                    // q⁴|q| = q⁵·sign(q), with the sign a constant of the state's value: its
                    // derivatives are then exact on either side and 0 at q = 0, where √(q²)
                    // would give 0/0 (a forced record starts there).
                    let sign = match q.re() {
                        r if r > 0.0 => 1.0,
                        r if r < 0.0 => -1.0,
                        _ => 0.0,
                    };
                    f += theta[k] * q3 * q * q * D::from(sign);
                    k += 1;
                }
                if rate.is_some() {
                    f += theta[k] * D::from(t) * q;
                    k += 1;
                }
                if let Some(change) = change {
                    for (i, w) in change.weights(t) {
                        if let Some(i) = i.filter(|_| w != 0.0) {
                            f += theta[k + i] * D::from(w) * q;
                        }
                    }
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

/// Appends an appendage's two states (z, ż) to A, C, x(0) and B: `theta` is (m_a, f_a, ζ_a[, F_r])
/// ([`Effect::Appendage`]), `j` its coordinate among the model's `n`, `reaction` the state
/// equation's column of a unit force at j ([0; M⁻¹e_j], as many rows as A, the appended states'
/// zero), and `accelerations` the acceleration outputs' share of columns of the state equation
/// (C's rows that read q̈ are rows of A, so they change with it).
///
/// With k_a = m_a ω_a² and c_a = 2ζ_a m_a ω_a, the coordinate feels f = k_a (z − q_j) + c_a (ż − q̇_j)
/// through `reaction`, and z̈ = −ω_a² (z − q_j) − 2ζ_a ω_a (ż − q̇_j); z(0) = q_j(0) + F_r/k_a,
/// ż(0) = q̇_j(0).
pub(crate) fn append_appendage<D: Scalar>(
    space: &mut mem::StateSpace<D>,
    theta: &[D],
    j: usize,
    n: usize,
    reaction: &DVector<D>,
    accelerations: impl Fn(&DMatrix<D>) -> DMatrix<D>,
) {
    let big = space.a.nrows();
    let (mass, omega) = (theta[0], theta[1] * D::from(2.0 * std::f64::consts::PI));
    let zeta = theta[2];
    let (k, c) = (mass * omega * omega, D::from(2.0) * zeta * mass * omega);
    let (z, zdot) = (big, big + 1);
    // The change of A: the reaction on the coordinate, and the appendage's own rows.
    let mut delta = DMatrix::from_element(big + 2, big + 2, D::from(0.0));
    for r in 0..big.min(reaction.len()) {
        let w = reaction[r];
        delta[(r, j)] -= k * w;
        delta[(r, n + j)] -= c * w;
        delta[(r, z)] += k * w;
        delta[(r, zdot)] += c * w;
    }
    let (w2, cw) = (omega * omega, D::from(2.0) * zeta * omega);
    delta[(z, zdot)] = D::from(1.0);
    delta[(zdot, z)] = -w2;
    delta[(zdot, zdot)] = -cw;
    delta[(zdot, j)] = w2;
    delta[(zdot, n + j)] = cw;
    let mut a = DMatrix::from_element(big + 2, big + 2, D::from(0.0));
    a.view_mut((0, 0), (big, big)).copy_from(&space.a);
    let p = space.c.nrows();
    let mut c_out = DMatrix::from_element(p, big + 2, D::from(0.0));
    c_out.view_mut((0, 0), (p, big)).copy_from(&space.c);
    c_out += accelerations(&delta);
    let mut x0 = DVector::from_element(big + 2, D::from(0.0));
    x0.rows_mut(0, big).copy_from(&space.x0);
    x0[z] = space.x0[j] + theta.get(3).map_or(D::from(0.0), |&f| f / k);
    x0[zdot] = space.x0[n + j];
    if let Some(b) = &space.b {
        let mut wide = DMatrix::from_element(big + 2, b.ncols(), D::from(0.0));
        wide.view_mut((0, 0), (big, b.ncols())).copy_from(b);
        space.b = Some(wide);
    }
    space.a = a + delta;
    space.c = c_out;
    space.x0 = x0;
}
