//! The MEM iteration (the paper's Algorithm, steps 1–4), made robust.

use crate::evaluate::{Evaluation, evaluate};
use crate::report::{FitReport, IterationRecord, derivative_check, identifiability, statistics};
use crate::solve::StepSolver;
use crate::{Experiment, MemError};

/// How a step is safeguarded.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Safeguard {
    /// The paper's plain Gauss–Newton: every step is taken (it may increase the error).
    None,
    /// Levenberg–Marquardt damping (Nielsen's update): a step is accepted only if it lowers
    /// the error; otherwise the damping grows and the step shrinks toward steepest descent.
    LevenbergMarquardt,
}

/// Why the iteration stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Termination {
    /// The Gauss–Newton step satisfies |ΔP_i| ≤ tol·|P_i| for every i (paper step 4), or the
    /// decrease it predicts is below 1e-12 of the error (the gradient vanishes at working
    /// precision, MINPACK's relative-reduction test).
    Converged,
    /// No step with any damping lowers the error: a (local) minimum at the resolution of the
    /// arithmetic, or a minimum on a bound.
    Stagnated,
    /// The iteration cap was reached first.
    MaxIterations,
    /// Plain Gauss–Newton only: a step made the model fail or the error non-finite; the
    /// report holds the last parameters that could be evaluated.
    Diverged,
}

/// One plain iteration of the paper's Algorithm: outputs and sensitivities at P (steps 1–2) and
/// the SVD least-squares step ΔP (step 3), without line search or statistics.
#[derive(Clone, Debug)]
pub struct GaussNewtonStep {
    /// ΔP.
    pub delta: Vec<f64>,
    /// ‖Y_error‖ at P (Eq. 22, weighted).
    pub error: f64,
    /// Singular values of the column-scaled S.
    pub singular_values: Vec<f64>,
    /// How many were kept.
    pub rank: usize,
}

