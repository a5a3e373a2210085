//! A model as `mem` sees it: its free parameters, its response with sensitivities (the exact
//! exponential path for a linear model, the ODE path otherwise, with the sensors' offsets,
//! scales and drifts applied), and its simulated record.

use super::{Integrator, Model};
use crate::ModelError;
use crate::exponential::{ExponentialResponse, StructureExponential};
use crate::ode::NonlinearResponse;
use crate::sensors::{SensorEffect, SensorTerm, TimeConstant, WithSensors};
use crate::slewing::SlewingFitModel;
use crate::structure::StructureFitModel;
use mem::{Parameter, ResponseModel};

impl Model {
    /// The free parameters as `mem` parameters (names, current values, bounds, typical sizes).
    ///
    /// # Errors
    /// Unknown names.
    pub fn parameters(&self, free: &[&str]) -> Result<Vec<Parameter>, ModelError> {
        Ok(match self {
            Model::Slewing(m) => SlewingFitModel::new(m.clone(), free)?.parameters(),
            Model::Structure(m) => StructureFitModel::new(m.clone(), free)?.parameters(),
        })
    }

    /// The model with the free parameters set to `values`.
    ///
    /// # Errors
    /// Unknown names or impossible values.
    pub fn with_values(&self, free: &[&str], values: &[f64]) -> Result<Model, ModelError> {
        let mut model = self.clone();
        for (name, value) in free.iter().zip(values) {
            model.set(name, *value)?;
        }
        Ok(model)
    }

    /// The response model with `free` parameters: the exact exponential path for a linear
    /// model, the ODE path otherwise.
    ///
    /// # Errors
    /// Unknown parameter names.
    pub fn response(&self, free: &[&str]) -> Result<Box<dyn ResponseModel + Send + Sync>, ModelError> {
        self.response_with(free, Integrator::default())
    }

    /// As [`Model::response`], with the integrator of a nonlinear model (the exponential path
    /// of a linear one is exact and ignores it).
    ///
    /// # Errors
    /// Unknown parameter names.
    pub fn response_with(
        &self,
        free: &[&str],
        integrator: Integrator,
    ) -> Result<Box<dyn ResponseModel + Send + Sync>, ModelError> {
        // The sensor effects' parameters are the adapter's; the rest are the dynamics'.
        let sensor_effects = self.sensor_effects();
        let is_sensor = |name: &str| {
            sensor_effects
                .iter()
                .any(|(n, e)| n == name || e.time_constant.as_ref().is_some_and(|c| c.name == name))
        };
        let physics: Vec<&str> = free.iter().copied().filter(|n| !is_sensor(n)).collect();
        let inner: Box<dyn ResponseModel + Send + Sync> = match self {
            Model::Slewing(m)
                if m.is_linear_for(
                    &physics.iter().filter_map(|n| m.parameter(n).ok()).collect::<Vec<_>>(),
                ) =>
            {
                Box::new(SlewingFitModel::new(m.clone(), &physics)?.response())
            }
            Model::Slewing(m) => match integrator {
                Integrator::Adaptive { rtol } => {
                    Box::new(NonlinearResponse::new(m.clone(), &physics)?.with_tolerances(rtol, 1e-2 * rtol))
                }
                Integrator::Exponential { max_step } => {
                    Box::new(ExponentialResponse::new(m.clone(), &physics)?.with_max_step(max_step))
                }
            },
            Model::Structure(m) if m.is_linear_for(&physics) => {
                Box::new(StructureFitModel::new(m.clone(), &physics)?.response())
            }
            Model::Structure(m) => {
                let max_step = match integrator {
                    Integrator::Exponential { max_step } => max_step,
                    Integrator::Adaptive { .. } => crate::exponential::DEFAULT_MAX_STEP,
                };
                Box::new(StructureExponential::new(m.clone(), &physics)?.with_max_step(max_step))
            }
        };
        if sensor_effects.is_empty() {
            return Ok(inner);
        }
        // Positions in the caller's order: the sensor parameters may come anywhere in `free`.
        let positions = free.iter().enumerate().filter(|(_, n)| !is_sensor(n)).map(|(i, _)| i).collect();
        let effects = sensor_effects
            .into_iter()
            .map(|(name, mut e)| {
                e.free = free.iter().position(|n| *n == name);
                if let Some(c) = e.time_constant.as_mut() {
                    c.free = free.iter().position(|n| *n == c.name);
                }
                e
            })
            .collect();
        Ok(Box::new(WithSensors::new(inner, effects, positions)))
    }

