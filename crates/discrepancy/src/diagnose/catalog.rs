//! The candidates: each catalog effect where it can act on this model, with starting values
//! taken from the model and the data (never from a study's truth) and plausible bounds.

use crate::localise::Localisation;
use plant::{Effect, EffectKind, ModeKind, ParamId, Sensor, SlewingModel};

/// A candidate to try: the effect with its starting values, the bounds of its parameters, and
/// which parameters measure its strength (0 means "no effect").
#[derive(Clone, Debug)]
pub struct Trial {
    /// The effect as it is added to the model.
    pub effect: Effect,
    /// Its kind.
    pub kind: EffectKind,
    /// The sensor it acts on, for a sensor effect.
    pub sensor: Option<Sensor>,
    /// The catalog name with its target, e.g. `output_offset(theta)`.
    pub label: String,
    /// Bounds of the effect's parameters.
    pub bounds: Vec<(ParamId, (f64, f64))>,
    /// How far from "no effect" the fitted effect is.
    pub strength: Vec<Strength>,
}

/// A parameter that measures an effect's strength, and where the effect vanishes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Strength {
    /// The effect vanishes at 0 (either sign acts).
    Nonzero(ParamId),
    /// A limit on the loop's current or voltage: it vanishes once the limit is well above the
    /// largest demand on it (1.5× the demand at the start, where the smooth limiter's
    /// compression is below 0.05 %); the demand is the fitted model's.
    Limit(ParamId, Demand),
}

/// What a limit limits.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Demand {
    /// The armature current G K_p θ(0)/R_a at the start.
    Current,
    /// The amplifier's output G K_p θ(0) at the start.
    Voltage,
}

impl Demand {
    /// Its value for `model`.
    pub fn of(self, model: &SlewingModel) -> f64 {
        let c = model.constants();
        let volts = c.amplifier_gain * c.position_gain * model.initial_state()[0].abs();
        match self {
            Demand::Current => volts / c.armature_resistance,
            Demand::Voltage => volts,
        }
    }
}

impl Strength {
    /// The parameter.
    pub fn id(self) -> ParamId {
        match self {
            Strength::Nonzero(id) | Strength::Limit(id, _) => id,
        }
    }
    /// The distance of `value` from "no effect" in units of `std_error` for the fitted `model`
    /// (negative for a limit above where it acts).
    pub fn z(self, value: f64, std_error: f64, model: &SlewingModel) -> f64 {
        match self {
            Strength::Nonzero(_) => value.abs() / std_error,
            Strength::Limit(_, demand) => (1.5 * demand.of(model) - value) / std_error,
        }
    }
}

/// The scales the starting values come from: the loop's own quantities at the start.
struct Scales {
    theta0: f64,
    /// Servo stiffness k_s \[N·m/rad\].
    servo_stiffness: f64,
    /// The current the loop demands at the start \[A\].
    demand_current: f64,
    /// The voltage the amplifier is asked for at the start \[V\].
    demand_voltage: f64,
    /// A typical peak rate ω_servo·θ(0) \[rad/s\].
    rate: f64,
}

fn scales(model: &SlewingModel) -> Scales {
    let c = model.constants();
    let theta0 = model.initial_state()[0].abs().max(1e-3);
    let servo_stiffness = c.amplifier_gain * c.position_gain * c.torque_constant / c.armature_resistance;
    let omega = model
        .modal()
        .ok()
        .and_then(|rows| rows.into_iter().find(|r| r.kind == ModeKind::Servo))
        .map_or(1.0, |r| 2.0 * std::f64::consts::PI * r.frequency_hz);
    Scales {
        theta0,
        servo_stiffness,
        demand_current: c.amplifier_gain * c.position_gain * theta0 / c.armature_resistance,
        demand_voltage: c.amplifier_gain * c.position_gain * theta0,
        rate: omega * theta0,
    }
}

fn trial(
    effect: Effect,
    label: String,
    bounds: Vec<(ParamId, (f64, f64))>,
    strength: Vec<Strength>,
) -> Trial {
    let kind = effect.kind();
    let sensor = effect.sensor();
    Trial { effect, kind, sensor, label, bounds, strength }
}

