//! The model kinds a model file may describe, behind one type: the slewing rig (`plant`) and any
//! linear structure (`structure`). The file's content chooses the kind (a top-level `structure`
//! field), in one place: [`Model::from_ron`].

use crate::ModelError;
use crate::exponential::{ExponentialResponse, StructureExponential};
use crate::ode::NonlinearResponse;
use crate::sensors::{SensorEffect, SensorTerm, WithSensors};
use crate::slewing::SlewingFitModel;
use crate::structure::StructureFitModel;
use mem::{Hold, Parameter, ResponseModel};
use plant::SlewingModel;
use serde::Serialize;
use structure::StructureModel;

/// A model read from a model file.
#[derive(Clone, Debug)]
#[allow(clippy::large_enum_variant)] // one model per command; boxing would only add indirection
pub enum Model {
    /// The closed-loop slewing beam of Garcia & Inman.
    Slewing(SlewingModel),
    /// Any linear structure (second- or first-order form, expressions of named parameters).
    Structure(StructureModel),
}

/// An effect added to a model, of the model's own kind (`plant::Effect` for the slewing rig,
/// `structure::Effect` for a structure).
#[derive(Clone, Debug, PartialEq)]
pub enum ModelEffect {
    /// An effect of the slewing rig.
    Slewing(plant::Effect),
    /// An effect on a structure.
    Structure(structure::Effect),
}

impl From<plant::Effect> for ModelEffect {
    fn from(effect: plant::Effect) -> Self {
        ModelEffect::Slewing(effect)
    }
}

impl From<structure::Effect> for ModelEffect {
    fn from(effect: structure::Effect) -> Self {
        ModelEffect::Structure(effect)
    }
}

impl From<SlewingModel> for Model {
    fn from(model: SlewingModel) -> Self {
        Model::Slewing(model)
    }
}

impl From<StructureModel> for Model {
    fn from(model: StructureModel) -> Self {
        Model::Structure(model)
    }
}

/// How a nonlinear slewing model is integrated.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Integrator {
    /// diffsol's adaptive Tsitouras 5(4) with forward sensitivities, to this relative tolerance
    /// (`crate::ode`).
    Adaptive {
        /// Relative tolerance of the states (absolute: 1 % of it).
        rtol: f64,
    },
    /// The exponential integrator (`crate::exponential`) with this longest substep \[s\].
    Exponential {
        /// Longest substep.
        max_step: f64,
    },
}

impl Default for Integrator {
    /// The adaptive solver at its default tolerance.
    fn default() -> Self {
        Integrator::Adaptive { rtol: crate::ode::DEFAULT_RTOL }
    }
}

/// Which kind of model a file describes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ModelKind {
    /// The slewing rig.
    Slewing,
    /// A structure.
    Structure,
}

/// One mode of a model (for `memid modal`).
#[derive(Clone, Debug, Serialize)]
pub struct ModeRow {
    /// `servo`, `flexible_<i>` for the slewing rig; `mode_<i>` for a structure.
    pub kind: String,
    /// Undamped natural frequency |s|/2π \[Hz\].
    pub frequency_hz: f64,
    /// Damping ratio −Re(s)/|s|.
    pub damping_ratio: f64,
    /// The eigenvalue s (upper half plane).
    pub eigenvalue: (f64, f64),
    /// The mode shape over the coordinates (structures in second-order form), largest entry 1.
    pub shape: Option<Vec<f64>>,
}

impl Model {
    /// Parses a model file of either kind; `origin` names it in errors.
    ///
    /// # Errors
    /// The kind's located parse and validation errors.
    pub fn from_ron(text: &str, origin: &str) -> Result<Self, ModelError> {
        if structure::is_structure_file(text) {
            Ok(Model::Structure(StructureModel::from_ron(text, origin)?))
        } else {
            Ok(Model::Slewing(SlewingModel::from_ron(text, origin)?))
        }
    }

    /// Reads and parses a model file.
    ///
    /// # Errors
    /// [`ModelError::Io`] naming the path, else as [`Model::from_ron`].
    pub fn load(path: &std::path::Path) -> Result<Self, ModelError> {
        let text = std::fs::read_to_string(path)
            .map_err(|source| ModelError::Io { path: path.display().to_string(), source })?;
        Self::from_ron(&text, &path.display().to_string())
    }

    /// The kind.
    pub fn kind(&self) -> ModelKind {
        match self {
            Model::Slewing(_) => ModelKind::Slewing,
            Model::Structure(_) => ModelKind::Structure,
        }
    }

    /// The model's name.
    pub fn name(&self) -> String {
        match self {
            Model::Slewing(m) => m.file().name,
            Model::Structure(m) => m.name().to_string(),
        }
    }

    /// Output names (the CSV columns), in order.
    pub fn output_names(&self) -> Vec<String> {
        match self {
            Model::Slewing(m) => m.output_names().iter().map(|s| s.to_string()).collect(),
            Model::Structure(m) => m.output_names(),
        }
    }

