//! The model's physical, control and effect constants, generic over the scalar, and their names.

use crate::PlantError;
use crate::effects::Effect;
use crate::sensors::Sensor;

/// Every constant of the closed-loop slewing model (SI units), generic over the scalar so that
/// num-dual numbers carry derivatives through the whole assembly.
#[derive(Clone, Debug, PartialEq)]
pub struct Constants<D> {
    /// Beam length L \[m\].
    pub length: D,
    /// EI/ρ \[N·m³/kg\] (printed in the paper: 0.857).
    pub ei_over_rho: D,
    /// Mass per unit length ρ \[kg/m\] (not printed in the paper; calibrated).
    pub mass_per_length: D,
    /// Hub radius a \[m\].
    pub hub_radius: D,
    /// Beam thickness \[m\] (converts root curvature to surface strain).
    pub thickness: D,
    /// Hub inertia I_H \[kg·m²\].
    pub hub_inertia: D,
    /// Motor inertia I_m \[kg·m²\].
    pub motor_inertia: D,
    /// Motor torque constant K_t \[N·m/A\].
    pub torque_constant: D,
    /// Back-EMF constant K_b \[V·s/rad\].
    pub back_emf_constant: D,
    /// Armature resistance R_a \[Ω\].
    pub armature_resistance: D,
    /// Power-amplifier voltage gain G \[V/V\] (not printed in the paper; calibrated).
    pub amplifier_gain: D,
    /// Position feedback gain K_p \[V/rad\].
    pub position_gain: D,
    /// Viscous damping C_v \[N·m·s/rad\].
    pub viscous_damping: D,
    /// Modal damping terms 2ζ_iω_i \[1/s\], one per flexible mode.
    pub modal_damping: Vec<D>,
    /// Effects added to the paper's model.
    pub effects: Vec<Effect<D>>,
}

/// A named, tunable constant of the model.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ParamId {
    /// `cv`: viscous damping C_v.
    ViscousDamping,
    /// `kp`: position gain K_p.
    PositionGain,
    /// `modal_damping_<i>` (1-based): 2ζ_iω_i.
    ModalDamping(usize),
    /// `rho`: mass per length.
    MassPerLength,
    /// `ei_over_rho`: EI/ρ.
    EiOverRho,
    /// `length`: beam length.
    Length,
    /// `hub_radius`: a.
    HubRadius,
    /// `thickness`: beam thickness.
    Thickness,
    /// `hub_inertia`: I_H.
    HubInertia,
    /// `motor_inertia`: I_m.
    MotorInertia,
    /// `kt`: torque constant.
    TorqueConstant,
    /// `kb`: back-EMF constant.
    BackEmfConstant,
    /// `ra`: armature resistance.
    ArmatureResistance,
    /// `amplifier_gain`: G.
    AmplifierGain,
    /// `current_limit` of `AmplifierSaturation`.
    CurrentLimit,
    /// `coulomb_torque` of `CoulombFriction`.
    CoulombTorque,
    /// `drag_hub` of `QuadraticDrag`.
    DragHub,
    /// `delay` of `TimeDelay`.
    Delay,
    /// `offset_<output>` of `OutputOffset`.
    Offset(Sensor),
    /// `scale_<output>` of `SensorScale`.
    Scale(Sensor),
    /// `drift_<output>` of `SensorDrift`.
    Drift(Sensor),
    /// `drift_time_<output>` of `SensorDrift` (when given): the time constant it levels off with.
    DriftTime(Sensor),
    /// `crosstalk_<output>_<from>` of `SensorCrosstalk`: the gain of `from`'s signal in
    /// `output`'s reading.
    Crosstalk(Sensor, Sensor),
    /// `lag_<output>` of `SensorLag`: how late the output's channel reads it.
    Lag(Sensor),
    /// `voltage_limit` of `VoltageSaturation`.
    VoltageLimit,
    /// `drag_exponent` of `QuadraticDrag` (when given).
    DragExponent,
    /// `cubic_stiffness` of `CubicStiffness`.
    CubicStiffness,
    /// `hub_stiffness` of `CubicStiffness` (when given): its linear part.
    HubStiffness,
    /// `quintic_stiffness` of `CubicStiffness` (when given): k₅ of −k₅θ⁵.
    QuinticStiffness,
    /// `stiffness_rate` of `CubicStiffness` (when given): k₁′ of −k₁′·t·θ.
    StiffnessRate,
    /// `extra_mode_stiffness_coupling` of `UnmodeledMode` (when given).
    ExtraModeStiffnessCoupling,
    /// `extra_mode_damping_coupling` of `UnmodeledMode` (when given).
    ExtraModeDampingCoupling,
    /// `extra_mode_frequency` of `UnmodeledMode`.
    ExtraModeFrequency,
    /// `extra_mode_damping` of `UnmodeledMode`.
    ExtraModeDamping,
    /// `extra_mode_coupling` of `UnmodeledMode`.
    ExtraModeCoupling,
    /// `backlash` of `Backlash`: the dead band's total width.
    Backlash,
    /// `gear_frequency` of `Backlash`.
    GearFrequency,
    /// `current_knee` of `AmplifierSaturation` (when given): the limiter's knee n.
    CurrentKnee,
    /// `voltage_knee` of `VoltageSaturation` (when given): the limiter's knee n.
    VoltageKnee,
    /// `static_peak` of `CoulombFriction` (when given): F_s − F_c.
    StaticPeak,
    /// `stribeck_velocity` of `CoulombFriction` (when given).
    StribeckVelocity,
}

