//! The MEM iteration (the paper's Algorithm, steps 1–4), made robust: a Levenberg–Marquardt
//! safeguard and bounds handled as constraints by an active set.
//!
//! ## Bounds
//! At P, a parameter is *active* if it sits on a bound and the descent direction Sᵀr points
//! out of the box, or if the step solved with it free would push it out (Lawson & Hanson 1974,
//! ch. 23): it is held there and the step is solved for the others only (their Gauss–Newton
//! step is then the right one, not the projection of a step that assumed the held parameter
//! would move). A trial step that crosses a bound is projected onto it; the
//! Levenberg–Marquardt gain compares the actual decrease with the one the linear model
//! predicts for the projected step, ‖r‖² − ‖r − SΔP‖². When the bounds are inactive at the
//! optimum the iteration is the unbounded one; when one is active the parameter ends exactly on it.

mod iterate;
pub(crate) mod settings;

pub use iterate::{GaussNewtonStep, gauss_newton_step};
pub use settings::{Covariance, DerivativeCheck, Fit, Safeguard, Termination};