    /// Input names (the CSV columns that drive the model).
    pub fn input_names(&self) -> Vec<String> {
        match self {
            Model::Slewing(m) => m.input_names().iter().map(|s| s.to_string()).collect(),
            Model::Structure(m) => m.input_names(),
        }
    }

    /// How the inputs are held between samples.
    pub fn hold(&self) -> Hold {
        match self {
            Model::Slewing(_) => Hold::Zero,
            Model::Structure(m) => m.hold(),
        }
    }

    /// The parameters the model file marks as free.
    pub fn file_free(&self) -> Vec<String> {
        match self {
            Model::Slewing(m) => m.file().free,
            Model::Structure(m) => m.free(),
        }
    }

    /// Every parameter name that `set` accepts.
    pub fn parameter_names(&self) -> Vec<String> {
        match self {
            Model::Slewing(m) => m.parameter_ids().iter().map(|id| id.name()).collect(),
            Model::Structure(m) => m.parameter_names(),
        }
    }

    /// A parameter's value.
    ///
    /// # Errors
    /// An unknown name, listing the valid ones.
    pub fn value(&self, name: &str) -> Result<f64, ModelError> {
        Ok(match self {
            Model::Slewing(m) => m.get(m.parameter(name)?),
            Model::Structure(m) => m.value(name)?,
        })
    }

    /// Sets a parameter.
    ///
    /// # Errors
    /// An unknown name (listing the valid ones) or an impossible value.
    pub fn set(&mut self, name: &str, value: f64) -> Result<(), ModelError> {
        match self {
            Model::Slewing(m) => {
                let id = m.parameter(name)?;
                m.set(id, value)?;
            }
            Model::Structure(m) => m.set(name, value)?,
        }
        Ok(())
    }

    /// Adds an effect of the model's kind.
    ///
    /// # Errors
    /// An effect of the other kind ([`ModelError::WrongKind`]), or the kind's own refusal
    /// (an unknown place, a duplicate, an impossible value).
    pub fn add_effect(&mut self, effect: ModelEffect) -> Result<(), ModelError> {
        match (self, effect) {
            (Model::Slewing(m), ModelEffect::Slewing(e)) => m.add_effect(e)?,
            (Model::Structure(m), ModelEffect::Structure(e)) => m.add_effect(e)?,
            (model, effect) => {
                return Err(ModelError::WrongKind { effect: format!("{effect:?}"), model: model.kind() });
            }
        }
        Ok(())
    }

    /// Sets the (lower, upper) bounds a fit keeps a parameter within (for a structure, an
    /// effect's parameter; a file's parameter keeps the file's bounds).
    ///
    /// # Errors
    /// An unknown name.
    pub fn set_bounds(&mut self, name: &str, bounds: (f64, f64)) -> Result<(), ModelError> {
        match self {
            Model::Slewing(m) => {
                let id = m.parameter(name)?;
                m.set_bounds(id, bounds);
            }
            Model::Structure(m) => m.set_bounds(name, bounds)?,
        }
        Ok(())
    }

    /// The slewing model, mutably, if this is one.
    pub fn as_slewing_mut(&mut self) -> Option<&mut SlewingModel> {
        match self {
            Model::Slewing(m) => Some(m),
            Model::Structure(_) => None,
        }
    }

    /// The structure model, if this is one.
    pub fn as_structure(&self) -> Option<&StructureModel> {
        match self {
            Model::Slewing(_) => None,
            Model::Structure(m) => Some(m),
        }
    }

    /// The coordinates a mode shape is given over (structures), or the slewing rig's θ, q_i.
    pub fn coordinates(&self) -> Vec<String> {
        match self {
            Model::Slewing(m) => std::iter::once("theta".to_string())
                .chain((1..=m.n_modes()).map(|i| format!("q{i}")))
                .collect(),
            Model::Structure(m) => m.coordinates(),
        }
    }

    /// The model file with the current values written in.
    pub fn to_ron(&self) -> String {
        match self {
            Model::Slewing(m) => m.to_ron(),
            Model::Structure(m) => m.to_ron(),
        }
    }

    /// The sensors' quantization steps per output (measurement-only effects).
    pub fn quantization(&self) -> Vec<Option<f64>> {
        match self {
            Model::Slewing(m) => m.quantization(),
            Model::Structure(m) => m.quantization(),
        }
    }

    /// Whether the exact exponential path applies (no nonlinear effect).
    pub fn is_linear(&self) -> bool {
        match self {
            Model::Slewing(m) => m.is_linear(),
            Model::Structure(m) => m.is_linear(),
        }
    }

