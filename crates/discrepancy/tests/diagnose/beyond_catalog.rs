//! Physics beyond the catalog (cogging, a fading torque constant, crosstalk, gravity) is not
//! given a catalog name, and a named effect is not set aside for it. (Its module sorts first, so
//! that its two long chains start early when the tests run in parallel.)

use super::*;

/// A cogging torque (−3 mN·m · sin 36θ at the hub, physics outside the catalog) from the study's
/// independent truth plant (`fixtures/independent/slewing_hub_torques.py`), released from 0.75 rad.
/// Over the decay it is a slow ripple of a few cycles; a mode fitted to it finds a frequency
/// (0.18 Hz) but not a decay rate, and a mode is named only where its pole is located
/// (before that rule, `unmodeled_mode(inertia, 0.18 Hz)` was named here).
#[test]
fn a_cogging_ripple_is_not_named_a_mode() {
    let d = decimated_fixture_from("slewing_cogging", |t| t.replace("hub_angle: 0.5,", "hub_angle: 0.75,"));
    assert!(d.named().is_none_or(|c| !c.label.starts_with("unmodeled_mode")), "{:?}", d.answer());
    // The mode candidates were fitted and their strength was there; their decay was not.
    assert!(
        d.candidates.iter().any(|c| c.label.starts_with("unmodeled_mode(inertia")),
        "the inertia-coupled mode was tried: {:?}",
        d.answer()
    );
}

/// A finer cogging torque (−3 mN·m · sin 48θ at the hub, outside the catalog) from the study's
/// independent truth plant (`fixtures/independent/slewing_hub_torques.py`), released from
/// 0.5 rad, read at 12.8 Hz. Near rest a position-periodic torque adds stiffness and softens as
/// θ³, so a softening spring predicts the held-out blocks (123 nats) — but it removes only 16 %
/// of the reference residual's structure, where a spring that is the missing physics removes
/// most of it: a named cubic stiffness must remove
/// [`discrepancy::diagnose::MIN_SPRING_STRUCTURE_EXPLAINED`] (before that bar,
/// `cubic_stiffness` was named here).
#[test]
fn a_cogging_torque_is_not_named_a_spring() {
    let d = decimated_fixture_from("slewing_cogging_48", |t| t);
    assert_ne!(d.effect(), "cubic_stiffness", "{:?}", d.answer());
    let spring = d.candidates.iter().find(|c| c.label == "cubic_stiffness").expect("the spring was tried");
    assert!(spring.evidence.held_out.is_some_and(|h| h >= d.threshold), "it predicts: {:?}", spring.evidence);
    assert_eq!(spring.verdict, discrepancy::Verdict::Superficial, "{:?}", d.answer());
}

/// The motor's torque constant fading as it warms, K_t·(1 − 0.35 t/30 s) (physics outside the
/// catalog), from the study's independent truth plant
/// (`fixtures/independent/slewing_hub_torques.py`), released from 0.55 rad, read at 128 Hz. In
/// one free decay the amplitude falls as time passes, so a hardening spring takes up the
/// stiffness lost late in the decay and predicts the held-out blocks by far more than the
/// threshold — but it removes less than half of the reference residual's structure (0.43; the
/// back-EMF damping fades too, and not with the amplitude), where a spring that is the missing
/// physics leaves little: a named cubic stiffness must remove
/// [`discrepancy::diagnose::MIN_SPRING_STRUCTURE_EXPLAINED`] (when that bar was 0.3,
/// `cubic_stiffness` was named here).
#[test]
fn a_fading_torque_constant_is_not_named_a_spring() {
    let d = fixture_at("slewing_torque_fade", None, |t| t.replace("hub_angle: 0.5,", "hub_angle: 0.55,"));
    assert_ne!(d.effect(), "cubic_stiffness", "{:?}", d.answer());
    let spring = d.candidates.iter().find(|c| c.label == "cubic_stiffness").expect("the spring was tried");
    assert!(
        spring.evidence.held_out.is_some_and(|h| h >= 10.0 * d.threshold),
        "it predicts: {:?}",
        spring.evidence
    );
    assert_eq!(spring.verdict, discrepancy::Verdict::Superficial, "{:?}", d.answer());
}