    /// The sensor effects (offset, scale, drift) with their parameter names.
    fn sensor_effects(&self) -> Vec<(String, SensorEffect)> {
        match self {
            Model::Slewing(m) => m
                .sensor_effects()
                .into_iter()
                .filter_map(|(output, e)| {
                    let name = plant::ParamId::of_effect(&e).first().map(|id| id.name())?;
                    let term = match &e {
                        plant::Effect::SensorCrosstalk { from, .. } => {
                            SensorTerm::Crosstalk { from: m.sensors().iter().position(|s| s == from)? }
                        }
                        other => SensorTerm::of(other.kind())?,
                    };
                    let (value, time_constant) = match e {
                        plant::Effect::OutputOffset { offset, .. } => (offset, None),
                        plant::Effect::SensorScale { scale, .. } => (scale, None),
                        plant::Effect::SensorCrosstalk { gain, .. } => (gain, None),
                        plant::Effect::SensorDrift { sensor, rate, time_constant } => (
                            rate,
                            time_constant.map(|value| TimeConstant {
                                name: plant::ParamId::DriftTime(sensor).name(),
                                value,
                                free: None,
                            }),
                        ),
                        _ => return None,
                    };
                    Some((name, SensorEffect { output, term, value, free: None, time_constant }))
                })
                .collect(),
            Model::Structure(m) => {
                let outputs = m.output_names();
                m.effects()
                    .iter()
                    .filter_map(|e| {
                        let (output, term, value, tau) = match e {
                            structure::Effect::OutputOffset { output, offset } => {
                                (output, SensorTerm::Offset, *offset, None)
                            }
                            structure::Effect::SensorScale { output, scale } => {
                                (output, SensorTerm::Scale, *scale, None)
                            }
                            structure::Effect::SensorDrift { output, rate, time_constant } => {
                                (output, SensorTerm::Drift, *rate, *time_constant)
                            }
                            structure::Effect::SensorCrosstalk { output, from, gain } => {
                                let from = outputs.iter().position(|o| o == from)?;
                                (output, SensorTerm::Crosstalk { from }, *gain, None)
                            }
                            _ => return None,
                        };
                        let parameters = e.parameters(&outputs);
                        let name = parameters.first()?.0.clone();
                        let time_constant = tau.and_then(|value| {
                            Some(TimeConstant { name: parameters.get(1)?.0.clone(), value, free: None })
                        });
                        let output = outputs.iter().position(|o| o == output)?;
                        Some((name, SensorEffect { output, term, value, free: None, time_constant }))
                    })
                    .collect()
            }
        }
    }

    /// The model's response on `n_samples` samples of `grid` (driven by the grid's inputs), as the
    /// sensors read it (quantized where they are quantized).
    ///
    /// # Errors
    /// Model or solver failures; [`ModelError::NonFinite`] if the response overflows.
    pub fn simulate(&self, grid: &mem::Grid<'_>, n_samples: usize) -> Result<faer::Mat<f64>, ModelError> {
        let response = self.response(&[])?;
        let mut out = mem::Response::zeros(n_samples, self.output_names().len(), 0);
        response.respond(&[], grid, &mut out).map_err(|source| {
            ModelError::Mem(mem::MemError::Model {
                experiment: 0,
                parameters: "the file's values".into(),
                source,
            })
        })?;
        let mut y = out.outputs;
        for (o, step) in self.quantization().into_iter().enumerate() {
            if let Some(step) = step {
                for k in 0..y.nrows() {
                    y[(k, o)] = step * (y[(k, o)] / step).round();
                }
            }
        }
        if !y.as_ref().is_all_finite() {
            return Err(ModelError::NonFinite { what: "the simulated response".into() });
        }
        Ok(y)
    }
}
