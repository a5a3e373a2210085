//! The closed-loop equations of motion (paper Eqs. 17–21) and their first-order form.

use crate::{Constants, PlantError};
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
    let size = n + 1;
    let zero = D::from(0.0);
    let mut m = DMatrix::from_element(size, size, zero);
    let mut d = DMatrix::from_element(size, size, zero);
    let mut k = DMatrix::from_element(size, size, zero);
    let mut b = DVector::from_element(size, zero);
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
    }
    Ok(SecondOrder { m, d, k, b, modes, servo_stiffness: ks })
}

/// A = [[0, I], [−M⁻¹K, −M⁻¹D]], by one LU factorisation of M and two solves (no inverse).
///
/// # Errors
/// [`PlantError::SingularMass`] if M cannot be factorised.
pub fn first_order<D: Scalar>(so: &SecondOrder<D>) -> Result<DMatrix<D>, PlantError> {
    let size = so.m.nrows();
    let lu = so.m.clone().lu();
    let mk = lu.solve(&so.k).ok_or(PlantError::SingularMass)?;
    let md = lu.solve(&so.d).ok_or(PlantError::SingularMass)?;
    let zero = D::from(0.0);
    let mut a = DMatrix::from_element(2 * size, 2 * size, zero);
    for i in 0..size {
        a[(i, size + i)] = D::from(1.0);
        for j in 0..size {
            a[(size + i, j)] = -mk[(i, j)];
            a[(size + i, size + j)] = -md[(i, j)];
        }
    }
    Ok(a)
}