/// The catalog's candidates for `model` (which already carries the effects found so far), with
/// the residual modes of `localisation` for an unmodeled mode. Effects the model has are not
/// tried again (sensor effects: not again on the same sensor).
pub fn trials(model: &SlewingModel, localisation: &Localisation) -> Vec<Trial> {
    let s = scales(model);
    let c = model.constants();
    let mut out = vec![
        trial(
            Effect::AmplifierSaturation { current_limit: 0.5 * s.demand_current, sharp: false },
            "amplifier_saturation".into(),
            vec![(ParamId::CurrentLimit, (0.01 * s.demand_current, 3.0 * s.demand_current))],
            vec![Strength::Limit(ParamId::CurrentLimit, Demand::Current)],
        ),
        trial(
            Effect::VoltageSaturation { voltage_limit: 0.5 * s.demand_voltage, sharp: false },
            "voltage_saturation".into(),
            vec![(ParamId::VoltageLimit, (0.01 * s.demand_voltage, 3.0 * s.demand_voltage))],
            vec![Strength::Limit(ParamId::VoltageLimit, Demand::Voltage)],
        ),
        trial(
            // Smoothing over 0.05 % of the peak rate: a dry-friction switch, as sharp as the
            // solver follows without fuss.
            Effect::CoulombFriction {
                torque: 0.02 * s.servo_stiffness * s.theta0,
                smoothing_velocity: 5e-4 * s.rate,
            },
            "coulomb_friction".into(),
            vec![(ParamId::CoulombTorque, (0.0, s.servo_stiffness * s.theta0))],
            vec![Strength::Nonzero(ParamId::CoulombTorque)],
        ),
        trial(
            // Drag equal to 20 % of the viscous torque at the peak rate.
            Effect::QuadraticDrag { hub: 0.2 * c.viscous_damping.max(1e-3) / s.rate, exponent: Some(2.0) },
            "quadratic_drag".into(),
            vec![
                (ParamId::DragHub, (0.0, 200.0 * c.viscous_damping.max(1e-3) / s.rate)),
                (ParamId::DragExponent, (1.2, 3.5)),
            ],
            vec![Strength::Nonzero(ParamId::DragHub)],
        ),
        trial(
            Effect::CubicStiffness { coefficient: 0.0 },
            "cubic_stiffness".into(),
            vec![(
                ParamId::CubicStiffness,
                (-10.0 * s.servo_stiffness / s.theta0.powi(2), 10.0 * s.servo_stiffness / s.theta0.powi(2)),
            )],
            vec![Strength::Nonzero(ParamId::CubicStiffness)],
        ),
        trial(
            Effect::TimeDelay { delay: 0.02 },
            "time_delay".into(),
            vec![(ParamId::Delay, (1e-4, 2.0))],
            vec![Strength::Nonzero(ParamId::Delay)],
        ),
    ];
    for sensor in model.sensors() {
        let name = sensor.output_name();
        out.push(trial(
            Effect::OutputOffset { sensor: *sensor, offset: 0.0 },
            format!("output_offset({name})"),
            vec![],
            vec![Strength::Nonzero(ParamId::Offset(*sensor))],
        ));
        out.push(trial(
            Effect::SensorScale { sensor: *sensor, scale: 0.0 },
            format!("sensor_scale({name})"),
            vec![(ParamId::Scale(*sensor), (-0.9, 9.0))],
            vec![Strength::Nonzero(ParamId::Scale(*sensor))],
        ));
        out.push(trial(
            Effect::SensorDrift { sensor: *sensor, rate: 0.0 },
            format!("sensor_drift({name})"),
            vec![],
            vec![Strength::Nonzero(ParamId::Drift(*sensor))],
        ));
    }
    let existing: Vec<f64> =
        model.modal().map(|rows| rows.iter().map(|r| r.frequency_hz).collect()).unwrap_or_default();
    if let Some(m) = localisation
        .residual_modes
        .iter()
        .find(|m| existing.iter().all(|f| (m.frequency_hz / f - 1.0).abs() > 0.1))
    {
        let bounds = |f: f64| {
            vec![
                (ParamId::ExtraModeFrequency, (0.5 * f, 2.0 * f)),
                (ParamId::ExtraModeDamping, (0.0, 0.5)),
                (ParamId::ExtraModeCoupling, (-0.5, 0.5)),
                (
                    ParamId::ExtraModeStiffnessCoupling,
                    (-100.0 * s.servo_stiffness, 100.0 * s.servo_stiffness),
                ),
            ]
        };
        let damping = m.damping_ratio.clamp(0.005, 0.3);
        out.push(trial(
            Effect::UnmodeledMode {
                frequency_hz: m.frequency_hz,
                damping_ratio: damping,
                coupling: 0.02,
                stiffness_coupling: None,
            },
            "unmodeled_mode".into(),
            bounds(m.frequency_hz)[..3].to_vec(),
            vec![Strength::Nonzero(ParamId::ExtraModeCoupling)],
        ));
        out.push(trial(
            Effect::UnmodeledMode {
                frequency_hz: m.frequency_hz,
                damping_ratio: damping,
                coupling: 0.0,
                stiffness_coupling: Some(0.02 * s.servo_stiffness),
            },
            "unmodeled_mode(stiffness)".into(),
            bounds(m.frequency_hz),
            vec![Strength::Nonzero(ParamId::ExtraModeStiffnessCoupling)],
        ));
    }
    out.retain(|t| !model.effects().iter().any(|e| e.kind() == t.kind && e.sensor() == t.sensor));
    out
}

/// The parameters a trial frees besides the baseline's: the effect's own, except the mass
/// coupling of a stiffness-coupled mode (held at 0).
pub fn freed(trial: &Trial) -> Vec<ParamId> {
    ParamId::of_effect(&trial.effect)
        .into_iter()
        .filter(|id| !(trial.label.ends_with("(stiffness)") && *id == ParamId::ExtraModeCoupling))
        .collect()
}
