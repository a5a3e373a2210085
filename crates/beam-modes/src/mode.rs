//! Mass-normalised mode shapes and the quantities the slewing plant needs.

use crate::characteristic::{
    SERIES_LIMIT, characteristic, clamped_free_root, pinned_free_root, safeguarded_newton,
};
use crate::krylov::krylov;
use crate::{Beam, BeamError};
use num_dual::{Dual64, DualNum};

/// How the unnormalised shape φ̃(u), u = λx/L, is represented.
#[derive(Clone, Copy, Debug)]
enum Shape<D> {
    /// κ = 0, λ = 0: rigid rotation about the root, φ̃ = x/L.
    Rigid,
    /// λ < 3: φ̃ = λS₂(u) + κS₃(u) + cS₄(u) (Krylov–Duncan series).
    Series { kappa: D, c: D },
    /// λ ≥ 3: φ̃ = G e^{−(λ−u)} + H e^{−u} + P cos u + Q sin u (bounded basis).
    Exponential { g: D, h: D, p: D, q: D },
}

/// One mode of the spring-hinged/free beam, mass-normalised: ∫₀ᴸ ρ φ² dx = 1.
#[derive(Clone, Copy, Debug)]
pub struct Mode<D> {
    /// λ = βL, the dimensionless root of the characteristic equation.
    pub lambda: D,
    /// Natural frequency ω = (λ/L)²·√(EI/ρ) \[rad/s\].
    pub omega: D,
    /// Participation integral I = ∫₀ᴸ ρ (a + x) φ(x) dx \[√kg·m\].
    pub participation: D,
    /// Root slope φ′(0) \[1/(√kg·m)\].
    pub root_slope: D,
    /// Root curvature φ″(0) \[1/(√kg·m²)\]: a root strain gauge reads (thickness/2)·φ″(0)·q.
    pub root_curvature: D,
    /// Tip deflection φ(L) \[1/√kg\].
    pub tip_deflection: D,
    length: D,
    /// Normalisation factor applied to φ̃.
    scale: D,
    shape: Shape<D>,
}

impl<D: DualNum<Primitive = f64> + Copy> Mode<D> {
    /// [φ(x), φ′(x), φ″(x), φ‴(x)] (mass-normalised, derivatives with respect to x).
    pub fn shape(&self, x: D) -> [D; 4] {
        let xi = x / self.length;
        match self.shape {
            Shape::Rigid => [self.scale * x, self.scale, D::from(0.0), D::from(0.0)],
            _ => {
                let raw = raw_shape(self.lambda, &self.shape, self.lambda * xi);
                let beta = self.lambda / self.length;
                [
                    self.scale * raw[0],
                    self.scale * raw[1] * beta,
                    self.scale * raw[2] * beta * beta,
                    self.scale * raw[3] * beta * beta * beta,
                ]
            }
        }
    }
}

/// φ̃ and its first three u-derivatives.
fn raw_shape<D: DualNum<Primitive = f64> + Copy>(lambda: D, shape: &Shape<D>, u: D) -> [D; 4] {
    match *shape {
        Shape::Rigid => unreachable!("handled by the caller"),
        Shape::Series { kappa, c } => {
            let [s1, s2, s3, s4] = krylov(u);
            [
                lambda * s2 + kappa * s3 + c * s4,
                lambda * s1 + kappa * s2 + c * s3,
                lambda * s4 + kappa * s1 + c * s2,
                lambda * s3 + kappa * s4 + c * s1,
            ]
        }
        Shape::Exponential { g, h, p, q } => {
            let grow = g * (u - lambda).exp();
            let decay = h * (-u).exp();
            let (s, c) = u.sin_cos();
            [
                grow + decay + p * c + q * s,
                grow - decay - p * s + q * c,
                grow + decay - p * c - q * s,
                grow - decay + p * s - q * c,
            ]
        }
    }
}

/// The shape coefficients for root λ. The root condition φ(0) = 0, EI φ″(0) = k φ′(0) fixes
/// φ̃ = λS₂ + κS₃ + cS₄, and φ″(L) = 0 gives c = −(λS₄(λ) + κS₁(λ))/S₂(λ). For λ ≥ 3 the
/// same function is rewritten in exponentials with every growing factor divided out
/// analytically (ŝ_i = 4e^{−λ}S_i(λ)), so that no coefficient is the difference of two
/// numbers of size e^λ.
fn coefficients<D: DualNum<Primitive = f64> + Copy>(lambda: D, kappa: D) -> Shape<D> {
    if lambda.re() < SERIES_LIMIT {
        let [s1, s2, _, s4] = krylov(lambda);
        Shape::Series { kappa, c: -(lambda * s4 + kappa * s1) / s2 }
    } else {
        let e = (-lambda).exp();
        let (s, c) = lambda.sin_cos();
        let hat1 = e * e + e * c * 2.0 + 1.0;
        let hat2 = -(e * e) + e * s * 2.0 + 1.0;
        let hat4 = -(e * e) - e * s * 2.0 + 1.0;
        let cc = -(lambda * hat4 + kappa * hat1) / hat2;
        // λ + κ + c = [λ sin λ + κ(sin λ − cos λ − e^{−λ})/2] / S₂(λ), without cancellation.
        let g = (lambda * s + kappa * (s - c - e) * 0.5) / hat2;
        Shape::Exponential { g, h: (kappa - lambda - cc) * 0.25, p: -kappa * 0.5, q: (lambda - cc) * 0.5 }
    }
}

