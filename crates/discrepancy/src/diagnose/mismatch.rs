//! The model's own parameters a mismatch lives in: those the reference frees beside the user's
//! (the mismatch parameters, [`mismatch_parameters`], and the secondary ones tried one at a
//! time, [`secondary_mismatch_parameters`]), with the ranges they are refitted in, and those a
//! named effect is set against alone ([`rival_parameters`]).

use super::answer::AddedTerm;
use super::catalog::structure::{has_effect, scales};
use mem::Measurement;
use models::{FitOutcome, Model, ModelEffect};
use plant::{ParamId, SlewingModel};

/// The model's own linear parameters a mismatch would live in, that the user did not free:
/// the modal damping of every flexible mode, the hub and motor inertias and the beam's
/// stiffness (the mass per length is tried after them, [`secondary_mismatch_parameters`]).
///
/// For a structure: the parameters its file marks free that the user did not.
pub fn mismatch_parameters(model: &Model, free: &[String]) -> Vec<String> {
    let names: Vec<String> = match model {
        Model::Slewing(m) => mismatch_ids(m).into_iter().map(|(id, _)| id.name()).collect(),
        Model::Structure(m) => m.free(),
    };
    names.into_iter().filter(|n| !free.contains(n)).collect()
}

/// The mismatch parameters with the range a mismatch is looked for in: a fifth to five times a
/// modal damping, half to twice the hub and motor inertias, ±30 % of the beam's stiffness
/// (wider ranges only let a refit wander into stiff, slow and implausible models).
///
/// Each range is narrowed to the bounds the model file states for the parameter ([`within`]).
fn mismatch_ids(model: &SlewingModel) -> Vec<(ParamId, (f64, f64))> {
    let around = |id: ParamId, low: f64, high: f64| {
        let v = model.get(id);
        (id, if v > 0.0 { (low * v, high * v) } else { (0.0, 1.0) })
    };
    (1..=model.n_modes())
        .map(|i| around(ParamId::ModalDamping(i), 0.2, 5.0))
        .chain([
            around(ParamId::HubInertia, 0.5, 2.0),
            around(ParamId::MotorInertia, 0.5, 2.0),
            around(ParamId::EiOverRho, 0.7, 1.3),
        ])
        .filter_map(|(id, range)| Some((id, within(model.get(id), range, model.bounds(id))?)))
        .collect()
}

/// Mismatch parameters tried one at a time after the others, each kept only when the data
/// determine it without unsettling those: the beam's mass per length (±30 %, within the file's
/// bounds), which trades off against the hub and motor inertias in the rigid-body inertia.
fn secondary_mismatch_ids(model: &SlewingModel) -> Vec<(ParamId, (f64, f64))> {
    let id = ParamId::MassPerLength;
    let v = model.get(id);
    if v > 0.0 {
        within(v, (0.7 * v, 1.3 * v), model.bounds(id)).map(|r| (id, r)).into_iter().collect()
    } else {
        Vec::new()
    }
}

/// `range` narrowed to the bounds the model file states for its parameter, if it states any: a
/// user who has measured a beam's length, say, confines a mismatch of it to what the
/// measurement allows, and a mismatch the file rules out is neither absorbed nor set against a
/// named effect. `None` when nothing is left to move in, or when the parameter's `value` lies
/// outside what is left (a file whose bounds exclude its own value: the parameter is not
/// refitted, as `memid fit` would refuse to start it there).
fn within(value: f64, range: (f64, f64), stated: Option<(f64, f64)>) -> Option<(f64, f64)> {
    let (lo, hi) = stated.map_or(range, |(a, b)| (range.0.max(a), range.1.min(b)));
    (lo < hi && lo <= value && value <= hi).then_some((lo, hi))
}

/// The names of [`secondary_mismatch_ids`] the user did not free.
pub fn secondary_mismatch_parameters(model: &Model, free: &[String]) -> Vec<String> {
    match model {
        Model::Slewing(m) => secondary_mismatch_ids(m)
            .into_iter()
            .map(|(id, _)| id.name())
            .filter(|n| !free.contains(n))
            .collect(),
        Model::Structure(m) => {
            structure_fixed(m).into_iter().map(|(n, _)| n).filter(|n| !free.contains(n)).collect()
        }
    }
}