/// The shortest transport delay or channel lag a model accepts \[s\].
///
/// A delay τ enters A through its Padé state with entries of order 1/τ; below about 10⁻⁹ s the
/// exponential of so stiff an A no longer keeps the other states' accuracy (at 10⁻³⁰⁰ s the strain
/// is off by 1 %), while a delay of a nanosecond is no delay at any rate a rig is sampled at.
pub const MIN_DELAY: f64 = 1e-9;

/// The sign a parameter may take.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SignRule {
    /// Strictly positive.
    Positive,
    /// Zero or positive.
    NonNegative,
    /// Any finite value.
    Any,
}

const CORE: [(&str, ParamId, &str); 13] = [
    ("cv", ParamId::ViscousDamping, "control.viscous_damping"),
    ("kp", ParamId::PositionGain, "control.position_gain"),
    ("rho", ParamId::MassPerLength, "beam.mass_per_length"),
    ("ei_over_rho", ParamId::EiOverRho, "beam.ei_over_rho"),
    ("length", ParamId::Length, "beam.length"),
    ("hub_radius", ParamId::HubRadius, "beam.hub_radius"),
    ("thickness", ParamId::Thickness, "beam.thickness"),
    ("hub_inertia", ParamId::HubInertia, "hub.inertia"),
    ("motor_inertia", ParamId::MotorInertia, "motor.inertia"),
    ("kt", ParamId::TorqueConstant, "motor.torque_constant"),
    ("kb", ParamId::BackEmfConstant, "motor.back_emf_constant"),
    ("ra", ParamId::ArmatureResistance, "motor.armature_resistance"),
    ("amplifier_gain", ParamId::AmplifierGain, "motor.amplifier_gain"),
];

const EFFECT_PARAMS: [(&str, ParamId, &str); 21] = [
    ("backlash", ParamId::Backlash, "dead_band"),
    ("gear_frequency", ParamId::GearFrequency, "gear_frequency_hz"),
    ("current_limit", ParamId::CurrentLimit, "current_limit"),
    ("voltage_limit", ParamId::VoltageLimit, "voltage_limit"),
    ("drag_exponent", ParamId::DragExponent, "exponent"),
    ("cubic_stiffness", ParamId::CubicStiffness, "coefficient"),
    ("hub_stiffness", ParamId::HubStiffness, "linear"),
    ("quintic_stiffness", ParamId::QuinticStiffness, "quintic"),
    ("stiffness_rate", ParamId::StiffnessRate, "rate"),
    ("extra_mode_stiffness_coupling", ParamId::ExtraModeStiffnessCoupling, "stiffness_coupling"),
    ("extra_mode_damping_coupling", ParamId::ExtraModeDampingCoupling, "damping_coupling"),
    ("current_knee", ParamId::CurrentKnee, "knee"),
    ("voltage_knee", ParamId::VoltageKnee, "knee"),
    ("coulomb_torque", ParamId::CoulombTorque, "torque"),
    ("static_peak", ParamId::StaticPeak, "static_peak"),
    ("stribeck_velocity", ParamId::StribeckVelocity, "stribeck_velocity"),
    ("drag_hub", ParamId::DragHub, "hub"),
    ("delay", ParamId::Delay, "delay"),
    ("extra_mode_frequency", ParamId::ExtraModeFrequency, "frequency_hz"),
    ("extra_mode_damping", ParamId::ExtraModeDamping, "damping_ratio"),
    ("extra_mode_coupling", ParamId::ExtraModeCoupling, "coupling"),
];

