//! The closed-loop equations of motion (paper Eqs. 17–21) and their first-order form.

use crate::{Constants, Effect, EffectKind, PlantError, Sensor};
use beam_modes::{Beam, Mode};
use nalgebra::{DMatrix, DVector, RealField};
use num_dual::DualNum;

/// Scalars the model can be evaluated in: f64 and num-dual numbers over f64.
pub trait Scalar: DualNum<Primitive = f64> + RealField + Copy {}
impl<T: DualNum<Primitive = f64> + RealField + Copy> Scalar for T {}

/// M q̈ + D q̇ + K q = B θ_ref with q = [θ, q_1, …, q_n] (Eq. 20).
#[derive(Clone, Debug)]
pub struct SecondOrder<D: Scalar> {
    /// Mass matrix M (Eq. 21).
    pub m: DMatrix<D>,
    /// Damping matrix D.
    pub d: DMatrix<D>,
    /// Stiffness matrix K (not symmetric: the participation factors sit below the diagonal).
    pub k: DMatrix<D>,
    /// Input vector B for θ_ref (the paper's first entry, printed as 1.0, is K_pK_t/R_a).
    pub b: DVector<D>,
    /// The flexible beam modes used (spring-hinged roots 2…n+1).
    pub modes: Vec<Mode<D>>,
    /// Servo stiffness k_s = G·K_p·K_t/R_a \[N·m/rad\], which is also the modes' root spring.
    pub servo_stiffness: D,
    /// Where the servo torque enters: [1, Γ_1, …, Γ_n, (0 for an unmodeled mode)].
    pub servo_vector: DVector<D>,
}

/// Where each part of the (possibly augmented) state lives.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Layout {
    /// Number of flexible beam modes n.
    pub n_modes: usize,
    /// Mechanical degrees of freedom: 1 (hub) + n (+1 with an unmodeled mode).
    pub n_dof: usize,
    /// Index of the unmodeled mode's coordinate among the degrees of freedom.
    pub extra_mode: Option<usize>,
    /// Index of the motor's angle θ_m among the degrees of freedom (with backlash).
    pub motor: Option<usize>,
    /// State index of the Padé delay state w.
    pub delay: Option<usize>,
    /// State index of each sensor's lag state (by [`Sensor::index`]), where its channel reads
    /// late ([`Effect::SensorLag`]).
    pub lags: [Option<usize>; Sensor::COUNT],
    /// Total number of states.
    pub n_states: usize,
}

impl Layout {
    /// The layout that a set of constants (with its effects) needs.
    pub fn of<D>(c: &Constants<D>) -> Self {
        let n_modes = c.modal_damping.len();
        let has = |kind: EffectKind| c.effects.iter().any(|e| e.kind() == kind);
        let extra_mode = has(EffectKind::UnmodeledMode).then_some(n_modes + 1);
        let mut n_dof = n_modes + 1 + usize::from(extra_mode.is_some());
        let motor = has(EffectKind::Backlash).then(|| {
            n_dof += 1;
            n_dof - 1
        });
        let mut n_states = 2 * n_dof;
        let delay = has(EffectKind::TimeDelay).then(|| {
            n_states += 1;
            n_states - 1
        });
        let mut lags = [None; Sensor::COUNT];
        for e in &c.effects {
            if let Effect::SensorLag { sensor, .. } = e {
                lags[sensor.index()] = Some(n_states);
                n_states += 1;
            }
        }
        Self { n_modes, n_dof, extra_mode, motor, delay, lags, n_states }
    }
}

/// Servo stiffness G·K_p·K_t/R_a \[N·m/rad\].
pub fn servo_stiffness<D: Scalar>(c: &Constants<D>) -> D {
    c.amplifier_gain * c.position_gain * c.torque_constant / c.armature_resistance
}

