//! # expm — the matrix exponential, its Fréchet derivative, and MEM sensitivities on faer
//!
//! The lowest numerical layer of memid. It computes
//!
//! * **e^A** ([`expm`]) by scaling and squaring: e^A = r_m(2⁻ˢA)^{2ˢ}, with r_m the diagonal
//!   Padé approximant of degree m ∈ {3, 5, 7, 9, 13}.  m and s are chosen by the backward-error
//!   bounds of Al-Mohy & Higham (2009a), evaluated with α_p(A) = max(‖Aᵖ‖^{1/p},
//!   ‖A^{p+1}‖^{1/(p+1)}) (norms of powers, estimated without forming them when they are not
//!   needed anyway) so that non-normal matrices are not over-scaled, plus the ℓ(A, m) correction
//!   that guards the evaluation of r_m against rounding.
//! * **L(A, E)** ([`expm_frechet`], [`ExpmFrechet`]), the Fréchet derivative
//!   L(A, E) = ∫₀¹ e^{A(1−t)} E e^{At} dt, by differentiating the Padé and squaring recurrences
//!   (Al-Mohy & Higham 2009b, Algorithm 6.4).  It costs about 3× the flops of e^A per direction,
//!   instead of 8× for the exponential of the 2N×2N block [[A, E], [0, A]]; several directions
//!   share the powers, the LU factors of the Padé denominator and the squares.
//! * **κ_exp(A)** ([`ExpmFrechet::condition`], [`ExpmFrechet::ill_conditioned`]): the relative
//!   condition number ‖L(A)‖‖A‖/‖e^A‖ by the power method on L(A)*L(A) = L(Aᵀ, L(A, ·))
//!   (Al-Mohy & Higham 2009b, §7); an answer with κ·u beyond the caller's tolerance is flagged
//!   ([`IllConditioned`]) rather than returned silently.
//! * **The MEM sensitivity propagator** ([`SensitivityPropagator`]).  Garcia & Inman (paper
//!   Eq. 9) obtain the state sensitivities ∂x/∂P_i from
//!
//!   ```text
//!   Ż = A' Z,   A' = [[A, 0], [∂A/∂P_i, A]],   Z = [x; ∂x/∂P_i],   Z(0) = [x(0); 0].
//!   ```
//!
//!   At a constant sample interval h, exp(A'h) = [[Φ, 0], [Ψ_i, Φ]] with Φ = e^{Ah} and
//!   Ψ_i = L(Ah, h·∂A/∂P_i), so the exact sampled solution is the recursion
//!   x_{k+1} = Φ x_k,  s_{i,k+1} = Φ s_{i,k} + Ψ_i x_k,  y_k = C x_k,  ∂y_k/∂P_i = C s_{i,k}
//!   (paper Eqs. 7–10).  One exponential serves every sample; the state and all j
//!   sensitivities advance together as one N×(j+1) block per step.
//!   For N ≤ 16 the propagator computes Φ and Ψ_i with the same Padé/Fréchet code on stack
//!   matrices of compile-time order (`Square` storage; no heap allocation per intermediate),
//!   and runs the recursion with the order fixed at compile time under run-time SIMD dispatch.
//!
//! * **Modal coordinates** ([`free_decay`] with [`Strategy::Auto`], from
//!   [`MODAL_MIN_STATES`] states on): with A = VΛV⁻¹, the Fréchet derivative in modal
//!   coordinates is Daleckii–Krein's (hV⁻¹∂A/∂P_iV) ∘ [(e^{λ_jh} − e^{λ_lh})/(λ_jh − λ_lh)], and
//!   the sensitivity recursion sums in closed form as a geometric series, so all outputs and
//!   sensitivities are Re(P₁·\[μᵏ\] + P₂·\[kμᵏ⁻¹\]) — two complex GEMMs instead of k propagation
//!   steps. It is used only when κ₁(V)·(1 + max|μ|/min gap) ≤ 1e8; otherwise (defective or
//!   nearly repeated spectra) the propagator answers.
//!
//! ## References
//! * J. L. Daleckii, S. G. Krein (1965), *Integration and differentiation of functions of
//!   Hermitian operators and applications to the theory of perturbations*, AMS Transl. 47.
//! * A. H. Al-Mohy, N. J. Higham (2009a), *A new scaling and squaring algorithm for the matrix
//!   exponential*, SIAM J. Matrix Anal. Appl. 31(3), 970–989.
//! * A. H. Al-Mohy, N. J. Higham (2009b), *Computing the Fréchet derivative of the matrix
//!   exponential, with an application to condition number estimation*, SIAM J. Matrix Anal.
//!   Appl. 30(4), 1639–1657.
//! * N. J. Higham (2005), *The scaling and squaring method for the matrix exponential
//!   revisited*, SIAM J. Matrix Anal. Appl. 26(4), 1179–1193.
//! * E. Garcia, D. J. Inman, *Identification of system parameters in a slewing control
//!   experiment* (the paper memid implements; Eq. 9).

mod check;
mod error;
mod exponential;
mod fixed;
mod frechet;
mod kernel;
mod modal;
mod norm;
mod pade;
mod propagate;
mod response;
mod square;

pub use error::ExpmError;
pub use exponential::expm;
pub use frechet::{ExpmFrechet, IllConditioned, expm_frechet, expm_frechet_many};
pub use norm::norm1;
pub use propagate::{
    Forcing, Hold, MODAL_MIN_STATES, Method, Response, ResponseProblem, SensitivityPropagator, StepGains,
    Strategy, free_decay, step_gains,
};
