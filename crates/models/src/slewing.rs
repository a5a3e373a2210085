//! The slewing plant as a `mem` model (exact path).
//!
//! `mem` knows nothing of the slewing experiment and `plant` nothing of identification; this
//! module joins them. [`SlewingFitModel`] exposes a chosen set of the plant's named
//! parameters as the MEM parameter vector P: A(P), ∂A/∂P (through the beam modes, by num-dual),
//! C(P) and ∂C/∂P (the strain gauge reads the mode curvatures), x(0) (the file's initial angle,
//! independent of P as in the paper's Eq. 10).

use mem::{LinearModel, LinearResponse, Linearized, Parameter};
use plant::{ParamId, PlantError, SlewingModel};

/// The slewing plant with `free` parameters tuned by the MEM.
#[derive(Clone, Debug)]
pub struct SlewingFitModel {
    model: SlewingModel,
    free: Vec<ParamId>,
}

impl SlewingFitModel {
    /// Frees `free` (names as in the model file, e.g. `cv`, `kp`).
    ///
    /// # Errors
    /// [`PlantError::UnknownParameter`] listing the valid names.
    pub fn new(model: SlewingModel, free: &[&str]) -> Result<Self, PlantError> {
        let free = free.iter().map(|n| model.parameter(n)).collect::<Result<Vec<_>, _>>()?;
        Ok(Self { model, free })
    }

    /// The free parameters.
    pub fn free(&self) -> &[ParamId] {
        &self.free
    }

    /// Their names.
    pub fn names(&self) -> Vec<String> {
        self.free.iter().map(|id| id.name()).collect()
    }

    /// Their current values (the start of a fit).
    pub fn values(&self) -> Vec<f64> {
        self.free.iter().map(|id| self.model.get(*id)).collect()
    }

    /// Bounds from the model file, or (0⁺, ∞), [0, ∞) or (−∞, ∞) by the parameter's sign rule;
    /// a lower bound below the smallest value the parameter may take ([`plant::ParamId::lowest`],
    /// e.g. [`plant::MIN_DELAY`] for a delay) is raised to it, so no step leaves the model's
    /// domain.
    pub fn bounds(&self) -> Vec<(f64, f64)> {
        self.free
            .iter()
            .map(|id| {
                let (lo, hi) = self.model.bounds(*id).unwrap_or((f64::NEG_INFINITY, f64::INFINITY));
                (lo.max(id.lowest()), hi)
            })
            .collect()
    }

    /// The free parameters as `mem` parameters: names, current values, bounds.
    pub fn parameters(&self) -> Vec<Parameter> {
        self.names()
            .into_iter()
            .zip(self.values())
            .zip(self.bounds())
            .map(|((name, value), (lo, hi))| Parameter::new(name, value).with_bounds(lo, hi))
            .collect()
    }

    /// The underlying model with P written in.
    ///
    /// # Errors
    /// [`PlantError::InvalidValue`] if a value is physically impossible.
    pub fn model_at(&self, p: &[f64]) -> Result<SlewingModel, PlantError> {
        let mut m = self.model.clone();
        for (id, v) in self.free.iter().zip(p) {
            m.set(*id, *v)?;
        }
        Ok(m)
    }

    /// The model at its current values.
    pub fn model(&self) -> &SlewingModel {
        &self.model
    }

    /// As a [`mem::ResponseModel`].
    pub fn response(self) -> LinearResponse<Self> {
        LinearResponse(self)
    }
}

impl LinearModel for SlewingFitModel {
    type Error = PlantError;
    fn n_states(&self) -> usize {
        self.model.n_states()
    }
    fn n_params(&self) -> usize {
        self.free.len()
    }
    fn output_names(&self) -> Vec<String> {
        self.model.output_names().iter().map(|s| s.to_string()).collect()
    }
    fn input_names(&self) -> Vec<String> {
        self.model.input_names().iter().map(|s| s.to_string()).collect()
    }
    fn linearize(&self, p: &[f64]) -> Result<Linearized, PlantError> {
        let m = self.model_at(p)?;
        let lin = m.linearization(&self.free)?;
        let needs_dc = lin.dc.iter().any(|d| d.norm_max() > 0.0);
        let mut out = Linearized::new(lin.a, lin.da, lin.c, m.initial_state());
        out.dc = needs_dc.then_some(lin.dc);
        if let Some((b, db)) = lin.b {
            out.b = Some(b);
            out.db = Some(db);
        }
        Ok(out)
    }
}
