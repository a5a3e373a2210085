//! Models with nonlinear effects by an exponential integrator: the linear part exactly, the
//! nonlinear forces as a forcing that is linear over each short step.
//!
//! The model is ẋ = A x + B τ(x), y = C x + H τ(x) — for the slewing rig B = [b_s, b_h] and
//! τ = (Δτ_s, τ_h) (`plant::nonlinear`); for a structure B = G, the columns of forces at its
//! coordinates, and τ = f (`structure::effects`), with H the acceleration outputs' share.
//! Over a step h the variation-of-constants formula gives
//! x(t + h) = Φ x(t) + ∫₀ʰ e^{A(h−σ)} B τ(x(t + σ)) dσ, Φ = e^{Ah}; taking τ linear over the
//! step gives x(t + h) = Φ x + Γ_now τ(x(t)) + Γ_next τ(x(t + h)), with the first-order-hold
//! gains of `expm::step_gains` (one augmented exponential per simulation, none per sample).
//! The unknown τ(x(t + h)) is predicted with the zero-order-hold step (ETD2RK, Cox & Matthews
//! 2002, J. Comput. Phys. 176:430):
//!
//! ```text
//! a = Φ x + (Γ_now + Γ_next) τ(x),     x⁺ = Φ x + Γ_now τ(x) + Γ_next τ(a),
//! ```
//!
//! second order in h for the nonlinear part, exact for the linear part (the beam's modes, the
//! servo, a delay's Padé state) however stiff. The sensitivities s_i = ∂x/∂P_i are the exact
//! derivatives of this recursion — Φ, Γ and their parameter derivatives from the same
//! exponential's Fréchet derivatives, ∂τ/∂x and ∂τ/∂P_i in dual numbers on the plant's generic
//! torques — so a fit sees the gradient of exactly what it simulates:
//!
//! ```text
//! u_i = τ_x(x) s_i + τ_P_i(x),     c_i = Φ s_i + Φ_i x,
//! ∂a/∂P_i = c_i + G u_i + G_i τ(x)                       (G = Γ_now + Γ_next),
//! s_i⁺ = c_i + Γ_now u_i + Γ_now,i τ(x) + Γ_next (τ_x(a) ∂a/∂P_i + τ_P_i(a)) + Γ_next,i τ(a).
//! ```
//!
//! The step is the sample interval divided into equal substeps no longer than the model's
//! `max_step` (default 1/1280 s); the tests hold it to the adaptive solver's answer. The kernel,
//! the same for both kinds of model, is in `step`; this module adapts each kind to it.

mod step;

use crate::ode::{NonlinearError, free_decay, model_at};
use expm::Response;
use faer::Mat;
use mem::{BoxedError, Grid, ResponseModel};
use num_dual::Dual64;
use plant::nonlinear::Dynamics;
use plant::{ParamId, PlantError, SlewingModel};
use step::{Forces, Forcing, Linear, integrate};

pub use structure_path::StructureExponential;
mod structure_path;

/// The longest substep by default \[s\].
pub const DEFAULT_MAX_STEP: f64 = 1.0 / 1280.0;

/// A slewing model with effects, with `free` parameters, simulated by the exponential
/// integrator, as a [`ResponseModel`].
#[derive(Clone, Debug)]
pub struct ExponentialResponse {
    model: SlewingModel,
    free: Vec<ParamId>,
    max_step: f64,
}

/// The slewing rig's torques and their derivatives.
struct TorqueModel<'a> {
    real: &'a Dynamics<f64>,
    lifted: &'a Dynamics<Dual64>,
    seeded: &'a [Dynamics<Dual64>],
    acts: Vec<bool>,
    states: Vec<usize>,
    scratch: Vec<Dual64>,
}

impl Forcing for TorqueModel<'_> {
    fn at(&mut self, t: f64, x: &[f64], with_derivatives: bool, out: &mut Forces) {
        // Only a hub spring's stiffness rate depends on time.
        let (servo, hub) = self.real.torques(t, x);
        out.reset(2, self.seeded.len());
        out.value.copy_from_slice(&[servo, hub]);
        if !with_derivatives {
            return;
        }
        for (d, v) in self.scratch.iter_mut().zip(x) {
            *d = Dual64::from(*v);
        }
        for &k in &self.states {
            self.scratch[k].eps = 1.0;
            let (s, h) = self.lifted.torques(t, &self.scratch);
            self.scratch[k].eps = 0.0;
            out.states.push(k);
            out.by_state.extend([s.eps, h.eps]);
        }
        for (i, dynamics) in self.seeded.iter().enumerate() {
            if self.acts[i] {
                let (s, h) = dynamics.torques(t, &self.scratch);
                out.by_parameter[2 * i..2 * i + 2].copy_from_slice(&[s.eps, h.eps]);
            }
        }
    }
}

