//! The Whittle fit of the residual's spectra to the sensors' floors and the inputs' noise
//! ([`whittle`]).

use faer::Mat;
use faer::linalg::solvers::SolveLstsq;

/// Reweighting passes of the Whittle fit.
const PASSES: usize = 12;

/// θ maximising Whittle's likelihood of the levels P_r (mean periodograms, each a scaled χ²
/// about its expectation (Xθ)_r), each θ_j in `bounds[j]` (lower, upper; a coefficient whose
/// bounds meet is held there): least squares weighted by 1/(Xθ)_r², reweighted [`PASSES`]
/// times, a coefficient that leaves its bounds held at the bound it crossed (an active set: the
/// one furthest below its lower bound first, then the one furthest above its upper).
pub(super) fn whittle(design: &Mat<f64>, level: &[f64], bounds: &[(f64, f64)]) -> Option<Vec<f64>> {
    let (n, q) = (design.nrows(), design.ncols());
    let lower = |j: usize| bounds.get(j).map_or(0.0, |b| b.0.max(0.0));
    let upper = |j: usize| bounds.get(j).map(|b| b.1).filter(|u| *u >= lower(j)).unwrap_or(f64::INFINITY);
    let mut fitted: Vec<f64> = level.to_vec();
    let floor = level.iter().copied().fold(0.0, f64::max) * 1e-12;
    let mut theta = vec![0.0; q];
    for _ in 0..PASSES {
        let weight: Vec<f64> = fitted.iter().map(|f| 1.0 / f.max(floor).max(f64::MIN_POSITIVE)).collect();
        // Each coefficient free (None) or held at a bound; one whose bounds meet is held from
        // the start.
        let mut held: Vec<Option<f64>> = (0..q).map(|j| (lower(j) >= upper(j)).then(|| lower(j))).collect();
        loop {
            let free: Vec<usize> = (0..q).filter(|&j| held[j].is_none()).collect();
            let fixed = |r: usize| (0..q).filter_map(|j| held[j].map(|v| design[(r, j)] * v)).sum::<f64>();
            theta = (0..q).map(|j| held[j].unwrap_or(0.0)).collect();
            if !free.is_empty() {
                let x = Mat::from_fn(n, free.len(), |r, c| weight[r] * design[(r, free[c])]);
                let y = Mat::from_fn(n, 1, |r, _| weight[r] * (level[r] - fixed(r)));
                let solution = x.qr().solve_lstsq(&y);
                for (c, &j) in free.iter().enumerate() {
                    theta[j] = solution[(c, 0)];
                }
            }
            let below = free
                .iter()
                .copied()
                .filter(|&j| theta[j] < lower(j))
                .min_by(|&a, &b| (theta[a] - lower(a)).total_cmp(&(theta[b] - lower(b))));
            let above = || {
                free.iter()
                    .copied()
                    .filter(|&j| theta[j] > upper(j))
                    .max_by(|&a, &b| (theta[a] / upper(a)).total_cmp(&(theta[b] / upper(b))))
            };
            match below.map(|j| (j, lower(j))).or_else(|| above().map(|j| (j, upper(j)))) {
                Some((j, value)) => held[j] = Some(value),
                None => break,
            }
        }
        fitted = (0..n).map(|r| (0..q).map(|c| design[(r, c)] * theta[c]).sum()).collect();
    }
    theta
        .iter()
        .all(|t| t.is_finite())
        .then_some(theta.into_iter().enumerate().map(|(j, t)| t.clamp(lower(j), upper(j))).collect())
}