/// A lighter fade of the torque constant, K_t·(1 − 0.15 t/30 s), on a lightly damped servo
/// (C_v 0.08, K_p 8.5), released from 0.6 rad, read at 12.8 Hz (`slewing_torque_fade_light`,
/// the independent truth plant). The hardening spring that takes it up removes more than half
/// of the structure, so the structure bar lets it through; but refitted with a stiffness that
/// changes with time beside it and a quintic, k₁′·t·θ is demanded: the servo's stiffness
/// k_s = G K_p K_t/R_a = 0.426 N·m/rad loses 0.15 of itself over 30 s, k₁′ = −0.00213 N·m/(rad·s).
/// Before the hub spring's form was tested, `cubic_stiffness` was named here.
#[test]
fn a_fading_torque_constant_is_found_to_change_with_time() {
    let d = decimated_fixture_from("slewing_torque_fade_light", |t| {
        t.replace("hub_angle: 0.5,", "hub_angle: 0.6,")
    });
    assert_ne!(d.effect(), "cubic_stiffness", "{:?}", d.answer());
    let spring = d.candidates.iter().find(|c| c.label == "cubic_stiffness").expect("the spring was tried");
    assert_eq!(spring.verdict, discrepancy::Verdict::TimeVarying, "{:?}", d.answer());
    let form = d.spring.as_ref().expect("the hub spring's form was tested");
    assert!(form.asymmetric.is_none(), "a hub spring is not tested for asymmetry: {form:?}");
    let rate = &form.changing;
    assert_eq!(rate.parameter.name, "stiffness_rate");
    let se = rate.parameter.std_error.expect("determined");
    let truth = -0.15 * 1.8204 * 8.5 * 0.05508 / 2.0 / 30.0;
    assert!(rate.demanded && rate.parameter.value.abs() > 3.0 * se, "{rate:?}");
    assert!((rate.parameter.value / truth - 1.0).abs() < 0.3, "k₁′ {} against {truth}", rate.parameter.value);
    assert!(d.answer().iter().any(|s| s.contains("changes with time")), "{:?}", d.answer());
}

/// Two effects at once from the independent truth plant (`slewing_spring_and_drag`): a
/// softening spring at the hub (+0.04 θ³) and air drag −0.08 |θ̇|θ̇, released from 0.7 rad,
/// read at 12.8 Hz. The spring is named first; refitted with a stiffness that changes with time
/// beside it, the rate takes up part of the drag the model still lacks — as a stiffness gained
/// with time (k₁′ > 0), well beyond the threshold. A servo loses stiffness as its motor warms
/// and does not gain it, so only a loss is demanded of the hub spring: the spring stays named.
/// (With either sign demanded, nothing was named here.)
#[test]
fn a_spring_ahead_of_a_drag_is_not_called_time_varying() {
    let d = decimated_fixture_from("slewing_spring_and_drag", |t| {
        t.replace("hub_angle: 0.5,", "hub_angle: 0.7,")
    });
    assert_eq!(d.effect(), "cubic_stiffness", "{:?}", d.answer());
    let named = d.named().expect("named");
    let k3 = named.parameters.iter().find(|p| p.name == "cubic_stiffness").unwrap().value;
    assert!(k3 < 0.0, "softening: k₃ = {k3}");
    let rate = &d.spring.as_ref().expect("the hub spring's form was tested").changing;
    assert!(rate.parameter.value > 0.0 && rate.gain > d.threshold && !rate.demanded, "{rate:?}");
}

/// The strain channel picking up the tachometer's signal through a 20 Hz first-order coupling,
/// y_strain + c·F(θ̇) with c = 1.3456 (`slewing_crosstalk`, the independent truth plant),
/// released from 0.6 rad, read at 12.8 Hz: a wiring fault outside the catalog. A loop delay
/// of some 30 ms explains it nearly as well (to first order in τ the servo gains a torque
/// ∝ θ̇ whose share the model's damping does not take up reaches the gauge), and before the
/// crosstalk was set against a named effect `time_delay` was named here. Refitted in its place,
/// the pickup gains more, after the ln 6 nats it is charged for being the best of the six
/// ordered pairs of three outputs, and recovers c.
#[test]
fn a_channel_picking_up_another_is_not_named_a_delay() {
    let d = decimated_fixture_from("slewing_crosstalk", |t| t.replace("hub_angle: 0.5,", "hub_angle: 0.6,"));
    assert_eq!(d.effect(), "none", "{:?}", d.answer());
    let delay = d.candidates.iter().find(|c| c.label == "time_delay").expect("tried");
    assert_eq!(delay.verdict, discrepancy::Verdict::MatchedByMismatch, "{:?}", d.answer());
    let pickup =
        d.rivals.iter().find(|r| r.name == "crosstalk_strain_theta_dot").expect("the pickup was refitted");
    assert_eq!(
        pickup.adds,
        Some(discrepancy::diagnose::AddedTerm::Crosstalk {
            output: "strain".into(),
            from: "theta_dot".into()
        })
    );
    assert!((pickup.penalty - 6f64.ln()).abs() < 1e-12, "{pickup:?}");
    assert!(pickup.unseats(delay.evidence.in_sample), "{pickup:?} against {:?}", delay.evidence);
    assert!((pickup.value / 1.3456 - 1.0).abs() < 0.05, "g = {} against c = 1.3456", pickup.value);
    assert!(d.answer().iter().any(|s| s.contains("picked up")), "{:?}", d.answer());
}

