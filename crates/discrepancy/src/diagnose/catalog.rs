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
    /// Other starting values of the same effect: a nonlinear effect's error surface can hold
    /// a local minimum in which the free parameters partly stand in for it, and the refit keeps
    /// the best of its starts.
    pub alternatives: Vec<Effect>,
    /// The effect of the model it takes the place of: a sibling already named (a current limit
    /// for a voltage limit, or back), which an earlier run could not tell from this one.
    pub replaces: Option<EffectKind>,
}

impl Trial {
    /// Adds another starting point.
    fn or_from(mut self, effect: Effect) -> Self {
        self.alternatives.push(effect);
        self
    }
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
    /// The rotating inertia about the hub, I_H + I_m + ρ((a + L)³ − a³)/3 \[kg·m²\]: a mode's
    /// mass coupling c keeps the mass matrix positive only for c² < it.
    inertia: f64,
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
        inertia: c.hub_inertia
            + c.motor_inertia
            + c.mass_per_length * ((c.hub_radius + c.length).powi(3) - c.hub_radius.powi(3)) / 3.0,
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
    Trial { effect, kind, sensor, label, bounds, strength, alternatives: Vec::new(), replaces: None }
}

/// The catalog's candidates for `model` (which already carries the effects found so far), with
/// the residual modes of `localisation` for an unmodeled mode. Effects the model has are not
/// tried again (sensor effects: not again on the same sensor).
pub fn trials(model: &SlewingModel, localisation: &Localisation) -> Vec<Trial> {
    let s = scales(model);
    let c = model.constants();
    let mut out = vec![
        out_of(&s, EffectKind::AmplifierSaturation),
        out_of(&s, EffectKind::VoltageSaturation),
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
        )
        .or_from(Effect::CoulombFriction {
            torque: 0.1 * s.servo_stiffness * s.theta0,
            smoothing_velocity: 5e-4 * s.rate,
        }),
        trial(
            // Drag equal to 20 % of the viscous torque at the peak rate.
            Effect::QuadraticDrag { hub: 0.2 * c.viscous_damping.max(1e-3) / s.rate, exponent: Some(2.0) },
            "quadratic_drag".into(),
            vec![
                (ParamId::DragHub, (0.0, 200.0 * c.viscous_damping.max(1e-3) / s.rate)),
                (ParamId::DragExponent, (1.2, 3.5)),
            ],
            vec![Strength::Nonzero(ParamId::DragHub)],
        )
        .or_from(Effect::QuadraticDrag { hub: c.viscous_damping.max(1e-3) / s.rate, exponent: Some(2.0) }),
        trial(
            // Hardening and softening starts: a cubic changes the frequency with amplitude, and
            // the position gain can take up part of it from either side of zero.
            Effect::CubicStiffness { coefficient: 0.05 * s.servo_stiffness / s.theta0.powi(2) },
            "cubic_stiffness".into(),
            vec![(
                ParamId::CubicStiffness,
                (-10.0 * s.servo_stiffness / s.theta0.powi(2), 10.0 * s.servo_stiffness / s.theta0.powi(2)),
            )],
            vec![Strength::Nonzero(ParamId::CubicStiffness)],
        )
        .or_from(Effect::CubicStiffness { coefficient: -0.05 * s.servo_stiffness / s.theta0.powi(2) }),
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
    let servo = model
        .modal()
        .ok()
        .and_then(|rows| rows.into_iter().find(|r| r.kind == ModeKind::Servo))
        .map(|r| r.frequency_hz);
    for (f, zeta, (low, high)) in mode_seeds(servo, localisation) {
        let damping = zeta.clamp(0.005, 0.15);
        let bounds = vec![
            (ParamId::ExtraModeFrequency, (low, high)),
            (ParamId::ExtraModeDamping, (0.0, 0.2)),
            (ParamId::ExtraModeCoupling, (-0.95 * s.inertia.sqrt(), 0.95 * s.inertia.sqrt())),
            (ParamId::ExtraModeStiffnessCoupling, (-100.0 * s.servo_stiffness, 100.0 * s.servo_stiffness)),
        ];
        out.push(trial(
            Effect::UnmodeledMode {
                frequency_hz: f,
                damping_ratio: damping,
                coupling: 0.02,
                stiffness_coupling: None,
                damping_coupling: None,
            },
            format!("unmodeled_mode(inertia, {f:.2} Hz)"),
            bounds[..3].to_vec(),
            vec![Strength::Nonzero(ParamId::ExtraModeCoupling)],
        ));
        out.push(trial(
            Effect::UnmodeledMode {
                frequency_hz: f,
                damping_ratio: damping,
                coupling: 0.0,
                stiffness_coupling: Some(0.02 * s.servo_stiffness),
                damping_coupling: None,
            },
            format!("unmodeled_mode(stiffness, {f:.2} Hz)"),
            bounds[..4].to_vec(),
            vec![Strength::Nonzero(ParamId::ExtraModeStiffnessCoupling)],
        ));
        // Through damping: a damper between the hub and the mode. The damping matrix stays
        // positive semi-definite for c_d² ≤ d_hub·2ζω, d_hub = C_v + K_bK_t/R_a.
        let d_hub = c.viscous_damping + c.back_emf_constant * c.torque_constant / c.armature_resistance;
        let omega = 2.0 * std::f64::consts::PI * f;
        let limit = (d_hub * 2.0 * 0.2 * 2.0 * std::f64::consts::PI * high).sqrt();
        let mut bounds = bounds;
        bounds.push((ParamId::ExtraModeDampingCoupling, (-limit, limit)));
        bounds.remove(3);
        out.push(trial(
            Effect::UnmodeledMode {
                frequency_hz: f,
                damping_ratio: damping,
                coupling: 0.0,
                stiffness_coupling: None,
                damping_coupling: Some(0.3 * (d_hub * 2.0 * damping * omega).sqrt()),
            },
            format!("unmodeled_mode(damping, {f:.2} Hz)"),
            bounds,
            vec![Strength::Nonzero(ParamId::ExtraModeDampingCoupling)],
        ));
    }
    out.retain(|t| !model.effects().iter().any(|e| e.kind() == t.kind && e.sensor() == t.sensor));
    // A saturation already named may be its sibling: at the start of a decay both limits act
    // alike, and only the rest of the model tells them apart. Offer the swap, from the limit
    // that gives the same torque at rest (V = R_a·I).
    let swap = |t: Trial, replaces: EffectKind| Trial {
        label: format!("{} (in place of {})", t.label, replaces.name()),
        replaces: Some(replaces),
        ..t
    };
    for effect in model.effects().to_vec() {
        let r = c.armature_resistance;
        match effect {
            Effect::VoltageSaturation { voltage_limit, sharp } => {
                let mut t = out_of(&s, EffectKind::AmplifierSaturation);
                t.effect = Effect::AmplifierSaturation { current_limit: voltage_limit / r, sharp };
                out.push(swap(t, EffectKind::VoltageSaturation));
            }
            Effect::AmplifierSaturation { current_limit, sharp } => {
                let mut t = out_of(&s, EffectKind::VoltageSaturation);
                t.effect = Effect::VoltageSaturation { voltage_limit: current_limit * r, sharp };
                out.push(swap(t, EffectKind::AmplifierSaturation));
            }
            _ => {}
        }
    }
    out
}

