//! The slewing rig's candidates: saturations, friction, drag, a cubic spring and a delay in the
//! loop, sensor effects, and an unmodeled mode coupled to the hub.

use super::{Clear, Demand, LIGHTLY_DAMPED, Located, Pole, Seed, Strength, Trial, mode_seeds};
use crate::localise::Localisation;
use plant::{Effect, EffectKind, ModeKind, ParamId, SlewingModel};

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
    let servo_stiffness = plant::assemble::servo_stiffness(c);
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

/// The scales a hub spring's form is bounded in (`spring`): the servo stiffness k_s
/// \[N·m/rad\] and the release angle θ(0) \[rad\].
pub(in crate::diagnose) fn spring_scales(model: &SlewingModel) -> (f64, f64) {
    let s = scales(model);
    (s.servo_stiffness, s.theta0)
}

fn trial(
    effect: Effect,
    label: String,
    bounds: Vec<(ParamId, (f64, f64))>,
    strength: Vec<Strength>,
) -> Trial {
    let kind = effect.kind();
    let sensor = effect.sensor();
    let freed = freed(&effect).into_iter().map(ParamId::name).collect();
    let bounds = bounds.into_iter().map(|(id, b)| (id.name(), b)).collect();
    let mut t = Trial::new(effect.into(), kind, label, bounds, strength, freed);
    t.sensor = sensor;
    t
}

/// The trial of an unmodeled mode from `seed`.
fn mode_trial(
    effect: Effect,
    prefix: String,
    bounds: Vec<(ParamId, (f64, f64))>,
    strength: Vec<Strength>,
    seed: &Seed,
) -> Trial {
    let located = Located {
        name: ParamId::ExtraModeFrequency.name(),
        limits: seed.limits,
        prefix,
        damping: ParamId::ExtraModeDamping.name(),
        pole: Pole::Ringing,
    };
    let at = |f: f64| {
        let mut e = effect.clone();
        if let Effect::UnmodeledMode { frequency_hz, .. } = &mut e {
            *frequency_hz = f;
        }
        e
    };
    let mut t = trial(at(seed.frequency), located.label(seed.frequency), bounds, strength)
        .or_from_other_starts(seed, at);
    t.located = Some(located);
    t
}

/// "No effect" at zero of `id`.
fn nonzero(id: ParamId) -> Strength {
    Strength::Nonzero(id.name())
}

/// The parameters a trial frees besides the baseline's: the effect's own, except the mass
/// coupling of a mode coupled through stiffness or damping (held at 0).
fn freed(effect: &Effect) -> Vec<ParamId> {
    let stiffness_coupled = matches!(
        effect,
        Effect::UnmodeledMode { stiffness_coupling: Some(_), .. }
            | Effect::UnmodeledMode { damping_coupling: Some(_), .. }
    );
    ParamId::of_effect(effect)
        .into_iter()
        .filter(|id| !(stiffness_coupled && *id == ParamId::ExtraModeCoupling))
        .collect()
}

/// Where a named dry friction's static peak is looked for ([`super::StaticPeakSearch`]): the
/// peak ΔF = F_s − F_c within the Coulomb torque's own range (0 to the servo torque at θ(0)),
/// the Stribeck velocity v_st from 0.2 % to half the typical peak rate (its lower end four
/// smoothing velocities, so that the peak is not a second smoothing of the switch), started at
/// 1 % and 5 % of that rate — the Stribeck velocities of servo bearings and gears are a small
/// fraction of their working speeds (Armstrong-Hélouvry et al. 1994).
pub(super) fn static_peak(model: &SlewingModel, smoothing_velocity: f64) -> super::StaticPeakSearch {
    let s = scales(model);
    super::StaticPeakSearch {
        peak: (ParamId::StaticPeak.name(), (0.0, s.servo_stiffness * s.theta0)),
        velocity: (ParamId::StribeckVelocity.name(), (2e-3 * s.rate, 0.5 * s.rate)),
        coulomb: ParamId::CoulombTorque.name(),
        velocity_starts: vec![1e-2 * s.rate, 5e-2 * s.rate],
        smoothing_velocity,
    }
}

