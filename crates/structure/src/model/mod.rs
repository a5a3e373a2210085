//! [`StructureModel`]: a validated model file, its compiled expressions and current values; its
//! linear state space (`linear.rs`), its text (`text.rs`) and its forces (`forces.rs`).

use crate::StructureError;
use crate::compile::{Checked, Ctx, compile};
use crate::effects::Effect;
use crate::scan::Path;
use crate::schema::{self, ModelFile};

/// A linear structure read from a model file: its parameters (with their current values), the
/// compiled expressions of its matrices, its inputs and outputs.
///
/// [`state_space`](Self::state_space) assembles A, C, x(0), B, D for any scalar — `f64` for
/// values, `num_dual::Dual64` (or any num-dual number) for exact derivatives — from the
/// expressions parsed once when the file was read. The model also implements
/// [`mem::StateSpaceModel`], so `mem::Exact(model)` is ready to fit.
///
/// ```
/// use structure::StructureModel;
///
/// let text = r#"(
///     name: "one storey",
///     parameters: { "m": (value: 1000, unit: "kg"), "k": (value: 4e6, unit: "N/m", free: true, bounds: (0, 1e9)) },
///     structure: SecondOrder(
///         coordinates: ["q"],
///         mass: [["m"]],
///         stiffness: [["k"]],
///         damping: Modal([0.02]),
///     ),
///     outputs: [(column: "q", measures: Displacement("q"))],
///     initial: (displacement: [0.01]),
/// )"#;
/// let mut model = StructureModel::from_ron(text, "one_storey.ron")?;
/// assert_eq!(model.free(), ["k"]);
/// let f = model.modes()?[0].frequency_hz;
/// assert!((f - (4e6f64 / 1000.0).sqrt() / (2.0 * std::f64::consts::PI)).abs() < 1e-9);
/// model.set("k", 5e6)?;
/// assert_eq!(model.value("k")?, 5e6);
/// # Ok::<(), structure::StructureError>(())
/// ```
#[derive(Clone, Debug)]
pub struct StructureModel {
    name: String,
    origin: String,
    text: String,
    file: ModelFile,
    checked: Checked,
    values: Vec<f64>,
    effects: Vec<Effect>,
    /// Bounds of effect parameters, by name.
    effect_bounds: Vec<(String, (f64, f64))>,
}

/// Where a parameter lives: the file's list, or the k-th parameter of the e-th effect.
#[derive(Clone, Copy)]
enum Slot {
    File(usize),
    Effect(usize, usize),
}

impl StructureModel {
    /// Reads and validates a model file; `origin` names it in error messages (a path, or e.g.
    /// `<string>`).
    ///
    /// # Errors
    /// [`StructureError::Syntax`] for malformed RON, unknown or missing fields;
    /// [`StructureError::Expression`] for an entry that does not parse or names an unknown
    /// parameter; [`StructureError::InvalidValue`] and [`StructureError::Invalid`] for an
    /// impossible value, size, name or model at the file's values. All carry the line and column.
    pub fn from_ron(text: &str, origin: &str) -> Result<Self, StructureError> {
        let file = schema::from_str(text).map_err(|e| syntax_error(text, origin, &e))?;
        let checked = compile(&file, &Ctx::new(text, origin))?;
        let values = checked.params.iter().map(|p| p.value).collect();
        let mut model = StructureModel {
            name: file.name.clone(),
            origin: origin.to_string(),
            text: text.to_string(),
            file: file.clone(),
            checked,
            values,
            effects: Vec::new(),
            effect_bounds: Vec::new(),
        };
        let ctx = Ctx::new(text, origin);
        for (i, effect) in file.effects.into_iter().enumerate() {
            model.add_effect(effect).map_err(|e| {
                let message = match e {
                    StructureError::InvalidEffect { reason } => reason,
                    other => other.to_string(),
                };
                ctx.invalid(&Path::default().field("effects").index(i), message)
            })?;
        }
        Ok(model)
    }

    /// Reads a model file from disk (its path is the origin in error messages).
    ///
    /// # Errors
    /// [`StructureError::Io`] if the file cannot be read; otherwise as [`from_ron`](Self::from_ron).
    pub fn load(path: &std::path::Path) -> Result<Self, StructureError> {
        let text = std::fs::read_to_string(path)
            .map_err(|source| StructureError::Io { path: path.display().to_string(), source })?;
        Self::from_ron(&text, &path.display().to_string())
    }

