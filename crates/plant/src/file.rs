//! The RON model file: schema, parsing with located errors, and writing.

use crate::effects::Effect;
use crate::sensors::Sensor;
use crate::{Constants, ParamId, PlantError};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// A slewing-experiment model file (RON). Units are SI; see `docs/model-file.md`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ModelFile {
    /// A human-readable name.
    pub name: String,
    /// The flexible beam.
    pub beam: BeamSection,
    /// The rigid hub.
    pub hub: HubSection,
    /// The DC motor and its amplifier.
    pub motor: MotorSection,
    /// The position loop.
    pub control: ControlSection,
    /// 2ζ_iω_i \[1/s\] for each flexible mode; its length sets the number of modes n.
    pub modal_damping: Vec<f64>,
    /// The free decay's initial condition.
    pub initial_condition: InitialCondition,
    /// Measured outputs, in CSV column order.
    pub outputs: Vec<Sensor>,
    /// Parameters to tune (names as in `memid fit --free`).
    #[serde(default)]
    pub free: Vec<String>,
    /// Optional bounds (lower, upper) per parameter name.
    #[serde(default)]
    pub bounds: BTreeMap<String, (f64, f64)>,
    /// Optional physical effects beyond the paper's model (see `docs/effects.md`).
    #[serde(default)]
    pub effects: Vec<Effect>,
    /// Measured inputs that drive the model (none: a free decay).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub inputs: Vec<SlewingInput>,
}

/// A measured input of the slewing experiment.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum SlewingInput {
    /// The commanded hub angle θ_ref \[rad\] (paper Eq. 17: the servo acts on θ_ref − θ), CSV
    /// column `theta_ref`, held between samples.
    ReferenceAngle,
}

impl SlewingInput {
    /// The CSV column it is read from.
    pub fn column(self) -> &'static str {
        match self {
            SlewingInput::ReferenceAngle => "theta_ref",
        }
    }
}

/// Beam constants.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BeamSection {
    /// L \[m\].
    pub length: f64,
    /// EI/ρ \[N·m³/kg\].
    pub ei_over_rho: f64,
    /// ρ \[kg/m\].
    pub mass_per_length: f64,
    /// a \[m\].
    pub hub_radius: f64,
    /// Thickness \[m\].
    pub thickness: f64,
}

/// Hub constants.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HubSection {
    /// I_H \[kg·m²\].
    pub inertia: f64,
}

/// Motor and amplifier constants.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MotorSection {
    /// I_m \[kg·m²\].
    pub inertia: f64,
    /// K_t \[N·m/A\].
    pub torque_constant: f64,
    /// K_b \[V·s/rad\].
    pub back_emf_constant: f64,
    /// R_a \[Ω\].
    pub armature_resistance: f64,
    /// L_a \[H\]: recorded for completeness; neglected in the model as in the paper (Eq. 18).
    #[serde(default)]
    pub armature_inductance: Option<f64>,
    /// Amplifier voltage gain G \[V/V\].
    pub amplifier_gain: f64,
}

/// Control constants.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ControlSection {
    /// K_p \[V/rad\].
    pub position_gain: f64,
    /// C_v \[N·m·s/rad\].
    pub viscous_damping: f64,
}

/// Initial condition of the free decay: the beam starts undeformed and at rest.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InitialCondition {
    /// θ(0) \[rad\].
    pub hub_angle: f64,
    /// θ̇(0) \[rad/s\].
    #[serde(default)]
    pub hub_rate: f64,
}

impl ModelFile {
    /// Parses and validates a model file.
    ///
    /// # Errors
    /// [`PlantError::Syntax`] with line and column for malformed RON, unknown or missing fields;
    /// [`PlantError::InvalidValue`] with the field's line and column for impossible values;
    /// [`PlantError::UnknownParameter`] for a bad name in `free` or `bounds`.
    pub fn parse(text: &str, origin: &str) -> Result<Self, PlantError> {
        let file: ModelFile = ron::from_str(text).map_err(|e| PlantError::Syntax {
            origin: origin.to_string(),
            line: e.position.line,
            column: e.position.col,
            message: e.code.to_string(),
        })?;
        file.validate(text, origin)?;
        Ok(file)
    }