/// The catalog's saturation trial of `kind` (amplifier current or voltage limit).
fn out_of(s: &Scales, kind: EffectKind) -> Trial {
    match kind {
        EffectKind::VoltageSaturation => trial(
            Effect::VoltageSaturation { voltage_limit: 0.5 * s.demand_voltage, sharp: false },
            "voltage_saturation".into(),
            vec![(ParamId::VoltageLimit, (0.01 * s.demand_voltage, 3.0 * s.demand_voltage))],
            vec![Strength::Limit(ParamId::VoltageLimit, Demand::Voltage)],
        )
        .or_from(Effect::VoltageSaturation { voltage_limit: 0.9 * s.demand_voltage, sharp: false }),
        _ => trial(
            Effect::AmplifierSaturation { current_limit: 0.5 * s.demand_current, sharp: false },
            "amplifier_saturation".into(),
            vec![(ParamId::CurrentLimit, (0.01 * s.demand_current, 3.0 * s.demand_current))],
            vec![Strength::Limit(ParamId::CurrentLimit, Demand::Current)],
        )
        .or_from(Effect::AmplifierSaturation { current_limit: 0.9 * s.demand_current, sharp: false }),
    }
}

/// The parameters a trial frees besides the baseline's: the effect's own, except the mass
/// coupling of a mode coupled through stiffness or damping (held at 0).
pub fn freed(trial: &Trial) -> Vec<ParamId> {
    let stiffness_coupled = matches!(
        trial.effect,
        Effect::UnmodeledMode { stiffness_coupling: Some(_), .. }
            | Effect::UnmodeledMode { damping_coupling: Some(_), .. }
    );
    ParamId::of_effect(&trial.effect)
        .into_iter()
        .filter(|id| !(stiffness_coupled && *id == ParamId::ExtraModeCoupling))
        .collect()
}

/// Cycles an unmodeled mode must complete within the record.
const MIN_CYCLES: f64 = 3.0;

/// Where an unmodeled mode may be: lightly damped physical modes of the baseline's residual and
/// of the data itself, at most two, more than 25 % from the servo mode and 10 % from each other,
/// with the frequency within a factor 2 of the seed and 25 % clear of the servo. A mode near a
/// modelled flexible mode is allowed: coupled to the hub, a new mode and a modelled one beat
/// (two peaks where the model has one), which no retuning of the modelled mode reproduces;
/// near the servo, a heavily coupled "mode" would only reshape the servo's own response.
fn mode_seeds(servo: Option<f64>, localisation: &Localisation) -> Vec<(f64, f64, (f64, f64))> {
    let record = localisation.windows.last().map_or(f64::INFINITY, |w| w.1);
    let mut seeds: Vec<(f64, f64, (f64, f64))> = Vec::new();
    for m in localisation.residual_modes.iter().chain(&localisation.data_modes) {
        let f = m.frequency_hz;
        let near_servo = servo.is_some_and(|s| (f / s - 1.0).abs() < 0.25);
        if !(m.physical && m.damping_ratio < 0.2)
            || near_servo
            || seeds.iter().any(|s| (s.0 / f - 1.0).abs() < 0.1)
        {
            continue;
        }
        // A mode needs three cycles in the record to be told from a trend.
        let (mut low, mut high) = (0.5 * f, 2.0 * f);
        low = low.max(MIN_CYCLES / record);
        if let Some(s) = servo {
            if s < f {
                low = low.max(1.25 * s);
            } else {
                high = high.min(s / 1.25);
            }
        }
        if low < f && f < high {
            seeds.push((f, m.damping_ratio, (low, high)));
        }
        if seeds.len() == 2 {
            break;
        }
    }
    seeds
}
