//! How far a refit's effect stands from "no effect": its strength in standard errors, with
//! the shape parameters held at their estimates, and where an unmodeled mode's pole or a body
//! is located at all; and the refit's effect parameters and residual whiteness as reported.

use super::answer::EffectParameter;
use super::catalog::{Pole, Strength, Trial};
use crate::stats::ljung_box;
use models::{FitOutcome, Model};

/// The effect's parameters as fitted.
pub fn effect_parameters(outcome: &FitOutcome, trial: &Trial) -> Vec<EffectParameter> {
    trial
        .freed
        .iter()
        .filter_map(|name| {
            let name = name.clone();
            let i = outcome.report.names.iter().position(|n| *n == name)?;
            Some(EffectParameter {
                name,
                value: outcome.report.parameters[i],
                std_error: outcome.report.std_error(i),
            })
        })
        .collect()
}

/// The smallest distance of the effect's strength parameters from "no effect", in standard
/// errors (0 where a standard error is not determined, and for an unmodeled mode whose
/// frequency or damping ratio ends on a bound of its range). For a mode, the smaller of that and
/// [`pole_z`]: a mode is named only where the data locate its pole.
///
/// The standard error is conditional on the effect's shape parameters (a drag exponent, a
/// friction's smoothing, an extra mode's frequency and damping): they are not identified when
/// the effect is absent (Davies 1987), so the test of "no effect" holds them at their estimates,
/// σ²_s|H = Σ_ss − Σ_sH Σ_HH⁻¹ Σ_Hs (a Schur complement of the fit's covariance; the model's own
/// parameters stay free). A shape parameter the fit held on a bound of its range is held there
/// too, through its local row ([`mem::Statistics::conditional_std_error`]): the same fit with
/// the exponent a hair inside its bound and on it must test the same (a drag exponent at
/// 3.49993 and at 3.5 gave z 9.6 and 0.6 when the bound one was left free).
pub fn strength_z(outcome: &FitOutcome, trial: &Trial) -> f64 {
    let report = &outcome.report;
    let index = |name: &str| report.names.iter().position(|n| n == name);
    let estimate = |name: &String| {
        index(name).map(|i| Estimate {
            value: report.parameters[i],
            std_error: report.std_error(i),
            on_bound: report.on_bound[i].is_some(),
        })
    };
    let pole = match trial.located.as_ref().map(|l| (l.pole, estimate(&l.name), estimate(&l.damping))) {
        Some((Pole::Ringing, Some(frequency), Some(damping))) => pole_z(frequency, damping),
        Some((Pole::Body, Some(frequency), Some(damping))) => body_z(frequency, damping),
        _ => f64::INFINITY,
    };
    // A shape parameter the data must locate: off its bounds, its standard error below half
    // its value.
    if pole == 0.0 || !trial.interior.iter().all(|name| super::mismatch::determined(outcome, name)) {
        return 0.0;
    }
    let strength: Vec<&str> = trial.strength.iter().flat_map(|s| s.names()).collect();
    let shape: Vec<usize> =
        trial.freed.iter().filter(|n| !strength.contains(&n.as_str())).filter_map(|n| index(n)).collect();
    trial
        .strength
        .iter()
        .map(|s| {
            s.names()
                .into_iter()
                .map(|name| {
                    index(name).map_or(0.0, |i| {
                        match (s, report.statistics.conditional_std_error(i, &shape)) {
                            (Strength::Limit(_, demand), Some(se)) if se > 0.0 && shape.is_empty() => {
                                limit_z(outcome, i, *demand)
                                    .unwrap_or_else(|| s.z(report.parameters[i], se, &outcome.fitted))
                            }
                            (_, Some(se)) if se > 0.0 => s.z(report.parameters[i], se, &outcome.fitted),
                            _ => 0.0,
                        }
                    })
                })
                .fold(f64::NEG_INFINITY, f64::max)
        })
        .fold(f64::INFINITY, f64::min)
        .min(pole)
        .min(1e6)
}