/// A structure file's fixed, nonzero parameters with ±30 % ranges: for a structure, the
/// secondary mismatch parameters are what its file fixes (masses, say), freed one at a time
/// and kept only where the data determine them.
fn structure_fixed(model: &structure::StructureModel) -> Vec<(String, (f64, f64))> {
    let free = model.free();
    let effects: Vec<String> =
        model.effects().iter().flat_map(|e| e.parameters(&model.output_names())).map(|(n, _)| n).collect();
    model
        .parameter_names()
        .into_iter()
        .filter(|n| !free.contains(n) && !effects.contains(n))
        .filter_map(|n| {
            let v = model.value(&n).ok().filter(|v| *v != 0.0 && v.is_finite())?;
            let range = within(v, around(v, 0.3), model.bounds(&n))?;
            Some((n, range))
        })
        .collect()
}

/// Whether a fit determines parameter `name`: a local standard error below half its value's
/// size, and not at a bound. The local one ([`mem::Statistics::local_std_error`]): the ranges
/// the diagnosis refits its parameters in are its own search boxes, not the model file's bounds,
/// and a parameter resolved to a third of its size is determined here though its interval would
/// hold all of a ±30 % box (where the report tells no interval).
pub fn determined(outcome: &FitOutcome, name: &str) -> bool {
    let r = &outcome.report;
    r.names.iter().position(|n| n == name).is_some_and(|i| {
        r.on_bound[i].is_none()
            && r.statistics.local_std_error(i).is_some_and(|se| se < 0.5 * r.parameters[i].abs())
    })
}

/// A parameter a named effect is tried against ([`rival_parameters`]): its name, the range it is
/// refitted in, and the effect that carries it when the model has none yet.
#[derive(Clone)]
pub struct RivalTrial {
    /// Parameter name.
    pub name: String,
    /// The range it is refitted in.
    pub bounds: (f64, f64),
    /// The effect added (at zero strength) to make the parameter exist, if the model lacks it,
    /// and the term it is.
    pub adds: Option<(ModelEffect, AddedTerm)>,
    /// The nats its gain is charged for having been chosen among others of its class
    /// ([`Rival::penalty`](super::Rival::penalty)); 0 for a parameter of the model's own.
    pub penalty: f64,
}

/// The model's own parameters, not refitted, that a named effect is tried against as a
/// mismatch, with the ranges they are refitted in: the mismatch parameters the
/// reference left fixed, and the file's geometry (for the slewing rig the beam's length and the
/// hub's radius, ±10 %; for a structure its fixed parameters, ±30 %), each within the bounds the
/// model file states for it, if any ([`within`]). A sensor scale's exact
/// equivalents (`scale_equivalents_of`) are left out by the caller: they are reported as such.
///
/// For the slewing rig also a linear spring at the hub (`hub_stiffness`, within ± the servo's
/// own stiffness K_a K_p K_t / R, from zero) when the model has no stiffness effect: a restoring
/// torque the model lacks — gravity on a tilted axis, cables, a centring spring — moves the
/// servo's settling point and its closed-loop frequency as a low, damping-coupled mode can, with
/// one parameter for the mode's three.
///
/// For a second-order structure also a linear damper at each coordinate that has no drag, sized
/// by its response to `record` ([`scales`]),
/// (`drag_<c>` with exponent 1, within ± twice the model's diagonal damping there, at least 1 %
/// critical): damping distributed otherwise than the model's — Rayleigh damping sets every
/// mode's ratio from two numbers — leaves a decay a drag or a dry friction at one storey can
/// shave, and an amplitude-dependent force is named only where the data demand more than a
/// linear one.
pub fn rival_parameters(model: &Model, record: Option<&Measurement>, refitted: &[String]) -> Vec<RivalTrial> {
    let named = |ids: Vec<(ParamId, (f64, f64))>| {
        ids.into_iter()
            .map(|(id, bounds)| RivalTrial { name: id.name(), bounds, adds: None, penalty: 0.0 })
            .collect::<Vec<_>>()
    };
    let all = match model {
        Model::Slewing(m) => {
            let geometry = [ParamId::Length, ParamId::HubRadius]
                .into_iter()
                .filter(|&id| m.get(id) > 0.0)
                .filter_map(|id| Some((id, within(m.get(id), around(m.get(id), 0.1), m.bounds(id))?)));
            let mut all =
                named(mismatch_ids(m).into_iter().chain(secondary_mismatch_ids(m)).chain(geometry).collect());
            let has_spring = m.effects().iter().any(|e| e.kind() == plant::EffectKind::CubicStiffness);
            let servo = plant::assemble::servo_stiffness(m.constants());
            if !has_spring && servo.is_finite() && servo > 0.0 {
                all.push(RivalTrial {
                    name: ParamId::HubStiffness.name(),
                    bounds: (-servo, servo),
                    adds: Some((
                        plant::Effect::CubicStiffness {
                            coefficient: 0.0,
                            linear: Some(0.0),
                            quintic: None,
                            rate: None,
                        }
                        .into(),
                        AddedTerm::HubSpring,
                    )),
                    penalty: 0.0,
                });
            }
            all
        }
        Model::Structure(m) => {
            let mut bounds = structure_fixed(m);
            bounds.extend(m.free().into_iter().filter_map(|n| {
                let v = m.value(&n).ok().filter(|v| *v != 0.0 && v.is_finite())?;
                let range = within(v, around(v, 0.3), m.bounds(&n))?;
                Some((n, range))
            }));
            let mut all: Vec<RivalTrial> = bounds
                .into_iter()
                .map(|(name, bounds)| RivalTrial { name, bounds, adds: None, penalty: 0.0 })
                .collect();
            all.extend(linear_dampers(m, record));
            all
        }
    };
    all.into_iter().filter(|t| !refitted.contains(&t.name)).collect()
}