impl ParamId {
    /// The parameter's name, as used on the command line and in model files.
    pub fn name(self) -> String {
        match self {
            ParamId::ModalDamping(i) => format!("modal_damping_{i}"),
            ParamId::Offset(s) => format!("offset_{}", s.output_name()),
            ParamId::Scale(s) => format!("scale_{}", s.output_name()),
            ParamId::Drift(s) => format!("drift_{}", s.output_name()),
            ParamId::DriftTime(s) => format!("drift_time_{}", s.output_name()),
            ParamId::Crosstalk(s, from) => format!("crosstalk_{}_{}", s.output_name(), from.output_name()),
            ParamId::Lag(s) => format!("lag_{}", s.output_name()),
            other => CORE
                .iter()
                .chain(EFFECT_PARAMS.iter())
                .find(|(_, id, _)| *id == other)
                .map(|(n, _, _)| (*n).to_string())
                .expect("every parameter has a name"),
        }
    }

    /// Where the parameter lives in a model file, e.g. `control.viscous_damping`, or for an
    /// effect `effects.current_limit`.
    pub fn field_path(self) -> String {
        match self {
            ParamId::ModalDamping(i) => format!("modal_damping[{}]", i - 1),
            ParamId::Offset(_) => "effects.offset".into(),
            ParamId::Scale(_) => "effects.scale".into(),
            ParamId::Drift(_) => "effects.rate".into(),
            ParamId::DriftTime(_) => "effects.time_constant".into(),
            ParamId::Crosstalk(..) => "effects.gain".into(),
            ParamId::Lag(_) => "effects.lag".into(),
            other => CORE
                .iter()
                .map(|(_, id, path)| (*id, (*path).to_string()))
                .chain(EFFECT_PARAMS.iter().map(|(_, id, field)| (*id, format!("effects.{field}"))))
                .find(|(id, _)| *id == other)
                .map(|(_, p)| p)
                .expect("every parameter has a path"),
        }
    }

    /// The sign rule of the parameter.
    pub fn sign_rule(self) -> SignRule {
        match self {
            ParamId::Length
            | ParamId::EiOverRho
            | ParamId::MassPerLength
            | ParamId::Thickness
            | ParamId::TorqueConstant
            | ParamId::ArmatureResistance
            | ParamId::AmplifierGain
            | ParamId::CurrentLimit
            | ParamId::Delay
            | ParamId::VoltageLimit
            | ParamId::DragExponent
            | ParamId::ExtraModeFrequency
            | ParamId::Backlash
            | ParamId::GearFrequency
            | ParamId::StribeckVelocity
            | ParamId::CurrentKnee
            | ParamId::VoltageKnee
            | ParamId::Lag(_)
            | ParamId::DriftTime(_) => SignRule::Positive,
            ParamId::Offset(_)
            | ParamId::Scale(_)
            | ParamId::Drift(_)
            | ParamId::Crosstalk(..)
            | ParamId::CubicStiffness
            | ParamId::HubStiffness
            | ParamId::QuinticStiffness
            | ParamId::StiffnessRate
            | ParamId::ExtraModeCoupling
            | ParamId::ExtraModeStiffnessCoupling
            | ParamId::ExtraModeDampingCoupling => SignRule::Any,
            _ => SignRule::NonNegative,
        }
    }

    /// Whether the value must be strictly positive.
    pub fn must_be_positive(self) -> bool {
        self.sign_rule() == SignRule::Positive
    }

    /// Whether the parameter is a delay (of the loop or of a sensor's channel), held to at
    /// least [`MIN_DELAY`].
    pub fn is_delay(self) -> bool {
        matches!(self, ParamId::Delay | ParamId::Lag(_))
    }

