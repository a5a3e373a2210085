//! # mem — the matrix exponential method
//!
//! Tunes chosen parameters P of a linear model ẋ = A(P)x (+ B(P)u), y = C(P)x (+ D(P)u), x(0)
//! given (paper Eqs. 1–2), until its response matches a measured one (Garcia & Inman §II, after
//! Tsien & Mook).
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
//! * **Exact sensitivities at constant h**: the `expm` crate computes Φ = e^{Ah} and
//!   Ψ_i = L(Ah, h∂A/∂P_i) once per evaluation and recurses x_{k+1} = Φx_k,
//!   s_{k+1} = Φs_k + Ψ_i x_k — Eq. 9 exactly, never an exponential per sample. If C depends on
//!   P, ∂y/∂P_i = (∂C/∂P_i)x + C s_i (Eq. 6 without dropping its first term).
//! * **Measured inputs** (Van Loan 1978): with u held between samples, Φ and Γ come from
//!   exp(h[[A, B], [0, 0]]) and their derivatives from its Fréchet derivative in the direction
//!   h[[∂A/∂P_i, ∂B/∂P_i], [0, 0]]: x_{k+1} = Φx_k + Γu_k, s_{k+1} = Φs_k + Ψ_i x_k + ∂Γ/∂P_i u_k,
//!   ∂y = ∂C x + C s + ∂D u ([`Hold`] chooses zero- or first-order hold).
//! * **Models written once** ([`StateSpaceModel`], [`Exact`]): A(P), C(P), x(0)(P), B, D generic
//!   over the scalar; num-dual numbers give ∂A/∂P_i and the rest exactly, from the same code.
//! * **SVD instead of (SᵀS)⁻¹** (the paper's own suggestion): S is column-equilibrated and
//!   decomposed (Householder QR, then the SVD of the small factor); singular values below an
//!   explicit cutoff (reported) are dropped, so ΔP is the minimum-norm least-squares solution.
//! * **Safeguard**: Levenberg–Marquardt damping, min ‖SΔP − E‖² + μ‖DΔP‖²; a step is accepted
//!   only if Eq. 22 decreases. μ = 0 is the paper's step ([`Safeguard::None`] reproduces it).
//!   After a rejected trial, the next ones are first simulated for their outputs alone
//!   ([`ResponseModel::respond_outputs`]): Eq. 22 needs no S, so a rejected retry never pays for
//!   one, and the accepted point is simulated again with its sensitivities (the outputs are the
//!   same bits, so the iterates are those of evaluating every trial in full).
//! * **Bounds as constraints**: an active set holds a parameter on its bound when the data
//!   pull it outward, or when the step solved with it free would push it outward (Lawson &
//!   Hanson 1974, ch. 23), and solves the step for the others ([`Fit`]).
//! * **Weights and several experiments**: each output's residual is multiplied by a weight
//!   (e.g. 1/RMS); experiments with shared parameters (and their own, e.g. initial states)
//!   stack their E and S row-wise ([`Experiment::with_parameters`]).
//! * **Correlated noise** ([`Experiment::with_noise_correlation`]): under AR(1) noise
//!   e_k = ρ_o e_{k−1} + u_k per output, E and S are whitened row-wise to the innovations
//!   u_k = e_k − ρ_o e_{k−1} (u₀ = (1 − ρ_o²)^½ e₀, and likewise after a left-out sample) before
//!   the weights; with weights 1/s_o (the innovations' standard deviation) Eq. 22 becomes −2 × the
//!   Gaussian AR(1) log-likelihood up to a constant — generalised least squares (Aitken 1935).
//!   Noise of any known spectrum ([`Experiment::with_noise_predictors`]) is whitened alike by
//!   its linear predictors of orders 1…q (Levinson–Durbin, [`NoisePredictor`]): the innovations
//!   algorithm, the exact Gaussian quadratic form of an AR(q) series.
//! * **Decimation without bias** ([`Measurement::decimate`]): the model's outputs and
//!   sensitivities go through the very filter the data went through (a root-raised-cosine,
//!   which keeps decimated white noise white), simulated at the raw rate.
//! * **Records that start later** ([`Measurement::start`]): x(t₀) = e^{At₀}x(0) and its
//!   sensitivities come from one more exponential.
//! * **Quantized readings** ([`Experiment::with_quantization`]): a reading y of a quantizer with
//!   step Δ is the interval [y − Δ/2, y + Δ/2]; its residual is the model output's distance to it.
//! * **Honest uncertainty** ([`Statistics`]): a sandwich covariance over output series (white,
//!   or AR(1) when the residuals are correlated, [`Covariance`]), Student-t intervals; no
//!   interval for a parameter the data do not determine (in a dependent combination, or
//!   resolved no better than its bounds allow), a one-sided profile interval for one held on a
//!   bound; [`FitReport::warnings`] says what the user must know.
//! * **Identifiability** ([`Identifiability`]): nearly dependent columns of the equilibrated S,
//!   told in words ("scaling m1, k1 together leaves the outputs unchanged").
//! * **Checks at the start**: the sensitivities against central differences (an error on a
//!   mismatch, by default), output names against the data's, a stable model, data that move.
//!
//! ## Bring your own model
//! Write A(P), C(P), x(0)(P) once, generic over the scalar; the derivatives come from num-dual.
//! A three-storey shear building with its storey stiffnesses and Rayleigh damping free:
//! ```
//! use mem::nalgebra::DMatrix;
//! use mem::{BoxedError, Exact, Fit, LinearResponse, Measurement, Parameter, Problem, Experiment};
//! use mem::{Quantity, Scalar, SecondOrder, StateSpace, StateSpaceModel};
//!
//! struct Building;
//! impl StateSpaceModel for Building {
//!     fn parameter_names(&self) -> Vec<String> {
//!         ["k1", "k2", "k3", "alpha", "beta"].map(String::from).to_vec()
//!     }
//!     fn output_names(&self) -> Vec<String> {
//!         vec!["q1".into(), "q3".into()]
//!     }
//!     fn state_space<D: Scalar>(&self, p: &[D]) -> Result<StateSpace<D>, BoxedError> {
//!         let (k1, k2, k3, alpha, beta, z) = (p[0], p[1], p[2], p[3], p[4], D::from(0.0));
//!         let m = DMatrix::from_diagonal_element(3, 3, D::from(1000.0));
//!         let k = DMatrix::from_row_slice(3, 3, &[k1 + k2, -k2, z, -k2, k2 + k3, -k3, z, -k3, k3]);
//!         let d = &m * alpha + &k * beta;
//!         let q0 = [0.01, 0.02, 0.03].map(D::from);
//!         let outputs = [Quantity::Displacement(0), Quantity::Displacement(2)];
//!         Ok(SecondOrder::new(m, d, k).state_space(&outputs, &q0, &[z; 3])?)
//!     }
//! }
//!
//! let model = LinearResponse(Exact(Building));
//! let truth = [2.6e6, 2.2e6, 1.9e6, 0.4, 1.2e-3];
//! let data = Measurement::simulate(&model, &truth, 0.005, 2001).unwrap(); // noise-free twin
//! let start = [2.5e6, 2.25e6, 1.875e6, 0.375, 1.25e-3];
//! let names = ["k1", "k2", "k3", "alpha", "beta"];
//! let parameters = names.iter().zip(start).map(|(n, v)| Parameter::new(*n, v).with_bounds(0.0, f64::INFINITY)).collect();
//! let problem = Problem::new(vec![Experiment::normalized(&model, &data)], parameters).unwrap();
//! let report = Fit::new().run(&problem).unwrap();
//! assert!((report.parameters[0] / 2.6e6 - 1.0).abs() < 1e-8);
//! println!("{report}");
//! ```