    /// The model's name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// All parameter names, in declaration order (the order of P in
    /// [`state_space`](Self::state_space)).
    ///
    /// The parameters of added effects follow the file's, effect by effect.
    pub fn parameter_names(&self) -> Vec<String> {
        self.checked
            .params
            .iter()
            .map(|p| p.name.clone())
            .chain(self.effect_parameters().into_iter().map(|(n, _)| n))
            .collect()
    }

    /// The current values of all parameters, in declaration order (then the effects').
    pub fn values(&self) -> Vec<f64> {
        self.values.iter().copied().chain(self.effect_parameters().into_iter().map(|(_, v)| v)).collect()
    }

    /// The effects' parameters (name, value), effect by effect.
    fn effect_parameters(&self) -> Vec<(String, f64)> {
        let outputs = self.output_names();
        self.effects.iter().flat_map(|e| e.parameters(&outputs)).collect()
    }

    fn slot(&self, name: &str) -> Result<Slot, StructureError> {
        if let Some(i) = self.checked.params.iter().position(|p| p.name == name) {
            return Ok(Slot::File(i));
        }
        let outputs = self.output_names();
        for (e, effect) in self.effects.iter().enumerate() {
            if let Some(k) = effect.parameters(&outputs).iter().position(|(n, _)| n == name) {
                return Ok(Slot::Effect(e, k));
            }
        }
        Err(StructureError::UnknownParameter {
            name: name.to_string(),
            valid: self.parameter_names().join(", "),
        })
    }

    fn info(&self, name: &str) -> Option<&crate::compile::ParamInfo> {
        self.checked.params.iter().find(|p| p.name == name)
    }

    /// The current value of a parameter.
    ///
    /// # Errors
    /// [`StructureError::UnknownParameter`] (listing the valid names).
    pub fn value(&self, name: &str) -> Result<f64, StructureError> {
        Ok(match self.slot(name)? {
            Slot::File(i) => self.values[i],
            Slot::Effect(e, k) => self.effects[e].parameters(&self.output_names())[k].1,
        })
    }

    /// Sets a parameter's current value.
    ///
    /// # Errors
    /// [`StructureError::UnknownParameter`] (listing the valid names),
    /// [`StructureError::NotFinite`], or [`StructureError::OutOfBounds`] for a value outside the
    /// parameter's declared bounds (so that [`to_ron`](Self::to_ron) always writes a valid file).
    pub fn set(&mut self, name: &str, value: f64) -> Result<(), StructureError> {
        let slot = self.slot(name)?;
        if !value.is_finite() {
            return Err(StructureError::NotFinite { name: name.to_string(), value });
        }
        if let Some((lower, upper)) = self.bounds(name)
            && !(lower..=upper).contains(&value)
        {
            return Err(StructureError::OutOfBounds { name: name.to_string(), value, lower, upper });
        }
        match slot {
            Slot::File(i) => self.values[i] = value,
            Slot::Effect(e, k) => {
                let mut effect = self.effects[e].clone();
                effect.set(k, value);
                if let Some(reason) = effect.invalid(
                    &self.output_names(),
                    &self.coordinates(),
                    &self.input_names(),
                    self.is_second_order(),
                ) {
                    return Err(StructureError::InvalidEffect { reason });
                }
                self.effects[e] = effect;
            }
        }
        Ok(())
    }

    /// Checks that M at the current values gives positive kinetic energy for every motion
    /// (`Compiled::positive_mass` in module `assemble`), as the file's values were checked when it
    /// was read: for values a user set by hand ([`Self::set`] checks each alone, and a fit moves
    /// them as the data ask).
    ///
    /// # Errors
    /// [`StructureError::Assembly`] naming the mass matrix.
    pub fn check_mass(&self) -> Result<(), StructureError> {
        if self.checked.compiled.positive_mass(&self.values)? {
            Ok(())
        } else {
            Err(StructureError::Assembly {
                part: crate::assemble::MASS.into(),
                reason: crate::assemble::NOT_POSITIVE_MASS.into(),
            })
        }
    }