    /// The smallest value the parameter may take: [`MIN_DELAY`] for a delay, the smallest
    /// positive normal number for other positive parameters, 0 or −∞ by the sign rule. A fit's
    /// lower bound is never below it.
    pub fn lowest(self) -> f64 {
        match self.sign_rule() {
            SignRule::Positive if self.is_delay() => MIN_DELAY,
            SignRule::Positive => f64::MIN_POSITIVE,
            SignRule::NonNegative => 0.0,
            SignRule::Any => f64::NEG_INFINITY,
        }
    }

    /// Checks a value against the sign rule; `Err` holds the requirement.
    pub fn check(self, value: f64) -> Result<(), String> {
        let rule = self.sign_rule();
        if self.is_delay() && !(value.is_finite() && value >= MIN_DELAY) {
            return Err(format!(
                "must be finite and ≥ {MIN_DELAY:e} s (a shorter delay is no delay at the \
                 exponential's precision: remove the effect instead)"
            ));
        }
        let ok = value.is_finite()
            && match rule {
                SignRule::Positive => value > 0.0,
                SignRule::NonNegative => value >= 0.0,
                SignRule::Any => true,
            };
        match (ok, rule) {
            (true, _) => Ok(()),
            (false, SignRule::Positive) => Err("must be finite and > 0".into()),
            (false, SignRule::NonNegative) => Err("must be finite and ≥ 0".into()),
            (false, SignRule::Any) => Err("must be finite".into()),
        }
    }

    /// The core (effect-free) parameter names of a model with `n_modes` flexible modes.
    pub fn all(n_modes: usize) -> Vec<ParamId> {
        let mut ids = vec![ParamId::ViscousDamping, ParamId::PositionGain];
        ids.extend((1..=n_modes).map(ParamId::ModalDamping));
        ids.extend(CORE[2..].iter().map(|(_, id, _)| *id));
        ids
    }

    /// The parameters an effect brings.
    pub fn of_effect<D>(effect: &Effect<D>) -> Vec<ParamId> {
        match effect {
            Effect::AmplifierSaturation { knee, .. } => {
                [Some(ParamId::CurrentLimit), knee.as_ref().map(|_| ParamId::CurrentKnee)]
                    .into_iter()
                    .flatten()
                    .collect()
            }
            Effect::VoltageSaturation { knee, .. } => {
                [Some(ParamId::VoltageLimit), knee.as_ref().map(|_| ParamId::VoltageKnee)]
                    .into_iter()
                    .flatten()
                    .collect()
            }
            Effect::CoulombFriction { static_peak, stribeck_velocity, .. } => {
                let mut ids = vec![ParamId::CoulombTorque];
                if static_peak.is_some() {
                    ids.push(ParamId::StaticPeak);
                }
                if stribeck_velocity.is_some() {
                    ids.push(ParamId::StribeckVelocity);
                }
                ids
            }
            Effect::QuadraticDrag { exponent, .. } => {
                let mut ids = vec![ParamId::DragHub];
                if exponent.is_some() {
                    ids.push(ParamId::DragExponent);
                }
                ids
            }
            Effect::CubicStiffness { linear, quintic, rate, .. } => {
                let mut ids = vec![ParamId::CubicStiffness];
                if linear.is_some() {
                    ids.push(ParamId::HubStiffness);
                }
                if quintic.is_some() {
                    ids.push(ParamId::QuinticStiffness);
                }
                if rate.is_some() {
                    ids.push(ParamId::StiffnessRate);
                }
                ids
            }
            Effect::Backlash { .. } => vec![ParamId::Backlash, ParamId::GearFrequency],
            Effect::SensorQuantization { .. } => vec![],
            Effect::OutputOffset { sensor, .. } => vec![ParamId::Offset(*sensor)],
            Effect::SensorScale { sensor, .. } => vec![ParamId::Scale(*sensor)],
            Effect::SensorDrift { sensor, time_constant, .. } => {
                let mut ids = vec![ParamId::Drift(*sensor)];
                if time_constant.is_some() {
                    ids.push(ParamId::DriftTime(*sensor));
                }
                ids
            }
            Effect::TimeDelay { .. } => vec![ParamId::Delay],
            Effect::SensorCrosstalk { sensor, from, .. } => vec![ParamId::Crosstalk(*sensor, *from)],
            Effect::SensorLag { sensor, .. } => vec![ParamId::Lag(*sensor)],
            Effect::UnmodeledMode { stiffness_coupling, damping_coupling, .. } => {
                let mut ids =
                    vec![ParamId::ExtraModeFrequency, ParamId::ExtraModeDamping, ParamId::ExtraModeCoupling];
                if stiffness_coupling.is_some() {
                    ids.push(ParamId::ExtraModeStiffnessCoupling);
                }
                if damping_coupling.is_some() {
                    ids.push(ParamId::ExtraModeDampingCoupling);
                }
                ids
            }
        }
    }

