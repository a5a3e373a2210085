//! What a fit reports: history, uncertainty, identifiability, derivative check.

use crate::evaluate::evaluate;
use crate::fit::Termination;
use crate::solve::{StepSolver, tall_svd};
use crate::{Experiment, MemError};
use faer::{Mat, MatRef};

/// One accepted iteration.
#[derive(Clone, Debug)]
pub struct IterationRecord {
    /// 1-based iteration number.
    pub iteration: usize,
    /// P after the step.
    pub parameters: Vec<f64>,
    /// ‖Y_error‖ (Eq. 22, weighted) after the step.
    pub error: f64,
    /// ΔP.
    pub step: Vec<f64>,
    /// Singular values of the column-scaled S at the start of the iteration.
    pub singular_values: Vec<f64>,
    /// How many were kept.
    pub rank: usize,
    /// Levenberg–Marquardt damping μ used (0 for plain Gauss–Newton).
    pub damping: f64,
    /// Trial steps rejected before this one was accepted.
    pub rejected_trials: usize,
}

/// Parameter uncertainty from the final S and the residual variance.
#[derive(Clone, Debug)]
pub struct Statistics {
    /// σ̂² = ‖E‖²/(m − rank).
    pub residual_variance: f64,
    /// Degrees of freedom m − rank.
    pub degrees_of_freedom: usize,
    /// σ̂² (SᵀS)⁺, from the SVD (the normal matrix is never formed or inverted).
    pub covariance: Mat<f64>,
    /// √diag(covariance).
    pub std_errors: Vec<f64>,
    /// P ± t_{0.975, dof}·std_error.
    pub ci95: Vec<(f64, f64)>,
    /// Correlation matrix.
    pub correlation: Mat<f64>,
}

/// A direction in relative parameter changes that the data do not determine.
#[derive(Clone, Debug)]
pub struct Combination {
    /// σ_i/σ_max of the relatively scaled S.
    pub ratio: f64,
    /// Unit vector v: changing ln P along v leaves the outputs (nearly) unchanged.
    pub direction: Vec<f64>,
    /// "∏ P_i^{v_i}", e.g. `cv^0.71 · kp^-0.71` (the ratio cv/kp is not determined).
    pub description: String,
}

/// Identifiability of the parameters from the data at the final P.
#[derive(Clone, Debug)]
pub struct Identifiability {
    /// Singular values of S·diag(|P_i|) (relative sensitivities), divided by the largest.
    pub relative_singular_values: Vec<f64>,
    /// σ_max/σ_min of that matrix.
    pub condition_number: f64,
    /// Combinations whose ratio lies below the threshold.
    pub undetermined: Vec<Combination>,
}

/// S compared with central finite differences of the outputs.
#[derive(Clone, Debug)]
pub struct DerivativeCheck {
    /// max over parameters of ‖S_fd − S‖_∞ / ‖S‖_∞ for that column.
    pub worst_relative_mismatch: f64,
    /// The same per parameter.
    pub per_parameter: Vec<f64>,
}

/// The outcome of [`crate::Fit::run`].
#[derive(Clone, Debug)]
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
    /// Numerical rank of S at the end.
    pub rank: usize,
    /// The rank cutoff used.
    pub rank_cutoff: f64,
    /// Uncertainty.
    pub statistics: Statistics,
    /// Identifiability.
    pub identifiability: Identifiability,
    /// Present if requested.
    pub derivative_check: Option<DerivativeCheck>,
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
}

/// Two-sided 95 % quantile of Student's t with `dof` degrees of freedom: a table for small
/// dof, then the Cornish–Fisher expansion about the normal quantile (error < 1e-4 for dof ≥ 10).
pub fn t_quantile_975(dof: usize) -> f64 {
    const TABLE: [f64; 9] = [12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306, 2.262];
    if dof == 0 {
        return f64::INFINITY;
    }
    if dof <= TABLE.len() {
        return TABLE[dof - 1];
    }
    let z: f64 = 1.959_963_984_540_054;
    let v = dof as f64;
    z + (z.powi(3) + z) / (4.0 * v) + (5.0 * z.powi(5) + 16.0 * z.powi(3) + 3.0 * z) / (96.0 * v * v)
}