/// An exact transport delay of 25 ms in the position feedback (`slewing_delay`, the independent
/// truth plant, which interpolates its stored θ rather than a Padé approximant), released from
/// 0.55 rad, read at 12.8 Hz: the crosstalk tried against it does not unseat it, and the delay
/// is named with its value (a named effect has no rival that unseats it, by construction).
#[test]
fn a_transport_delay_keeps_its_name_beside_a_crosstalk() {
    let d = decimated_fixture_from("slewing_delay", |t| t.replace("hub_angle: 0.5,", "hub_angle: 0.55,"));
    assert_eq!(d.effect(), "time_delay", "{:?}", d.answer());
    let delay = d.named().expect("named").parameters[0].value;
    assert!((delay / 0.025 - 1.0).abs() < 0.1, "τ = {delay} against 25 ms");
}

/// Two effects that act alike, from the study's independent truth plant
/// (`fixtures/independent/slewing_hub_torques.py`): a softening spring at the hub (+0.06 θ³) and
/// the armature current clamped at 98 % or at 95 % of the demand at θ(0) = 0.5 rad. Both take
/// torque from the servo at large angles, so each stands in for part of the other. Run after
/// run, each run refitting the model the one before wrote, the diagnosis names one of the two
/// first, never anything else, and every named effect shrinks the gap; the chain ends in
/// `none` within three runs. (Measured: the spring is named first at 98 %, the clamp at 95 %,
/// and behind it the other is not resolved — docs/diagnose.md, "Two effects that act alike".)
#[test]
fn a_spring_and_a_clamp_that_act_alike_are_named_one_at_a_time() {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../../fixtures");
    let text = std::fs::read_to_string(format!("{root}/slewing.ron")).unwrap();
    let mut options = options();
    options.decimate = Some(10);
    let alike = ["cubic_stiffness", "amplifier_saturation", "voltage_saturation"];
    for name in ["slewing_spring_and_clamp_98", "slewing_spring_and_clamp_95"] {
        let data = mem::Measurement::read_csv(std::path::Path::new(&format!(
            "{root}/independent/effects/{name}.csv"
        )))
        .unwrap();
        let mut model = Model::from_ron(&text, "slewing.ron").unwrap();
        let mut named = Vec::new();
        for run in 1..=3 {
            let d = diagnose(&model, &data, &options).unwrap();
            let effect = d.effect().to_string();
            if effect == "none" {
                break;
            }
            assert!(
                alike.contains(&effect.as_str()),
                "{name}, run {run}: {effect} ({named:?}): {:?}",
                d.answer()
            );
            assert!(d.augmented_error() < d.baseline_error(), "{name}, run {run}: the gap must shrink");
            named.push(effect);
            model = d.augmented().clone();
        }
        assert!(!named.is_empty() && named.len() < 3, "{name}: one or two named, then `none`: {named:?}");
    }
}