    /// The number of flexible modes n.
    pub fn n_modes(&self) -> usize {
        self.modal_damping.len()
    }

    fn validate(&self, text: &str, origin: &str) -> Result<(), PlantError> {
        let invalid = |path: &str, value: f64, requirement: String| {
            let (line, column) = locate(text, path);
            PlantError::InvalidValue {
                origin: origin.to_string(),
                line,
                column,
                field: path.to_string(),
                value,
                requirement,
            }
        };
        if self.modal_damping.is_empty() {
            return Err(invalid(
                "modal_damping",
                0.0,
                "needs one entry per flexible mode (at least one)".into(),
            ));
        }
        let constants = self.constants();
        let ids = constants.parameter_ids();
        for &id in &ids {
            let value = constants.get(id);
            id.check(value).map_err(|req| invalid(&id.field_path(), value, req))?;
        }
        for (i, e) in self.effects.iter().enumerate() {
            // One of each kind; sensor effects once per sensor.
            let duplicate =
                self.effects[..i].iter().any(|f| f.kind() == e.kind() && f.sensor() == e.sensor());
            if duplicate {
                return Err(invalid(
                    "effects",
                    i as f64,
                    format!("effect {} is listed twice", e.kind().name()),
                ));
            }
            if let Some(sensor) = e.sensor()
                && !self.outputs.contains(&sensor)
            {
                return Err(invalid(
                    "effects",
                    i as f64,
                    format!("{} refers to {sensor:?}, which is not in `outputs`", e.kind().name()),
                ));
            }
            if let Effect::SensorCrosstalk { sensor, from, .. } = e
                && (from == sensor || !self.outputs.contains(from))
            {
                return Err(invalid(
                    "effects.from",
                    i as f64,
                    format!("must be another sensor in `outputs` than {sensor:?}, not {from:?}"),
                ));
            }
            if let Effect::SensorQuantization { step, .. } = e
                && !(step.is_finite() && *step > 0.0)
            {
                return Err(invalid("effects.step", *step, "must be finite and > 0".into()));
            }
            if let Effect::Backlash { gear_damping_ratio, .. } = e
                && !(gear_damping_ratio.is_finite() && *gear_damping_ratio >= 0.0)
            {
                return Err(invalid(
                    "effects.gear_damping_ratio",
                    *gear_damping_ratio,
                    "must be finite and ≥ 0".into(),
                ));
            }
            if let Effect::CoulombFriction { static_peak, stribeck_velocity, .. } = e
                && static_peak.is_some() != stribeck_velocity.is_some()
            {
                let given = if static_peak.is_some() { "static_peak" } else { "stribeck_velocity" };
                return Err(invalid(
                    &format!("effects.{given}"),
                    static_peak.or(*stribeck_velocity).unwrap_or(f64::NAN),
                    "give `static_peak` and `stribeck_velocity` together (or neither)".into(),
                ));
            }
            if let Effect::CoulombFriction { smoothing_velocity, .. } = e
                && !(smoothing_velocity.is_finite() && *smoothing_velocity > 0.0)
            {
                return Err(invalid(
                    "effects.smoothing_velocity",
                    *smoothing_velocity,
                    "must be finite and > 0".into(),
                ));
            }
        }
        let ic = &self.initial_condition;
        for (path, value) in
            [("initial_condition.hub_angle", ic.hub_angle), ("initial_condition.hub_rate", ic.hub_rate)]
        {
            if !value.is_finite() {
                return Err(invalid(path, value, "must be finite".into()));
            }
        }
        if self.outputs.is_empty() {
            return Err(invalid("outputs", 0.0, "list at least one sensor".into()));
        }
        for (i, s) in self.outputs.iter().enumerate() {
            if self.outputs[..i].contains(s) {
                return Err(invalid("outputs", i as f64, format!("sensor {s:?} is listed twice")));
            }
        }
        for name in self.free.iter().chain(self.bounds.keys()) {
            ParamId::parse_among(name, &ids)?;
        }
        for (name, (lo, hi)) in &self.bounds {
            if lo.partial_cmp(hi) != Some(std::cmp::Ordering::Less) {
                return Err(invalid("bounds", *lo, format!("bounds of `{name}` must have lower < upper")));
            }
            let lowest = ParamId::parse_among(name, &ids)?.lowest();
            if *hi <= lowest {
                return Err(invalid(
                    "bounds",
                    *hi,
                    format!("the upper bound of `{name}` must exceed {lowest:e}, the least it may take"),
                ));
            }
        }
        Ok(())
    }