/// The sharpest knee a limiter is given: the clamp end of the family x/(1 + |x/L|ⁿ)^{1/n}
/// (within 0.35 % of the clamp at the limit), the trial's clamp start and the knee's bound.
const SHARPEST_KNEE: f64 = 200.0;

/// Where a named saturation's knee is looked for ([`super::KneeSearch`]): n from 1 (a limiter
/// as soft as x/(1 + |x/L|)) to 200 (within 0.35 % of the clamp at the limit; at 50, 1.4 %
/// left the limit of the blind set's clamps 1–2 % high, 4–6 standard errors), started at 2 (the
/// soft limit x/√(1 + (x/L)²), near a tanh) and at 50 (a clamp: from the catalog's 8 the same
/// optimum took longer to reach: 4.35 against 4.10 s a command over the 13 blind clamps); the limit beside it from
/// 1 % to 10 times the demand at θ(0), since a soft limiter bends the output well below its
/// level.
pub(super) fn knee(model: &SlewingModel, kind: EffectKind) -> super::KneeSearch {
    let s = scales(model);
    let (id, limit, demand) = match kind {
        EffectKind::VoltageSaturation => (ParamId::VoltageKnee, ParamId::VoltageLimit, s.demand_voltage),
        _ => (ParamId::CurrentKnee, ParamId::CurrentLimit, s.demand_current),
    };
    super::KneeSearch {
        knee: (id.name(), (1.0, SHARPEST_KNEE)),
        limit: (limit.name(), (0.01 * demand, 10.0 * demand)),
        knee_starts: vec![2.0, 50.0],
        kind,
    }
}