    /// Looks a name up among `ids`.
    ///
    /// # Errors
    /// [`PlantError::UnknownParameter`] listing the valid names.
    pub fn parse_among(name: &str, ids: &[ParamId]) -> Result<ParamId, PlantError> {
        ids.iter().copied().find(|id| id.name() == name).ok_or_else(|| PlantError::UnknownParameter {
            name: name.to_string(),
            valid: ids.iter().map(|id| id.name()).collect::<Vec<_>>().join(", "),
        })
    }
}

/// The field of `Constants` that a core `ParamId` names, borrowed with the given reference kind.
macro_rules! core_field {
    ([$($borrow:tt)+] $s:ident, $id:expr) => {
        match $id {
            ParamId::ViscousDamping => Some($($borrow)+ $s.viscous_damping),
            ParamId::PositionGain => Some($($borrow)+ $s.position_gain),
            ParamId::ModalDamping(i) => (i >= 1 && i <= $s.modal_damping.len()).then(|| $($borrow)+ $s.modal_damping[i - 1]),
            ParamId::MassPerLength => Some($($borrow)+ $s.mass_per_length),
            ParamId::EiOverRho => Some($($borrow)+ $s.ei_over_rho),
            ParamId::Length => Some($($borrow)+ $s.length),
            ParamId::HubRadius => Some($($borrow)+ $s.hub_radius),
            ParamId::Thickness => Some($($borrow)+ $s.thickness),
            ParamId::HubInertia => Some($($borrow)+ $s.hub_inertia),
            ParamId::MotorInertia => Some($($borrow)+ $s.motor_inertia),
            ParamId::TorqueConstant => Some($($borrow)+ $s.torque_constant),
            ParamId::BackEmfConstant => Some($($borrow)+ $s.back_emf_constant),
            ParamId::ArmatureResistance => Some($($borrow)+ $s.armature_resistance),
            ParamId::AmplifierGain => Some($($borrow)+ $s.amplifier_gain),
            _ => None,
        }
    };
}

