//! A structure model file's free parameters as a `mem` model: the file's expressions evaluated
//! over num-dual give A(P), B(P), C(P), D(P), x(0)(P) and their exact derivatives
//! (`mem::Exact`), the exponential path does the rest.

use crate::ModelError;
use mem::{BoxedError, Exact, LinearResponse, Parameter, Scalar, StateSpace, StateSpaceModel};
use structure::StructureModel;

/// A structure with `free` parameters tuned by the MEM (the others fixed at the file's values).
#[derive(Clone, Debug)]
pub struct StructureFitModel {
    model: StructureModel,
    /// Positions of the free parameters among all of the file's parameters.
    free: Vec<usize>,
    names: Vec<String>,
    values: Vec<f64>,
}

/// The positions of the named parameters among all of `model`'s.
///
/// # Errors
/// [`ModelError::UnknownParameter`] listing the valid names.
pub(crate) fn positions(model: &StructureModel, free: &[&str]) -> Result<Vec<usize>, ModelError> {
    let names = model.parameter_names();
    free.iter()
        .map(|n| {
            names
                .iter()
                .position(|m| m == n)
                .ok_or_else(|| ModelError::UnknownParameter { name: n.to_string(), valid: names.join(", ") })
        })
        .collect()
}

impl StructureFitModel {
    /// Frees the named parameters.
    ///
    /// # Errors
    /// [`ModelError::UnknownParameter`] listing the valid names.
    pub fn new(model: StructureModel, free: &[&str]) -> Result<Self, ModelError> {
        let names = model.parameter_names();
        let free = positions(&model, free)?;
        let values = model.values();
        Ok(Self { model, free, names, values })
    }

    /// The free parameters as `mem` parameters: names, values, bounds and typical sizes.
    pub fn parameters(&self) -> Vec<Parameter> {
        self.free
            .iter()
            .map(|&i| {
                let name = &self.names[i];
                let mut p = Parameter::new(name.clone(), self.values[i]);
                if let Some((lo, hi)) = self.model.bounds(name) {
                    p = p.with_bounds(lo, hi);
                }
                if let Some(t) = self.model.typical(name) {
                    p = p.with_typical(t);
                }
                p
            })
            .collect()
    }

    /// As a [`mem::ResponseModel`] (exact derivatives by num-dual).
    pub fn response(self) -> LinearResponse<Exact<Self>> {
        LinearResponse(Exact(self))
    }
}

impl StateSpaceModel for StructureFitModel {
    fn parameter_names(&self) -> Vec<String> {
        self.free.iter().map(|&i| self.names[i].clone()).collect()
    }
    fn output_names(&self) -> Vec<String> {
        self.model.output_names()
    }
    fn input_names(&self) -> Vec<String> {
        self.model.input_names()
    }
    fn state_space<D: Scalar>(&self, p: &[D]) -> Result<StateSpace<D>, BoxedError> {
        let mut all: Vec<D> = self.values.iter().map(|v| D::from(*v)).collect();
        for (slot, value) in self.free.iter().zip(p) {
            all[*slot] = *value;
        }
        Ok(self.model.linear_state_space(&all)?)
    }
}
