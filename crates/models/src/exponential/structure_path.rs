//! A structure with forces at its coordinates (`structure::effects`) on the exponential
//! integrator: A, G, C, H, x(0) and their exact derivatives from the file's expressions over
//! num-dual, the forces' derivatives likewise.
//!
//! A structure driven by measured inputs u (a forced response) takes them as forces the state
//! does not move: G = [G_f  B], H = [H_f  D], and u(t) held between samples as the record says.
//! Held constant (zero-order hold), u is the same at both ends of every substep of an interval,
//! where the first-order-hold gains sum to the zero-order-hold ones (Γ_now + Γ_next = Γ), so the
//! linear part of a forced response is exact, as on the linear path; held linearly, the gains
//! integrate the ramp exactly too. Before the first sample u = 0, as on the linear path.

use super::DEFAULT_MAX_STEP;
use super::step::{Forces, Forcing, Linear, integrate};
use crate::ModelError;
use crate::ode::NonlinearError;
use expm::Response;
use faer::Mat;
use mem::nalgebra::DMatrix;
use mem::{BoxedError, Grid, Hold, ResponseModel};
use num_dual::Dual64;
use structure::{ForceLaw, StructureModel};

/// A structure model with force effects and `free` parameters, as a [`ResponseModel`].
#[derive(Clone, Debug)]
pub struct StructureExponential {
    model: StructureModel,
    /// Positions of the free parameters among all of the model's.
    free: Vec<usize>,
    max_step: f64,
}

fn mat<D: mem::Scalar>(m: &DMatrix<D>, part: impl Fn(&D) -> f64) -> Mat<f64> {
    Mat::from_fn(m.nrows(), m.ncols(), |r, c| part(&m[(r, c)]))
}

/// Measured inputs as the integrator reads them: u(t) in the sample interval it is in.
struct InputFeed<'a> {
    /// u_k, one row per sample of the model's grid.
    values: &'a Mat<f64>,
    hold: Hold,
    /// t₀ and the sample interval h.
    start: f64,
    interval: f64,
}

impl InputFeed<'_> {
    /// u(t) into `out` for `t` in the interval [t_k, t_{k+1}] (`k` = None before the first
    /// sample, where u = 0). At t_{k+1} itself a held input is still u_k: the left limit, which
    /// is what the step ending there integrates.
    fn fill(&self, k: Option<usize>, t: f64, out: &mut [f64]) {
        let Some(k) = k else {
            out.fill(0.0);
            return;
        };
        let last = self.values.nrows() - 1;
        let k = k.min(last);
        for (c, o) in out.iter_mut().enumerate() {
            let now = self.values[(k, c)];
            *o = match self.hold {
                Hold::Zero => now,
                Hold::FirstOrder => {
                    let next = self.values[((k + 1).min(last), c)];
                    let fraction = (t - (self.start + k as f64 * self.interval)) / self.interval;
                    now + fraction * (next - now)
                }
            };
        }
    }
}

/// The forces of a structure and their derivatives; measured inputs, if any, follow the forces.
struct StructureForces<'a> {
    laws: Vec<structure::ForceLaw>,
    inputs: Option<InputFeed<'a>>,
    /// The sample interval the integrator is in (None before the first sample).
    current: Option<usize>,
    p: &'a [f64],
    lifted: Vec<Dual64>,
    free: &'a [usize],
    /// Whether each free parameter is one of the forces' own (the others do not enter f).
    acts: Vec<bool>,
    states: Vec<usize>,
    scratch: Vec<Dual64>,
}

impl Forcing for StructureForces<'_> {
    fn interval(&mut self, k: Option<usize>) {
        self.current = k;
    }

    fn at(&mut self, t: f64, x: &[f64], with_derivatives: bool, out: &mut Forces) {
        let forces = self.laws.len();
        let m = forces + self.inputs.as_ref().map_or(0, |i| i.values.ncols());
        out.reset(m, self.free.len());
        for (v, law) in out.value.iter_mut().zip(&self.laws) {
            *v = law.force(t, x, self.p);
        }
        if let Some(inputs) = &self.inputs {
            inputs.fill(self.current, t, &mut out.value[forces..]);
        }
        if !with_derivatives {
            return;
        }
        for (d, v) in self.scratch.iter_mut().zip(x) {
            *d = Dual64::from(*v);
        }
        for &k in &self.states {
            self.scratch[k].eps = 1.0;
            out.states.push(k);
            for law in &self.laws {
                out.by_state.push(law.force(t, &self.scratch, &self.lifted).eps);
            }
            // The inputs do not depend on the state (nor on P: their entries stay zero).
            out.by_state.resize(out.by_state.len() + (m - forces), 0.0);
            self.scratch[k].eps = 0.0;
        }
        for (i, &slot) in self.free.iter().enumerate().filter(|(i, _)| self.acts[*i]) {
            self.lifted[slot].eps = 1.0;
            for (o, law) in out.by_parameter[i * m..(i + 1) * m].iter_mut().zip(&self.laws) {
                *o = law.force(t, &self.scratch, &self.lifted).eps;
            }
            self.lifted[slot].eps = 0.0;
        }
    }
}

