//! Slewing models with nonlinear effects, simulated with forward sensitivities.
//!
//! A model with amplifier saturation, dry friction or drag obeys
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

use diffsol::{
    DenseMatrix, MatrixCommon, NalgebraMat, OdeBuilder, OdeSolverMethod, SensitivitiesOdeSolverMethod,
};
use expm::Response;
use mem::{BoxedError, Grid, ResponseModel};
use num_dual::Dual64;
use plant::nonlinear::Dynamics;
use plant::{ParamId, PlantError, SlewingModel};

type M = NalgebraMat<f64>;

/// Failures of a nonlinear simulation.
#[derive(Debug, thiserror::Error)]
pub enum NonlinearError {
    /// The plant rejected the parameters.
    #[error(transparent)]
    Plant(#[from] PlantError),
    /// The ODE solver failed.
    #[error("the ODE solver failed: {0}")]
    Solver(String),
}

/// A slewing model with effects, with `free` parameters, as a [`ResponseModel`].
#[derive(Clone, Debug)]
pub struct NonlinearResponse {
    model: SlewingModel,
    free: Vec<ParamId>,
    rtol: f64,
    atol: f64,
}

impl NonlinearResponse {
    /// Frees the named parameters of `model`.
    ///
    /// # Errors
    /// [`PlantError::UnknownParameter`] listing the valid names.
    pub fn new(model: SlewingModel, free: &[&str]) -> Result<Self, PlantError> {
        let free = free.iter().map(|n| model.parameter(n)).collect::<Result<Vec<_>, _>>()?;
        Ok(Self { model, free, rtol: 1e-9, atol: 1e-11 })
    }

    /// Integration tolerances (relative, absolute) for states and sensitivities.
    pub fn with_tolerances(mut self, rtol: f64, atol: f64) -> Self {
        self.rtol = rtol;
        self.atol = atol;
        self
    }

    fn model_at(&self, p: &[f64]) -> Result<SlewingModel, PlantError> {
        let mut m = self.model.clone();
        for (id, v) in self.free.iter().zip(p) {
            m.set(*id, *v)?;
        }
        Ok(m)
    }