/// Assembles M, D, K, B.
///
/// The beam is spring-hinged at the hub with the servo stiffness as its root spring (the paper,
/// §III). Root 1 of that beam is the quasi-rigid rotation against the spring, which the hub
/// angle θ already describes; the modal coordinates q_1..q_n are roots 2..n+1, the flexible
/// modes (see docs/paper-reproduction.md for why this reading reproduces Table 2).
///
/// # Errors
/// [`PlantError::Beam`] for an impossible beam.
pub fn second_order<D: Scalar>(c: &Constants<D>) -> Result<SecondOrder<D>, PlantError> {
    let n = c.modal_damping.len();
    let ks = servo_stiffness(c);
    let beam = Beam {
        length: c.length,
        flexural_rigidity: c.ei_over_rho * c.mass_per_length,
        mass_per_length: c.mass_per_length,
        hub_radius: c.hub_radius,
        root_stiffness: ks,
    };
    let modes: Vec<Mode<D>> = beam_modes::modes(&beam, n + 1)?.into_iter().skip(1).collect();
    let (a, l, rho) = (c.hub_radius, c.length, c.mass_per_length);
    // ∫₀ᴸ ρ (a + x)² dx = ρ((a + L)³ − a³)/3
    let beam_inertia = rho * (DualNum::powi(&(a + l), 3) - DualNum::powi(&a, 3)) / D::from(3.0);
    let layout = Layout::of(c);
    let size = layout.n_dof;
    let zero = D::from(0.0);
    let mut m = DMatrix::from_element(size, size, zero);
    let mut d = DMatrix::from_element(size, size, zero);
    let mut k = DMatrix::from_element(size, size, zero);
    let mut b = DVector::from_element(size, zero);
    let mut servo_vector = DVector::from_element(size, zero);
    servo_vector[0] = D::from(1.0);
    m[(0, 0)] = beam_inertia + c.hub_inertia + c.motor_inertia;
    d[(0, 0)] = c.viscous_damping + c.back_emf_constant * c.torque_constant / c.armature_resistance;
    k[(0, 0)] = ks;
    b[0] = ks;
    for (i, mode) in modes.iter().enumerate() {
        let r = i + 1;
        m[(0, r)] = mode.participation;
        m[(r, 0)] = mode.participation;
        m[(r, r)] = D::from(1.0);
        d[(r, r)] = c.modal_damping[i];
        k[(r, r)] = mode.omega * mode.omega;
        // Participation factor Γ_i = φ_i′(0): the restoring torque enters the beam as a root
        // moment, whose generalised force on mode i is (moment)·φ_i′(0).
        k[(r, 0)] = ks * mode.root_slope;
        b[r] = ks * mode.root_slope;
        servo_vector[r] = mode.root_slope;
    }
    if let Some(r) = layout.extra_mode {
        for e in &c.effects {
            if let Effect::UnmodeledMode {
                frequency_hz,
                damping_ratio,
                coupling,
                stiffness_coupling,
                damping_coupling,
            } = e
            {
                let omega = *frequency_hz * D::from(2.0 * std::f64::consts::PI);
                m[(0, r)] = *coupling;
                m[(r, 0)] = *coupling;
                m[(r, r)] = D::from(1.0);
                d[(r, r)] = D::from(2.0) * *damping_ratio * omega;
                k[(r, r)] = omega * omega;
                if let Some(kc) = stiffness_coupling {
                    k[(0, r)] = *kc;
                    k[(r, 0)] = *kc;
                }
                if let Some(dc) = damping_coupling {
                    d[(0, r)] = *dc;
                    d[(r, 0)] = *dc;
                }
            }
        }
    }
    if let Some(r) = layout.motor {
        backlash_gear(c, r, &mut m, &mut d, &mut k, &mut b, &mut servo_vector);
    }
    // A hub spring's linear part k₁θ is linear physics: it joins K at the hub (θ, the hub's
    // angle, with or without a backlash's motor). Its cubic part is a force
    // ([`crate::nonlinear`]).
    for e in &c.effects {
        if let Effect::CubicStiffness { linear: Some(k1), .. } = e {
            k[(0, 0)] += *k1;
        }
    }
    Ok(SecondOrder { m, d, k, b, modes, servo_stiffness: ks, servo_vector })
}