/// Two effects from the study's independent truth generator (`slewing_soft_limit_and_drag`, a
/// held-out case of draw 20261401): the amplifier's voltage limited softly, u/√(1 + (u/V)²) at
/// four times the demand at θ(0) — to first order a softening of the loop, which a hub spring
/// stands for — and drag with exponent 2.5. The drag is named first; on the model with the drag
/// added, the spring stands for the limit (about 655 nats in sample), and a stiffness changing
/// with time beside it gains about 10 nats, just over the threshold, from the misfit the spring's
/// form leaves. Such a term must gain a tenth of what the spring explains before the spring is
/// set aside as `time_varying`, so the second run names the limit (or the spring standing for
/// it), not `none`.
#[test]
fn a_soft_limit_behind_a_drag_is_not_set_aside_for_a_change_with_time() {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../../fixtures");
    let text = std::fs::read_to_string(format!("{root}/slewing.ron"))
        .unwrap()
        .replace("hub_angle: 0.5,", "hub_angle: 0.455196284389444,")
        .replace("free: [\"cv\"],", "free: [\"cv\", \"kp\"],");
    let data = mem::Measurement::read_csv(std::path::Path::new(&format!(
        "{root}/independent/effects/slewing_soft_limit_and_drag.csv"
    )))
    .unwrap();
    let mut options = options();
    options.decimate = Some(10);
    let first = diagnose(&Model::from_ron(&text, "slewing.ron").unwrap(), &data, &options).unwrap();
    assert_eq!(first.effect(), "quadratic_drag", "{:?}", first.answer());
    let second = diagnose(first.augmented(), &data, &options).unwrap();
    let limit = ["cubic_stiffness", "voltage_saturation", "amplifier_saturation"];
    assert!(limit.contains(&second.effect()), "{}: {:?}", second.effect(), second.answer());
    if let Some(form) = &second.spring {
        let rate = &form.changing;
        assert!(!rate.demanded, "{rate:?}");
    }
}

/// A sensor warming up, from the study's independent truth plant
/// (`fixtures/independent/slewing_warmup.py`), about 8 noise σ each, read at 12.8 Hz. The strain
/// gauge's reading drifts by −0.5 · (1 − e^{−t/12 s}): it levels off over the 30 s record, and it
/// is named `sensor_drift(strain), levelling off` with its time constant within a fifth. The
/// potentiometer's drifts by 7.5 mrad · (1 − e^{−t/5 s}), levelling off within the record's first
/// third: the form's time constant is looked for from a third of the record on
/// (`drift_time_range`), so it is not a drift that levels off — it is answered an offset, a
/// drift at a constant rate or `none`, nothing else.
#[test]
fn a_sensor_warming_up_over_the_record_is_named_a_drift_that_levels_off() {
    let gauge = decimated_fixture("slewing_gauge_warmup");
    let named = gauge.named().unwrap_or_else(|| panic!("{:?}", gauge.answer()));
    assert_eq!(named.label, "sensor_drift(strain), levelling off", "{:?}", gauge.answer());
    let tau = named.parameters.iter().find(|p| p.name == "drift_time_strain").expect("its time constant");
    assert!((tau.value / 12.0 - 1.0).abs() < 0.2, "τ = {} s against 12 s", tau.value);
    let pot =
        decimated_fixture_from("slewing_pot_warmup", |t| t.replace("hub_angle: 0.5,", "hub_angle: 0.6,"));
    let label = pot.named().map_or("none", |c| c.label.as_str());
    assert!(["output_offset(theta)", "sensor_drift(theta)", "none"].contains(&label), "{:?}", pot.answer());
}

/// Gravity on a tilted rig (−22 mN·m · sin θ at the hub, outside the catalog) from the study's
/// independent truth plant (`fixtures/independent/slewing_hub_torques.py`), released from 0.7 rad.
/// A strain-gauge scale predicts the held-out blocks best, but it leaves more than half of the
/// strain's structure (0.42 removed): a hub torque acts on the strain through the dynamics, and
/// a sensor effect must explain most of what is left on its own output (before that rule,
/// `sensor_scale(strain)` was named here). What is left is a cubic stiffness at the hub (the
/// study accepts it for gravity; here it is a hardening one, itself a stand-in, since K_p takes
/// up the linear part only in part) or `none`.
#[test]
fn gravity_on_the_hub_is_no_strain_gauge_scale() {
    let d = decimated_fixture_from("slewing_gravity", |t| t.replace("hub_angle: 0.5,", "hub_angle: 0.7,"));
    assert!(matches!(d.effect(), "cubic_stiffness" | "none"), "{:?}", d.answer());
    let scale = d.candidates.iter().find(|c| c.label == "sensor_scale(strain)").expect("the scale was tried");
    assert_eq!(scale.verdict, discrepancy::Verdict::LeavesItsOutput, "{:?}", d.answer());
}
