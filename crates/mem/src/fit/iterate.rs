//! The iteration itself: Gauss–Newton steps with the Levenberg–Marquardt safeguard and the
//! active set, ending in the report.

use super::settings::{Fit, PERFECT_FIT, Safeguard, Termination, columns, free_set};
use crate::evaluate::{Evaluation, Wanted, evaluate, evaluate_for};
use crate::report::{FitReport, IterationRecord, finish, start_checks};
use crate::solve::StepSolver;
use crate::vector::dot;
use crate::{MemError, Problem};

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
    problem: &Problem<'_>,
    p: &[f64],
    rank_cutoff: f64,
) -> Result<GaussNewtonStep, MemError> {
    let e = evaluate(problem, p)?;
    let solver = StepSolver::from_owned(e.sensitivity, &e.residual, rank_cutoff)?;
    let (delta, _) = solver.step(0.0);
    Ok(GaussNewtonStep {
        delta,
        error: e.cost,
        singular_values: solver.singular_values.clone(),
        rank: solver.rank,
    })
}

impl Fit {
    /// Runs the iteration on a validated problem.
    ///
    /// # Errors
    /// [`MemError::Model`] if the model cannot be evaluated at the start;
    /// [`MemError::DerivativeMismatch`] if its sensitivities disagree with central differences;
    /// [`MemError::Unstable`] for an unstable model at the start; [`MemError::NothingToFit`]
    /// for constant data or a response that does not depend on anything.
    pub fn run(&self, problem: &Problem<'_>) -> Result<FitReport, MemError> {
        let p0 = problem.initial();
        let mut p = p0.clone();
        let mut current = evaluate(problem, &p)?;
        let start = start_checks(self, problem, &p, &current)?;
        let mut records = Vec::new();
        let mut error_history = vec![current.cost];
        let mut mu = f64::NAN;
        let mut nu = 2.0;
        let mut termination = Termination::MaxIterations;
        let perfect = PERFECT_FIT * start.data_energy;
        for iteration in 0..self.max_iterations {
            if current.cost <= perfect {
                termination = Termination::Converged;
                break;
            }
            let free = free_set(problem, &p, &current);
            if free.is_empty() {
                termination = Termination::Converged;
                break;
            }
            let solver = StepSolver::from_owned(
                columns(&current.sensitivity, &free),
                &current.residual,
                self.rank_cutoff,
            )?;
            let (free_step, predicted) = solver.step(0.0);
            let gauss_newton = scatter(&free_step, &free, p.len());
            let at_precision = predicted <= self.cost_tolerance * current.cost;
            if mu.is_nan() {
                mu = 1e-3 * solver.max_scaled_diagonal();
            }
            let accepted = match self.safeguard {
                Safeguard::None => {
                    let trial = project(problem, &p, &gauss_newton);
                    match evaluate(problem, &trial) {
                        Ok(e) => Some((trial, e, 0.0, 0)),
                        Err(_) => {
                            termination = Termination::Diverged;
                            None
                        }
                    }
                }
                Safeguard::LevenbergMarquardt => {
                    if self.small(problem, &gauss_newton, &p) || at_precision {
                        termination = Termination::Converged;
                        break;
                    }
                    self.damped_step(problem, &solver, &free, &p, &current, &mut mu, &mut nu)
                }
            };
            let Some((trial, next, damping, rejected)) = accepted else {
                if termination != Termination::Diverged {
                    termination =
                        if current.cost <= perfect { Termination::Converged } else { Termination::Stagnated };
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
            // Converged when the step is small, or when it lowered the error by less than the
            // cost tolerance (MINPACK's ftol test on the actual reduction).
            let converged = self.small(problem, &step, &p)
                || current.cost - next.cost <= self.cost_tolerance * current.cost;
            p = trial;
            current = next;
            if converged {
                termination = Termination::Converged;
                break;
            }
        }
        finish(self, problem, p, current, records, error_history, termination, start)
    }

    fn small(&self, problem: &Problem<'_>, step: &[f64], p: &[f64]) -> bool {
        step.iter().zip(p).zip(&problem.parameters).all(|((d, v), q)| d.abs() <= self.tolerance * q.scale(*v))
    }

    /// Levenberg–Marquardt on the free parameters: damp until the error drops; None if it
    /// never does. The first trial is simulated in full (it is usually accepted). Once one is
    /// rejected, each further trial is first simulated for its outputs alone (a rejected one
    /// needs only its cost) and, if accepted, again with its sensitivities. The outputs are the
    /// same bits either way ([`crate::ResponseModel::respond_outputs`]), so the iterates are
    /// those of evaluating every trial in full.
    #[allow(clippy::too_many_arguments)]
    fn damped_step(
        &self,
        problem: &Problem<'_>,
        solver: &StepSolver,
        free: &[usize],
        p: &[f64],
        current: &Evaluation,
        mu: &mut f64,
        nu: &mut f64,
    ) -> Option<(Vec<f64>, Evaluation, f64, usize)> {
        // The set the steps are solved over: `free`, less any parameter on a bound that a step
        // would push out of the box (see `held_by_step`).
        let mut reduced: Option<(StepSolver, Vec<usize>)> = None;
        for rejected in 0..60 {
            let (delta, free) = loop {
                let (solver, free) = reduced.as_ref().map_or((solver, free), |(s, f)| (s, f.as_slice()));
                let (delta, _) = solver.step(*mu);
                let outward = held_by_step(problem, p, free, &delta);
                if outward.is_empty() {
                    break (delta, free.to_vec());
                }
                let kept: Vec<usize> = free.iter().copied().filter(|i| !outward.contains(i)).collect();
                if kept.is_empty() {
                    return None;
                }
                let solver = StepSolver::from_owned(
                    columns(&current.sensitivity, &kept),
                    &current.residual,
                    self.rank_cutoff,
                )
                .ok()?;
                reduced = Some((solver, kept));
            };
            let trial = project(problem, p, &scatter(&delta, &free, p.len()));
            if trial == p {
                return None;
            }
            let predicted = predicted_decrease(current, p, &trial);
            let lower = if rejected == 0 {
                evaluate(problem, &trial).ok().filter(|e| e.cost < current.cost)
            } else {
                // The full simulation decides as well: a user's model whose outputs alone
                // differ from its full response's never gets a step that raises the error.
                match evaluate_for(problem, &trial, Wanted::Cost) {
                    Ok(e) if e.cost < current.cost => {
                        evaluate(problem, &trial).ok().filter(|f| f.cost < current.cost)
                    }
                    _ => None,
                }
            };
            if let Some(e) = lower {
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
}

/// The parameters of `free` that sit on a bound and that `step` (solved with them free) would
/// push out of the box. The active set releases a parameter on a bound when the descent
/// direction Sᵀr points inward; the Gauss–Newton step, which moves the correlated parameters
/// together, may still push it outward, and its projection then moves the others as if it had
/// moved — a poor step the damping rejects until it is tiny. Such a parameter is held and the
/// step solved for the rest (the subproblem step of an active-set method: Lawson & Hanson 1974,
/// ch. 23).
fn held_by_step(problem: &Problem<'_>, p: &[f64], free: &[usize], step: &[f64]) -> Vec<usize> {
    free.iter()
        .zip(step)
        .filter(|&(&i, &d)| {
            let q = &problem.parameters[i];
            (p[i] <= q.lower && d < 0.0) || (p[i] >= q.upper && d > 0.0)
        })
        .map(|(&i, _)| i)
        .collect()
}

/// ‖r‖² − ‖r − SΔP‖² for the step to `trial`: the decrease the linear model predicts.
fn predicted_decrease(current: &Evaluation, p: &[f64], trial: &[f64]) -> f64 {
    let delta: Vec<f64> = trial.iter().zip(p).map(|(a, b)| a - b).collect();
    let s = &current.sensitivity;
    let mut change = vec![0.0; s.nrows()];
    for (i, d) in delta.iter().enumerate() {
        if *d != 0.0 {
            let column = s.col(i).try_as_col_major().expect("an owned Mat is column-major").as_slice();
            change.iter_mut().zip(column).for_each(|(c, v)| *c += v * d);
        }
    }
    // ‖r‖² − ‖r − c‖² = 2 r·c − ‖c‖²
    2.0 * dot(&current.residual, &change) - dot(&change, &change)
}

/// A step over the free parameters as a full vector (zeros for the held ones).
fn scatter(step: &[f64], free: &[usize], j: usize) -> Vec<f64> {
    let mut full = vec![0.0; j];
    for (v, &i) in step.iter().zip(free) {
        full[i] = *v;
    }
    full
}

/// p + step, projected onto the bounds.
fn project(problem: &Problem<'_>, p: &[f64], step: &[f64]) -> Vec<f64> {
    p.iter().zip(step).zip(&problem.parameters).map(|((v, d), q)| (v + d).clamp(q.lower, q.upper)).collect()
}