/// A linear damper at each coordinate of a second-order structure that has no drag there
/// ([`rival_parameters`]).
pub(super) fn linear_dampers(
    model: &structure::StructureModel,
    record: Option<&Measurement>,
) -> Vec<RivalTrial> {
    let outputs = model.output_names();
    scales(model, record)
        .into_iter()
        .filter_map(|s| {
            let effect =
                structure::Effect::Drag { coordinate: s.coordinate.clone(), coefficient: 0.0, exponent: 1.0 };
            if has_effect(model, &effect) {
                return None;
            }
            let (name, _) = effect.parameters(&outputs).into_iter().next()?;
            let c = 2.0 * s.viscous / s.v;
            Some(RivalTrial {
                name,
                bounds: (-c, c),
                adds: Some((effect.into(), AddedTerm::LinearDamper { coordinate: s.coordinate })),
                penalty: 0.0,
            })
        })
        .collect()
}

/// The range within `share` of `v` on either side, ordered for a negative `v` too.
fn around(v: f64, share: f64) -> (f64, f64) {
    let (a, b) = ((1.0 - share) * v, (1.0 + share) * v);
    (a.min(b), a.max(b))
}

/// `model` with the mismatch parameters' ranges.
pub fn with_mismatch_bounds(mut model: Model) -> Model {
    if let Some(m) = model.as_slewing_mut() {
        for (id, b) in mismatch_ids(m).into_iter().chain(secondary_mismatch_ids(m)) {
            m.set_bounds(id, b);
        }
    }
    let fixed = model.as_structure().map(structure_fixed).unwrap_or_default();
    for (name, b) in fixed {
        // Inside its own range by construction.
        let _ = model.set_bounds(&name, b);
    }
    model
}

#[cfg(test)]
mod tests {
    use super::{AddedTerm, Model, rival_parameters, within};

    /// A file's bounds narrow a range; bounds that leave nothing, or exclude the parameter's
    /// own value, leave the parameter out.
    #[test]
    fn a_files_bounds_narrow_the_range_or_leave_the_parameter_out() {
        assert_eq!(within(1.0, (0.5, 2.0), None), Some((0.5, 2.0)));
        assert_eq!(within(1.0, (0.5, 2.0), Some((0.9, 1.1))), Some((0.9, 1.1)));
        assert_eq!(within(1.0, (0.5, 2.0), Some((0.0, 1.5))), Some((0.5, 1.5)));
        assert_eq!(within(1.0, (0.5, 2.0), Some((3.0, 4.0))), None, "disjoint");
        assert_eq!(within(1.0, (0.5, 2.0), Some((1.5, 3.0))), None, "the value outside");
        assert_eq!(within(f64::NAN, (0.5, 2.0), None), None);
    }