/// The effect field that an effect `ParamId` names.
macro_rules! effect_field {
    ([$($borrow:tt)+] $effects:expr, $id:expr) => {
        $effects.into_iter().find_map(|e| match (e, $id) {
            (Effect::AmplifierSaturation { current_limit, .. }, ParamId::CurrentLimit) => Some(current_limit),
            (Effect::VoltageSaturation { voltage_limit, .. }, ParamId::VoltageLimit) => Some(voltage_limit),
            (Effect::AmplifierSaturation { knee: Some(n), .. }, ParamId::CurrentKnee) => Some(n),
            (Effect::VoltageSaturation { knee: Some(n), .. }, ParamId::VoltageKnee) => Some(n),
            (Effect::CoulombFriction { torque, .. }, ParamId::CoulombTorque) => Some(torque),
            (Effect::CoulombFriction { static_peak: Some(p), .. }, ParamId::StaticPeak) => Some(p),
            (Effect::CoulombFriction { stribeck_velocity: Some(v), .. }, ParamId::StribeckVelocity) => {
                Some(v)
            }
            (Effect::QuadraticDrag { hub, .. }, ParamId::DragHub) => Some(hub),
            (Effect::QuadraticDrag { exponent: Some(p), .. }, ParamId::DragExponent) => Some(p),
            (Effect::CubicStiffness { coefficient, .. }, ParamId::CubicStiffness) => Some(coefficient),
            (Effect::CubicStiffness { linear: Some(k), .. }, ParamId::HubStiffness) => Some(k),
            (Effect::CubicStiffness { quintic: Some(k), .. }, ParamId::QuinticStiffness) => Some(k),
            (Effect::CubicStiffness { rate: Some(k), .. }, ParamId::StiffnessRate) => Some(k),
            (Effect::TimeDelay { delay }, ParamId::Delay) => Some(delay),
            (Effect::Backlash { dead_band, .. }, ParamId::Backlash) => Some(dead_band),
            (Effect::Backlash { gear_frequency_hz, .. }, ParamId::GearFrequency) => Some(gear_frequency_hz),
            (Effect::OutputOffset { sensor, offset }, ParamId::Offset(s)) if *sensor == s => Some(offset),
            (Effect::SensorScale { sensor, scale }, ParamId::Scale(s)) if *sensor == s => Some(scale),
            (Effect::SensorDrift { sensor, rate, .. }, ParamId::Drift(s)) if *sensor == s => Some(rate),
            (Effect::SensorCrosstalk { sensor, from, gain }, ParamId::Crosstalk(s, f))
                if *sensor == s && *from == f =>
            {
                Some(gain)
            }
            (Effect::SensorLag { sensor, lag }, ParamId::Lag(s)) if *sensor == s => Some(lag),
            (Effect::SensorDrift { sensor, time_constant: Some(tau), .. }, ParamId::DriftTime(s))
                if *sensor == s =>
            {
                Some(tau)
            }
            (
                Effect::UnmodeledMode { stiffness_coupling: Some(k), .. },
                ParamId::ExtraModeStiffnessCoupling,
            ) => Some(k),
            (Effect::UnmodeledMode { damping_coupling: Some(c), .. }, ParamId::ExtraModeDampingCoupling) => {
                Some(c)
            }
            (Effect::UnmodeledMode { frequency_hz, .. }, ParamId::ExtraModeFrequency) => Some(frequency_hz),
            (Effect::UnmodeledMode { damping_ratio, .. }, ParamId::ExtraModeDamping) => Some(damping_ratio),
            (Effect::UnmodeledMode { coupling, .. }, ParamId::ExtraModeCoupling) => Some(coupling),
            _ => None,
        })
    };
}

impl<D: Clone> Constants<D> {
    /// The value of one parameter.
    ///
    /// # Panics
    /// If the parameter belongs to an effect the model does not have (ids obtained from
    /// [`crate::SlewingModel::parameter`] always exist).
    pub fn get(&self, id: ParamId) -> D {
        self.try_get(id).expect("the parameter exists in this model")
    }

    /// The value of one parameter, if the model has it.
    pub fn try_get(&self, id: ParamId) -> Option<D> {
        core_field!([&] self, id).or_else(|| effect_field!([&] self.effects.iter(), id)).cloned()
    }

    /// A mutable reference to one parameter.
    ///
    /// # Panics
    /// As [`Self::get`].
    pub fn field_mut(&mut self, id: ParamId) -> &mut D {
        if let Some(f) = core_field!([&mut] self, id) {
            return f;
        }
        effect_field!([&mut] self.effects.iter_mut(), id).expect("the parameter exists in this model")
    }

    /// Every parameter this model has: the core ones and those of its effects.
    pub fn parameter_ids(&self) -> Vec<ParamId> {
        let mut ids = ParamId::all(self.modal_damping.len());
        for e in &self.effects {
            ids.extend(ParamId::of_effect(e));
        }
        ids
    }

    /// Converts every value with `f` (e.g. f64 → dual number).
    pub fn map<E>(&self, f: impl Fn(&D) -> E) -> Constants<E> {
        Constants {
            length: f(&self.length),
            ei_over_rho: f(&self.ei_over_rho),
            mass_per_length: f(&self.mass_per_length),
            hub_radius: f(&self.hub_radius),
            thickness: f(&self.thickness),
            hub_inertia: f(&self.hub_inertia),
            motor_inertia: f(&self.motor_inertia),
            torque_constant: f(&self.torque_constant),
            back_emf_constant: f(&self.back_emf_constant),
            armature_resistance: f(&self.armature_resistance),
            amplifier_gain: f(&self.amplifier_gain),
            position_gain: f(&self.position_gain),
            viscous_damping: f(&self.viscous_damping),
            modal_damping: self.modal_damping.iter().map(&f).collect(),
            effects: self.effects.iter().map(|e| e.map(&f)).collect(),
        }
    }
}
