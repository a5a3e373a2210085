//! A structure with forces at its coordinates (`structure::effects`) on the exponential
//! integrator: A, G, C, H, x(0) and their exact derivatives from the file's expressions over
//! num-dual, the forces' derivatives likewise.

use super::DEFAULT_MAX_STEP;
use super::step::{Forces, Forcing, Linear, integrate};
use crate::ModelError;
use crate::ode::NonlinearError;
use expm::Response;
use faer::Mat;
use mem::nalgebra::DMatrix;
use mem::{BoxedError, Grid, ResponseModel};
use num_dual::Dual64;
use structure::StructureModel;

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

/// The forces of a structure and their derivatives.
struct StructureForces<'a> {
    laws: Vec<structure::ForceLaw>,
    p: &'a [f64],
    lifted: Vec<Dual64>,
    free: &'a [usize],
    /// Whether each free parameter is one of the forces' own (the others do not enter f).
    acts: Vec<bool>,
    states: Vec<usize>,
    scratch: Vec<Dual64>,
}

impl Forcing for StructureForces<'_> {
    fn at(&mut self, t: f64, x: &[f64], with_derivatives: bool, out: &mut Forces) {
        let m = self.laws.len();
        out.reset(m, self.free.len());
        for (v, law) in out.value.iter_mut().zip(&self.laws) {
            *v = law.force(t, x, self.p);
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
        Ok(Linear {
            a: mat(&space.a, part),
            g: mat(&forces.g, part),
            c: mat(&space.c, part),
            h: Some(mat(&forces.h, part)),
            x0: space.x0.iter().map(part).collect(),
        })
    }

    /// Simulates at P (the free parameters' values): fills `out` at t_k = start + k·h.
    ///
    /// # Errors
    /// Assembly failures, an invalid grid, or a response that does not stay finite.
    pub fn simulate(&self, p: &[f64], start: f64, h: f64, out: &mut Response) -> Result<(), NonlinearError> {
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
        let mut states: Vec<usize> = laws.iter().flat_map(|l| l.states()).collect();
        states.sort_unstable();
        states.dedup();
        let n = lin.a.nrows();
        let mut forces = StructureForces {
            acts: self.free.iter().map(|&slot| laws.iter().any(|l| l.uses(slot))).collect(),
            laws,
            p: &all,
            lifted,
            free: &self.free,
            states,
            scratch: vec![Dual64::from(0.0); n],
        };
        integrate(&lin, &d, &mut forces, start, h, self.max_step, out)
    }
}

impl ResponseModel for StructureExponential {
    fn n_params(&self) -> usize {
        self.free.len()
    }
    fn output_names(&self) -> Vec<String> {
        self.model.output_names()
    }
    fn respond(&self, p: &[f64], grid: &Grid<'_>, out: &mut Response) -> Result<(), BoxedError> {
        if grid.inputs.is_some() {
            return Err(NonlinearError::Solver(
                "a structure with forces at its coordinates is simulated in free decay only; drop the inputs \
                 or the force effects"
                    .into(),
            )
            .into());
        }
        Ok(self.simulate(p, grid.start, grid.interval, out)?)
    }
    fn respond_outputs(&self, p: &[f64], grid: &Grid<'_>, out: &mut Response) -> Result<(), BoxedError> {
        // As the slewing path: x alone, through the same Φ and force gains.
        self.respond(p, grid, out)
    }
    fn accuracy(&self) -> f64 {
        // As the slewing path: exact sensitivities of the simulated recursion, O(h²) from the
        // true flow in the nonlinear forcing.
        1e-9
    }
}