/// The gear's stiffness k_g = I_m ω_g² and damping c_g = 2ζ_g I_m ω_g of a backlash effect.
pub fn gear<D: Scalar>(c: &Constants<D>) -> Option<(D, D)> {
    c.effects.iter().find_map(|e| match e {
        Effect::Backlash { gear_frequency_hz, gear_damping_ratio, .. } => {
            let omega = *gear_frequency_hz * D::from(2.0 * std::f64::consts::PI);
            Some((
                c.motor_inertia * omega * omega,
                D::from(2.0 * gear_damping_ratio) * c.motor_inertia * omega,
            ))
        }
        _ => None,
    })
}

/// Backlash: the motor (DOF `r`) is split from the hub. The hub's row loses the motor's inertia,
/// the servo's stiffness k_s θ (θ from the potentiometer on the hub), C_v and the back-EMF,
/// which act on the motor instead, and gains the gear k_g(θ_m − θ) + c_g(θ̇_m − θ̇) (the dead
/// band is a nonlinear correction, [`crate::nonlinear`]). The modes' rows keep the lumped
/// model's root-spring coupling k_sΓ_i θ, so that a rigid gear with the band closed is the
/// lumped model exactly (adding the motor's and the hub's rows gives the lumped hub row).
fn backlash_gear<D: Scalar>(
    c: &Constants<D>,
    r: usize,
    m: &mut DMatrix<D>,
    d: &mut DMatrix<D>,
    k: &mut DMatrix<D>,
    b: &mut DVector<D>,
    servo_vector: &mut DVector<D>,
) {
    let (kg, cg) = gear(c).expect("the layout has a motor only with a Backlash effect");
    let servo_damping = d[(0, 0)];
    let ks = k[(0, 0)];
    m[(0, 0)] -= c.motor_inertia;
    m[(r, r)] = c.motor_inertia;
    // The servo on the motor, fed back from the hub.
    d[(0, 0)] = cg;
    k[(0, 0)] = kg;
    d[(r, r)] = servo_damping + cg;
    k[(r, r)] = kg;
    k[(r, 0)] = ks - kg;
    d[(r, 0)] = -cg;
    k[(0, r)] = -kg;
    d[(0, r)] = -cg;
    b[r] = b[0];
    b[0] = D::from(0.0);
    // A change of the servo's torque (a limit, a delay) acts on the motor alone; the gear passes
    // it on.
    servo_vector.fill(D::from(0.0));
    servo_vector[r] = D::from(1.0);
}

/// The first-order form and the input directions of the servo and hub torques.
#[derive(Clone, Debug)]
pub struct FirstOrder<D: Scalar> {
    /// A (n_states square): [[0, I], [−M⁻¹K, −M⁻¹D]] plus the delay state.
    pub a: DMatrix<D>,
    /// [0; M⁻¹·servo_vector; 0…]: how a change of servo torque enters ẋ.
    pub servo_input: DVector<D>,
    /// [0; M⁻¹e₀; 0…]: how an extra torque on the hub enters ẋ.
    pub hub_input: DVector<D>,
    /// The state layout.
    pub layout: Layout,
}

