//! The model kinds a model file may describe, behind one type: the slewing rig (`plant`) and any
//! linear structure (`structure`). The file's content chooses the kind (a top-level `structure`
//! field), in one place: [`Model::from_ron`]. Its response lives in `response.rs`, what it shows
//! of itself (modes, matrices) in `export.rs`.

mod export;
mod response;

use crate::ModelError;
use mem::Hold;
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

    /// Checks the values a user set by hand as the file's were checked when it was read: a
    /// structure's mass matrix must give positive kinetic energy
    /// ([`structure::StructureModel::check_mass`]); the slewing rig's values are checked one by
    /// one as they are set.
    ///
    /// # Errors
    /// The structure's error, naming the mass matrix.
    pub fn check_values(&self) -> Result<(), ModelError> {
        match self {
            Model::Slewing(_) => Ok(()),
            Model::Structure(m) => Ok(m.check_mass()?),
        }
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

    /// Whether the model has no nonlinear effect, so that the exact exponential path applies
    /// whatever is freed. [`Model::response_with`] takes that path also for a model that is
    /// linear for the parameters it frees: a hub spring whose cubic part stays zero
    /// (`plant::SlewingModel::is_linear_for`), a drag of exponent 1 held there
    /// (`structure::StructureModel::is_linear_for`).
    pub fn is_linear(&self) -> bool {
        match self {
            Model::Slewing(m) => m.is_linear(),
            Model::Structure(m) => m.is_linear(),
        }
    }

    /// The slewing model, if this is one.
    pub fn as_slewing(&self) -> Option<&SlewingModel> {
        match self {
            Model::Slewing(m) => Some(m),
            Model::Structure(_) => None,
        }
    }
}
