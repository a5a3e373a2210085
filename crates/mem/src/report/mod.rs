//! What a fit reports: history, uncertainty that says what the data support, identifiability,
//! the derivative check, and warnings.

mod checks;
mod identifiability;
mod statistics;
mod summary;

pub(crate) use checks::{StartInfo, start_checks};
pub use identifiability::{Combination, Identifiability};
pub use statistics::{Interval, SeriesNoise, Statistics};

use crate::evaluate::{Evaluation, RowLayout};
use crate::fit::settings::{Fit, Termination, active_side, columns};
use crate::solve::StepSolver;
use crate::{MemError, Problem};
use serde::Serialize;

/// One accepted iteration.
#[derive(Clone, Debug, Serialize)]
pub struct IterationRecord {
    /// 1-based iteration number.
    pub iteration: usize,
    /// P after the step.
    pub parameters: Vec<f64>,
    /// ‖Y_error‖ (Eq. 22, weighted) after the step.
    pub error: f64,
    /// ΔP.
    pub step: Vec<f64>,
    /// Singular values of the column-scaled S (free parameters) at the start of the iteration.
    pub singular_values: Vec<f64>,
    /// How many were kept.
    pub rank: usize,
    /// Levenberg–Marquardt damping μ used (0 for plain Gauss–Newton).
    pub damping: f64,
    /// Trial steps rejected before this one was accepted.
    pub rejected_trials: usize,
}

/// S compared with central finite differences of the outputs at the start.
#[derive(Clone, Debug, Serialize)]
pub struct DerivativeCheck {
    /// max over parameters of the relative mismatch.
    pub worst_relative_mismatch: f64,
    /// ‖S_fd − S‖/‖S‖ per parameter (weighted outputs, all experiments).
    pub per_parameter: Vec<f64>,
    /// The tolerance, from the models' accuracy ε: max(1e-4, 100·ε^{2/3}).
    pub tolerance: f64,
}

/// Which side of its box a parameter is held on.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Side {
    /// The lower bound.
    Lower,
    /// The upper bound.
    Upper,
}

/// Something the user must know to read the estimates.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
#[non_exhaustive]
pub enum Warning {
    /// A parameter combination the data do not determine; its parameters get no interval.
    RankDeficient {
        /// The parameters involved.
        parameters: Vec<String>,
        /// What cannot be told, in words.
        sentence: String,
        /// σ/σ_max of the combination.
        ratio: f64,
    },
    /// A parameter's 95 % interval would hold all of its bounded range: the data do not narrow
    /// it beyond its bounds (every column of S small beside the noise), and it gets no interval.
    SpansBounds {
        /// The parameter.
        parameter: String,
        /// The half width t·σ the interval would have (a one-sided interval's whole width).
        half_width: f64,
        /// Its lower bound.
        lower: f64,
        /// Its upper bound.
        upper: f64,
    },
    /// A parameter ended on a bound that the data pull it beyond.
    ActiveBound {
        /// The parameter.
        parameter: String,
        /// Which bound.
        side: Side,
        /// The bound's value.
        bound: f64,
        /// The fraction of the error the linear model predicts would go if the bound were released.
        release_gain: f64,
    },
    /// The sensitivities disagree with central differences (the check was set to warn).
    DerivativeMismatch {
        /// The parameter.
        parameter: String,
        /// Its relative mismatch.
        mismatch: f64,
    },
    /// No step lowered the error although a decrease was predicted.
    Stagnated,
    /// The iteration cap was reached before convergence.
    IterationCap {
        /// The cap.
        iterations: usize,
    },
    /// Plain Gauss–Newton diverged.
    Diverged,
    /// The fitted model is unstable.
    Unstable {
        /// Experiment index.
        experiment: usize,
        /// The largest real part of its eigenvalues.
        growth: f64,
    },
    /// An output's residuals are correlated: the white-noise covariance would be too optimistic.
    CorrelatedResiduals {
        /// Experiment index.
        experiment: usize,
        /// Output name.
        output: String,
        /// Lag-one autocorrelation.
        rho: f64,
        /// Ljung–Box p-value (lags 1–20).
        p_value: f64,
        /// The covariance that was used.
        covariance: crate::Covariance,
    },
    /// Decimation removed part of an output's signal, which the fit therefore cannot use.
    DecimationDiscards {
        /// Experiment index.
        experiment: usize,
        /// Output name.
        output: String,
        /// The fraction of its energy that lay above the filter's band.
        fraction: f64,
        /// The filter's stop-band edge \[Hz\].
        above_hz: f64,
    },
    /// An output is constant: it carries no information.
    ConstantOutput {
        /// Experiment index.
        experiment: usize,
        /// Output name.
        output: String,
    },
}