    /// The parameters marked `free: true`, in declaration order.
    pub fn free(&self) -> Vec<String> {
        self.checked.params.iter().filter(|p| p.free).map(|p| p.name.clone()).collect()
    }

    /// A parameter's declared bounds (lower, upper), if any.
    pub fn bounds(&self, name: &str) -> Option<(f64, f64)> {
        match self.info(name) {
            Some(info) => info.bounds,
            None => self.effect_bounds.iter().find(|(n, _)| n == name).map(|(_, b)| *b),
        }
    }

    /// Sets the (lower, upper) bounds fits keep a parameter within (in memory: the file written
    /// back keeps its own bounds).
    ///
    /// # Errors
    /// [`StructureError::UnknownParameter`]; [`StructureError::OutOfBounds`] if the current
    /// value lies outside the new bounds.
    pub fn set_bounds(&mut self, name: &str, bounds: (f64, f64)) -> Result<(), StructureError> {
        let value = self.value(name)?;
        if !(bounds.0..=bounds.1).contains(&value) {
            return Err(StructureError::OutOfBounds {
                name: name.to_string(),
                value,
                lower: bounds.0,
                upper: bounds.1,
            });
        }
        match self.slot(name)? {
            Slot::File(i) => {
                self.checked.params[i].bounds = Some(bounds);
                Ok(())
            }
            Slot::Effect(..) => {
                self.effect_bounds.retain(|(n, _)| n != name);
                self.effect_bounds.push((name.to_string(), bounds));
                Ok(())
            }
        }
    }

    /// A parameter's declared typical size (a positive scale for its steps), if any.
    pub fn typical(&self, name: &str) -> Option<f64> {
        self.info(name)?.typical
    }

    /// A parameter's declared unit, if any.
    pub fn unit(&self, name: &str) -> Option<&str> {
        self.info(name)?.unit.as_deref()
    }

    /// A parameter's declared description, if any.
    pub fn description(&self, name: &str) -> Option<&str> {
        self.info(name)?.description.as_deref()
    }

    /// The outputs' CSV columns, in order (the rows of C).
    pub fn output_names(&self) -> Vec<String> {
        self.checked.outputs.iter().map(|o| o.name.clone()).collect()
    }

    /// An output column's declared unit, if any.
    pub fn output_unit(&self, column: &str) -> Option<&str> {
        self.checked.outputs.iter().find(|o| o.name == column)?.unit.as_deref()
    }

    /// The inputs' names (CSV columns), in order (the columns of B).
    pub fn input_names(&self) -> Vec<String> {
        self.checked.inputs.iter().map(|i| i.name.clone()).collect()
    }

    /// An input's declared unit, if any.
    pub fn input_unit(&self, name: &str) -> Option<&str> {
        self.checked.inputs.iter().find(|i| i.name == name)?.unit.as_deref()
    }

    /// How inputs are held between samples (`hold:` in the file, zero-order by default).
    pub fn hold(&self) -> mem::Hold {
        self.checked.hold
    }

    /// The coordinates (second-order file) or the states (first-order file), in order.
    pub fn coordinates(&self) -> Vec<String> {
        self.checked.coordinates.clone()
    }

    /// Whether the file is second order (`SecondOrder(…)`), with state x = [q; q̇].
    pub fn is_second_order(&self) -> bool {
        matches!(self.checked.compiled.dynamics, crate::assemble::Dynamics::Second { .. })
    }

    /// The number of states N: twice the number of coordinates for a second-order file.
    pub fn n_states(&self) -> usize {
        match self.checked.compiled.dynamics {
            crate::assemble::Dynamics::Second { n, .. } => 2 * n,
            crate::assemble::Dynamics::First { n, .. } => n,
        }
    }

    /// The index of a coordinate's displacement in the state (its velocity is at this index
    /// plus the number of coordinates), or of a first-order state; `None` for an unknown name.
    pub fn coordinate_index(&self, name: &str) -> Option<usize> {
        self.checked.coordinates.iter().position(|c| c == name)
    }
}

mod forces;
mod linear;
mod text;
pub use forces::{ForceLaw, ForceParts};
pub use text::is_structure_file;
use text::syntax_error;

#[cfg(test)]
mod tests;