/// A = [[0, I], [−M⁻¹K, −M⁻¹D]] by one LU factorisation of M and solves (no inverse), augmented
/// with the effects' states:
/// * time delay τ (Padé(1,1)): the servo acts on θ_d = −θ + w instead of θ, ẇ = (2/τ)(2θ − w);
/// * a sensor read late by τ_s (Padé(1,1)): ẇ_s = (2/τ_s)(2y − w_s), y = c·x its undelayed
///   reading (the sensor's row of C before the lag); the output matrix reads −y + w_s.
///
/// # Errors
/// [`PlantError::SingularMass`] if M cannot be factorised.
pub fn first_order<D: Scalar>(c: &Constants<D>, so: &SecondOrder<D>) -> Result<FirstOrder<D>, PlantError> {
    let layout = Layout::of(c);
    let size = layout.n_dof;
    let lu = so.m.clone().lu();
    let mk = lu.solve(&so.k).ok_or(PlantError::SingularMass)?;
    let md = lu.solve(&so.d).ok_or(PlantError::SingularMass)?;
    let msv = lu.solve(&so.servo_vector).ok_or(PlantError::SingularMass)?;
    let mut e0 = DVector::from_element(size, D::from(0.0));
    e0[0] = D::from(1.0);
    let me0 = lu.solve(&e0).ok_or(PlantError::SingularMass)?;
    let zero = D::from(0.0);
    let n = layout.n_states;
    let mut a = DMatrix::from_element(n, n, zero);
    let mut servo_input = DVector::from_element(n, zero);
    let mut hub_input = DVector::from_element(n, zero);
    for i in 0..size {
        a[(i, size + i)] = D::from(1.0);
        for j in 0..size {
            a[(size + i, j)] = -mk[(i, j)];
            a[(size + i, size + j)] = -md[(i, j)];
        }
        servo_input[size + i] = msv[i];
        hub_input[size + i] = me0[i];
    }
    if let Some(w) = layout.delay {
        let tau = c
            .effects
            .iter()
            .find_map(|e| if let Effect::TimeDelay { delay } = e { Some(*delay) } else { None })
            .expect("the layout has a delay state only with a TimeDelay effect");
        let ks = so.servo_stiffness;
        for i in 0..size {
            // −M⁻¹ k_s sv θ becomes −M⁻¹ k_s sv (−θ + w).
            a[(size + i, 0)] += D::from(2.0) * msv[i] * ks;
            a[(size + i, w)] = -msv[i] * ks;
        }
        a[(w, 0)] = D::from(4.0) / tau;
        a[(w, w)] = D::from(-2.0) / tau;
    }
    for e in &c.effects {
        if let Effect::SensorLag { sensor, lag } = e {
            let w = layout.lags[sensor.index()].expect("the layout has a lag state for each SensorLag");
            let y = reading(c, so, &layout, *sensor);
            for j in 0..n {
                a[(w, j)] = D::from(4.0) * y[j] / *lag;
            }
            a[(w, w)] = D::from(-2.0) / *lag;
        }
    }
    Ok(FirstOrder { a, servo_input, hub_input, layout })
}

/// The sensor's undelayed reading y = c·x as a row over the state (`layout.n_states` long):
/// the potentiometer's hub angle, the tachometer's rate (the motor's with backlash unless the
/// file says otherwise), the strain gauge's root strain from the mode shapes.
pub fn reading<D: Scalar>(c: &Constants<D>, so: &SecondOrder<D>, layout: &Layout, sensor: Sensor) -> Vec<D> {
    let size = layout.n_dof;
    let mut row = vec![D::from(0.0); layout.n_states];
    match sensor {
        Sensor::Potentiometer => row[0] = D::from(1.0),
        Sensor::Tachometer => {
            // With backlash the tachometer sits on the motor's shaft unless the file says otherwise.
            let tachometer = layout
                .motor
                .filter(|_| {
                    c.effects
                        .iter()
                        .any(|e| matches!(e, crate::Effect::Backlash { tachometer_on_motor: true, .. }))
                })
                .unwrap_or(0);
            row[size + tachometer] = D::from(1.0);
        }
        Sensor::StrainGauge => {
            for (i, mode) in so.modes.iter().enumerate() {
                row[i + 1] = c.thickness * D::from(0.5e6) * mode.root_curvature;
            }
        }
    }
    row
}