impl std::fmt::Display for Warning {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Warning::RankDeficient { sentence, ratio, .. } => {
                write!(
                    f,
                    "not determined by the data: {sentence} (relative singular value {ratio:.1e}); no interval for these"
                )
            }
            Warning::SpansBounds { parameter, half_width, lower, upper } => write!(
                f,
                "`{parameter}` is not determined by the data: its 95 % interval (± {half_width:.3e}) would hold all of its bounds [{}, {}]; no interval for it (is the record long and fine enough for the model's dynamics?)",
                Number(*lower),
                Number(*upper)
            ),
            Warning::ActiveBound { parameter, side, bound, release_gain } => write!(
                f,
                "`{parameter}` stopped on its {} bound {}; the data pull it beyond (releasing the bound would lower ‖Y_error‖ by about {:.1} %): its interval is one-sided",
                if *side == Side::Lower { "lower" } else { "upper" },
                Number(*bound),
                100.0 * release_gain
            ),
            Warning::DerivativeMismatch { parameter, mismatch } => write!(
                f,
                "the sensitivities of `{parameter}` disagree with central differences (relative mismatch {mismatch:.2e})"
            ),
            Warning::Stagnated => write!(
                f,
                "stagnated: no step lowered the error although the linear model predicted a decrease"
            ),
            Warning::IterationCap { iterations } => {
                write!(
                    f,
                    "stopped at the iteration cap ({iterations}) before converging; the estimates are not final"
                )
            }
            Warning::Diverged => {
                write!(f, "plain Gauss–Newton diverged; try the Levenberg–Marquardt safeguard")
            }
            Warning::Unstable { experiment, growth } => {
                write!(
                    f,
                    "the fitted model of experiment {experiment} is unstable (an eigenvalue with real part {growth:.3e} 1/s)"
                )
            }
            Warning::CorrelatedResiduals { experiment, output, rho, p_value, covariance } => write!(
                f,
                "the residuals of `{output}` (experiment {experiment}) are correlated (lag-one ρ = {rho:.2}, Ljung–Box p = {p_value:.1e}); the {} covariance was used",
                match covariance {
                    crate::Covariance::Ar1 => "AR(1) sandwich",
                    _ => "white-noise (too optimistic here)",
                }
            ),
            Warning::DecimationDiscards { experiment, output, fraction, above_hz } => write!(
                f,
                "decimation removed {:.1} % of the energy of `{output}` (experiment {experiment}) above {above_hz:.3} Hz; the fit cannot use it (decimate less to keep it)",
                100.0 * fraction
            ),
            Warning::ConstantOutput { experiment, output } => {
                write!(
                    f,
                    "output `{output}` of experiment {experiment} is constant: it carries no information"
                )
            }
        }
    }
}

