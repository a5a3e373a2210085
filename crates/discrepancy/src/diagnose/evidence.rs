//! The evidence every candidate is scored by: the log-likelihood of the same data under one
//! stated measurement model, in sample and on held-out blocks.
//!
//! **Measurement model.** Each output o carries Gaussian AR(1) noise,
//! e_k = ρ_o e_{k−1} + u_k, u_k ~ N(0, s_o²), independent between outputs; (ρ_o, s_o) are
//! profiled out (their maximum-likelihood values for the residual at hand), so the
//! log-likelihood of an output's n residuals is, up to a constant common to every model,
//! ℓ_o = −(n/2) ln(U_o/n), U_o = (1 − ρ²)e₀² + Σ (e_k − ρ e_{k−1})² (the innovations' sum of
//! squares). A candidate is compared with the baseline by Σ_o (ℓ_o,c − ℓ_o,b) — on the same
//! rows, with the same definition of residual; quantized sensors are the one place where the
//! residual is the distance to the reading's interval, and then in both models.
//!
//! **Held-out evidence.** The record is cut into blocks, alternately assigned to two folds. Each
//! model is fitted on one fold (the other's samples weighted 0) and scores its prediction of the
//! other; the two scores are summed. A parameter that only fits noise does not predict the other
//! fold and earns nothing there; a smooth misfit shaved by the wrong physics gains less out of
//! sample than in it.

use faer::Mat;

/// Samples per block: about a second of record, at least four samples, and at least 24 blocks.
pub fn block_length(n_rows: usize, interval: f64) -> usize {
    let second = (1.0 / interval).round().max(1.0) as usize;
    second.min(n_rows / 24).max(4)
}

/// The two folds' sample weights (1 in the fold, 0 outside): alternate blocks of `block` rows.
pub fn folds(n_rows: usize, block: usize) -> [Vec<f64>; 2] {
    let fold = |f: usize| (0..n_rows).map(|k| if (k / block) % 2 == f { 1.0 } else { 0.0 }).collect();
    [fold(0), fold(1)]
}

/// Per output, the profiled AR(1) log-likelihood −(n/2) ln(U/n) of the residual's rows whose
/// weight is positive (`rows`; all rows if None). Consecutive rows are chained; a gap starts a
/// new segment, whose first innovation is (1 − ρ²)^½ e.
pub fn log_likelihoods(residual: &Mat<f64>, rows: Option<&[f64]>) -> Vec<f64> {
    (0..residual.ncols())
        .map(|o| {
            let keep = |k: usize| rows.is_none_or(|w| w[k] > 0.0);
            let (mut power, mut lagged, mut n) = (0.0, 0.0, 0usize);
            for k in 0..residual.nrows() {
                if keep(k) {
                    let e = residual[(k, o)];
                    power += e * e;
                    n += 1;
                    if k > 0 && keep(k - 1) {
                        lagged += e * residual[(k - 1, o)];
                    }
                }
            }
            if n == 0 || power == 0.0 {
                return 0.0;
            }
            let rho = (lagged / power).clamp(-0.99, 0.99);
            let mut u = 0.0;
            for k in 0..residual.nrows() {
                if keep(k) {
                    let e = residual[(k, o)];
                    u += if k > 0 && keep(k - 1) {
                        (e - rho * residual[(k - 1, o)]).powi(2)
                    } else {
                        (1.0 - rho * rho) * e * e
                    };
                }
            }
            let n = n as f64;
            -0.5 * n * (u / n).max(f64::MIN_POSITIVE).ln()
        })
        .collect()
}

/// Σ_o of a per-output difference.
pub fn gain(candidate: &[f64], baseline: &[f64]) -> f64 {
    candidate.iter().zip(baseline).map(|(c, b)| c - b).sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn folds_alternate_blocks_and_cover_every_row_once() {
        let [a, b] = folds(10, 3);
        assert_eq!(a, vec![1.0, 1.0, 1.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 0.0]);
        assert!(a.iter().zip(&b).all(|(x, y)| x + y == 1.0));
        assert_eq!(block_length(385, 1.0 / 12.8), 13);
        assert_eq!(block_length(3841, 1.0 / 128.0), 128);
        assert_eq!(block_length(50, 0.01), 4);
    }

    #[test]
    fn white_residuals_score_their_gaussian_likelihood() {
        // A white series: ρ̂ ≈ 0, so ℓ = −(n/2) ln(Σe²/n) to O(ρ̂²).
        let e: Vec<f64> = (0..400).map(|k| (((k * 7919) % 13) as f64 - 6.0) * 0.1).collect();
        let residual = Mat::from_fn(400, 1, |k, _| e[k]);
        let power: f64 = e.iter().map(|v| v * v).sum();
        let white = -200.0 * (power / 400.0).ln();
        assert!((log_likelihoods(&residual, None)[0] - white).abs() < 0.05 * white.abs());
        // Halving the residual gains n ln 2 exactly (ρ̂ is scale free).
        let half = Mat::from_fn(400, 1, |k, _| 0.5 * e[k]);
        let gained = log_likelihoods(&half, None)[0] - log_likelihoods(&residual, None)[0];
        assert!((gained - 400.0 * 2f64.ln()).abs() < 1e-9);
        // Only the selected rows count.
        let rows: Vec<f64> = (0..400).map(|k| if k < 100 { 1.0 } else { 0.0 }).collect();
        let part = Mat::from_fn(100, 1, |k, _| e[k]);
        assert!((log_likelihoods(&residual, Some(&rows))[0] - log_likelihoods(&part, None)[0]).abs() < 1e-9);
    }

    #[test]
    fn a_smooth_misfit_counts_as_few_independent_samples() {
        // A slowly varying residual is almost all predictable from its last value: its
        // innovations are small, and shrinking it by 10 % gains the same n ln(1/0.9) either way,
        // but the AR(1) model does not grant a smooth residual white-noise precision.
        let smooth = Mat::from_fn(400, 1, |k, _| (k as f64 * 0.01).sin());
        let white = Mat::from_fn(400, 1, |k, _| (((k * 7919) % 13) as f64 - 6.0) * 0.1);
        assert!(log_likelihoods(&smooth, None)[0] > log_likelihoods(&white, None)[0] + 400.0);
    }
}