    /// The constants as numbers.
    pub fn constants(&self) -> Constants<f64> {
        Constants {
            length: self.beam.length,
            ei_over_rho: self.beam.ei_over_rho,
            mass_per_length: self.beam.mass_per_length,
            hub_radius: self.beam.hub_radius,
            thickness: self.beam.thickness,
            hub_inertia: self.hub.inertia,
            motor_inertia: self.motor.inertia,
            torque_constant: self.motor.torque_constant,
            back_emf_constant: self.motor.back_emf_constant,
            armature_resistance: self.motor.armature_resistance,
            amplifier_gain: self.motor.amplifier_gain,
            position_gain: self.control.position_gain,
            viscous_damping: self.control.viscous_damping,
            modal_damping: self.modal_damping.clone(),
            effects: self.effects.clone(),
        }
    }

    /// Writes constants back into the file's fields.
    pub fn set_constants(&mut self, c: &Constants<f64>) {
        self.beam.length = c.length;
        self.beam.ei_over_rho = c.ei_over_rho;
        self.beam.mass_per_length = c.mass_per_length;
        self.beam.hub_radius = c.hub_radius;
        self.beam.thickness = c.thickness;
        self.hub.inertia = c.hub_inertia;
        self.motor.inertia = c.motor_inertia;
        self.motor.torque_constant = c.torque_constant;
        self.motor.back_emf_constant = c.back_emf_constant;
        self.motor.armature_resistance = c.armature_resistance;
        self.motor.amplifier_gain = c.amplifier_gain;
        self.control.position_gain = c.position_gain;
        self.control.viscous_damping = c.viscous_damping;
        self.modal_damping = c.modal_damping.clone();
        self.effects = c.effects.clone();
    }

    /// The file as pretty RON text.
    pub fn to_ron(&self) -> String {
        let config = ron::ser::PrettyConfig::new().depth_limit(3).struct_names(false);
        ron::ser::to_string_pretty(self, config).expect("a model file always serialises")
    }
}

/// 1-based (line, column) of a field path such as `control.viscous_damping` or
/// `modal_damping[2]` in RON text: each component is searched as `name:` after the previous
/// one; an index moves past that many commas. (0, 0) if the text does not contain it (a value
/// set programmatically).
pub fn locate(text: &str, path: &str) -> (usize, usize) {
    let mut pos = 0;
    for part in path.split('.') {
        let (name, index) = match part.split_once('[') {
            Some((n, rest)) => (n, rest.trim_end_matches(']').parse::<usize>().ok()),
            None => (part, None),
        };
        let Some(found) = find_key(&text[pos..], name) else {
            return (0, 0);
        };
        pos += found;
        if let Some(index) = index
            && let Some(open) = text[pos..].find('[')
        {
            pos += open + 1;
            for _ in 0..index {
                match text[pos..].find(',') {
                    Some(c) => pos += c + 1,
                    None => return (0, 0),
                }
            }
            pos += text[pos..].len() - text[pos..].trim_start().len();
        }
    }
    let line = text[..pos].matches('\n').count() + 1;
    let column = pos - text[..pos].rfind('\n').map_or(0, |i| i + 1) + 1;
    (line, column)
}

/// Offset of `name` used as a key (`name` followed by optional spaces and `:`).
fn find_key(text: &str, name: &str) -> Option<usize> {
    let mut start = 0;
    while let Some(i) = text[start..].find(name) {
        let at = start + i;
        let before_ok = at == 0 || !text[..at].ends_with(|c: char| c.is_alphanumeric() || c == '_');
        let after = text[at + name.len()..].trim_start();
        if before_ok && after.starts_with(':') {
            return Some(at);
        }
        start = at + name.len();
    }
    None
}