/// A limit's distance from "no effect" ([`Strength::Limit`]: 1.5× the demand) in standard
/// errors of its depth below the demand, r = L/D: the demand D = G K_p θ(0)/R_a (or G K_p θ(0))
/// is the fitted model's, and where its factors are fitted too, their errors are the limit's
/// reference's. Through θ and θ̇ alone a record fixes the loop's torques only relative to its
/// inertia (the beam's mass per length freed beside K_p scales both), so a clamp's level L and
/// K_p move together, each poorly determined (the blind set's medium current clamp read without
/// its strain gauge: L = 2.75 ± 0.67 A, K_p ± 24 %, ΔBIC −252), while how deep the limit cuts
/// into the demand is what the record shows. By the delta method, σ_r/r = √(gᵀΣg) with
/// g = e_L/L − ∇ln D over the fitted parameters (∇ln D by a relative step in each;
/// [`mem::Statistics::std_error_of`] over the fit's covariance, sandwich included), and z = (1.5 − r)/σ_r. With no factor of D
/// fitted this is (1.5 D − L)/σ_L. None where a needed covariance entry is not determined (the
/// caller then uses σ_L alone).
fn limit_z(outcome: &FitOutcome, i: usize, demand: super::catalog::Demand) -> Option<f64> {
    let report = &outcome.report;
    let demand_of = |model: &Model| model.as_slewing().map(|m| demand.of(m));
    let d = demand_of(&outcome.fitted)?;
    let limit = report.parameters[i];
    if !(d > 0.0 && limit > 0.0) {
        return None;
    }
    let gradient: Vec<f64> = (0..report.names.len())
        .map(|j| {
            if j == i {
                return Some(1.0 / limit);
            }
            let p = report.parameters[j];
            let h = 1e-6 * p.abs().max(1e-6);
            let mut moved = outcome.fitted.clone();
            moved.set(&report.names[j], p + h).ok()?;
            Some(-(demand_of(&moved)? / d).ln() / h)
        })
        .collect::<Option<_>>()?;
    let relative = report.statistics.std_error_of(&gradient)?;
    let r = limit / d;
    Some((1.5 - r) / (r * relative))
}

/// A parameter as a refit left it.
#[derive(Clone, Copy, Debug)]
pub struct Estimate {
    /// The estimate.
    pub value: f64,
    /// Its standard error, where the data determine it.
    pub std_error: Option<f64>,
    /// Whether it ended on a bound of its range.
    pub on_bound: bool,
}

/// How surely a refit located an unmodeled mode's pole, in standard errors (0 where it did
/// not): the smaller of its damping ratio's distance from zero and its frequency's distance
/// from a factor 2 off (f/2), either 0 on a bound of its range or where its standard error is
/// not determined. A mode is a resonance the data must locate — a frequency on a bound of its
/// search range was not found there, whatever the coupling does — and locating a resonance is
/// locating a pole: a damping ratio not resolved from zero is an oscillation of unknown decay,
/// which any slow disturbance fitted over a few cycles can be, and a frequency not pinned within
/// the factor 2 its search spans is a band, not a pole (a smooth misfit fitted with a heavily
/// damped "mode" anywhere in it).
pub fn pole_z(frequency: Estimate, damping: Estimate) -> f64 {
    let z = |e: Estimate, share: f64| match e.std_error {
        Some(se) if se > 0.0 && !e.on_bound => share * e.value.abs() / se,
        _ => 0.0,
    };
    z(damping, 1.0).min(z(frequency, 0.5))
}

/// How surely a refit located a body hung on the structure ([`Pole::Body`]), in standard errors
/// (0 where it did not): its frequency's distance from a factor 2 off, as for [`pole_z`]; 0 on a
/// bound of its range, where its standard error is not determined, or where its damping ratio
/// ended on the upper bound of its range (a band, not a body). Its damping ratio need not be
/// resolved from zero.
pub fn body_z(frequency: Estimate, damping: Estimate) -> f64 {
    if damping.on_bound && damping.value > 0.1 {
        return 0.0;
    }
    match frequency.std_error {
        Some(se) if se > 0.0 && !frequency.on_bound => 0.5 * frequency.value.abs() / se,
        _ => 0.0,
    }
}