impl StructureExponential {
    /// Frees the named parameters of `model` (a model with force effects).
    ///
    /// # Errors
    /// [`ModelError::UnknownParameter`] listing the valid names.
    pub fn new(model: StructureModel, free: &[&str]) -> Result<Self, ModelError> {
        let free = crate::structure::positions(&model, free)?;
        Ok(Self { model, free, max_step: DEFAULT_MAX_STEP })
    }

    /// The longest substep (finite and > 0).
    pub fn with_max_step(mut self, max_step: f64) -> Self {
        self.max_step = max_step;
        self
    }

    /// The linear parts at `p` (all parameters) in scalar D, as values via `part`.
    fn linear<D: mem::Scalar>(
        &self,
        p: &[D],
        part: impl Fn(&D) -> f64 + Copy,
    ) -> Result<Linear, NonlinearError> {
        let failed = |e: structure::StructureError| NonlinearError::Solver(e.to_string());
        let space = self.model.state_space(p).map_err(failed)?;
        let forces = self.model.force_parts(p).map_err(failed)?.ok_or_else(|| {
            NonlinearError::Solver("the structure has no force effect; use its linear path".into())
        })?;
        let (g, h) = (mat(&forces.g, part), mat(&forces.h, part));
        // Measured inputs enter as forces the state does not move: [G_f B], [H_f D].
        let (g, h) = match &space.b {
            Some(b) => {
                let b = mat(b, part);
                let d = space.d.as_ref().map_or_else(|| Mat::zeros(h.nrows(), b.ncols()), |d| mat(d, part));
                (faer::concat![[g, b]], faer::concat![[h, d]])
            }
            None => (g, h),
        };
        Ok(Linear {
            a: mat(&space.a, part),
            g,
            c: mat(&space.c, part),
            h: Some(h),
            x0: space.x0.iter().map(part).collect(),
        })
    }

    /// Simulates the free decay at P (the free parameters' values): fills `out` at
    /// t_k = start + k·h.
    ///
    /// # Errors
    /// Assembly failures, an invalid grid, or a response that does not stay finite.
    pub fn simulate(&self, p: &[f64], start: f64, h: f64, out: &mut Response) -> Result<(), NonlinearError> {
        self.simulate_driven(p, start, h, None, out)
    }

    /// As [`simulate`](Self::simulate), driven by measured inputs u_k (one row per sample of
    /// the grid, one column per input of the model, held as `hold` says; zero before t₀).
    ///
    /// # Errors
    /// As [`simulate`](Self::simulate); inputs that do not match the model's or the grid.
    pub fn simulate_driven(
        &self,
        p: &[f64],
        start: f64,
        h: f64,
        inputs: Option<(&Mat<f64>, Hold)>,
        out: &mut Response,
    ) -> Result<(), NonlinearError> {
        let wanted = self.model.input_names().len();
        match inputs {
            None if wanted > 0 => {
                return Err(NonlinearError::Solver(format!(
                    "the model is driven by {}; give the record's inputs",
                    self.model.input_names().join(", ")
                )));
            }
            Some((u, _)) if u.ncols() != wanted || u.nrows() != out.outputs.nrows() => {
                return Err(NonlinearError::Solver(format!(
                    "{} × {} inputs for a model of {wanted} inputs on {} samples",
                    u.nrows(),
                    u.ncols(),
                    out.outputs.nrows()
                )));
            }
            _ => {}
        }
        let mut all = self.model.values();
        for (slot, value) in self.free.iter().zip(p) {
            all[*slot] = *value;
        }
        let mut lin = self.linear(&all, |v: &f64| *v)?;
        let mut d = Vec::with_capacity(self.free.len());
        let mut lifted: Vec<Dual64> = all.iter().map(|v| Dual64::from(*v)).collect();
        for &slot in &self.free {
            lifted[slot].eps = 1.0;
            d.push(self.linear(&lifted, |v: &Dual64| v.eps)?);
            lifted[slot].eps = 0.0;
        }
        // H holds the acceleration outputs' share of the forces: without such an output it is
        // zero, with its derivatives, and the outputs skip it.
        let zero = |h: &Option<Mat<f64>>| h.as_ref().is_none_or(|h| h.norm_max() == 0.0);
        if zero(&lin.h) && d.iter().all(|di| zero(&di.h)) {
            lin.h = None;
            d.iter_mut().for_each(|di| di.h = None);
        }
        let laws = self.model.force_laws();
        let step =
            self.max_step.min(friction_step(&self.model, &laws, &all)).max(self.max_step / MAX_SUBSTEP_SHARE);
        let mut states: Vec<usize> = laws.iter().flat_map(|l| l.states()).collect();
        states.sort_unstable();
        states.dedup();
        let n = lin.a.nrows();
        let mut forces = StructureForces {
            inputs: inputs.map(|(values, hold)| InputFeed { values, hold, start, interval: h }),
            current: None,
            acts: self.free.iter().map(|&slot| laws.iter().any(|l| l.uses(slot))).collect(),
            laws,
            p: &all,
            lifted,
            free: &self.free,
            states,
            scratch: vec![Dual64::from(0.0); n],
        };
        integrate(&lin, &d, &mut forces, start, h, step, out)
    }
}