/// The outcome of [`crate::Fit::run`].
#[derive(Clone, Debug, Serialize)]
pub struct FitReport {
    /// Parameter names.
    pub names: Vec<String>,
    /// P at the start.
    pub initial: Vec<f64>,
    /// P at the end.
    pub parameters: Vec<f64>,
    /// Why it stopped.
    pub termination: Termination,
    /// Number of accepted steps.
    pub iterations: usize,
    /// ‖Y_error‖ (Eq. 22, weighted) at the start and after each accepted step.
    pub error_history: Vec<f64>,
    /// Per-iteration details.
    pub records: Vec<IterationRecord>,
    /// Number of residuals m (samples × outputs, all experiments).
    pub n_residuals: usize,
    /// Numerical rank of S (free parameters) at the end.
    pub rank: usize,
    /// The rank cutoff used.
    pub rank_cutoff: f64,
    /// Parameters held on a bound at the end.
    pub on_bound: Vec<Option<Side>>,
    /// Uncertainty.
    pub statistics: Statistics,
    /// Identifiability.
    pub identifiability: Identifiability,
    /// The derivative check at the start (None if skipped).
    pub derivative_check: Option<DerivativeCheck>,
    /// Per experiment, ‖Y_error‖ of its rows at the end.
    pub experiment_errors: Vec<f64>,
    /// What the user must know.
    pub warnings: Vec<Warning>,
}

impl FitReport {
    /// ΔP = final − initial.
    pub fn change(&self) -> Vec<f64> {
        self.parameters.iter().zip(&self.initial).map(|(a, b)| a - b).collect()
    }
    /// Initial and final error.
    pub fn error_change(&self) -> (f64, f64) {
        (self.error_history[0], *self.error_history.last().expect("history starts with the initial error"))
    }
    /// What the user must know: rank deficiency, active bounds, derivative mismatch,
    /// stagnation, the iteration cap, an unstable model, correlated residuals, discarded signal.
    pub fn warnings(&self) -> &[Warning] {
        &self.warnings
    }
    /// The standard error of parameter i (None where the data do not determine it).
    pub fn std_error(&self, i: usize) -> Option<f64> {
        self.statistics.std_errors[i]
    }
}