    /// A structure's rivals include a linear damper at each coordinate without a drag, within
    /// ± twice the file's diagonal damping there: D = αM + βK with α 0.375, β 1.25·10⁻³, masses
    /// 10³ kg and storey stiffnesses 2.5, 2.25, 1.875 MN/m give D₁₁ = 375 + 5,937.5 and
    /// D₃₃ = 375 + 2,343.75 N·s/m.
    #[test]
    fn a_damper_at_each_storey_is_tried_where_the_structure_has_no_drag() {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../fixtures/shear_building.ron");
        let text = std::fs::read_to_string(path).unwrap();
        let model = Model::from_ron(&text, "shear_building.ron").unwrap();
        let rivals = rival_parameters(&model, None, &["k1".into(), "k2".into(), "k3".into()]);
        let damper = |c: &str| rivals.iter().find(|r| r.name == format!("drag_{c}"));
        for (c, d) in [("q1", 6_312.5), ("q3", 2_718.75)] {
            let r = damper(c).expect("tried");
            assert!(
                (r.bounds.0 + 2.0 * d).abs() < 1e-6 && (r.bounds.1 - 2.0 * d).abs() < 1e-6,
                "{c}: {:?}",
                r.bounds
            );
            let (effect, term) = r.adds.clone().expect("added");
            assert_eq!(term, AddedTerm::LinearDamper { coordinate: c.into() });
            let mut with = model.clone();
            with.add_effect(effect).unwrap();
            assert_eq!(with.value(&format!("drag_exponent_{c}")).unwrap(), 1.0);
            assert_eq!(with.value(&format!("drag_{c}")).unwrap(), 0.0);
        }
        assert!(damper("q2").is_some());
        // Not where the model has a drag already.
        let dragged = Model::from_ron(
            &text.replace(
                "    outputs: [",
                "    effects: [Drag(coordinate: \"q2\", coefficient: 10.0, exponent: 2.0)],\n    outputs: [",
            ),
            "shear_building.ron",
        )
        .unwrap();
        let rivals = rival_parameters(&dragged, None, &[]);
        assert!(!rivals.iter().any(|r| r.name == "drag_q2") && rivals.iter().any(|r| r.name == "drag_q1"));
    }

    fn paper_model(edit: impl Fn(String) -> String) -> Model {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../fixtures/slewing.ron");
        let text = std::fs::read_to_string(path).unwrap();
        Model::from_ron(&edit(text), "slewing.ron").unwrap()
    }

    /// The slewing rig's rivals include a linear spring at the hub, added at zero, within ± the
    /// servo's stiffness K_a K_p K_t / R (the paper's file: 1.8204 · 8 · 0.05508 / 2 N·m/rad);
    /// not when the model already has a stiffness effect, nor when the reference refits it.
    #[test]
    fn a_spring_at_the_hub_is_tried_where_the_model_has_none() {
        let model = paper_model(|t| t);
        let rivals = rival_parameters(&model, None, &["cv".to_string()]);
        let spring = rivals.iter().find(|r| r.name == "hub_stiffness").expect("tried");
        let servo = 1.8204 * 8.0 * 0.05508 / 2.0;
        assert!(
            (spring.bounds.0 + servo).abs() < 1e-12 && (spring.bounds.1 - servo).abs() < 1e-12,
            "{:?}",
            spring.bounds
        );
        assert!(spring.adds.is_some());
        assert!(rivals.iter().filter(|r| r.name != "hub_stiffness").all(|r| r.adds.is_none()));
        let mut with = model.clone();
        with.add_effect(spring.adds.clone().unwrap().0).unwrap();
        assert_eq!(with.value("hub_stiffness").unwrap(), 0.0);
        assert_eq!(with.value("cubic_stiffness").unwrap(), 0.0);
        assert!(!rival_parameters(&with, None, &[]).iter().any(|r| r.name == "hub_stiffness"));
        let cubic = paper_model(|t| {
            t.replace(
                "    free: [\"cv\"],",
                "    effects: [CubicStiffness(coefficient: 1.0)],\n    free: [\"cv\"],",
            )
        });
        assert!(!rival_parameters(&cubic, None, &[]).iter().any(|r| r.name == "hub_stiffness"));
        assert!(
            !rival_parameters(&model, None, &["hub_stiffness".to_string()])
                .iter()
                .any(|r| r.name == "hub_stiffness")
        );
    }
}
