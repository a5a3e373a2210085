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
//! integrated together with x by diffsol's explicit Tsitouras 5(4) method, with error control
//! on the states (the sensitivities ride along on the same steps: the exact derivatives of the
//! discrete solution, and as accurate as the states; controlling them too only shortens the
//! steps in proportion to the number of parameters). The Jacobian-vector products (∂f/∂x)v and (∂f/∂P)v are evaluated exactly in num-dual
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

/// The solver's default relative tolerance (absolute: 1 % of it), for states and sensitivities.
pub const DEFAULT_RTOL: f64 = 1e-9;

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
        Ok(Self { model, free, rtol: DEFAULT_RTOL, atol: 1e-2 * DEFAULT_RTOL })
    }

    /// Integration tolerances (relative, absolute) for states and sensitivities.
    pub fn with_tolerances(mut self, rtol: f64, atol: f64) -> Self {
        self.rtol = rtol;
        self.atol = atol;
        self
    }

    fn model_at(&self, p: &[f64]) -> Result<SlewingModel, PlantError> {
        model_at(&self.model, &self.free, p)
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
        // f(x) = A x + b_s Δτ_s(x) + b_h τ_h(x): the linear part in plain numbers, the torques
        // (scalar functions of a few states) in dual numbers where a derivative is needed —
        // (∂f/∂x)v = A v + b_s (∇Δτ_s·v) + b_h (∇τ_h·v) and
        // ∂f/∂P_i = (∂A/∂P_i) x + (∂b_s/∂P_i) Δτ_s + b_s ∂Δτ_s/∂P_i + (likewise for the hub).
        let linear = Linear::of(&real);
        let derivatives: Vec<Linear> = seeded.iter().map(Linear::of_eps).collect();
        let nonlinear = !real.is_linear();
        let rhs = |x: &[f64], _p: &[f64], t: f64, y: &mut [f64]| {
            if evaluations.fetch_add(1, std::sync::atomic::Ordering::Relaxed) > RHS_BUDGET {
                y.iter_mut().for_each(|v| *v = REJECT);
            } else {
                linear.apply(x, y);
                if nonlinear {
                    let (servo, hub) = real.torques(t, x);
                    linear.add_torques(servo, hub, y);
                }
                sanitize(y);
            }
        };
        // The torques, their gradient in the few states they depend on, and their parameter
        // derivatives, at the last state asked for: diffsol asks for (∂f/∂x)v and ∂f/∂P_i of
        // every sensitivity at the same state, so each is computed once per state.
        let torque_states = real.torque_states();
        let acts: Vec<bool> =
            seeded.iter().map(|d| d.torque_constants().iter().any(|c| c.eps != 0.0)).collect();
        let cache = std::cell::RefCell::new(TorqueCache::new(n, j, torque_states.len()));
        let update = |cache: &mut TorqueCache, t: f64, x: &[f64]| {
            if cache.valid && cache.t == t && cache.x == x {
                return;
            }
            cache.x.copy_from_slice(x);
            cache.t = t;
            cache.valid = true;
            cache.value = real.torques(t, x);
            let mut xd: Vec<Dual64> = x.iter().map(|a| Dual64::from(*a)).collect();
            for (g, &k) in cache.gradient.iter_mut().zip(&torque_states) {
                xd[k].eps = 1.0;
                let (servo, hub) = lifted.torques(t, &xd);
                xd[k].eps = 0.0;
                *g = (k, servo.eps, hub.eps);
            }
            for (i, dynamics) in seeded.iter().enumerate() {
                cache.by_parameter[i] = if acts[i] {
                    let (servo, hub) = dynamics.torques(t, &xd);
                    (servo.eps, hub.eps)
                } else {
                    (0.0, 0.0)
                };
            }
        };
        let jac = |x: &[f64], _p: &[f64], t: f64, v: &[f64], y: &mut [f64]| {
            linear.apply(v, y);
            if nonlinear {
                let mut cache = cache.borrow_mut();
                update(&mut cache, t, x);
                let (servo, hub) = cache
                    .gradient
                    .iter()
                    .fold((0.0, 0.0), |(s, h), (k, gs, gh)| (s + gs * v[*k], h + gh * v[*k]));
                linear.add_torques(servo, hub, y);
            }
            sanitize(y);
        };
        let sens = |x: &[f64], _p: &[f64], t: f64, v: &[f64], y: &mut [f64]| {
            y.iter_mut().for_each(|yi| *yi = 0.0);
            let mut cache = cache.borrow_mut();
            if nonlinear {
                update(&mut cache, t, x);
            }
            let torques = cache.value;
            let mut term = std::mem::take(&mut cache.term);
            for (i, d) in derivatives.iter().enumerate() {
                if v[i] == 0.0 {
                    continue;
                }
                d.apply(x, &mut term);
                if nonlinear {
                    d.add_torques(torques.0, torques.1, &mut term);
                    let (servo, hub) = cache.by_parameter[i];
                    linear.add_torques(servo, hub, &mut term);
                }
                for (yi, ti) in y.iter_mut().zip(&term) {
                    *yi += v[i] * ti;
                }
            }
            cache.term = term;
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

/// The torques at one state, their state gradient and parameter derivatives.
struct TorqueCache {
    x: Vec<f64>,
    t: f64,
    valid: bool,
    value: (f64, f64),
    gradient: Vec<(usize, f64, f64)>,
    by_parameter: Vec<(f64, f64)>,
    term: Vec<f64>,
}

impl TorqueCache {
    fn new(n: usize, j: usize, states: usize) -> Self {
        Self {
            x: vec![0.0; n],
            t: 0.0,
            valid: false,
            value: (0.0, 0.0),
            gradient: vec![(0, 0.0, 0.0); states],
            by_parameter: vec![(0.0, 0.0); j],
            term: vec![0.0; n],
        }
    }
}

/// The linear part of the dynamics in plain numbers: A and the torque directions b_s, b_h
/// (or their derivatives, the ε parts of seeded dual dynamics).
struct Linear {
    a: Vec<f64>,
    servo: Vec<f64>,
    hub: Vec<f64>,
    n: usize,
}

impl Linear {
    fn of(d: &Dynamics<f64>) -> Self {
        let n = d.layout.n_states;
        Self {
            a: (0..n * n).map(|k| d.a[(k / n, k % n)]).collect(),
            servo: d.servo_input.iter().copied().collect(),
            hub: d.hub_input.iter().copied().collect(),
            n,
        }
    }
    fn of_eps(d: &Dynamics<Dual64>) -> Self {
        let n = d.layout.n_states;
        Self {
            a: (0..n * n).map(|k| d.a[(k / n, k % n)].eps).collect(),
            servo: d.servo_input.iter().map(|v| v.eps).collect(),
            hub: d.hub_input.iter().map(|v| v.eps).collect(),
            n,
        }
    }
    /// y = A x.
    fn apply(&self, x: &[f64], y: &mut [f64]) {
        for (i, yi) in y.iter_mut().enumerate().take(self.n) {
            let row = &self.a[i * self.n..(i + 1) * self.n];
            *yi = row.iter().zip(x).map(|(a, b)| a * b).sum();
        }
    }
    /// y += b_s servo + b_h hub.
    fn add_torques(&self, servo: f64, hub: f64, y: &mut [f64]) {
        for ((yi, s), h) in y.iter_mut().zip(&self.servo).zip(&self.hub) {
            *yi += s * servo + h * hub;
        }
    }
}

/// The dynamics in dual numbers with ε = 1 on parameter `id` only.
pub(crate) fn seed(model: &SlewingModel, id: ParamId) -> Result<Dynamics<Dual64>, PlantError> {
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
        free_decay(grid, |start, h| self.simulate(p, start, h, out))
    }
    fn accuracy(&self) -> f64 {
        // The solver controls the local error to rtol; the global error of the outputs and
        // sensitivities is a few times that.
        10.0 * self.rtol
    }
}

/// `model` with the parameters `free` set to `p`.
pub(crate) fn model_at(
    model: &SlewingModel,
    free: &[ParamId],
    p: &[f64],
) -> Result<SlewingModel, PlantError> {
    let mut m = model.clone();
    for (id, v) in free.iter().zip(p) {
        m.set(*id, *v)?;
    }
    Ok(m)
}

/// A free decay's response on `grid` (a slewing model takes no measured inputs).
pub(crate) fn free_decay(
    grid: &Grid<'_>,
    run: impl FnOnce(f64, f64) -> Result<(), NonlinearError>,
) -> Result<(), BoxedError> {
    if grid.inputs.is_some() {
        return Err(NonlinearError::Solver(
            "a slewing model with nonlinear effects cannot yet be driven by measured inputs (theta_ref); \
             drop the inputs or the nonlinear effects"
                .into(),
        )
        .into());
    }
    Ok(run(grid.start, grid.interval)?)
}
