//! The names of the model's constants: [`ParamId`], its sign rules and bounds, and the names
//! used on the command line and in model files.

use crate::PlantError;
use crate::effects::Effect;
use crate::sensors::Sensor;

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
