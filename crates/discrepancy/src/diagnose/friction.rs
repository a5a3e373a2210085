//! The form of a named dry friction (`coulomb_friction` at the slewing rig's hub, or at a
//! structure's coordinate): a constant level F_c, as the catalog's candidate has it, or one with
//! a static peak?
//!
//! Real bearings, gears, brushes and sliding joints stick: the force that starts the motion
//! (the static, breakaway level F_s) exceeds the one that keeps it sliding, and the friction
//! falls from one to the other as the rate grows — the Stribeck effect (Armstrong-Hélouvry,
//! Dupont & Canudas de Wit, "A survey of models, analysis tools and compensation methods for the
//! control of machines with friction", Automatica 30(7), 1994). The candidate is scored with
//! Coulomb's constant level, which a static peak changes only where the motion nearly stops (at
//! the start, at reversals and while it settles); once the friction is named, the peak is
//! refitted beside it, F = (F_c + ΔF e^{−(v/v_st)²})·s(v), with s the friction's smooth sign,
//! ΔF = F_s − F_c and the Stribeck velocity v_st free
//! ([`crate::diagnose::catalog::StaticPeakSearch`] gives their ranges and starts).
//!
//! From the candidate's fit the friction is refitted to the fitter's own convergence, first as
//! it is, then with the peak (from each start; the best is kept). The peak's gain is the
//! difference of their in-sample log-likelihoods; the data demand it when it gains at least the
//! held-out threshold and ΔF, v_st and the sliding level F_c beside them are all determined
//! inside their ranges (standard error below half the value, off the bounds: a friction that
//! sticks above a level at which it slides). Demanded, the named effect carries it (its
//! parameters, the augmented model); otherwise the friction stays Coulomb's and the report says
//! how far the peak got.

use super::answer::{SpringTerm, StaticPeak};
use super::catalog::Trial;
use super::named::{FormTest, parameter_of};
use super::{Candidate, EffectParameter, mismatch, run, strength};

use plant::EffectKind;

/// The static-peak test of a named `coulomb_friction` ([`StaticPeak`]), refitted from the
/// test's reference (which lacks the friction) with the candidate's values; when the data demand the
/// peak, the candidate's model, refit and parameters become those with it. `None` for any other
/// candidate, for a friction that already has a peak, or when a refit fails.
pub(super) fn static_peak(candidate: &mut Candidate, trial: &Trial, test: &FormTest) -> Option<StaticPeak> {
    let FormTest { free, threshold, gain, .. } = *test;
    if candidate.kind != EffectKind::CoulombFriction {
        return None;
    }
    let fitted = candidate.model.as_ref()?;
    let search = super::catalog::static_peak(fitted, &trial.effect)?;
    let (peak_name, peak_range) = search.peak.clone();
    let (velocity_name, velocity_range) = search.velocity.clone();
    let coulomb = search.coulomb.clone();
    let torque = fitted.value(&coulomb).ok()?;
    // The peak starts at half the fitted Coulomb level (or a hundredth of its range if that is
    // nothing), inside its range.
    let peak_start =
        if torque > 0.0 { 0.5 * torque } else { 0.01 * peak_range.1 }.clamp(peak_range.0, peak_range.1);
    // The reference (which lacks the friction) with the friction and its peak added, every
    // other value the candidate's fit, in the candidate's ranges and the peak's.
    let peak_bounds = [(peak_name.clone(), peak_range), (velocity_name.clone(), velocity_range)];
    let with_peak = |velocity: f64| {
        let friction =
            search.friction_with(torque, peak_start, velocity.clamp(velocity_range.0, velocity_range.1));
        test.reference_with(friction, fitted, trial.bounds.iter().chain(&peak_bounds))
    };
    let named: Vec<String> = free.iter().chain(&trial.freed).cloned().collect();
    let (as_named, best) = test.refit_pair(
        fitted,
        &named,
        &[peak_name.clone(), velocity_name.clone()],
        &search.velocity_starts,
        with_peak,
    )?;
    let parameter = |name: &String| parameter_of(&best, name);
    let added = gain(&best) - gain(&as_named);
    // A peak is a friction that sticks above the level at which it slides: the sliding level
    // must be there too (a "peak" over a Coulomb level fitted to nothing is a friction that acts
    // only near rest — another form, which the peak would only stand in for).
    let demanded = added >= threshold
        && [&peak_name, &velocity_name, &coulomb].into_iter().all(|name| mismatch::determined(&best, name));
    let result = StaticPeak {
        peak: parameter(&peak_name)?,
        stribeck_velocity: parameter(&velocity_name)?,
        coulomb_torque: parameter(&coulomb)?,
        gain: added,
        demanded,
    };
    if demanded {
        let mut wider = trial.clone();
        wider.freed.extend([peak_name, velocity_name]);
        candidate.parameters = strength::effect_parameters(&best, &wider);
        candidate.model = Some(best.fitted.clone());
        candidate.outcome = Some(best);
    }
    Some(result)
}