/// How far a dry friction's substep may cut the integrator's longest: at most this many times.
const MAX_SUBSTEP_SHARE: f64 = 16.0;

/// A dry friction's substep as a share of v_s m / F ([`friction_step`]).
const FRICTION_STEP: f64 = 0.25;

/// The longest substep at which every dry friction among `laws` (the force laws of `model`) at
/// the parameter values `all` is integrated accurately: h ≤ [`FRICTION_STEP`] · v_s m_jj / F, F the friction's force at rest
/// (F_c plus its static peak), v_s its smoothing velocity and m_jj the mass at its coordinate;
/// ∞ without one.
///
/// Below v_s a friction F·v/√(v² + v_s²) acts as a damper F/v_s, and the integrator takes the
/// forces explicitly over each substep (ETD2RK's predictor and corrector; the linear part is
/// exact), stable for h·F/(v_s m) up to about 2 as forward Euler is for a damper. A strong
/// friction smoothed over a small velocity broke that bound at the default substep: on draw
/// 20261355's `A_friction_strong_s1` (4,500 N at q2, a chirp, the catalog's v_s 0.9 mm/s from a
/// reference that took the friction up as damping) the refit stopped at 3,000 N with a Jacobian
/// of rank 1 (column-scaled singular values 2.4 and then 3·10⁻⁸), where at v_s 3 mm/s it came to
/// 4,616 N at full rank. The substep follows the friction's force as the fit moves it. At
/// v_s m / F itself (half the stability bound) the acceleration of the friction's own floor
/// (which holds the force) still chattered while the floor stuck, 47 % of its peak off a fine
/// solution; at a quarter of it, 1.5 %, the other floors within 1.4·10⁻⁴ (test
/// `a_strong_sharp_friction_is_integrated_at_a_substep_it_holds`). The diagnosis's estimate of
/// that friction was the same at both (4,462 N), its time 10 s against 22 s.
fn friction_step(model: &StructureModel, laws: &[ForceLaw], all: &[f64]) -> f64 {
    let frictions: Vec<(usize, f64, f64)> = laws.iter().filter_map(|l| l.friction_at_rest(all)).collect();
    if frictions.is_empty() {
        return f64::INFINITY;
    }
    let Ok(Some(matrices)) = model.second_order::<f64>(all) else { return f64::INFINITY };
    frictions
        .into_iter()
        .filter_map(|(j, at_rest, vs)| {
            let m = matrices.m[(j, j)];
            (at_rest > 0.0 && m > 0.0 && vs > 0.0).then(|| FRICTION_STEP * vs * m / at_rest)
        })
        .fold(f64::INFINITY, f64::min)
}

impl ResponseModel for StructureExponential {
    fn n_params(&self) -> usize {
        self.free.len()
    }
    fn output_names(&self) -> Vec<String> {
        self.model.output_names()
    }
    fn input_names(&self) -> Vec<String> {
        self.model.input_names()
    }
    fn respond(&self, p: &[f64], grid: &Grid<'_>, out: &mut Response) -> Result<(), BoxedError> {
        let inputs = grid.inputs.map(|i| (i.values(), i.hold()));
        Ok(self.simulate_driven(p, grid.start, grid.interval, inputs, out)?)
    }
    fn respond_outputs(&self, p: &[f64], grid: &Grid<'_>, out: &mut Response) -> Result<(), BoxedError> {
        // As the slewing path: x alone, through the same Φ and force gains.
        self.respond(p, grid, out)
    }
    fn accuracy(&self) -> f64 {
        // As the slewing path: the exact sensitivities of a recursion smooth in P to rounding.
        1e-12
    }
}