/// The smallest Ljung–Box p-value (lags 1–20) of the fit's residuals over the outputs.
pub fn whiteness(outcome: &FitOutcome) -> f64 {
    let residual = outcome.first().residual();
    (0..residual.ncols())
        .map(|o| ljung_box(&(0..residual.nrows()).map(|k| residual[(k, o)]).collect::<Vec<_>>(), 20).1)
        .fold(1.0, f64::min)
}

#[cfg(test)]
mod tests {
    use super::{Estimate, body_z, pole_z};

    fn e(value: f64, std_error: f64) -> Estimate {
        Estimate { value, std_error: Some(std_error), on_bound: false }
    }

    /// Estimates measured on the held-out draws (docs/diagnose.md): a true damping-coupled
    /// mode found weak, and the stand-in a strong pendulum torque was fitted with.
    #[test]
    fn a_pole_is_located_by_its_decay_and_by_its_frequency_within_a_factor_two() {
        // Seed 4711, a weak 0.86 Hz mode damped 34 %: f/se 8.3, ζ/se 6.3.
        let true_mode = pole_z(e(0.86, 0.86 / 8.3), e(0.342, 0.342 / 6.3));
        assert!((true_mode - 8.3 / 2.0).abs() < 1e-12, "{true_mode}");
        assert!(true_mode >= 3.0);
        // Seed 6101, gravity: 4.87 ± 1.10 Hz, ζ 0.497 ± 0.117 — a band, not a pole.
        let stand_in = pole_z(e(4.8713, 1.0975), e(0.4967, 0.1174));
        assert!((stand_in - 0.5 * 4.8713 / 1.0975).abs() < 1e-12 && stand_in < 3.0, "{stand_in}");
        // Seed 3307, cogging: a frequency pinned (0.19 Hz, f/se > 100) but ζ/se 1.3.
        let ripple = pole_z(e(0.19, 0.0019), e(0.07, 0.07 / 1.3));
        assert!((ripple - 1.3).abs() < 1e-12, "{ripple}");
        // On a bound of its range, or with no standard error: not located.
        let bound = Estimate { on_bound: true, ..e(0.3, 0.001) };
        assert_eq!(pole_z(bound, e(0.2, 0.01)), 0.0);
        assert_eq!(pole_z(e(0.3, 0.001), bound), 0.0);
        assert_eq!(pole_z(e(0.3, 0.001), Estimate { std_error: None, ..e(0.2, 0.01) }), 0.0);
        assert_eq!(pole_z(e(0.3, 0.001), e(0.2, 0.0)), 0.0);
    }

    /// A body is located by its frequency alone: the forced draw 20261360's 50 kg appendage at
    /// 20.7 Hz, refitted at 20.28 ± 0.36 Hz with ζ 0.025 ± 0.013 (unresolved from zero), is a
    /// body and not a ringing; a frequency on a bound, or a damping ratio pressed on the top of
    /// its range (a band), is not.
    #[test]
    fn a_body_is_located_by_its_frequency_and_its_damping_may_be_unresolved() {
        let (f, zeta) = (e(20.28, 0.36), e(0.025, 0.013));
        assert!(pole_z(f, zeta) < 3.0);
        let body = body_z(f, zeta);
        assert!((body - 0.5 * 20.28 / 0.36).abs() < 1e-12, "{body}");
        assert_eq!(body_z(f, Estimate { on_bound: true, ..e(0.0, 0.01) }), body);
        assert_eq!(body_z(f, Estimate { on_bound: true, ..e(0.2, 0.01) }), 0.0);
        assert_eq!(body_z(Estimate { on_bound: true, ..f }, zeta), 0.0);
        assert_eq!(body_z(Estimate { std_error: None, ..f }, zeta), 0.0);
    }
}
