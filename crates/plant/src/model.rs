//! The slewing model as a whole: a validated model file and the matrices it defines.

use crate::assemble::{Layout, first_order, second_order};
use crate::file::{ModelFile, locate};
use crate::output::output_matrix;
use crate::sensors::Sensor;
use crate::{Constants, Effect, ParamId, PlantError};
use faer::Mat;
use nalgebra::DMatrix;
use num_dual::Dual64;

/// The matrices of the model at its current parameter values.
#[derive(Clone, Debug)]
pub struct StateSpace {
    /// Mass matrix M ((n+1)×(n+1)).
    pub m: Mat<f64>,
    /// Damping matrix D.
    pub d: Mat<f64>,
    /// Stiffness matrix K.
    pub k: Mat<f64>,
    /// Input vector B ((n+1)×1).
    pub b: Mat<f64>,
    /// System matrix A (2(n+1) square).
    pub a: Mat<f64>,
    /// Output matrix C (p × 2(n+1)).
    pub c: Mat<f64>,
    /// Initial state x(0).
    pub x0: Vec<f64>,
}

/// A(P), C(P) and their exact derivatives with respect to chosen parameters.
#[derive(Clone, Debug)]
pub struct Linearization {
    /// A at P.
    pub a: Mat<f64>,
    /// C at P.
    pub c: Mat<f64>,
    /// ∂A/∂P_i, one per chosen parameter.
    pub da: Vec<Mat<f64>>,
    /// ∂C/∂P_i (zero unless a strain output is measured and P_i changes the mode shapes).
    pub dc: Vec<Mat<f64>>,
    /// B at P and ∂B/∂P_i, for a model driven by a commanded angle (`inputs: [ReferenceAngle]`):
    /// B = k_s·[0; M⁻¹·servo_vector], the servo torque k_s(θ_ref − θ) of Eq. 17.
    pub b: Option<(Mat<f64>, Vec<Mat<f64>>)>,
}

/// A validated slewing model, ready to assemble.
#[derive(Clone, Debug)]
pub struct SlewingModel {
    file: ModelFile,
    origin: String,
    text: String,
    constants: Constants<f64>,
}

fn to_faer(m: &DMatrix<f64>) -> Mat<f64> {
    Mat::from_fn(m.nrows(), m.ncols(), |i, j| m[(i, j)])
}

/// The paper's experiment, `fixtures/slewing.ron`, embedded in the library.
pub const PAPER_MODEL_RON: &str = include_str!("../../../fixtures/slewing.ron");

impl SlewingModel {
    /// The paper's experiment ([`PAPER_MODEL_RON`]).
    pub fn paper() -> Self {
        Self::from_ron(PAPER_MODEL_RON, "fixtures/slewing.ron").expect("the embedded fixture is valid")
    }

    /// Parses a model from RON text; `origin` names it in errors (a file name).
    ///
    /// # Errors
    /// As [`ModelFile::parse`].
    pub fn from_ron(text: &str, origin: &str) -> Result<Self, PlantError> {
        let file = ModelFile::parse(text, origin)?;
        let constants = file.constants();
        let model = Self { file, origin: origin.to_string(), text: text.to_string(), constants };
        // Assemble once so that a file whose values cannot be assembled fails at load time.
        model.state_space()?;
        Ok(model)
    }

    /// Reads and parses a model file.
    ///
    /// # Errors
    /// [`PlantError::Io`] if it cannot be read, else as [`Self::from_ron`].
    pub fn load(path: &std::path::Path) -> Result<Self, PlantError> {
        let text = std::fs::read_to_string(path)
            .map_err(|source| PlantError::Io { path: path.display().to_string(), source })?;
        Self::from_ron(&text, &path.display().to_string())
    }

    /// The model file with the current parameter values written in.
    pub fn file(&self) -> ModelFile {
        let mut f = self.file.clone();
        f.set_constants(&self.constants);
        f
    }

    /// Number of flexible modes n.
    pub fn n_modes(&self) -> usize {
        self.file.n_modes()
    }

    /// Where each part of the state lives (with the effects' extra states).
    pub fn layout(&self) -> Layout {
        Layout::of(&self.constants)
    }

    /// Number of states N: 2(n+1), plus 2 for an unmodeled mode, 1 for a delay.
    pub fn n_states(&self) -> usize {
        self.layout().n_states
    }