impl ExponentialResponse {
    /// Frees the named parameters of `model`.
    ///
    /// # Errors
    /// [`PlantError::UnknownParameter`] listing the valid names.
    pub fn new(model: SlewingModel, free: &[&str]) -> Result<Self, PlantError> {
        let free = free.iter().map(|n| model.parameter(n)).collect::<Result<Vec<_>, _>>()?;
        Ok(Self { model, free, max_step: DEFAULT_MAX_STEP })
    }

    /// The longest substep (finite and > 0; the sample interval is divided into equal substeps
    /// no longer than this).
    pub fn with_max_step(mut self, max_step: f64) -> Self {
        self.max_step = max_step;
        self
    }

    /// Simulates at P: fills `out` (K × p outputs, (K·p) × j sensitivities) at
    /// t_k = start + k·h.
    ///
    /// # Errors
    /// Plant failures, an invalid grid, or a response that does not stay finite.
    pub fn simulate(&self, p: &[f64], start: f64, h: f64, out: &mut Response) -> Result<(), NonlinearError> {
        let model = model_at(&self.model, &self.free, p)?;
        let real: Dynamics<f64> = model.dynamics_with(|v| *v)?;
        let lifted: Dynamics<Dual64> = model.dynamics_with(|v| Dual64::from(*v))?;
        // The seeded dynamics give the sensitivities only: the outputs alone need none of them.
        let seeded: Vec<Dynamics<Dual64>> = if out.sensitivities.ncols() == 0 {
            Vec::new()
        } else {
            self.free.iter().map(|&id| crate::ode::seed(&model, id)).collect::<Result<_, _>>()?
        };
        let n = real.layout.n_states;
        let parts = |a: &dyn Fn(usize, usize) -> f64,
                     g: &dyn Fn(usize, usize) -> f64,
                     c: &dyn Fn(usize, usize) -> f64,
                     x0: Vec<f64>| Linear {
            a: Mat::from_fn(n, n, a),
            g: Mat::from_fn(n, 2, g),
            c: Mat::from_fn(real.c.nrows(), n, c),
            h: None,
            x0,
        };
        let lin = parts(
            &|r, c| real.a[(r, c)],
            &|r, c| if c == 0 { real.servo_input[r] } else { real.hub_input[r] },
            &|r, c| real.c[(r, c)],
            model.initial_state(),
        );
        let d: Vec<Linear> = seeded
            .iter()
            .map(|s| {
                parts(
                    &|r, c| s.a[(r, c)].eps,
                    &|r, c| if c == 0 { s.servo_input[r].eps } else { s.hub_input[r].eps },
                    &|r, c| s.c[(r, c)].eps,
                    vec![0.0; n],
                )
            })
            .collect();
        let mut torques = TorqueModel {
            real: &real,
            lifted: &lifted,
            acts: seeded.iter().map(|d| d.torque_constants().iter().any(|c| c.eps != 0.0)).collect(),
            seeded: &seeded,
            states: real.torque_states(),
            scratch: vec![Dual64::from(0.0); n],
        };
        integrate(&lin, &d, &mut torques, start, h, self.max_step, out)
    }
}

impl ResponseModel for ExponentialResponse {
    fn n_params(&self) -> usize {
        self.free.len()
    }
    fn output_names(&self) -> Vec<String> {
        self.model.output_names().iter().map(|s| s.to_string()).collect()
    }
    fn respond(&self, p: &[f64], grid: &Grid<'_>, out: &mut Response) -> Result<(), BoxedError> {
        free_decay(grid, |start, h| self.simulate(p, start, h, out))
    }
    fn respond_outputs(&self, p: &[f64], grid: &Grid<'_>, out: &mut Response) -> Result<(), BoxedError> {
        // With no sensitivity columns the recursion steps x alone, through the same Φ and
        // force gains (the exponential does not depend on the directions).
        self.respond(p, grid, out)
    }
    fn accuracy(&self) -> f64 {
        // What the derivative check needs: how far the outputs are from a smooth function of P.
        // The sensitivities are the exact derivatives of the simulated recursion, whose outputs
        // are smooth in P to rounding (a record's thousands of substeps: about 1e-12). Its
        // distance from the true flow, O(h²) of the nonlinear forcing (10⁻⁵ of a peak for a
        // strong spring; far below any sensor's noise), is no error of the derivatives: with
        // 1e-9 here the check's central differences took steps of 10⁻³ of each parameter,
        // whose own truncation (5–9·10⁻⁵ on the building's springs) came near its tolerance.
        1e-12
    }
}