/// The catalog's candidates for `model` (which already carries the effects found so far), with
/// the residual modes of `localisation` for an unmodeled mode. Effects the model has are not
/// tried again (sensor effects: not again on the same sensor).
pub(super) fn trials(model: &SlewingModel, localisation: &Localisation) -> Vec<Trial> {
    let s = scales(model);
    let c = model.constants();
    // The dearest fits first, so that the parallel fits end together.
    let mut out = backlash(&s, model);
    out.extend([
        out_of(&s, EffectKind::AmplifierSaturation),
        out_of(&s, EffectKind::VoltageSaturation),
        trial(
            // Smoothing over 0.05 % of the peak rate: a dry-friction switch, as sharp as the
            // solver follows without fuss. Three starts on a log grid (0.4, 2 and 10 % of the
            // servo torque at θ(0), a factor 5 apart): a friction small against the servo's
            // torque (weak, or rising slowly as Dahl's does) is a local minimum the two larger
            // starts do not reach.
            Effect::CoulombFriction {
                torque: 0.02 * s.servo_stiffness * s.theta0,
                smoothing_velocity: 5e-4 * s.rate,
                static_peak: None,
                stribeck_velocity: None,
            },
            "coulomb_friction".into(),
            vec![(ParamId::CoulombTorque, (0.0, s.servo_stiffness * s.theta0))],
            vec![nonzero(ParamId::CoulombTorque)],
        )
        .or_from(Effect::CoulombFriction {
            torque: 0.1 * s.servo_stiffness * s.theta0,
            smoothing_velocity: 5e-4 * s.rate,
            static_peak: None,
            stribeck_velocity: None,
        })
        .or_from(Effect::CoulombFriction {
            torque: 0.004 * s.servo_stiffness * s.theta0,
            smoothing_velocity: 5e-4 * s.rate,
            static_peak: None,
            stribeck_velocity: None,
        }),
        trial(
            // Drag equal to 20 % of the viscous torque at the peak rate.
            Effect::QuadraticDrag { hub: 0.2 * c.viscous_damping.max(1e-3) / s.rate, exponent: Some(2.0) },
            "quadratic_drag".into(),
            vec![
                (ParamId::DragHub, (0.0, 200.0 * c.viscous_damping.max(1e-3) / s.rate)),
                (ParamId::DragExponent, (1.2, 3.5)),
            ],
            vec![nonzero(ParamId::DragHub)],
        )
        .or_from(Effect::QuadraticDrag { hub: c.viscous_damping.max(1e-3) / s.rate, exponent: Some(2.0) }),
        trial(
            // Hardening and softening starts: a cubic changes the frequency with amplitude, and
            // the position gain can take up part of it from either side of zero.
            Effect::CubicStiffness {
                coefficient: 0.05 * s.servo_stiffness / s.theta0.powi(2),
                linear: None,
                quintic: None,
                rate: None,
            },
            "cubic_stiffness".into(),
            vec![(
                ParamId::CubicStiffness,
                (-10.0 * s.servo_stiffness / s.theta0.powi(2), 10.0 * s.servo_stiffness / s.theta0.powi(2)),
            )],
            vec![nonzero(ParamId::CubicStiffness)],
        )
        .or_from(Effect::CubicStiffness {
            coefficient: -0.05 * s.servo_stiffness / s.theta0.powi(2),
            linear: None,
            quintic: None,
            rate: None,
        }),
        trial(
            Effect::TimeDelay { delay: 0.02 },
            "time_delay".into(),
            vec![(ParamId::Delay, (1e-4, 2.0))],
            vec![nonzero(ParamId::Delay)],
        ),
    ]);
    for (o, sensor) in model.sensors().iter().enumerate() {
        let name = sensor.output_name();
        out.push(
            trial(
                Effect::OutputOffset { sensor: *sensor, offset: 0.0 },
                format!("output_offset({name})"),
                vec![],
                vec![nonzero(ParamId::Offset(*sensor))],
            )
            .on_output(o),
        );
        out.push(
            trial(
                Effect::SensorScale { sensor: *sensor, scale: 0.0 },
                format!("sensor_scale({name})"),
                vec![(ParamId::Scale(*sensor), (-0.9, 9.0))],
                vec![nonzero(ParamId::Scale(*sensor))],
            )
            .on_output(o),
        );
        out.push(
            trial(
                Effect::SensorDrift { sensor: *sensor, rate: 0.0, time_constant: None },
                format!("sensor_drift({name})"),
                vec![],
                vec![nonzero(ParamId::Drift(*sensor))],
            )
            .on_output(o),
        );
        if let Some((range, [first, second])) = super::drift_time_range(super::record_length(localisation)) {
            let levelling =
                |tau: f64| Effect::SensorDrift { sensor: *sensor, rate: 0.0, time_constant: Some(tau) };
            out.push(
                trial(
                    levelling(first),
                    format!("sensor_drift({name}), levelling off"),
                    vec![(ParamId::DriftTime(*sensor), range)],
                    vec![nonzero(ParamId::Drift(*sensor))],
                )
                .on_output(o)
                .or_from(levelling(second))
                .located_inside(ParamId::DriftTime(*sensor).name()),
            );
        }
    }
    let modal = model.modal().unwrap_or_default();
    let servo: Vec<Clear> = modal
        .iter()
        .filter(|r| r.kind == ModeKind::Servo)
        .map(|r| Clear::by(r.frequency_hz, 0.25))
        .take(1)
        .collect();
    // Where the record shows no mode, the model's first flexible mode is seeded ([`mode_seeds`]).
    let first_flexible: Vec<(f64, f64)> = modal
        .iter()
        .filter(|r| r.kind == ModeKind::Flexible(1))
        .map(|r| (r.frequency_hz, r.damping_ratio))
        .collect();
    for seed in mode_seeds(&servo, LIGHTLY_DAMPED, localisation, &first_flexible) {
        let (f, (low, high)) = (seed.frequency, seed.range);
        let damping = seed.damping.clamp(0.005, 0.15);
        let bounds = [
            (ParamId::ExtraModeFrequency, (low, high)),
            (ParamId::ExtraModeDamping, (0.0, 0.2)),
            (ParamId::ExtraModeCoupling, (-0.95 * s.inertia.sqrt(), 0.95 * s.inertia.sqrt())),
            (ParamId::ExtraModeStiffnessCoupling, (-100.0 * s.servo_stiffness, 100.0 * s.servo_stiffness)),
        ];
        out.push(mode_trial(
            Effect::UnmodeledMode {
                frequency_hz: f,
                damping_ratio: damping,
                coupling: 0.02,
                stiffness_coupling: None,
                damping_coupling: None,
            },
            "unmodeled_mode(inertia, ".into(),
            bounds[..3].to_vec(),
            vec![nonzero(ParamId::ExtraModeCoupling)],
            &seed,
        ));
        out.push(mode_trial(
            Effect::UnmodeledMode {
                frequency_hz: f,
                damping_ratio: damping,
                coupling: 0.0,
                stiffness_coupling: Some(0.02 * s.servo_stiffness),
                damping_coupling: None,
            },
            "unmodeled_mode(stiffness, ".into(),
            bounds[..4].to_vec(),
            vec![nonzero(ParamId::ExtraModeStiffnessCoupling)],
            &seed,
        ));
    }
    // Through damping: a damper between the hub and the mode. The damping matrix stays positive
    // semi-definite for c_d² ≤ d_hub·2ζω, d_hub = C_v + K_bK_t/R_a. The damper damps the mode as
    // well (its share of 2ζω is at least c_d²/d_hub), so a mode coupled this way strongly is a
    // well damped one: its damping ratio may reach 0.5, and so may its seed's.
    let zeta_max = 0.5;
    for seed in mode_seeds(&servo, zeta_max, localisation, &first_flexible) {
        let (f, (low, high)) = (seed.frequency, seed.range);
        let damping = seed.damping.clamp(0.005, 0.9 * zeta_max);
        let d_hub = c.viscous_damping + c.back_emf_constant * c.torque_constant / c.armature_resistance;
        let omega = 2.0 * std::f64::consts::PI * f;
        let limit = (d_hub * 2.0 * zeta_max * 2.0 * std::f64::consts::PI * high).sqrt();
        let bounds = vec![
            (ParamId::ExtraModeFrequency, (low, high)),
            (ParamId::ExtraModeDamping, (0.0, zeta_max)),
            (ParamId::ExtraModeCoupling, (-0.95 * s.inertia.sqrt(), 0.95 * s.inertia.sqrt())),
            (ParamId::ExtraModeDampingCoupling, (-limit, limit)),
        ];
        out.push(mode_trial(
            Effect::UnmodeledMode {
                frequency_hz: f,
                damping_ratio: damping,
                coupling: 0.0,
                stiffness_coupling: None,
                damping_coupling: Some(0.3 * (d_hub * 2.0 * damping * omega).sqrt()),
            },
            "unmodeled_mode(damping, ".into(),
            bounds,
            vec![nonzero(ParamId::ExtraModeDampingCoupling)],
            &seed,
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
            // The swap keeps the named limiter's knee (its shape) and frees the level alone.
            Effect::VoltageSaturation { voltage_limit, sharp, knee } => {
                let mut t = out_of(&s, EffectKind::AmplifierSaturation);
                t.effect =
                    Effect::AmplifierSaturation { current_limit: voltage_limit / r, sharp, knee }.into();
                out.push(swap(t, EffectKind::VoltageSaturation));
            }
            Effect::AmplifierSaturation { current_limit, sharp, knee } => {
                let mut t = out_of(&s, EffectKind::VoltageSaturation);
                t.effect = Effect::VoltageSaturation { voltage_limit: current_limit * r, sharp, knee }.into();
                out.push(swap(t, EffectKind::AmplifierSaturation));
            }
            _ => {}
        }
    }
    out
}

/// Where a named backlash's gear frequency is fitted \[Hz\].
const GEAR_RANGE: (f64, f64) = (1.0, 100.0);

/// Backlash: a dead band between the motor and the hub, with the tachometer on the motor's shaft
/// (where one usually sits) or on the hub, if the model has a tachometer. The band starts at 0.5 %
/// of the initial angle and is the one parameter freed; the gear is held at 10 Hz. A gear's
/// ringing is rarely resolved in a decimated record, while the band shows as lost motion at every
/// reversal; freeing the gear's frequency too let the fit wander along a flat direction and more
/// than doubled the diagnosis time on the development set. Once named, the band is refitted with
/// the gear's frequency free (`super::super::polish`).
fn backlash(s: &Scales, model: &SlewingModel) -> Vec<Trial> {
    let placements: &[bool] =
        if model.sensors().contains(&plant::Sensor::Tachometer) { &[true, false] } else { &[true] };
    placements
        .iter()
        .map(|&on_motor| {
            let effect = |band: f64, f: f64| Effect::Backlash {
                dead_band: band * s.theta0,
                gear_frequency_hz: f,
                gear_damping_ratio: plant::DEFAULT_GEAR_DAMPING,
                tachometer_on_motor: on_motor,
            };
            let label = if placements.len() == 1 {
                "backlash".to_string()
            } else {
                format!("backlash(tachometer on the {})", if on_motor { "motor" } else { "hub" })
            };
            let mut t = trial(
                effect(0.005, 10.0),
                label,
                vec![(ParamId::Backlash, (1e-7, 0.2 * s.theta0)), (ParamId::GearFrequency, GEAR_RANGE)],
                vec![nonzero(ParamId::Backlash)],
            );
            t.freed = vec![ParamId::Backlash.name()];
            t
        })
        .collect()
}

/// The catalog's saturation trial of `kind` (amplifier current or voltage limit): the
/// catalog's limiter (knee n = 8) from half the demand at θ(0), and the limiter at the other
/// end of its family, a clamp (n = 200), from 0.9 of it; the refit keeps the better. A clamp
/// that acts on the first peak alone (0.97 of the demand) is hundreds of nats away from the
/// catalog's limiter at its level, and with less information in the record (coloured noise, a
/// rig without a strain gauge) the n = 8 refit slides to a limit above the demand, where it
/// bends every peak a little as a softening spring does, and the clamp's level is not found.
/// Which form fitted is settled by the knee test of a named saturation
/// ([`crate::diagnose::saturation`]).
fn out_of(s: &Scales, kind: EffectKind) -> Trial {
    match kind {
        EffectKind::VoltageSaturation => trial(
            Effect::VoltageSaturation { voltage_limit: 0.5 * s.demand_voltage, sharp: false, knee: None },
            "voltage_saturation".into(),
            vec![(ParamId::VoltageLimit, (0.01 * s.demand_voltage, 3.0 * s.demand_voltage))],
            vec![Strength::Limit(ParamId::VoltageLimit.name(), Demand::Voltage)],
        )
        .or_from(Effect::VoltageSaturation {
            voltage_limit: 0.9 * s.demand_voltage,
            sharp: false,
            knee: Some(SHARPEST_KNEE),
        }),
        _ => trial(
            Effect::AmplifierSaturation { current_limit: 0.5 * s.demand_current, sharp: false, knee: None },
            "amplifier_saturation".into(),
            vec![(ParamId::CurrentLimit, (0.01 * s.demand_current, 3.0 * s.demand_current))],
            vec![Strength::Limit(ParamId::CurrentLimit.name(), Demand::Current)],
        )
        .or_from(Effect::AmplifierSaturation {
            current_limit: 0.9 * s.demand_current,
            sharp: false,
            knee: Some(SHARPEST_KNEE),
        }),
    }
}