mod data;
mod error;
mod evaluate;
mod experiment;
mod fit;
mod generic;
mod model;
mod noise;
mod problem;
mod report;
mod solve;
pub mod stats;
mod vector;

pub use data::{Decimation, Inputs, MAX_SAMPLES, Measurement, csv_header};
pub use error::{BoxedError, MemError};
pub use evaluate::sampled_response;
pub use experiment::Experiment;
pub use expm::{Hold, Response};
pub use faer;
pub use fit::{Covariance, DerivativeCheck, Fit, GaussNewtonStep, Safeguard, Termination, gauss_newton_step};
pub use generic::{
    Exact, ExactError, Quantity, Scalar, SecondOrder, SingularMass, StateSpace, StateSpaceModel,
};
pub use model::{
    Grid, InconsistentModel, LinearModel, LinearResponse, Linearized, ResponseModel, growth_rate,
    interval_residual,
};
pub use nalgebra;
pub use noise::NoisePredictor;
pub use num_dual;
pub use problem::{Parameter, Problem};
pub use report::{
    Combination, DerivativeCheck as DerivativeCheckReport, FitReport, Identifiability, Interval,
    IterationRecord, SeriesNoise, Side, Statistics, Warning,
};
pub use solve::truncated_svd_solve;
pub use stats::t_quantile_975;