/// Computes one [`GaussNewtonStep`] at `p`.
///
/// # Errors
/// Model failures, SVD failure.
pub fn gauss_newton_step(
    experiments: &[Experiment<'_>],
    p: &[f64],
    rank_cutoff: f64,
) -> Result<GaussNewtonStep, MemError> {
    let e = evaluate(experiments, p)?;
    let solver = StepSolver::from_owned(e.sensitivity, &e.residual, rank_cutoff)?;
    let (delta, _) = solver.step(0.0);
    Ok(GaussNewtonStep {
        delta,
        error: e.cost,
        singular_values: solver.singular_values.clone(),
        rank: solver.rank,
    })
}

/// Relative decrease of the error below which the Gauss–Newton step cannot be told from rounding.
const PREDICTED_DECREASE_FLOOR: f64 = 1e-12;

/// The MEM solver and its settings. Build with [`Fit::new`] and the `with_*` setters.
#[derive(Clone, Debug)]
pub struct Fit {
    tolerance: f64,
    max_iterations: usize,
    rank_cutoff: f64,
    safeguard: Safeguard,
    bounds: Option<Vec<(f64, f64)>>,
    check_derivatives: bool,
    names: Option<Vec<String>>,
    identifiability_threshold: f64,
}

impl Default for Fit {
    fn default() -> Self {
        Self::new()
    }
}

fn setting(name: &'static str, value: f64, ok: bool, requirement: &'static str) -> Result<(), MemError> {
    if ok { Ok(()) } else { Err(MemError::InvalidSetting { name, value, requirement }) }
}

impl Fit {
    /// Defaults: tolerance 1e-8, 100 iterations, rank cutoff 1e-10, Levenberg–Marquardt on,
    /// no bounds, no derivative check, identifiability threshold 1e-6.
    pub fn new() -> Self {
        Self {
            tolerance: 1e-8,
            max_iterations: 100,
            rank_cutoff: 1e-10,
            safeguard: Safeguard::LevenbergMarquardt,
            bounds: None,
            check_derivatives: false,
            names: None,
            identifiability_threshold: 1e-6,
        }
    }

    /// Relative step tolerance: stop when |ΔP_i| ≤ tol·|P_i| for all i.
    ///
    /// # Errors
    /// Unless 0 < tol < 1.
    pub fn with_tolerance(mut self, tol: f64) -> Result<Self, MemError> {
        setting("tolerance", tol, tol > 0.0 && tol < 1.0, "0 < tolerance < 1")?;
        self.tolerance = tol;
        Ok(self)
    }

    /// The iteration cap.
    ///
    /// # Errors
    /// For 0.
    pub fn with_max_iterations(mut self, n: usize) -> Result<Self, MemError> {
        setting("max_iterations", n as f64, n > 0, "at least 1")?;
        self.max_iterations = n;
        Ok(self)
    }

    /// Singular values of the column-scaled S below `cutoff`·σ_max are treated as zero.
    ///
    /// # Errors
    /// Unless 0 ≤ cutoff < 1.
    pub fn with_rank_cutoff(mut self, cutoff: f64) -> Result<Self, MemError> {
        setting("rank_cutoff", cutoff, (0.0..1.0).contains(&cutoff), "0 ≤ rank_cutoff < 1")?;
        self.rank_cutoff = cutoff;
        Ok(self)
    }

    /// The step safeguard.
    pub fn with_safeguard(mut self, safeguard: Safeguard) -> Self {
        self.safeguard = safeguard;
        self
    }

    /// Box bounds (lower, upper) per parameter; steps are projected onto the box.
    ///
    /// # Errors
    /// Unless lower < upper for each.
    pub fn with_bounds(mut self, bounds: Vec<(f64, f64)>) -> Result<Self, MemError> {
        for (lo, hi) in &bounds {
            setting("bounds", *lo, lo < hi, "lower < upper")?;
        }
        self.bounds = Some(bounds);
        Ok(self)
    }

    /// After convergence, compare S with central finite differences and report the worst
    /// mismatch.
    pub fn with_derivative_check(mut self, on: bool) -> Self {
        self.check_derivatives = on;
        self
    }

    /// Parameter names, used in the identifiability report.
    pub fn with_parameter_names(mut self, names: Vec<String>) -> Self {
        self.names = Some(names);
        self
    }

    /// Relative singular value below which a parameter combination counts as not determined.
    ///
    /// # Errors
    /// Unless 0 < threshold < 1.
    pub fn with_identifiability_threshold(mut self, threshold: f64) -> Result<Self, MemError> {
        setting(
            "identifiability_threshold",
            threshold,
            threshold > 0.0 && threshold < 1.0,
            "between 0 and 1",
        )?;
        self.identifiability_threshold = threshold;
        Ok(self)
    }

    fn project(&self, p: &mut [f64]) {
        if let Some(b) = &self.bounds {
            for (v, (lo, hi)) in p.iter_mut().zip(b) {
                *v = v.clamp(*lo, *hi);
            }
        }
    }

    fn small(&self, step: &[f64], p: &[f64]) -> bool {
        step.iter().zip(p).all(|(d, v)| d.abs() <= self.tolerance * (v.abs() + self.tolerance))
    }

    /// Runs the iteration from `p0` on one or more experiments that share P.
    ///
    /// # Errors
    /// [`MemError::Shape`] if the experiments, P and the bounds disagree;
    /// [`MemError::InvalidData`] if `p0` is not finite or outside the bounds;
    /// [`MemError::Model`] if the model cannot be evaluated at `p0`.
    pub fn run(&self, experiments: &[Experiment<'_>], p0: &[f64]) -> Result<FitReport, MemError> {
        let j = p0.len();
        if experiments.is_empty() {
            return Err(MemError::Shape("at least one experiment is needed".into()));
        }
        for (i, e) in experiments.iter().enumerate() {
            e.validate(i, j)?;
        }
        if let Some(b) = &self.bounds {
            if b.len() != j {
                return Err(MemError::Shape(format!("{} bounds for {j} parameters", b.len())));
            }
            for (i, (v, (lo, hi))) in p0.iter().zip(b).enumerate() {
                if v < lo || v > hi {
                    return Err(MemError::InvalidData(format!(
                        "initial P[{i}] = {v} lies outside its bounds [{lo}, {hi}]"
                    )));
                }
            }
        }
        if let Some(bad) = p0.iter().position(|v| !v.is_finite()) {
            return Err(MemError::InvalidData(format!("initial P[{bad}] = {} is not finite", p0[bad])));
        }
        let mut p = p0.to_vec();
        let mut current = evaluate(experiments, &p)?;
        let mut records = Vec::new();
        let mut error_history = vec![current.cost];
        let mut mu = f64::NAN;
        let mut nu = 2.0;
        let mut termination = Termination::MaxIterations;
        for iteration in 0..self.max_iterations {
            let solver = StepSolver::new(current.sensitivity.as_ref(), &current.residual, self.rank_cutoff)?;
            let (gauss_newton, predicted) = solver.step(0.0);
            let at_precision = predicted <= PREDICTED_DECREASE_FLOOR * current.cost;
            if mu.is_nan() {
                mu = 1e-3 * solver.max_scaled_diagonal();
            }
            let accepted = match self.safeguard {
                Safeguard::None => {
                    let mut trial: Vec<f64> = p.iter().zip(&gauss_newton).map(|(a, b)| a + b).collect();
                    self.project(&mut trial);
                    match evaluate(experiments, &trial) {
                        Ok(e) if e.cost.is_finite() => Some((trial, e, 0.0, 0)),
                        _ => {
                            termination = Termination::Diverged;
                            None
                        }
                    }
                }
                Safeguard::LevenbergMarquardt => {
                    if self.small(&gauss_newton, &p) || at_precision {
                        termination = Termination::Converged;
                        break;
                    }
                    self.damped_step(experiments, &solver, &p, &current, &mut mu, &mut nu)
                }
            };
            let Some((trial, next, damping, rejected)) = accepted else {
                if termination != Termination::Diverged {
                    termination = Termination::Stagnated;
                }
                break;
            };
            let step: Vec<f64> = trial.iter().zip(&p).map(|(a, b)| a - b).collect();
            records.push(IterationRecord {
                iteration: iteration + 1,
                parameters: trial.clone(),
                error: next.cost,
                step: step.clone(),
                singular_values: solver.singular_values.clone(),
                rank: solver.rank,
                damping,
                rejected_trials: rejected,
            });
            error_history.push(next.cost);
            let converged = self.small(&step, &p);
            p = trial;
            current = next;
            if converged {
                termination = Termination::Converged;
                break;
            }
        }
        self.report(experiments, p0, p, current, records, error_history, termination)
    }

    /// Levenberg–Marquardt: damp until the error drops; None if it never does.
    fn damped_step(
        &self,
        experiments: &[Experiment<'_>],
        solver: &StepSolver,
        p: &[f64],
        current: &Evaluation,
        mu: &mut f64,
        nu: &mut f64,
    ) -> Option<(Vec<f64>, Evaluation, f64, usize)> {
        for rejected in 0..60 {
            let (delta, predicted) = solver.step(*mu);
            let mut trial: Vec<f64> = p.iter().zip(&delta).map(|(a, b)| a + b).collect();
            self.project(&mut trial);
            if trial == p {
                return None;
            }
            if let Ok(e) = evaluate(experiments, &trial)
                && e.cost < current.cost
            {
                let gain = (current.cost - e.cost) / predicted.max(f64::MIN_POSITIVE);
                let used = *mu;
                *mu *= (1.0 / 3.0f64).max(1.0 - (2.0 * gain - 1.0).powi(3));
                *nu = 2.0;
                return Some((trial, e, used, rejected));
            }
            *mu *= *nu;
            *nu *= 2.0;
        }
        None
    }

    #[allow(clippy::too_many_arguments)]
    fn report(
        &self,
        experiments: &[Experiment<'_>],
        p0: &[f64],
        p: Vec<f64>,
        last: Evaluation,
        records: Vec<IterationRecord>,
        error_history: Vec<f64>,
        termination: Termination,
    ) -> Result<FitReport, MemError> {
        let solver = StepSolver::new(last.sensitivity.as_ref(), &last.residual, self.rank_cutoff)?;
        let names =
            self.names.clone().unwrap_or_else(|| (0..p.len()).map(|i| format!("p{}", i + 1)).collect());
        let statistics = statistics(&solver, &p, last.cost, last.residual.len());
        let identifiability =
            identifiability(last.sensitivity.as_ref(), &p, &names, self.identifiability_threshold)?;
        let derivative_check = if self.check_derivatives {
            Some(derivative_check(experiments, &p, last.sensitivity.as_ref())?)
        } else {
            None
        };
        Ok(FitReport {
            initial: p0.to_vec(),
            iterations: records.len(),
            parameters: p,
            termination,
            error_history,
            records,
            n_residuals: last.residual.len(),
            rank: solver.rank,
            rank_cutoff: self.rank_cutoff,
            statistics,
            identifiability,
            derivative_check,
            names,
        })
    }
}
