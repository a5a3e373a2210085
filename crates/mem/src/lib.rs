//! # mem — the matrix exponential method
//!
//! Tunes chosen parameters P of a linear model ẋ = A(P)x, y = C x, x(0) given (paper Eqs. 1–2),
//! until its free decay matches a measured one (Garcia & Inman §II, after Tsien & Mook).
//!
//! ## The paper's method
//! Assume Y_meas = Y(P + ΔP) (Eq. 3) and expand to first order (Eq. 4):
//! Y_meas ≈ Y(P) + (∂Y/∂P) ΔP. The sensitivities are ∂Y/∂P_i = C ∂x/∂P_i (Eqs. 6–7), and
//! ∂x/∂P_i solves ∂ẋ/∂P_i = (∂A/∂P_i) x + A ∂x/∂P_i (Eq. 8), i.e. Ż = A′Z with
//! A′ = [[A, 0], [∂A/∂P_i, A]] (Eq. 9), Z(0) = [x(0); 0] (Eq. 10). Stacking k samples and
//! p outputs gives E = S ΔP (Eqs. 11–12) with E the (k·p) model error and S the (k·p) × j
//! sensitivities; the paper solves it by least squares, ΔP = (SᵀS)⁻¹SᵀE (Eq. 13), adds ΔP
//! to P and repeats until |ΔP_i| ≪ |P_i| (its Algorithm). Its error measure is
//! ‖Y_error‖ = (Y_meas − Y)ᵀ(Y_meas − Y) (Eq. 22).
//!
//! ## What this crate does, and how each extension changes the equations
//! * **Exact sensitivities at constant h**: the `expm` crate's propagator computes
//!   Φ = e^{Ah} and Ψ_i = L(Ah, h∂A/∂P_i) once per iteration and recurses
//!   x_{k+1} = Φx_k, s_{k+1} = Φs_k + Ψ_i x_k — Eq. 9 exactly, never an exponential per sample.
//!   If C depends on P, ∂y/∂P_i = (∂C/∂P_i)x + C s_i (Eq. 6 without dropping its first term).
//! * **SVD instead of (SᵀS)⁻¹** (the paper's own suggestion): S is column-equilibrated and
//!   decomposed by faer's thin SVD; singular values below an explicit cutoff (reported) are
//!   dropped, so ΔP is the minimum-norm least-squares solution and a non-identifiable
//!   combination does not wander.
//! * **Safeguard**: Levenberg–Marquardt damping solves min ‖SΔP − E‖² + μ‖DΔP‖², i.e.
//!   ΔP = D⁻¹V diag(σ/(σ² + μ))UᵀE; a step is accepted only if Eq. 22 decreases, so the error
//!   history is monotone. μ = 0 is the paper's step ([`Safeguard::None`] reproduces it).
//! * **Bounds**: trial points are projected onto a box (e.g. damping ≥ 0, gains > 0).
//! * **Weights**: each output's residual is multiplied by a weight w_o (e.g. 1/RMS), so E and S
//!   become W E and W S; unit weights give Eq. 22 exactly.
//! * **Several experiments** with shared P: their E and S are stacked row-wise.
//! * **Quantized readings** ([`Experiment::with_quantization`]): a reading y of a quantizer with
//!   step Δ is the interval [y − Δ/2, y + Δ/2]; its residual is the model output's distance to
//!   it, sign(e)·max(0, |e| − Δ/2), and its row of S is zero inside (interval-censored least
//!   squares), so the model is not charged for the quantizer's rounding.
//! * **Unknown initial states**: a model may give ∂x(0)/∂P; the sensitivity recursion then starts
//!   from s(0) = ∂x(0)/∂P instead of Eq. 10's zero, and for x(0) itself as a parameter the
//!   sensitivity is exactly C e^{At} e_i.
//! * **Uncertainty** after convergence: σ̂² = ‖E‖²/(m − rank), Cov = σ̂²(SᵀS)⁺ from the SVD,
//!   standard errors, Student-t 95 % intervals and correlations; an **identifiability** report
//!   from the SVD of the relative sensitivities S·diag(|P|) names parameter combinations
//!   ∏P_i^{v_i} the data do not determine.
//! * **Derivative check**: S against central finite differences of the whole response.
//!
//! ## Bring your own model
//! ```
//! use faer::{Mat, mat};
//! use mem::{Experiment, Fit, LinearModel, LinearResponse, Linearized, Measurement};
//!
//! /// m ẍ + c ẋ + k x = 0 with unit mass; P = [c, k].
//! struct Oscillator;
//! impl LinearModel for Oscillator {
//!     type Error = std::convert::Infallible;
//!     fn n_states(&self) -> usize { 2 }
//!     fn n_params(&self) -> usize { 2 }
//!     fn n_outputs(&self) -> usize { 1 }
//!     fn linearize(&self, p: &[f64]) -> Result<Linearized, Self::Error> {
//!         Ok(Linearized {
//!             a: mat![[0.0, 1.0], [-p[1], -p[0]]],
//!             da: vec![mat![[0.0, 0.0], [0.0, -1.0]], mat![[0.0, 0.0], [-1.0, 0.0]]],
//!             c: mat![[1.0, 0.0]],
//!             dc: None,
//!             x0: vec![1.0, 0.0],
//!             dx0: None,
//!         })
//!     }
//! }
//!
//! let model = LinearResponse(Oscillator);
//! // "Measured" data from c = 0.3, k = 4.
//! let mut truth = expm::Response::zeros(200, 1, 2);
//! mem::ResponseModel::respond(&model, &[0.3, 4.0], 0.05, &mut truth).unwrap();
//! let data = Measurement::new(vec!["x".into()], 0.0, 0.05, truth.outputs.clone()).unwrap();
//! let fit = Fit::new().with_tolerance(1e-12).unwrap();
//! let report = fit.run(&[Experiment::new(&model, &data)], &[0.2, 3.0]).unwrap();
//! assert!((report.parameters[1] - 4.0).abs() < 1e-8);
//! ```

mod data;
mod error;
mod evaluate;
mod fit;
mod model;
mod report;
mod solve;
mod vector;

pub use data::Measurement;
pub use error::{BoxedError, MemError};
pub use fit::{Fit, GaussNewtonStep, Safeguard, Termination, gauss_newton_step};
pub use model::{Experiment, LinearModel, LinearResponse, Linearized, ResponseModel, interval_residual};
pub use report::{
    Combination, DerivativeCheck, FitReport, Identifiability, IterationRecord, Statistics, t_quantile_975,
};