/// The first `n_modes` modes, in increasing frequency. With k = 0 the first is the rigid
/// rotation about the root (λ = 0, ω = 0).
///
/// Roots are bracketed and found in `f64` by Newton's method safeguarded by bisection, then lifted to the scalar type D
/// by one Newton step of the implicit function theorem,
/// λ = λ₀ − Δ(λ₀, κ)/∂_λΔ(λ₀, κ₀), whose dual part is −∂_κΔ·κ̇/∂_λΔ: the exact derivative of
/// the root, without differentiating through the iterations.
///
/// # Errors
/// [`BeamError::InvalidProperty`] for impossible properties, [`BeamError::NoModes`] for
/// `n_modes = 0`.
pub fn modes<D: DualNum<Primitive = f64> + Copy>(
    beam: &Beam<D>,
    n_modes: usize,
) -> Result<Vec<Mode<D>>, BeamError> {
    beam.validate()?;
    if n_modes == 0 {
        return Err(BeamError::NoModes);
    }
    let kappa = beam.kappa();
    let kappa0 = kappa.re();
    (1..=n_modes)
        .map(|i| {
            if kappa0 == 0.0 && i == 1 {
                return Ok(rigid_mode(beam));
            }
            let (lower, upper) = (pinned_free_root(i - 1), clamped_free_root(i));
            let lambda0 = if kappa0 == 0.0 { lower } else { flexible_root(i, kappa0, lower, upper)? };
            let slope = characteristic(Dual64::new(lambda0, 1.0), Dual64::from(kappa0)).eps;
            let lambda = D::from(lambda0) - characteristic(D::from(lambda0), kappa) / slope;
            Ok(flexible_mode(beam, lambda, kappa))
        })
        .collect()
}

/// Root λ_i(κ) in f64, remembered per thread for the last [`REMEMBERED_ROOTS`] (i, κ): a fit
/// of parameters that do not change κ (and a linearization, which evaluates the modes once in
/// f64 and once per parameter in dual numbers) asks for the same roots again and again. The
/// answer is the same as recomputing it, bit for bit.
fn flexible_root(i: usize, kappa0: f64, lower: f64, upper: f64) -> Result<f64, BeamError> {
    thread_local! {
        static ROOTS: std::cell::RefCell<Vec<(usize, u64, f64)>> = const { std::cell::RefCell::new(Vec::new()) };
    }
    let key = (i, kappa0.to_bits());
    if let Some(root) = ROOTS.with_borrow(|r| r.iter().find(|e| (e.0, e.1) == key).map(|e| e.2)) {
        return Ok(root);
    }
    let value_and_slope = |l: f64| {
        let d = characteristic(Dual64::new(l, 1.0), Dual64::from(kappa0));
        (d.re, d.eps)
    };
    let root = safeguarded_newton(value_and_slope, lower, upper).ok_or(BeamError::RootNotFound {
        mode: i,
        lower,
        upper,
        kappa: kappa0,
    })?;
    ROOTS.with_borrow_mut(|r| {
        if r.len() >= REMEMBERED_ROOTS {
            r.remove(0);
        }
        r.push((key.0, key.1, root));
    });
    Ok(root)
}

/// How many (mode, κ) roots each thread remembers.
const REMEMBERED_ROOTS: usize = 64;

fn rigid_mode<D: DualNum<Primitive = f64> + Copy>(beam: &Beam<D>) -> Mode<D> {
    let (l, rho, a) = (beam.length, beam.mass_per_length, beam.hub_radius);
    // ∫ρ (c x)² dx = ρ c² L³/3 = 1
    let scale = (rho * l * l * l / 3.0).sqrt().recip();
    Mode {
        lambda: D::from(0.0),
        omega: D::from(0.0),
        participation: rho * scale * (a * l * l * 0.5 + l * l * l / 3.0),
        root_slope: scale,
        root_curvature: D::from(0.0),
        tip_deflection: scale * l,
        length: l,
        scale,
        shape: Shape::Rigid,
    }
}

fn flexible_mode<D: DualNum<Primitive = f64> + Copy>(beam: &Beam<D>, lambda: D, kappa: D) -> Mode<D> {
    let (l, rho, a) = (beam.length, beam.mass_per_length, beam.hub_radius);
    let shape = coefficients(lambda, kappa);
    let at_root = raw_shape(lambda, &shape, D::from(0.0));
    let at_tip = raw_shape(lambda, &shape, lambda);
    // ∫₀¹ φ̃² dξ = φ̃(1)²/4 + φ̃_ξ(0)φ̃_ξξ(0)/(4λ⁴), from d/dξ[3φφ‴ − φ′φ″ + ξ(λ⁴φ² − 2φ′φ‴ + φ″²)]
    // = 4λ⁴φ² and the boundary conditions; with φ̃_ξξ(0) = κ φ̃_ξ(0) both terms are ≥ 0.
    let slope_xi = at_root[1] * lambda;
    let norm_sq = at_tip[0] * at_tip[0] * 0.25 + kappa * slope_xi * slope_xi / (lambda.powi(4) * 4.0);
    let scale = (rho * l * norm_sq).sqrt().recip();
    let beta = lambda / l;
    let root_curvature = scale * at_root[2] * beta * beta;
    let root_third = scale * at_root[3] * beta * beta * beta;
    // From EI φ'''' = ρω²φ: ∫φ dx = −φ‴(0)/β⁴ and ∫xφ dx = φ″(0)/β⁴ (free tip, φ(0) = 0).
    let participation = rho * (root_curvature - a * root_third) / beta.powi(4);
    Mode {
        lambda,
        omega: beta * beta * beam.wave_constant(),
        participation,
        root_slope: scale * at_root[1] * beta,
        root_curvature,
        tip_deflection: scale * at_tip[0],
        length: l,
        scale,
        shape,
    }
}
