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

use diffsol::{NalgebraMat, OdeBuilder, OdeSolverMethod, Vector, VectorView};
use expm::Response;
use mem::{BoxedError, Grid, ResponseModel};
use num_dual::Dual64;
use plant::nonlinear::Dynamics;
use plant::{ParamId, PlantError, SlewingModel};

type M = NalgebraMat<f64>;

/// Failures of a nonlinear simulation.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum NonlinearError {
    /// The plant rejected the parameters.
    #[error(transparent)]
    Plant(#[from] PlantError),
    /// The ODE solver failed.
    #[error("the ODE solver failed: {0}")]
    Solver(String),
    /// The integration took more steps than any reasonable record needs.
    #[error(
        "the ODE solver gave up after {evaluations} evaluations of the dynamics (its steps collapsed or \
         exceeded the budget): an effect is too strong or too sharp for the record (check its values, \
         e.g. a friction torque or smoothing velocity)"
    )]
    Budget {
        /// Right-hand-side evaluations made.
        evaluations: usize,
    },
}

/// Evaluations of the dynamics one simulation may take (a paper-size record with saturation,
/// friction and drag takes about 10⁴).
pub const RHS_BUDGET: usize = 2_000_000;
/// Accepted steps one simulation may take.
pub const STEP_BUDGET: usize = 200_000;
/// The smallest step, as a fraction of the record's end time.
const MIN_STEP: f64 = 1e-12;

/// What the dynamics return past the budget or where they are not finite: large enough that
/// the squared error estimate overflows, so the step is rejected.
const REJECT: f64 = 1e300;

fn sanitize(y: &mut [f64]) {
    for v in y.iter_mut() {
        if !v.is_finite() {
            *v = REJECT;
        }
    }
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
        // A step budget: past it the right-hand side returns a huge finite value, whose error
        // estimate overflows, so the solver rejects every step until it gives up (40 consecutive
        // rejections): an effect too strong or too sharp for the record ends with an error within
        // seconds instead of a hang. Non-finite values are replaced the same way (a NaN error
        // estimate would pass the acceptance test and stall the clock).
        let evaluations = std::sync::atomic::AtomicUsize::new(0);
        let exhausted = || evaluations.load(std::sync::atomic::Ordering::Relaxed) > RHS_BUDGET;
        let rhs = |x: &[f64], _p: &[f64], _t: f64, y: &mut [f64]| {
            if evaluations.fetch_add(1, std::sync::atomic::Ordering::Relaxed) > RHS_BUDGET {
                y.iter_mut().for_each(|v| *v = REJECT);
            } else {
                real.rhs(x, y);
                sanitize(y);
            }
        };
        let jac = |x: &[f64], _p: &[f64], _t: f64, v: &[f64], y: &mut [f64]| {
            let xd: Vec<Dual64> = x.iter().zip(v).map(|(a, b)| Dual64::new(*a, *b)).collect();
            let mut f = vec![Dual64::from(0.0); n];
            lifted.rhs(&xd, &mut f);
            for (yi, fi) in y.iter_mut().zip(&f) {
                *yi = fi.eps;
            }
            sanitize(y);
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
            sanitize(y);
        };
        let init = |_p: &[f64], _t: f64, y: &mut [f64]| y.copy_from_slice(&x0);
        let init_sens = |_p: &[f64], _t: f64, _v: &[f64], y: &mut [f64]| y.iter_mut().for_each(|v| *v = 0.0);
        let solver_error = |e: diffsol::error::DiffsolError| {
            if exhausted() {
                NonlinearError::Budget { evaluations: RHS_BUDGET }
            } else {
                NonlinearError::Solver(e.to_string())
            }
        };
        let t_last = *times.last().expect("at least one sample");
        // Outputs and sensitivities, sample by sample, as the solver passes them.
        let mut states = vec![vec![0.0; n]; k];
        let mut sensitivities = vec![vec![vec![0.0; n]; j]; k];
        macro_rules! march {
            ($solver:ident, $col:ident, $write:block) => {{
                let mut col = 0;
                let mut steps = 0usize;
                if t_last > 0.0 {
                    $solver.set_stop_time(t_last).map_err(solver_error)?;
                }
                while col < k {
                    if t_last == 0.0 {
                        let $col = col;
                        $write
                        col += 1;
                        continue;
                    }
                    let reason = $solver.step().map_err(solver_error)?;
                    steps += 1;
                    let (t_now, h_now) = ($solver.state().t, $solver.state().h);
                    if steps > STEP_BUDGET || exhausted() || !t_now.is_finite() || h_now.abs() < MIN_STEP * t_last {
                        return Err(NonlinearError::Budget { evaluations: evaluations.load(std::sync::atomic::Ordering::Relaxed) });
                    }
                    while col < k && times[col] <= t_now {
                        let $col = col;
                        $write
                        col += 1;
                    }
                    if matches!(reason, diffsol::OdeSolverStopReason::TstopReached) {
                        break;
                    }
                }
                if col < k {
                    return Err(NonlinearError::Solver(format!("stopped after {col} of {k} samples")));
                }
            }};
        }
        if j > 0 {
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
            march!(solver, col, {
                let y = solver.interpolate(times[col]).map_err(solver_error)?;
                let ds = solver.interpolate_sens(times[col]).map_err(solver_error)?;
                for r in 0..n {
                    states[col][r] = y.get_index(r);
                }
                for i in 0..j {
                    let lane = ds.get_batch(i);
                    for r in 0..n {
                        sensitivities[col][i][r] = lane.get_index(r);
                    }
                }
            });
        } else {
            let problem = OdeBuilder::<M>::new()
                .rtol(self.rtol)
                .atol(vec![self.atol; n])
                .rhs_implicit(rhs, jac)
                .init(init, n)
                .build()
                .map_err(solver_error)?;
            let mut solver = problem.tsit45().map_err(solver_error)?;
            march!(solver, col, {
                let y = solver.interpolate(times[col]).map_err(solver_error)?;
                for r in 0..n {
                    states[col][r] = y.get_index(r);
                }
            });
        }
        let c = &real.c;
        let p_out = c.nrows();
        for step in 0..k {
            for o in 0..p_out {
                out.outputs[(step, o)] = (0..n).map(|s| c[(o, s)] * states[step][s]).sum();
                for i in 0..j {
                    let dc = &seeded[i].c;
                    out.sensitivities[(step * p_out + o, i)] = (0..n)
                        .map(|s| c[(o, s)] * sensitivities[step][i][s] + dc[(o, s)].eps * states[step][s])
                        .sum();
                }
            }
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
