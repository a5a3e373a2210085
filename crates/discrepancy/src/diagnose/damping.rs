//! The rival of a named mode on a structure (an `unmodeled_mode`, ringing in the outputs or an
//! appendage at a coordinate), and of a named drag or dry friction there: no such effect, but
//! the model's damping distributed otherwise — a linear damper c_j·q̇_j at every coordinate
//! without a drag, all refitted at once beside the reference's parameters ([`DampingRival`]).
//!
//! A damping form of a few numbers (Rayleigh's α and β set every mode's ratio) leaves each
//! mode's decay or resonance a little off when the structure's damping is distributed otherwise
//! (modal ratios Rayleigh cannot give: a null of the structure study). A mode the model lacks
//! can stand in for that: an appendage beside a modelled mode damps it as a tuned mass does
//! (on the forced draw 20261306, a modal-damping null was answered an appendage at 8.28 Hz,
//! ζ_a 0.16, 14 % below its second mode, 702 nats in sample; three dampers gain more there).
//! With one damper per coordinate, each mode's ratio can be set apart from the others'
//! (ζ_k moves with Σ_j c_j φ_jk², and the modes' weights φ_jk² differ from floor to floor). The
//! mode keeps its name only where it explains the record better than the dampers by the
//! held-out threshold in sample ([`DampingRival::as_well`]); what only a mode holds is a
//! resonance of its own, which no damper makes. The dampers are not charged for their
//! parameters: they are the account of the model's own damping, and the mode must be earned
//! against it.

use super::answer::DampingRival;
use super::catalog::Trial;
use super::named::{FormTest, parameter_of};
use super::{mismatch, run};
use plant::EffectKind;

/// The dampers' rival to a named mode, drag or dry friction of `trial` on a second-order
/// structure, whose own account gains `effect_gain` nats in sample over the reference: `None`
/// for another effect, a model without coordinates free of a drag, or a failed refit.
pub(super) fn rival(trial: &Trial, test: &FormTest, effect_gain: f64) -> Option<DampingRival> {
    if !set_against_damping(trial.kind) {
        return None;
    }
    let structure = test.reference.as_structure()?;
    let dampers = mismatch::linear_dampers(structure, Some(test.data));
    if dampers.is_empty() {
        return None;
    }
    let mut model = test.reference.clone();
    for damper in &dampers {
        let (effect, _) = damper.adds.as_ref()?;
        model.add_effect(effect.clone()).ok()?;
        model.set_bounds(&damper.name, damper.bounds).ok()?;
    }
    let names: Vec<String> = dampers.iter().map(|d| d.name.clone()).collect();
    let free: Vec<String> = test.free.iter().chain(&names).cloned().collect();
    let outcome = run::refit_to(&model, test.data, &free, None, 60, run::Precision::Optimum).ok()?;
    let gain = (test.gain)(&outcome);
    gain.is_finite().then(|| DampingRival {
        dampers: names.iter().filter_map(|name| parameter_of(&outcome, name)).collect(),
        gain,
        effect_gain,
        as_well: effect_gain - gain < test.threshold,
    })
}

/// Whether a named effect of this kind is set against the dampers: a mode, and a force whose
/// only departure from a linear damper is its form in the rate. A drag c·v|v|^(e−1) is a damper
/// at e = 1; with its exponent free it bends the damping with the rate, and so with the
/// response's amplitude — on a forced record with the frequency too, since the response peaks at
/// the modes. A dry friction is the limit e → 0. Either can then stand for modal ratios the
/// model's damping form cannot give (on the forced draw 20261309 a modal-damping null was
/// answered a drag at q1, exponent 1.33 ± 0.06, 82.3 nats in sample; one linear damper at q1
/// alone gained 81.0).
fn set_against_damping(kind: EffectKind) -> bool {
    matches!(kind, EffectKind::UnmodeledMode | EffectKind::QuadraticDrag | EffectKind::CoulombFriction)
}
