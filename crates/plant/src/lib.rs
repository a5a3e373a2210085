//! # plant — the closed-loop slewing beam of Garcia & Inman
//!
//! A flexible beam clamped to a rigid hub of radius a, driven by an armature-controlled DC motor
//! under proportional position feedback (the paper's §III).
//!
//! ## Equations
//! With q = [θ, q_1, …, q_n] (hub angle and modal coordinates of the beam, y = Σ q_i φ_i):
//!
//! * open loop (Eq. 17): M̃ q̈ + K̃ q = [1, 0, …]ᵀ τ with
//!   M̃ = [[∫ρ(a+x)²dx + I_H, I_1 … I_n], [I_i, 1]], K̃ = diag(0, ω_1², …, ω_n²),
//!   I_i = ∫₀ᴸ ρ(a+x)φ_i dx;
//! * motor (Eq. 18, inductance neglected): τ = (K_t/R_a) e_a − I_m θ̈ − (C_v + K_bK_t/R_a) θ̇;
//! * amplifier and control (Eq. 19): e_a = G·K_p (θ_ref − θ), G the power amplifier's voltage
//!   gain (not printed in the paper; see `docs/paper-reproduction.md`);
//! * closed loop (Eqs. 20–21): M q̈ + D q̇ + K q = B θ_ref with
//!   M = M̃ + diag(I_m, 0), D = diag(C_v + K_bK_t/R_a, 2ζ_1ω_1, …),
//!   K = [[k_s, 0], [k_s Γ_i, diag(ω_i²)]], B = [k_s, k_s Γ_1, …]ᵀ, k_s = G K_p K_t/R_a,
//!   with participation factors Γ_i = φ_i′(0).
//!
//! The modes φ_i are those of a beam spring-hinged at the hub with the servo stiffness k_s as
//! its root spring (from the `beam-modes` crate); root 1 of that beam is the quasi-rigid
//! rotation that θ describes, so q_1..q_n are roots 2..n+1. First-order form: x = [q; q̇],
//! A = [[0, I], [−M⁻¹K, −M⁻¹D]] (by LU solves), y = C x for a potentiometer (θ), tachometer (θ̇)
//! and root strain gauge ((h/2)·Σ q_i φ_i″(0), microstrain).
//!
//! ## Exact derivatives
//! Every step is generic over the scalar ([`assemble::Scalar`]); [`SlewingModel::linearization`]
//! evaluates it in num-dual numbers, so ∂A/∂K_p contains the change of the mode frequencies,
//! shapes and participation integrals that K_p causes through the root spring.
//!
//! ## Model files
//! [`ModelFile`] is the RON schema (documented field by field in `docs/model-file.md`);
//! `fixtures/slewing.ron` holds the paper's experiment.

pub mod assemble;
mod effects;
mod error;
mod export;
mod file;
mod modal;
mod model;
pub mod nonlinear;
mod output;
mod params;
mod sensors;

pub use effects::{DEFAULT_GEAR_DAMPING, Effect, EffectKind};
pub use error::PlantError;
pub use file::{
    BeamSection, ControlSection, HubSection, InitialCondition, ModelFile, MotorSection, SlewingInput, locate,
};
pub use modal::{ModalRow, ModeKind, RawMode, modes_of};
pub use model::{Linearization, PAPER_MODEL_RON, SlewingModel, StateSpace};
pub use params::{Constants, MIN_DELAY, ParamId, SignRule};
pub use sensors::Sensor;
