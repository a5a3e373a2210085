//! # nonlinear — slewing models with nonlinear effects, simulated with forward sensitivities
//!
//! A model with amplifier saturation, Coulomb friction or quadratic drag obeys
//! ẋ = f(x, P) = A(P) x + b_s(P) Δτ_s(x, P) + b_h(P) τ_h(x, P) (see `plant::nonlinear`), which
//! has no matrix exponential. Its outputs y = C(P) x and sensitivities ∂y/∂P = C s + (∂C/∂P) x
//! come from the forward sensitivity equations
//!
//! ```text
//! ṡ_i = (∂f/∂x) s_i + ∂f/∂P_i,   s_i(0) = ∂x(0)/∂P_i,
//! ```
//!
//! integrated together with x by diffsol's explicit Tsitouras 5(4) method with error control on
//! both. The Jacobian-vector products (∂f/∂x)v and (∂f/∂P)v are evaluated exactly in num-dual
//! numbers on the plant's generic dynamics — nothing is hand-differentiated or finite-differenced.
//! [`NonlinearResponse`] implements [`mem::ResponseModel`], so the same MEM iteration fits these
//! models; [`simulate`] uses the exact exponential path whenever the model is linear.

mod response;
mod simulate;

pub use response::{NonlinearError, NonlinearResponse};
pub use simulate::{simulate, simulate_model, simulate_sensors};