    /// Whether the model is linear (no amplifier saturation, friction or drag), so that the
    /// exact matrix-exponential path applies.
    pub fn is_linear(&self) -> bool {
        !self.constants.effects.iter().any(|e| e.is_nonlinear())
    }

    /// Whether the model is linear with `free` the parameters that may move: no nonlinear
    /// effect but, perhaps, a hub spring whose cubic part is zero and stays so (its
    /// `cubic_stiffness` not in `free`), with no quintic or time-varying part, leaving its
    /// linear part k₁θ, which is in A ([`crate::assemble::second_order`]). The exact exponential
    /// path then applies.
    pub fn is_linear_for(&self, free: &[ParamId]) -> bool {
        self.constants.effects.iter().all(|e| match e {
            Effect::CubicStiffness { coefficient, quintic, rate, .. } => {
                *coefficient == 0.0
                    && !free.contains(&ParamId::CubicStiffness)
                    && quintic.is_none()
                    && rate.is_none()
            }
            e => !e.is_nonlinear(),
        })
    }

    /// The names of the measured inputs (CSV columns) that drive the model.
    pub fn input_names(&self) -> Vec<&'static str> {
        self.file.inputs.iter().map(|i| i.column()).collect()
    }

    /// The effects in the model.
    pub fn effects(&self) -> &[crate::Effect] {
        &self.constants.effects
    }

    /// Adds an effect (for the discrepancy workflow).
    ///
    /// # Errors
    /// [`PlantError::InvalidValue`] if the model already has an effect of that kind.
    pub fn add_effect(&mut self, effect: crate::Effect) -> Result<(), PlantError> {
        let mut file = self.file();
        file.effects.push(effect);
        let text = file.to_ron();
        *self = Self::from_ron(&text, &self.origin)?;
        Ok(())
    }

    /// Removes the effect of `kind` (on `sensor`, for a sensor effect), with its bounds; a
    /// no-op when the model has none.
    ///
    /// # Errors
    /// As [`Self::from_ron`] (the model is rebuilt from its file).
    pub fn remove_effect(
        &mut self,
        kind: crate::EffectKind,
        sensor: Option<crate::Sensor>,
    ) -> Result<(), PlantError> {
        let mut file = self.file();
        let removed: Vec<crate::Effect> =
            file.effects.iter().filter(|e| e.kind() == kind && e.sensor() == sensor).cloned().collect();
        if removed.is_empty() {
            return Ok(());
        }
        file.effects.retain(|e| !(e.kind() == kind && e.sensor() == sensor));
        for id in removed.iter().flat_map(crate::ParamId::of_effect) {
            file.bounds.remove(&id.name());
            file.free.retain(|name| *name != id.name());
        }
        let text = file.to_ron();
        *self = Self::from_ron(&text, &self.origin)?;
        Ok(())
    }

    /// Sets (lower, upper) bounds for a parameter, used by fits.
    pub fn set_bounds(&mut self, id: ParamId, bounds: (f64, f64)) {
        self.file.bounds.insert(id.name(), bounds);
    }

    /// Every parameter this model has (core and effects).
    pub fn parameter_ids(&self) -> Vec<ParamId> {
        self.constants.parameter_ids()
    }

    /// The nonlinear dynamics in scalar type D, with the constants converted by `lift`.
    ///
    /// # Errors
    /// As [`Self::state_space`].
    pub fn dynamics_with<D: crate::assemble::Scalar>(
        &self,
        lift: impl Fn(&f64) -> D,
    ) -> Result<crate::nonlinear::Dynamics<D>, PlantError> {
        crate::nonlinear::dynamics(&self.constants.map(lift), &self.file.outputs)
    }

    /// The measurement-side effects (offsets, scales, drifts, quantization) with the index of the
    /// output they act on; the adapter layer applies them.
    pub fn sensor_effects(&self) -> Vec<(usize, crate::Effect)> {
        self.constants
            .effects
            .iter()
            .filter_map(|e| {
                let sensor = e.sensor()?;
                let o = self.file.outputs.iter().position(|s| *s == sensor)?;
                Some((o, e.clone()))
            })
            .collect()
    }

    /// The sensors' quantization steps (measurement-only effects), per output.
    pub fn quantization(&self) -> Vec<Option<f64>> {
        self.file
            .outputs
            .iter()
            .map(|s| {
                self.constants.effects.iter().find_map(|e| match e {
                    crate::Effect::SensorQuantization { sensor, step } if sensor == s => Some(*step),
                    _ => None,
                })
            })
            .collect()
    }

    /// Current constants.
    pub fn constants(&self) -> &Constants<f64> {
        &self.constants
    }

    /// The measured sensors, in output order.
    pub fn sensors(&self) -> &[Sensor] {
        &self.file.outputs
    }

    /// Output names, in order.
    pub fn output_names(&self) -> Vec<&'static str> {
        self.file.outputs.iter().map(|s| s.output_name()).collect()
    }

    /// Looks a parameter name up.
    ///
    /// # Errors
    /// [`PlantError::UnknownParameter`] listing the valid names.
    pub fn parameter(&self, name: &str) -> Result<ParamId, PlantError> {
        ParamId::parse_among(name, &self.constants.parameter_ids())
    }

    /// The parameters the file marks as free.
    ///
    /// # Errors
    /// Never for a validated file; kept fallible for symmetry with [`Self::parameter`].
    pub fn free_parameters(&self) -> Result<Vec<ParamId>, PlantError> {
        self.file.free.iter().map(|n| self.parameter(n)).collect()
    }

    /// Bounds given in the file for a parameter, if any.
    pub fn bounds(&self, id: ParamId) -> Option<(f64, f64)> {
        self.file.bounds.get(&id.name()).copied()
    }

    /// The current value of a parameter.
    ///
    /// # Panics
    /// If `id` belongs to an effect this model does not have (ids from [`Self::parameter`] and
    /// [`Self::parameter_ids`] always exist).
    pub fn get(&self, id: ParamId) -> f64 {
        self.constants.get(id)
    }

    /// Sets a parameter.
    ///
    /// # Errors
    /// [`PlantError::InvalidValue`] if the value is physically impossible,
    /// [`PlantError::UnknownParameter`] if it belongs to an effect the model does not have.
    pub fn set(&mut self, id: ParamId, value: f64) -> Result<(), PlantError> {
        if self.constants.try_get(id).is_none() {
            return Err(PlantError::UnknownParameter {
                name: id.name(),
                valid: self.parameter_ids().iter().map(|p| p.name()).collect::<Vec<_>>().join(", "),
            });
        }
        id.check(value).map_err(|requirement| PlantError::InvalidValue {
            origin: self.origin.clone(),
            line: 0,
            column: 0,
            field: id.name(),
            value,
            requirement,
        })?;
        *self.constants.field_mut(id) = value;
        Ok(())
    }

    /// The same model observing only the named outputs (effects on other sensors dropped).
    ///
    /// # Errors
    /// [`PlantError::UnknownParameter`] (listing the outputs) for a name the model lacks.
    pub fn select_outputs(&self, names: &[&str]) -> Result<Self, PlantError> {
        let mut file = self.file();
        let mut chosen = Vec::new();
        for name in names {
            let sensor =
                file.outputs.iter().copied().find(|s| s.output_name() == *name).ok_or_else(|| {
                    PlantError::UnknownParameter {
                        name: (*name).to_string(),
                        valid: self.output_names().join(", "),
                    }
                })?;
            chosen.push(sensor);
        }
        file.effects.retain(|e| e.sensor().is_none_or(|sensor| chosen.contains(&sensor)));
        file.outputs = chosen;
        Self::from_ron(&file.to_ron(), &self.origin)
    }

    /// Sets the initial hub angle \[rad\].
    pub fn set_initial_angle(&mut self, hub_angle: f64) {
        self.file.initial_condition.hub_angle = hub_angle;
    }

    /// x(0) = [θ(0), 0, …, 0, θ̇(0), 0, …, 0]: the beam undeformed and at rest; the delay state
    /// in steady state for a held angle (w = 2θ(0), so θ_d = θ(0)).
    pub fn initial_state(&self) -> Vec<f64> {
        let layout = self.layout();
        let mut x = vec![0.0; layout.n_states];
        let theta = self.file.initial_condition.hub_angle;
        x[0] = theta;
        x[layout.n_dof] = self.file.initial_condition.hub_rate;
        if let Some(w) = layout.delay {
            x[w] = 2.0 * theta;
        }
        // With backlash the motor starts where the hub is, in the middle of the band.
        if let Some(r) = layout.motor {
            x[r] = theta;
            x[layout.n_dof + r] = self.file.initial_condition.hub_rate;
        }
        // A lagged sensor's state held at its reading (w = 2y(0), so −y + w = y(0)): the
        // potentiometer reads θ(0), the tachometer the rate, the strain gauge nothing (the beam
        // starts undeformed, its modal coordinates at zero).
        for sensor in Sensor::ALL {
            if let Some(w) = layout.lags[sensor.index()] {
                x[w] = 2.0
                    * match sensor {
                        Sensor::Potentiometer => theta,
                        Sensor::Tachometer => self.file.initial_condition.hub_rate,
                        Sensor::StrainGauge => 0.0,
                    };
            }
        }
        x
    }

    /// M, D, K, B, A, C, x(0) at the current values.
    ///
    /// # Errors
    /// [`PlantError::Beam`] or [`PlantError::SingularMass`] for impossible combinations.
    pub fn state_space(&self) -> Result<StateSpace, PlantError> {
        let so = second_order(&self.constants)?;
        let a = first_order(&self.constants, &so)?.a;
        let c = output_matrix(&self.constants, &so, &self.file.outputs);
        Ok(StateSpace {
            m: to_faer(&so.m),
            d: to_faer(&so.d),
            k: to_faer(&so.k),
            b: Mat::from_fn(so.b.len(), 1, |i, _| so.b[i]),
            a: to_faer(&a),
            c: to_faer(&c),
            x0: self.initial_state(),
        })
    }

    /// A, C and their exact derivatives with respect to `params`: the whole chain (beam roots,
    /// mode shapes, participation integrals, M⁻¹K, M⁻¹D) is evaluated in dual numbers.
    ///
    /// # Errors
    /// As [`Self::state_space`].
    pub fn linearization(&self, params: &[ParamId]) -> Result<Linearization, PlantError> {
        let ss = self.state_space()?;
        let driven = !self.file.inputs.is_empty();
        let reference_column = |so: &crate::assemble::SecondOrder<Dual64>,
                                fo: &crate::assemble::FirstOrder<Dual64>| {
            Mat::from_fn(fo.servo_input.len(), 1, |i, _| fo.servo_input[i] * so.servo_stiffness)
        };
        let mut da = Vec::with_capacity(params.len());
        let mut dc = Vec::with_capacity(params.len());
        let mut db = Vec::with_capacity(params.len());
        let mut b = None;
        for &id in params {
            let mut dual = self.constants.map(|v| Dual64::from(*v));
            dual.field_mut(id).eps = 1.0;
            let so = second_order(&dual)?;
            let fo = first_order(&dual, &so)?;
            let a = &fo.a;
            let c = output_matrix(&dual, &so, &self.file.outputs);
            da.push(Mat::from_fn(a.nrows(), a.ncols(), |i, j| a[(i, j)].eps));
            dc.push(Mat::from_fn(c.nrows(), c.ncols(), |i, j| c[(i, j)].eps));
            if driven {
                let column = reference_column(&so, &fo);
                db.push(Mat::from_fn(column.nrows(), 1, |i, _| column[(i, 0)].eps));
                b = Some(Mat::from_fn(column.nrows(), 1, |i, _| column[(i, 0)].re));
            }
        }
        if driven && b.is_none() {
            let dual = self.constants.map(|v| Dual64::from(*v));
            let so = second_order(&dual)?;
            let fo = first_order(&dual, &so)?;
            let column = reference_column(&so, &fo);
            b = Some(Mat::from_fn(column.nrows(), 1, |i, _| column[(i, 0)].re));
        }
        Ok(Linearization { a: ss.a, c: ss.c, da, dc, b: b.map(|b| (b, db)) })
    }

    /// The model as RON text with the current values.
    pub fn to_ron(&self) -> String {
        self.file().to_ron()
    }

    /// Line and column of a field in the text this model was read from ((0, 0) if absent).
    pub fn locate(&self, path: &str) -> (usize, usize) {
        locate(&self.text, path)
    }
}