    /// Simulates at P: fills `out` (K × p outputs, (K·p) × j sensitivities) at
    /// t_k = start + k·h.
    ///
    /// # Errors
    /// Plant or solver failures.
    pub fn simulate(&self, p: &[f64], start: f64, h: f64, out: &mut Response) -> Result<(), NonlinearError> {
        let model = self.model_at(p)?;
        let real: Dynamics<f64> = model.dynamics_with(|v| *v)?;
        let lifted: Dynamics<Dual64> = model.dynamics_with(|v| Dual64::from(*v))?;
        let seeded: Vec<Dynamics<Dual64>> =
            self.free.iter().map(|&id| seed(&model, id)).collect::<Result<_, _>>()?;
        let n = real.layout.n_states;
        let j = self.free.len();
        let x0 = model.initial_state();
        let k = out.outputs.nrows();
        let times: Vec<f64> = (0..k).map(|i| start + i as f64 * h).collect();
        let rhs = |x: &[f64], _p: &[f64], _t: f64, y: &mut [f64]| real.rhs(x, y);
        let jac = |x: &[f64], _p: &[f64], _t: f64, v: &[f64], y: &mut [f64]| {
            let xd: Vec<Dual64> = x.iter().zip(v).map(|(a, b)| Dual64::new(*a, *b)).collect();
            let mut f = vec![Dual64::from(0.0); n];
            lifted.rhs(&xd, &mut f);
            for (yi, fi) in y.iter_mut().zip(&f) {
                *yi = fi.eps;
            }
        };
        let sens = |x: &[f64], _p: &[f64], _t: f64, v: &[f64], y: &mut [f64]| {
            let xd: Vec<Dual64> = x.iter().map(|a| Dual64::from(*a)).collect();
            y.iter_mut().for_each(|yi| *yi = 0.0);
            let mut f = vec![Dual64::from(0.0); n];
            for (i, dynamics) in seeded.iter().enumerate() {
                if v[i] == 0.0 {
                    continue;
                }
                dynamics.rhs(&xd, &mut f);
                for (yi, fi) in y.iter_mut().zip(&f) {
                    *yi += v[i] * fi.eps;
                }
            }
        };
        let init = |_p: &[f64], _t: f64, y: &mut [f64]| y.copy_from_slice(&x0);
        let init_sens = |_p: &[f64], _t: f64, _v: &[f64], y: &mut [f64]| y.iter_mut().for_each(|v| *v = 0.0);
        let solver_error = |e: diffsol::error::DiffsolError| NonlinearError::Solver(e.to_string());
        let (states, sensitivities) = if j > 0 {
            let problem = OdeBuilder::<M>::new()
                .p(p.to_vec())
                .rtol(self.rtol)
                .atol(vec![self.atol; n])
                .sens_rtol(self.rtol)
                .sens_atol(vec![self.atol; n])
                .rhs_sens_implicit(rhs, jac, sens)
                .init_sens(init, init_sens, n)
                .build()
                .map_err(solver_error)?;
            let mut solver = problem.tsit45_sens().map_err(solver_error)?;
            let (ys, ss, _) = solver.solve_dense_sensitivities(&times).map_err(solver_error)?;
            (ys, ss)
        } else {
            let problem = OdeBuilder::<M>::new()
                .rtol(self.rtol)
                .atol(vec![self.atol; n])
                .rhs_implicit(rhs, jac)
                .init(init, n)
                .build()
                .map_err(solver_error)?;
            let mut solver = problem.tsit45().map_err(solver_error)?;
            let (ys, _) = solver.solve_dense(&times).map_err(solver_error)?;
            (ys, Vec::new())
        };
        let c = &real.c;
        let p_out = c.nrows();
        for step in 0..k.min(states.ncols()) {
            for o in 0..p_out {
                let y: f64 = (0..n).map(|s| c[(o, s)] * states.get_index(s, step)).sum();
                out.outputs[(step, o)] = y;
                for i in 0..j {
                    let dc = &seeded[i].c;
                    let v: f64 = (0..n)
                        .map(|s| {
                            c[(o, s)] * sensitivities[i].get_index(s, step)
                                + dc[(o, s)].eps * states.get_index(s, step)
                        })
                        .sum();
                    out.sensitivities[(step * p_out + o, i)] = v;
                }
            }
        }
        if states.ncols() < k {
            return Err(NonlinearError::Solver(format!("stopped after {} of {k} samples", states.ncols())));
        }
        Ok(())
    }
}

/// The dynamics in dual numbers with ε = 1 on parameter `id` only.
fn seed(model: &SlewingModel, id: ParamId) -> Result<Dynamics<Dual64>, PlantError> {
    let mut constants = model.constants().map(|v| Dual64::from(*v));
    constants.field_mut(id).eps = 1.0;
    plant::nonlinear::dynamics(&constants, model.sensors())
}

impl ResponseModel for NonlinearResponse {
    fn n_params(&self) -> usize {
        self.free.len()
    }
    fn output_names(&self) -> Vec<String> {
        self.model.output_names().iter().map(|s| s.to_string()).collect()
    }
    fn respond(&self, p: &[f64], grid: &Grid<'_>, out: &mut Response) -> Result<(), BoxedError> {
        if grid.inputs.is_some() {
            return Err(NonlinearError::Solver("this model takes no measured inputs".into()).into());
        }
        Ok(self.simulate(p, grid.start, grid.interval, out)?)
    }
    fn accuracy(&self) -> f64 {
        // The solver controls the local error to rtol; the global error of the outputs and
        // sensitivities is a few times that.
        10.0 * self.rtol
    }
}
