//! The order the candidates' refits run in: costliest first, each worker taking the next job
//! when it is free (Graham's longest-processing-time-first list scheduling, within 4/3 of the
//! best finishing time; Graham 1969, "Bounds on multiprocessing timing anomalies"). Rayon's
//! own split of a list in halves can leave one worker with the two slowest refits while the
//! other has finished; the results are the same either way, only their finishing time differs.

use super::catalog::Trial;
use super::run;
use models::Model;
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};

/// How much one refit of a nonlinear model costs against a linear one: a nonlinear response is
/// stepped through every substep of the record, a linear one is one exponential a sample.
const NONLINEAR_COST: usize = 20;

/// The relative cost of one refit of `model`.
pub(super) fn refit_cost(model: &Model) -> usize {
    if model.is_linear() { 1 } else { NONLINEAR_COST }
}

/// The relative cost of one refit of a trial's model (the reference with the trial's effect, as
/// [`run::with_effect`] builds it; priced as nonlinear if it cannot be built).
pub(super) fn trial_refit_cost(start: &Model, trial: &Trial) -> usize {
    run::with_effect(start, trial, &trial.effect).map_or(NONLINEAR_COST, |model| refit_cost(&model))
}

/// `f` applied to every job, on rayon's workers, the costliest job (by `cost`) started first;
/// the results in the jobs' order.
pub(super) fn largest_first<J: Sync, R: Send>(
    jobs: &[J],
    cost: impl Fn(&J) -> usize,
    f: impl Fn(&J) -> R + Sync,
) -> Vec<R> {
    let mut order: Vec<usize> = (0..jobs.len()).collect();
    // A stable sort keeps the jobs' own order among equal costs.
    order.sort_by_key(|&i| std::cmp::Reverse(cost(&jobs[i])));
    let next = AtomicUsize::new(0);
    let results: Mutex<Vec<Option<R>>> = Mutex::new((0..jobs.len()).map(|_| None).collect());
    let workers = rayon::current_num_threads().clamp(1, jobs.len().max(1));
    rayon::scope(|scope| {
        for _ in 0..workers {
            scope.spawn(|_| {
                loop {
                    let k = next.fetch_add(1, Ordering::Relaxed);
                    let Some(&i) = order.get(k) else { break };
                    let result = f(&jobs[i]);
                    // A worker that panicked poisons the lock; the panic is re-raised by
                    // `scope`, so the data behind it is never read.
                    if let Ok(mut results) = results.lock() {
                        results[i] = Some(result);
                    }
                }
            });
        }
    });
    results
        .into_inner()
        .unwrap_or_else(|poisoned| poisoned.into_inner())
        .into_iter()
        .map(|r| r.expect("every job ran"))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pool(threads: usize) -> rayon::ThreadPool {
        rayon::ThreadPoolBuilder::new().num_threads(threads).build().expect("a pool")
    }

    #[test]
    fn the_results_keep_the_jobs_order_and_the_costliest_start_first() {
        let jobs: Vec<usize> = vec![3, 9, 1, 9, 4, 0, 7];
        let want: Vec<usize> = jobs.iter().map(|j| 10 * j).collect();
        // One worker takes the jobs exactly by cost, the tie in the jobs' order.
        let started = Mutex::new(Vec::new());
        let out = pool(1).install(|| {
            largest_first(
                &jobs,
                |j| *j,
                |j| {
                    started.lock().unwrap().push(*j);
                    10 * j
                },
            )
        });
        assert_eq!(out, want);
        assert_eq!(started.into_inner().unwrap(), vec![9, 9, 7, 4, 3, 1, 0]);
        // Several workers, and more workers than jobs: the same results in the same order.
        for threads in [2, 3, 16] {
            assert_eq!(pool(threads).install(|| largest_first(&jobs, |j| *j, |j| 10 * j)), want);
        }
        assert!(largest_first(&Vec::<usize>::new(), |j| *j, |j| *j).is_empty());
    }
}
