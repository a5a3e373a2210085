//! Checks at the start of a fit: data and response carry information, the model is stable,
//! and its sensitivities agree with central differences.

use super::{DerivativeCheck, Warning};
use crate::evaluate::{Evaluation, Wanted, respond};
use crate::fit::settings::{DerivativeCheck as Mode, Fit};
use crate::{MemError, Problem};
use expm::Response;

/// A response growing by more than this factor in the exponent over the record (e^0.05 ≈ 5 %)
/// counts as unstable.
pub(crate) const GROWTH_LIMIT: f64 = 0.05;

/// What the start checks found.
#[derive(Clone, Debug)]
pub(crate) struct StartInfo {
    /// Σ (w·y_meas)² over every weighted row: the scale of a perfect fit's rounding.
    pub data_energy: f64,
    pub derivative_check: Option<DerivativeCheck>,
    pub warnings: Vec<Warning>,
}

/// Runs the checks.
pub(crate) fn start_checks(
    fit: &Fit,
    problem: &Problem<'_>,
    p: &[f64],
    current: &Evaluation,
) -> Result<StartInfo, MemError> {
    let mut warnings = Vec::new();
    let mut data_energy = 0.0;
    for (index, e) in problem.experiments.iter().enumerate() {
        let values = e.data.values();
        let mut constant = 0;
        for o in 0..e.data.n_outputs() {
            let column: Vec<f64> = (0..values.nrows()).map(|k| values[(k, o)]).collect();
            data_energy += column.iter().map(|v| (e.weights[o] * v).powi(2)).sum::<f64>();
            let (lo, hi) =
                column.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| (a.min(*v), b.max(*v)));
            if lo == hi {
                constant += 1;
                warnings
                    .push(Warning::ConstantOutput { experiment: index, output: e.data.names()[o].clone() });
            }
            let discarded = e.data.discarded()[o];
            if discarded > 0.02
                && let Some(d) = e.data.decimation()
            {
                warnings.push(Warning::DecimationDiscards {
                    experiment: index,
                    output: e.data.names()[o].clone(),
                    fraction: discarded,
                    above_hz: d.band().0,
                });
            }
        }
        if constant == e.data.n_outputs() && e.data.inputs().is_none() {
            return Err(MemError::NothingToFit {
                experiment: index,
                message:
                    "every measured output is constant: a free decay with no motion carries nothing to fit"
                        .into(),
            });
        }
        if !fit.allow_unstable
            && let Some(growth) = e.model.growth_rate(&e.local(p))
        {
            let duration = (e.data.n_samples() - 1) as f64 * e.data.interval();
            if growth * duration > GROWTH_LIMIT {
                return Err(MemError::Unstable { experiment: index, growth, duration });
            }
        }
    }
    // The raw responses at the start serve the derivative check and, where the evaluation's
    // sensitivities vanish, tell a response that depends on nothing from one the weighting
    // zeroed; otherwise the evaluation already answers, and a refit that skips the check (as
    // every refit of a diagnosis does) need not simulate the start a second time.
    let sensitive = current.sensitivity.norm_max() != 0.0;
    let responses = if fit.derivative_check == Mode::Skip && sensitive {
        Vec::new()
    } else {
        (0..problem.experiments.len())
            .map(|index| respond(problem, index, p, Wanted::Sensitivities))
            .collect::<Result<Vec<_>, _>>()?
    };
    if !sensitive && responses.iter().all(|r| r.sensitivities.norm_max() == 0.0) {
        return Err(MemError::NothingToFit {
            experiment: 0,
            message:
                "the model's response does not change with any parameter at the start (is x(0) zero and \
                      the model not driven?)"
                    .into(),
        });
    }
    let derivative_check = match fit.derivative_check {
        Mode::Skip => None,
        mode => {
            let check = derivative_check(problem, p, &responses)?;
            for (i, m) in check.per_parameter.iter().enumerate() {
                if *m > check.tolerance {
                    let name = problem.parameters[i].name.clone();
                    if mode == Mode::Error {
                        return Err(MemError::DerivativeMismatch {
                            parameter: name,
                            mismatch: *m,
                            tolerance: check.tolerance,
                        });
                    }
                    warnings.push(Warning::DerivativeMismatch { parameter: name, mismatch: *m });
                }
            }
            Some(check)
        }
    };
    Ok(StartInfo { data_energy, derivative_check, warnings })
}

