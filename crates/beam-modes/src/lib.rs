//! # beam-modes — modes of a beam spring-hinged at the hub and free at the tip
//!
//! The physics layer at the bottom of memid's slewing model (Garcia & Inman, §III, and their
//! ref. 9: K. R. Chun, *Free vibration of a beam with one end spring-hinged and the other free*,
//! J. Appl. Mech. 39, 1972).
//!
//! ## Boundary-value problem
//! A uniform Euler–Bernoulli beam of length L \[m\], flexural rigidity EI \[N·m²\] and mass per
//! length ρ \[kg/m\] vibrates as y(x, t) = φ(x) sin ωt with
//!
//! ```text
//! EI φ'''' = ρ ω² φ,   i.e.  φ'''' = β⁴ φ,  β⁴ = ρω²/EI,  0 < x < L.
//! ```
//!
//! Its root (x = 0, at radius a from the slewing axis) cannot translate and is held by a
//! rotational spring of stiffness k \[N·m/rad\]; its tip is free:
//!
//! ```text
//! φ(0) = 0,   EI φ''(0) = k φ'(0),   φ''(L) = 0,   φ'''(L) = 0.
//! ```
//!
//! (The bending moment EI φ″ at the root balances the spring moment k φ′; k → 0 is a pin,
//! k → ∞ a clamp.) With λ = βL and κ = kL/EI, the general solution
//! φ = A(cosh βx − cos βx) + B sinh βx + D sin βx has a non-trivial solution if and only if
//!
//! ```text
//! Δ(λ, κ) = λ (sin λ cosh λ − cos λ sinh λ) − κ (1 + cos λ cosh λ) = 0.
//! ```
//!
//! κ = 0 gives the pinned-free equation tan λ = tanh λ (λ = 0 — rigid rotation — and 3.9266,
//! 7.0686, 10.2102, …); κ → ∞ gives the clamped-free equation cos λ cosh λ = −1 (1.8751,
//! 4.6941, 7.8548, 10.9955, …). The i-th root increases monotonically with κ between the
//! (i−1)-th pinned-free root and the i-th clamped-free root, which bracket it.
//! The natural frequencies are ω_i = (λ_i/L)² √(EI/ρ) \[rad/s\]. For small κ,
//! λ₁⁴ ≈ 3κ, i.e. ω₁² ≈ k/(ρL³/3): the rod rotating rigidly against the spring.
//!
//! ## Normalisation and the plant's quantities
//! Modes are mass-normalised, ∫₀ᴸ ρ φ_i φ_j dx = δ_ij (units of φ: 1/√kg), so that the modal
//! equations read q̈_i + ω_i² q_i = … . Multiplying the ODE by φ, x or 1 and integrating by
//! parts with the boundary conditions gives closed forms:
//!
//! ```text
//! ∫₀ᴸ φ² dx      = L φ(L)²/4 + (k/EI) φ'(0)² / (4β⁴)
//! ∫₀ᴸ φ dx       = −φ'''(0)/β⁴
//! ∫₀ᴸ x φ dx     =  φ''(0)/β⁴
//! I_i = ∫₀ᴸ ρ (a + x) φ_i dx = ρ (φ_i''(0) − a φ_i'''(0)) / β_i⁴      [√kg·m]
//! ω_i² = ∫₀ᴸ EI φ_i''² dx + k φ_i'(0)²                                   (Rayleigh quotient)
//! ```
//!
//! The plant also needs the root slope φ′(0), the root curvature φ″(0) (a strain gauge at the
//! root reads strain = (h/2)·Σ q_i φ_i″(0) for a beam of thickness h) and the tip deflection φ(L).
//!
//! ## Numerics
//! Mode shapes are evaluated without cancellation: for λ < 3 through Krylov–Duncan series
//! (the closed forms lose every digit of cosh u − cos u as u → 0), for λ ≥ 3 in the bounded
//! basis e^{−β(L−x)}, e^{−βx}, cos βx, sin βx with every growing factor divided out analytically.
//!
//! ## Exact derivatives
//! Everything is generic over a num-dual scalar D, so derivatives with respect to k, EI, ρ, L
//! and a are exact. Roots are found in f64 and lifted by one Newton step in D (the implicit
//! function theorem), so no derivative passes through an iteration.
//!
//! ```
//! use beam_modes::{Beam, modes};
//! use num_dual::Dual64;
//! // ∂ω₁/∂k of a steel strip on a servo spring.
//! let beam = Beam {
//!     length: Dual64::from(1.19),
//!     flexural_rigidity: Dual64::from(0.407),
//!     mass_per_length: Dual64::from(0.475),
//!     hub_radius: Dual64::from(0.06),
//!     root_stiffness: Dual64::new(0.22, 1.0),
//! };
//! let m = modes(&beam, 3).unwrap();
//! assert!(m[0].omega.eps > 0.0); // a stiffer root raises the frequency
//! ```

mod beam;
mod characteristic;
mod error;
mod krylov;
mod mode;
pub mod quadrature;

pub use beam::Beam;
pub use characteristic::{characteristic, clamped_free_root, pinned_free_root};
pub use error::BeamError;
pub use mode::{Mode, modes};