pub(crate) fn statistics(solver: &StepSolver, p: &[f64], cost: f64, m: usize) -> Statistics {
    let j = p.len();
    let dof = m.saturating_sub(solver.rank);
    let variance = if dof > 0 { cost / dof as f64 } else { f64::NAN };
    let covariance = solver.normal_pseudo_inverse() * faer::Scale(variance);
    let std_errors: Vec<f64> = (0..j).map(|i| covariance[(i, i)].max(0.0).sqrt()).collect();
    let t = t_quantile_975(dof);
    let ci95 = p.iter().zip(&std_errors).map(|(v, s)| (v - t * s, v + t * s)).collect();
    let correlation = Mat::from_fn(j, j, |a, b| {
        let d = std_errors[a] * std_errors[b];
        if d > 0.0 {
            covariance[(a, b)] / d
        } else if a == b {
            1.0
        } else {
            0.0
        }
    });
    Statistics {
        residual_variance: variance,
        degrees_of_freedom: dof,
        covariance,
        std_errors,
        ci95,
        correlation,
    }
}

pub(crate) fn identifiability(
    s: MatRef<'_, f64>,
    p: &[f64],
    names: &[String],
    threshold: f64,
) -> Result<Identifiability, MemError> {
    let j = p.len();
    // Relative sensitivities ∂y/∂ln P_i = P_i ∂y/∂P_i (the column norm where P_i = 0).
    let scale: Vec<f64> = (0..j)
        .map(|c| if p[c] != 0.0 { p[c].abs() } else { s.col(c).norm_l2().recip().min(1e300) })
        .collect();
    let scaled = Mat::from_fn(s.nrows(), j, |i, c| s[(i, c)] * scale[c]);
    let (sv, v) = tall_svd(scaled.as_ref())?;
    let max = sv.first().copied().unwrap_or(0.0);
    let relative: Vec<f64> = sv.iter().map(|x| if max > 0.0 { x / max } else { 0.0 }).collect();
    let undetermined = (0..j)
        .filter(|&i| relative[i] < threshold)
        .map(|i| {
            let mut direction: Vec<f64> = (0..j).map(|c| v[(c, i)]).collect();
            // Sign convention: largest component positive.
            let big = direction.iter().copied().fold(0.0f64, |a, b| if b.abs() > a.abs() { b } else { a });
            if big < 0.0 {
                direction.iter_mut().for_each(|x| *x = -*x);
            }
            let description = direction
                .iter()
                .zip(names)
                .filter(|(x, _)| x.abs() > 1e-3)
                .map(|(x, n)| format!("{n}^{x:.2}"))
                .collect::<Vec<_>>()
                .join(" · ");
            Combination { ratio: relative[i], direction, description }
        })
        .collect();
    let min = sv.last().copied().unwrap_or(0.0);
    Ok(Identifiability {
        relative_singular_values: relative,
        condition_number: if min > 0.0 { max / min } else { f64::INFINITY },
        undetermined,
    })
}

pub(crate) fn derivative_check(
    experiments: &[Experiment<'_>],
    p: &[f64],
    s: MatRef<'_, f64>,
) -> Result<DerivativeCheck, MemError> {
    let mut per_parameter = Vec::with_capacity(p.len());
    for i in 0..p.len() {
        // Central differences with step 1e-6·max(|P_i|, 1e-3): O(h²) truncation, O(u/h) rounding.
        let h = 1e-6 * p[i].abs().max(1e-3);
        let shifted = |sign: f64| {
            let mut q = p.to_vec();
            q[i] += sign * h;
            evaluate(experiments, &q)
        };
        let (plus, minus) = (shifted(1.0)?, shifted(-1.0)?);
        // residual = w(y_meas − y), so ∂y/∂P = −∂residual/∂P.
        let mut worst: f64 = 0.0;
        let mut scale: f64 = 0.0;
        for r in 0..s.nrows() {
            let fd = -(plus.residual[r] - minus.residual[r]) / (2.0 * h);
            worst = worst.max((fd - s[(r, i)]).abs());
            scale = scale.max(s[(r, i)].abs());
        }
        per_parameter.push(if scale > 0.0 { worst / scale } else { worst });
    }
    Ok(DerivativeCheck {
        worst_relative_mismatch: per_parameter.iter().copied().fold(0.0, f64::max),
        per_parameter,
    })
}