/// Central differences of every experiment's (weighted) outputs against the analytic S.
///
/// Step h_i = ε^{1/3}·scale_i with ε the loosest model accuracy and scale_i = max(|P_i|,
/// typical_i) (or the change that moves the outputs by their own size, for a parameter at
/// zero): truncation O(h²) and rounding O(ε/h) are then both O(ε^{2/3}) relative. One-sided
/// second-order differences where a bound is closer than h. The mismatch of parameter i is
/// ‖S_fd − S‖/(max(‖S‖, ‖S_fd‖) + ε^{2/3}‖y‖/scale_i) over all rows; a wrong derivative is off by
/// O(1), rounding by O(ε^{2/3}), so the tolerance is max(1e-4, 100·ε^{2/3}). A parameter over
/// the tolerance is differenced again at h/2 and judged by the Richardson extrapolation
/// (4D(h/2) − D(h))/3, whose truncation is O(h⁴): a strongly curved response is not mistaken
/// for a wrong derivative.
fn derivative_check(
    problem: &Problem<'_>,
    p: &[f64],
    responses: &[Response],
) -> Result<DerivativeCheck, MemError> {
    let accuracy = problem.experiments.iter().map(|e| e.model.accuracy()).fold(1e-16, f64::max);
    let tolerance = (100.0 * accuracy.powf(2.0 / 3.0)).max(1e-4);
    let outputs_at = |q: &[f64]| -> Result<Vec<f64>, MemError> {
        let mut all = Vec::new();
        for (index, e) in problem.experiments.iter().enumerate() {
            let r = respond(problem, index, q, Wanted::Cost)?;
            for k in 0..r.outputs.nrows() {
                for o in 0..r.outputs.ncols() {
                    all.push(e.weights[o] * r.outputs[(k, o)]);
                }
            }
        }
        Ok(all)
    };
    let mut base = Vec::new();
    for (e, r) in problem.experiments.iter().zip(responses) {
        for k in 0..r.outputs.nrows() {
            for o in 0..r.outputs.ncols() {
                base.push(e.weights[o] * r.outputs[(k, o)]);
            }
        }
    }
    let y_norm = base.iter().map(|v| v * v).sum::<f64>().sqrt();
    // The analytic sensitivities of the weighted outputs, from the same responses (the
    // evaluation's S also carries the decimation's row scales and the quantization's zeros).
    let analytic = |i: usize| -> Vec<f64> {
        let mut all = Vec::new();
        for (e, r) in problem.experiments.iter().zip(responses) {
            let local = e.parameters.as_ref().map_or(Some(i), |ids| ids.iter().position(|g| *g == i));
            let n_out = r.outputs.ncols();
            for k in 0..r.outputs.nrows() {
                for o in 0..n_out {
                    all.push(local.map_or(0.0, |l| e.weights[o] * r.sensitivities[(k * n_out + o, l)]));
                }
            }
        }
        all
    };
    let mut per_parameter = Vec::with_capacity(p.len());
    for (i, q) in problem.parameters.iter().enumerate() {
        let exact = analytic(i);
        let exact_norm = exact.iter().map(|v| v * v).sum::<f64>().sqrt();
        let mut scale = q.scale(p[i]);
        if p[i] == 0.0 && q.typical.is_none() && exact_norm > 0.0 {
            scale = y_norm / exact_norm;
        }
        let h = accuracy.cbrt() * scale;
        let shifted = |d: f64| {
            let mut v = p.to_vec();
            v[i] += d;
            outputs_at(&v)
        };
        let difference = |h: f64| -> Result<Vec<f64>, MemError> {
            Ok(if p[i] - h >= q.lower && p[i] + h <= q.upper {
                let (plus, minus) = (shifted(h)?, shifted(-h)?);
                plus.iter().zip(&minus).map(|(a, b)| (a - b) / (2.0 * h)).collect()
            } else {
                // (−3f₀ + 4f₁ − f₂)/(2h) toward the interior.
                let toward = if p[i] + 2.0 * h <= q.upper { h } else { -h };
                let (one, two) = (shifted(toward)?, shifted(2.0 * toward)?);
                base.iter()
                    .zip(one.iter().zip(&two))
                    .map(|(f0, (f1, f2))| (-3.0 * f0 + 4.0 * f1 - f2) / (2.0 * toward))
                    .collect()
            })
        };
        let floor = accuracy.powf(2.0 / 3.0) * y_norm / scale;
        let mismatch = |fd: &[f64]| {
            let fd_norm = fd.iter().map(|v| v * v).sum::<f64>().sqrt();
            let diff = fd.iter().zip(&exact).map(|(a, b)| (a - b).powi(2)).sum::<f64>().sqrt();
            // Above the tolerance exactly when diff > tolerance·max(‖exact‖, ‖fd‖) + floor: the
            // differences' own rounding (≈ floor) is allowed in full, not at the tolerance's
            // share of it (a column the outputs do not depend on has only that rounding).
            diff / (exact_norm.max(fd_norm) + floor / tolerance).max(f64::MIN_POSITIVE)
        };
        let coarse = difference(h)?;
        let mut worst = mismatch(&coarse);
        if worst > tolerance {
            // A response strongly curved in P_i (a dead band, a sharp limit) leaves an O(h²)
            // truncation error above the tolerance: Richardson's (4D(h/2) − D(h))/3 cancels it
            // (both differences are second order), while a wrong derivative stays O(1) off.
            let fine = difference(0.5 * h)?;
            let extrapolated: Vec<f64> = fine.iter().zip(&coarse).map(|(f, c)| (4.0 * f - c) / 3.0).collect();
            worst = worst.min(mismatch(&extrapolated));
        }
        per_parameter.push(worst);
    }
    Ok(DerivativeCheck {
        worst_relative_mismatch: per_parameter.iter().copied().fold(0.0, f64::max),
        per_parameter,
        tolerance,
    })
}