/// The fade test of a named dry friction, in the form it is named with (its static peak, where
/// demanded): does a stiffness that changes with time explain what the friction stands for?
///
/// * On the slewing rig, a servo whose stiffness falls with time: a motor whose torque constant
///   fades as it warms (its magnets' flux falls, its winding's resistance rises) delivers less
///   torque for the same error as the record goes on, and a constant friction, which also takes
///   torque away, stands in for it. The term is a linear hub stiffness that grows at a rate k₁′
///   (−k₁′·t·θ, the hub spring's `stiffness_rate`, within ± the servo's stiffness over the
///   record), and only a loss (k₁′ < 0) is demanded, as for the hub spring.
/// * On a structure, a stiffness at the friction's coordinate c that changes with time (a storey
///   that degrades or a joint that loosens during the record), −k₁′·t·q_c
///   (`stiffness_rate_<c>`, within ±k_cc/(2T) as in the spring's form test), of either sign.
///   A dry friction takes energy out at a constant force, so the amplitude falls linearly; a
///   stiffness that degrades moves the frequencies as the record goes on, and with an
///   accelerometer's record, where each cycle's phase weighs heavily, a friction was named for
///   it (three storeys degrading by other laws, in a probe of floor accelerations).
///
/// From the candidate's fit, with the term added at zero, the friction is refitted to the
/// fitter's own convergence as it is and with k₁′ free beside it. On the slewing rig the change
/// is demanded when k₁′ is determined, gains at least the held-out threshold or lies
/// [`super::spring::WALD_Z`] standard errors from zero, and gains at least a tenth of what the
/// friction itself gains ([`super::spring::FORM_SHARE`]): a strong Stribeck friction read at
/// 128 Hz, 13,063 nats in sample, let k₁′ take up 1.8 nats at z 5.8 from the misfit its form
/// leaves, where the torque fades it stood for gave 114 and 912. On a structure it must gain
/// more than the friction itself gained over the reference (and at least the threshold): the
/// change is then the larger part of what is missing, and the friction at most a correction
/// beside it. A strong true friction, 7,369 nats in sample, let k₁′ take up 84 nats (z 8.6) of
/// the misfit its smooth sign leaves against another form; the degradations it stood for gave
/// k₁′ 807 nats beside a friction of 44. Demanded, the friction is [`super::Verdict::TimeVarying`] and not
/// named. `None` for another candidate, or when a refit fails.
pub(super) fn fading(candidate: &Candidate, trial: &Trial, test: &FormTest) -> Option<SpringTerm> {
    let FormTest { free, data, threshold, gain, .. } = *test;
    if candidate.kind != EffectKind::CoulombFriction {
        return None;
    }
    let last_time = super::spring::record_end(data)?;
    let mut from = candidate.model.clone()?;
    let (rate, range, on_structure) = match &trial.effect {
        models::ModelEffect::Structure(structure::Effect::DryFriction { coordinate, .. }) => {
            let scales = super::catalog::structure::scales(test.reference.as_structure()?, Some(data))
                .into_iter()
                .find(|s| s.coordinate == *coordinate)?;
            from.add_effect(
                structure::Effect::CubicStiffness {
                    coordinate: coordinate.clone(),
                    coefficient: 0.0,
                    quadratic: None,
                    quintic: None,
                    sided: None,
                    rate: Some(0.0),
                    change: None,
                }
                .into(),
            )
            .ok()?;
            (format!("stiffness_rate_{coordinate}"), 0.5 * scales.k / last_time, true)
        }
        _ => {
            let (stiffness, _) = super::catalog::slewing::spring_scales(test.reference.as_slewing()?);
            from.add_effect(
                plant::Effect::CubicStiffness {
                    coefficient: 0.0,
                    linear: None,
                    quintic: None,
                    rate: Some(0.0),
                }
                .into(),
            )
            .ok()?;
            (plant::ParamId::StiffnessRate.name(), stiffness / last_time, false)
        }
    };
    if range.is_nan() || range <= 0.0 {
        return None;
    }
    from.set_bounds(&rate, super::spring::symmetric(range)).ok()?;
    let refit = |model: &models::Model, free: &[String]| {
        run::refit_to(model, data, free, None, 60, run::Precision::Optimum).ok()
    };
    // The friction's own parameters as named (its level, and its peak where demanded).
    let named: Vec<String> =
        free.iter().cloned().chain(candidate.parameters.iter().map(|p| p.name.clone())).collect();
    let as_named = refit(&from, &named)?;
    let with_rate: Vec<String> = named.iter().chain([&rate]).cloned().collect();
    let outcome = refit(&as_named.fitted, &with_rate)?;
    let i = outcome.report.names.iter().position(|n| *n == rate)?;
    let (value, std_error) = (outcome.report.parameters[i], outcome.report.std_error(i));
    let added = gain(&outcome) - gain(&as_named);
    let resolved = std_error.is_some_and(|se| value.abs() >= super::spring::WALD_Z * se);
    let demanded = if on_structure {
        added >= threshold.max(candidate.evidence.in_sample)
    } else {
        // As a spring's form term ([`super::spring::FORM_SHARE`]): a tenth of what the friction
        // explains, whichever way the term is significant.
        value < 0.0
            && (added >= threshold || resolved)
            && added >= super::spring::FORM_SHARE * gain(&as_named)
    };
    Some(SpringTerm {
        parameter: EffectParameter { name: rate.clone(), value, std_error },
        gain: added,
        symmetric_gain: 0.0,
        demanded: demanded && mismatch::determined(&outcome, &rate),
    })
}