/// Builds the report at the final point.
#[allow(clippy::too_many_arguments)]
pub(crate) fn finish(
    fit: &Fit,
    problem: &Problem<'_>,
    p: Vec<f64>,
    last: Evaluation,
    records: Vec<IterationRecord>,
    error_history: Vec<f64>,
    termination: Termination,
    start: StartInfo,
) -> Result<FitReport, MemError> {
    let j = p.len();
    let names = problem.names();
    let on_bound: Vec<Option<Side>> = (0..j)
        .map(|i| active_side(problem, &p, &last, i).map(|s| if s < 0 { Side::Lower } else { Side::Upper }))
        .collect();
    // Uncertainty and identifiability use every column, also those held on a bound: a free
    // parameter correlated with a held one must carry the held one's local uncertainty (its
    // interval conditional on the bound would be too narrow).
    let all: Vec<usize> = (0..j).collect();
    let free: Vec<usize> = (0..j).filter(|&i| on_bound[i].is_none()).collect();
    let solver =
        Some(StepSolver::from_owned(columns(&last.sensitivity, &all), &last.residual, fit.rank_cutoff)?);
    let layout = RowLayout::of(problem);
    let identifiability =
        identifiability::analyse(problem, &p, &all, solver.as_ref(), fit.identifiability_threshold);
    let undetermined: Vec<bool> =
        (0..j).map(|i| identifiability.undetermined.iter().any(|c| c.involves(i))).collect();
    let rank = solver.as_ref().map_or(0, |s| s.rank);
    let statistics::Analysed { statistics, series, spanning } = statistics::analyse(
        fit,
        problem,
        &p,
        &last,
        &layout,
        &all,
        solver.as_ref(),
        &on_bound,
        &undetermined,
    )?;
    let mut warnings = start.warnings.clone();
    for c in &identifiability.undetermined {
        warnings.push(Warning::RankDeficient {
            parameters: c.parameters.clone(),
            sentence: c.sentence.clone(),
            ratio: c.ratio,
        });
    }
    for &(i, half_width) in &spanning {
        let parameter = &problem.parameters[i];
        warnings.push(Warning::SpansBounds {
            parameter: names[i].clone(),
            half_width,
            lower: parameter.lower,
            upper: parameter.upper,
        });
    }
    // An undetermined parameter resting on a bound is not held there by the data (the
    // rank-deficiency warning says what it is).
    // Nor is one whose interval from the bound would hold all of its box (`SpansBounds`).
    let told = |i: usize| undetermined[i] || spanning.iter().any(|&(s, _)| s == i);
    for (i, side) in on_bound.iter().enumerate().filter(|&(i, _)| !told(i)) {
        if let Some(side) = side {
            warnings.push(Warning::ActiveBound {
                parameter: names[i].clone(),
                side: *side,
                bound: p[i],
                release_gain: statistics::release_gain(&last, &free, i, fit.rank_cutoff)?,
            });
        }
    }
    if let Some(w) = termination_warning(termination, fit.max_iterations) {
        warnings.push(w);
    }
    for (index, e) in problem.experiments.iter().enumerate() {
        if let Some(growth) = e.model.growth_rate(&e.local(&p))
            && growth * e.data.n_samples() as f64 * e.data.interval() > checks::GROWTH_LIMIT
        {
            warnings.push(Warning::Unstable { experiment: index, growth });
        }
    }
    // A fit to rounding has residuals that are rounding's smooth pattern, not noise.
    let perfect = last.cost <= crate::fit::settings::PERFECT_FIT * start.data_energy;
    for s in series.iter().filter(|s| !perfect && s.p_value < statistics::WHITENESS_LEVEL) {
        warnings.push(Warning::CorrelatedResiduals {
            experiment: s.experiment,
            output: s.output.clone(),
            rho: s.rho,
            p_value: s.p_value,
            covariance: statistics.covariance_kind,
        });
    }
    let experiment_errors = layout
        .blocks
        .iter()
        .map(|&(first, k, n_out)| last.residual[first..first + k * n_out].iter().map(|v| v * v).sum())
        .collect();
    Ok(FitReport {
        names,
        initial: problem.initial(),
        iterations: records.len(),
        parameters: p,
        termination,
        error_history,
        records,
        n_residuals: last.residual.len(),
        rank,
        rank_cutoff: fit.rank_cutoff,
        on_bound,
        statistics,
        identifiability,
        derivative_check: start.derivative_check,
        experiment_errors,
        warnings,
    })
}

/// Which warnings a run adds besides the report's analysis.
fn termination_warning(termination: Termination, iterations: usize) -> Option<Warning> {
    match termination {
        Termination::Stagnated => Some(Warning::Stagnated),
        Termination::MaxIterations => Some(Warning::IterationCap { iterations }),
        Termination::Diverged => Some(Warning::Diverged),
        Termination::Converged => None,
    }
}

/// A number as a reader takes it in: plain between 10⁻⁴ and 10⁶, in exponent form outside (the
/// smallest positive bound would otherwise print as 300 zeros); always the shortest form that
/// reads back to the same value.
struct Number(f64);

impl std::fmt::Display for Number {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let a = self.0.abs();
        if a == 0.0 || !a.is_finite() || (1e-4..1e6).contains(&a) {
            write!(f, "{}", self.0)
        } else {
            write!(f, "{:e}", self.0)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::Number;

    #[test]
    fn numbers_print_short_and_read_back() {
        for (x, text) in [
            (f64::MIN_POSITIVE, "2.2250738585072014e-308"),
            (0.25, "0.25"),
            (0.0, "0"),
            (3e7, "3e7"),
            (-1.5e-6, "-1.5e-6"),
        ] {
            let shown = Number(x).to_string();
            assert_eq!(shown, text);
            assert_eq!(shown.parse::<f64>().unwrap(), x);
        }
    }
}