    /// The closed-loop modes (slewing: servo and flexible modes, Table 2's columns) or the
    /// structure's modes with their shapes.
    ///
    /// # Errors
    /// Assembly failures; [`ModelError::NonFinite`] if a mode is not finite.
    pub fn modes(&self) -> Result<Vec<ModeRow>, ModelError> {
        let rows: Vec<ModeRow> = match self {
            Model::Slewing(m) => m
                .modal()?
                .into_iter()
                .map(|r| ModeRow {
                    kind: match r.kind {
                        plant::ModeKind::Servo => "servo".into(),
                        plant::ModeKind::Flexible(i) => format!("flexible_{i}"),
                    },
                    frequency_hz: r.frequency_hz,
                    damping_ratio: r.damping_ratio,
                    eigenvalue: r.eigenvalue,
                    shape: None,
                })
                .collect(),
            Model::Structure(m) => m
                .modes()?
                .into_iter()
                .enumerate()
                .map(|(i, r)| ModeRow {
                    kind: format!("mode_{}", i + 1),
                    frequency_hz: r.frequency_hz,
                    damping_ratio: r.damping_ratio,
                    eigenvalue: r.eigenvalue,
                    shape: r.shape,
                })
                .collect(),
        };
        if let Some(r) = rows.iter().find(|r| !(r.frequency_hz.is_finite() && r.damping_ratio.is_finite())) {
            return Err(ModelError::NonFinite {
                what: format!("the {} mode ({} Hz)", r.kind, r.frequency_hz),
            });
        }
        Ok(rows)
    }

    /// The assembled matrices as JSON (`memid model`).
    ///
    /// # Errors
    /// Assembly failures; [`ModelError::NonFinite`] for a non-finite entry.
    pub fn matrices_json(&self) -> Result<serde_json::Value, ModelError> {
        let value = match self {
            Model::Slewing(m) => m.matrices_json()?,
            Model::Structure(m) => {
                let ss = m.state_space::<f64>(&m.values())?;
                let rows = |x: &mem::nalgebra::DMatrix<f64>| -> Vec<Vec<f64>> {
                    (0..x.nrows()).map(|i| (0..x.ncols()).map(|j| x[(i, j)]).collect()).collect()
                };
                let mut doc = serde_json::json!({
                    "name": m.name(),
                    "kind": "structure",
                    "coordinates": m.coordinates(),
                    "outputs": m.output_names(),
                    "inputs": m.input_names(),
                    "A": rows(&ss.a),
                    "C": rows(&ss.c),
                    "x0": ss.x0.iter().copied().collect::<Vec<_>>(),
                });
                if let Some(b) = &ss.b {
                    doc["B"] = serde_json::json!(rows(b));
                }
                if let Some(d) = &ss.d {
                    doc["D"] = serde_json::json!(rows(d));
                }
                if let Some(so) = m.second_order::<f64>(&m.values())? {
                    doc["M"] = serde_json::json!(rows(&so.m));
                    doc["damping"] = serde_json::json!(rows(&so.d));
                    doc["K"] = serde_json::json!(rows(&so.k));
                }
                doc
            }
        };
        if serde_json::to_string(&value).is_ok_and(|t| t.contains("null")) {
            return Err(ModelError::NonFinite { what: "the assembled matrices".into() });
        }
        Ok(value)
    }

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
        let is_sensor = |name: &str| sensor_effects.iter().any(|(n, _)| n == name);
        let physics: Vec<&str> = free.iter().copied().filter(|n| !is_sensor(n)).collect();
        let inner: Box<dyn ResponseModel + Send + Sync> = match self {
            Model::Slewing(m) if m.is_linear() => {
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
            Model::Structure(m) if m.is_linear() => {
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
                    let term = SensorTerm::of(e.kind())?;
                    let name = plant::ParamId::of_effect(&e).first().map(|id| id.name())?;
                    let value = match e {
                        plant::Effect::OutputOffset { offset, .. } => offset,
                        plant::Effect::SensorScale { scale, .. } => scale,
                        plant::Effect::SensorDrift { rate, .. } => rate,
                        _ => return None,
                    };
                    Some((name, SensorEffect { output, term, value, free: None }))
                })
                .collect(),
            Model::Structure(m) => {
                let outputs = m.output_names();
                m.effects()
                    .iter()
                    .filter_map(|e| {
                        let (output, term, value) = match e {
                            structure::Effect::OutputOffset { output, offset } => {
                                (output, SensorTerm::Offset, *offset)
                            }
                            structure::Effect::SensorScale { output, scale } => {
                                (output, SensorTerm::Scale, *scale)
                            }
                            structure::Effect::SensorDrift { output, rate } => {
                                (output, SensorTerm::Drift, *rate)
                            }
                            _ => return None,
                        };
                        let name = e.parameters(&outputs).first()?.0.clone();
                        let output = outputs.iter().position(|o| o == output)?;
                        Some((name, SensorEffect { output, term, value, free: None }))
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

    /// The slewing model, if this is one.
    pub fn as_slewing(&self) -> Option<&SlewingModel> {
        match self {
            Model::Slewing(m) => Some(m),
            Model::Structure(_) => None,
        }
    }
}
