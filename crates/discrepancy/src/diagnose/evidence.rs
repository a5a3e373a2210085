//! The evidence every candidate is scored by: the log-likelihood of the same data under one
//! stated measurement model, in sample and on held-out blocks.
//!
//! **Measurement model.** Each output o carries Gaussian AR(1) noise,
//! e_k = ρ_o e_{k−1} + u_k, u_k ~ N(0, s_o²), independent between outputs; ρ_o is fixed once
//! for every model ([`NoiseModel`]) and s_o profiled out, so the log-likelihood of an output's
//! n residuals is, up to a constant common to every model, ℓ_o = −(n/2) ln(U_o/n),
//! U_o = (1 − ρ²)e₀² + Σ (e_k − ρ e_{k−1})² (the innovations' sum of squares). A candidate is compared with the baseline by Σ_o (ℓ_o,c − ℓ_o,b) — on the same
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

/// The measurement model every candidate is scored under: per output, Gaussian AR(1) noise
/// with a lag-one coefficient ρ_o fixed once for all models, its innovation variance profiled.
///
/// ρ_o is the lag-one autocorrelation of the residual of the model that fits the data best (the
/// smallest weighted error among the reference and the candidates): the one whose residual is
/// closest to the noise itself. Profiling ρ per model instead would let a model that leaves a
/// smooth misfit call it correlated noise (ρ → 1) and score better than one that removes it.
#[derive(Clone, Debug, serde::Serialize)]
pub struct NoiseModel {
    /// ρ_o per output, in \[−0.99, 0.99\].
    pub rho: Vec<f64>,
    /// Per output, the structure (nats, [`structure_per_output`]) that the noise on a forced
    /// record's recorded force leaves in any model's residual through the model's own response
    /// ([`structure_of_spectrum`] of the noise's spectrum): a floor no model can remove, taken off
    /// the structure a refit leaves and the reference's before their shares are compared. Empty
    /// where there is no recorded input (then 0).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub structure_floor: Vec<f64>,
}

impl NoiseModel {
    /// ρ_o from a residual (K × p).
    pub fn of(residual: &Mat<f64>) -> Self {
        let rho = (0..residual.ncols())
            .map(|o| {
                let (mut power, mut lagged) = (0.0, 0.0);
                for k in 0..residual.nrows() {
                    let e = residual[(k, o)];
                    power += e * e;
                    if k > 0 {
                        lagged += e * residual[(k - 1, o)];
                    }
                }
                if power > 0.0 { (lagged / power).clamp(-0.99, 0.99) } else { 0.0 }
            })
            .collect();
        Self { rho, structure_floor: Vec::new() }
    }

    /// Per output, the log-likelihood −(n/2) ln(U/n) of the residual's rows whose weight is
    /// positive (`rows`; all rows if None), U the innovations' sum of squares under ρ_o.
    /// Consecutive rows are chained; a gap starts a new segment, whose first innovation is
    /// (1 − ρ²)^½ e.
    pub fn log_likelihoods(&self, residual: &Mat<f64>, rows: Option<&[f64]>) -> Vec<f64> {
        (0..residual.ncols())
            .map(|o| {
                let (u, n) = self.innovations(residual, o, rows);
                if n == 0 || u == 0.0 {
                    return 0.0;
                }
                let n = n as f64;
                -0.5 * n * (u / n).ln()
            })
            .collect()
    }

    /// Output o's innovations' sum of squares U under ρ_o over the rows of positive weight
    /// (all if None), and how many rows that is.
    fn innovations(&self, residual: &Mat<f64>, o: usize, rows: Option<&[f64]>) -> (f64, usize) {
        let rho = self.rho[o];
        let keep = |k: usize| rows.is_none_or(|w| w[k] > 0.0);
        let (mut u, mut n) = (0.0, 0usize);
        for k in 0..residual.nrows() {
            if keep(k) {
                let e = residual[(k, o)];
                u += if k > 0 && keep(k - 1) {
                    (e - rho * residual[(k - 1, o)]).powi(2)
                } else {
                    (1.0 - rho * rho) * e * e
                };
                n += 1;
            }
        }
        (u, n)
    }
}

/// The measurement model as a fit's weights: a refit that minimises
/// Σ_o Σ_k ((e_k − ρ_o e_{k−1})/s_o)² maximises the Gaussian AR(1) likelihood the evidence
/// scores, at the noise model's ρ_o and innovation scales s_o (generalised least squares).
#[derive(Clone, Debug)]
pub struct LikelihoodFit {
    /// ρ_o per output.
    pub rho: Vec<f64>,
    /// 1/s_o per output.
    pub weights: Vec<f64>,
}

impl NoiseModel {
    /// The fit weights of this model with innovation scales s_o from `residual` (the
    /// best-fitting model's): s_o² = U_o/n, floored at 10⁻¹² of the output's RMS so a perfect
    /// fit still weighs its output.
    pub fn fit_weights(&self, residual: &Mat<f64>) -> LikelihoodFit {
        let n = residual.nrows().max(1) as f64;
        let weights = (0..residual.ncols())
            .map(|o| {
                let (u, _) = self.innovations(residual, o, None);
                let power = residual.col(o).squared_norm_l2();
                let s2 = (u / n).max(1e-24 * power / n);
                if s2 > 0.0 { 1.0 / s2.sqrt() } else { 1.0 }
            })
            .collect();
        LikelihoodFit { rho: self.rho.clone(), weights }
    }
}

/// Σ_o of a per-output difference.
pub fn gain(candidate: &[f64], baseline: &[f64]) -> f64 {
    candidate.iter().zip(baseline).map(|(c, b)| c - b).sum()
}

/// Lags of the autoregression that measures the structure left in a residual.
const STRUCTURE_LAGS: usize = 20;

/// The structure a residual still holds beyond the measurement model (nats): per output, the
/// log-likelihood gain of an AR(20) least-squares predictor of e_k from its 20 predecessors over
/// the noise model's own AR(1) prediction ρ_o e_{k−1}, less the 10 nats white noise gains by
/// chance (half a χ² with 20 degrees of freedom), summed over the outputs and floored at 0. A
/// misfit — smooth, an offset, a trend — is predictable from its past and scores high; noise
/// that follows the measurement model scores about 0.
pub fn structure(residual: &Mat<f64>, noise: &NoiseModel) -> f64 {
    structure_per_output(residual, noise).iter().sum()
}

/// [`structure()`](fn@structure) output by output.
pub fn structure_per_output(residual: &Mat<f64>, noise: &NoiseModel) -> Vec<f64> {
    use faer::linalg::solvers::SolveLstsq;
    let (k, p) = (residual.nrows(), residual.ncols());
    if k <= 4 * STRUCTURE_LAGS {
        return vec![0.0; p];
    }
    let rows = k - STRUCTURE_LAGS;
    (0..p)
        .map(|o| {
            let rho = noise.rho.get(o).copied().unwrap_or(0.0);
            let y = Mat::<f64>::from_fn(rows, 1, |r, _| residual[(r + STRUCTURE_LAGS, o)]);
            let x =
                Mat::<f64>::from_fn(rows, STRUCTURE_LAGS, |r, l| residual[(r + STRUCTURE_LAGS - 1 - l, o)]);
            let beta = x.qr().solve_lstsq(&y);
            let fit = &x * &beta;
            let many: f64 = (0..rows).map(|r| (y[(r, 0)] - fit[(r, 0)]).powi(2)).sum();
            let one: f64 = (0..rows).map(|r| (y[(r, 0)] - rho * x[(r, 0)]).powi(2)).sum();
            if !(one > 0.0 && many > 0.0 && one.is_finite() && many.is_finite()) {
                return 0.0;
            }
            (0.5 * rows as f64 * (one / many).ln() - 0.5 * STRUCTURE_LAGS as f64).max(0.0)
        })
        .collect()
}

/// The structure ([`structure_per_output`]) that `n` samples of a stationary Gaussian residual
/// with the one-sided spectrum `levels` (Welch bins 0…L/2 − 1 of a segment of L) hold beyond
/// AR(1) prediction with coefficient `rho`: ½(n − 20) ln(e₁/e₂₀) − 10, floored at 0 (what a
/// residual made of that noise alone scores, on average).
pub fn structure_of_spectrum(levels: &[f64], rho: f64, n: usize) -> f64 {
    predictability(levels, rho, n).map_or(0.0, |p| (p - 0.5 * STRUCTURE_LAGS as f64).max(0.0))
}

/// The autocovariance γ_l, l = 0…`lags`, of a one-sided spectrum on Welch bins 0…L/2 − 1 of a
/// segment of L: Σ_b w_b S_b cos(2πbl/L), w₀ = 1, else 2 (up to a common scale).
pub fn autocovariance(levels: &[f64], lags: usize) -> Vec<f64> {
    let length = 2 * levels.len();
    (0..=lags)
        .map(|l| {
            levels
                .iter()
                .enumerate()
                .map(|(b, s)| {
                    let w = if b == 0 { 1.0 } else { 2.0 };
                    w * s * (2.0 * std::f64::consts::PI * (b * l) as f64 / length as f64).cos()
                })
                .sum()
        })
        .collect()
}

/// ½(n − 20) ln(e₁/e₂₀) of a spectrum: e₁ the AR(1) prediction's error variance
/// γ₀(1 + ρ²) − 2ργ₁, e₂₀ the best order-20 predictor's (Levinson–Durbin on the autocovariance
/// γ_l = Σ_b w_b S_b cos(2πbl/L), w₀ = 1, else 2). `None` for a degenerate spectrum or too few
/// samples.
fn predictability(levels: &[f64], rho: f64, n: usize) -> Option<f64> {
    if n <= 4 * STRUCTURE_LAGS || levels.is_empty() {
        return None;
    }
    let gamma = autocovariance(levels, STRUCTURE_LAGS);
    if !(gamma[0] > 0.0 && gamma.iter().all(|g| g.is_finite())) {
        return None;
    }
    let one = gamma[0] * (1.0 + rho * rho) - 2.0 * rho * gamma[1];
    // Levinson–Durbin: the prediction error of the best predictor of each order up to 20.
    let (mut a, mut error) = (vec![0.0; STRUCTURE_LAGS + 1], gamma[0]);
    for m in 1..=STRUCTURE_LAGS {
        let k = (gamma[m] - (1..m).map(|j| a[j] * gamma[m - j]).sum::<f64>()) / error;
        let previous = a.clone();
        a[m] = k;
        for j in 1..m {
            a[j] = previous[j] - k * previous[m - j];
        }
        error *= 1.0 - k * k;
        if error.is_nan() || error <= 0.0 {
            return None;
        }
    }
    (one > 0.0).then(|| 0.5 * (n - STRUCTURE_LAGS) as f64 * (one / error).ln())
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

    fn white(n: usize, sigma: f64, seed: u64) -> Vec<f64> {
        use rand::{Rng, SeedableRng};
        let mut rng = rand::rngs::StdRng::seed_from_u64(seed);
        (0..n).map(|_| sigma * rng.sample::<f64, _>(rand_distr::StandardNormal)).collect()
    }

    #[test]
    fn structure_is_about_zero_for_noise_and_large_for_a_misfit() {
        // White and AR(1) noise under their own measurement model: below chance (floored at 0)
        // in most draws, a few nats at most.
        let mut scores = Vec::new();
        for seed in 0..20 {
            let e = white(400, 0.1, seed);
            let mut ar = vec![0.0; 400];
            for k in 1..400 {
                ar[k] = 0.8 * ar[k - 1] + e[k];
            }
            for series in [e, ar] {
                let residual = Mat::from_fn(400, 1, |k, _| series[k]);
                scores.push(structure(&residual, &NoiseModel::of(&residual)));
            }
        }
        scores.sort_by(f64::total_cmp);
        assert!(scores[scores.len() / 2] < 1.0 && scores[scores.len() - 1] < 15.0, "{scores:?}");
        // A decaying oscillation of about the noise's RMS: predictable from its past.
        let e = white(400, 0.1, 99);
        let misfit =
            Mat::from_fn(400, 1, |k, _| e[k] + 0.3 * (0.3 * k as f64).sin() * (-0.005 * k as f64).exp());
        let noise = NoiseModel::of(&Mat::from_fn(400, 1, |k, _| e[k]));
        assert!(structure(&misfit, &noise) > 50.0, "{}", structure(&misfit, &noise));
    }

    /// The structure a spectrum implies is what realisations of that noise score: a resonance
    /// (an AR(2) pole pair at radius 0.97) under a white floor, against the mean of 12 draws
    /// scored by the least-squares AR(20) of [`structure_per_output`]; and white noise implies 0.
    #[test]
    fn the_structure_of_a_spectrum_is_what_its_noise_scores() {
        let (n, radius, omega, floor) = (4000, 0.97, 2.0 * std::f64::consts::PI * 0.05, 0.5);
        let (a1, a2) = (2.0 * radius * omega.cos(), -radius * radius);
        let mut scored = Vec::new();
        let mut rhos = Vec::new();
        for seed in 0..12 {
            let (w, v) = (white(n, 1.0, 100 + seed), white(n, floor, 200 + seed));
            let mut x = vec![0.0; n];
            for k in 2..n {
                x[k] = a1 * x[k - 1] + a2 * x[k - 2] + w[k];
            }
            let residual = Mat::from_fn(n, 1, |k, _| x[k] + v[k]);
            let noise = NoiseModel::of(&residual);
            rhos.push(noise.rho[0]);
            scored.push(structure_per_output(&residual, &noise)[0]);
        }
        let rho = rhos.iter().sum::<f64>() / rhos.len() as f64;
        let mean = scored.iter().sum::<f64>() / scored.len() as f64;
        let bins = 512;
        let levels: Vec<f64> = (0..bins)
            .map(|b| {
                let w = std::f64::consts::PI * b as f64 / bins as f64;
                let (re, im) =
                    (1.0 - a1 * w.cos() - a2 * (2.0 * w).cos(), a1 * w.sin() + a2 * (2.0 * w).sin());
                1.0 / (re * re + im * im) + floor * floor
            })
            .collect();
        let implied = structure_of_spectrum(&levels, rho, n);
        assert!(mean > 200.0, "{mean}");
        assert!((implied / mean - 1.0).abs() < 0.1, "implied {implied}, scored {mean}");
        assert_eq!(structure_of_spectrum(&vec![1.0; bins], 0.0, n), 0.0);
    }

    #[test]
    fn structure_is_found_on_the_output_that_holds_it() {
        // Two outputs of noise; a misfit on the second only.
        let (a, b) = (white(400, 0.1, 7), white(400, 0.1, 8));
        let noise = NoiseModel::of(&Mat::from_fn(400, 2, |k, o| if o == 0 { a[k] } else { b[k] }));
        let residual = Mat::from_fn(400, 2, |k, o| {
            if o == 0 { a[k] } else { b[k] + 0.3 * (0.3 * k as f64).sin() * (-0.005 * k as f64).exp() }
        });
        let per = structure_per_output(&residual, &noise);
        assert_eq!(per.len(), 2);
        assert!(per[0] < 15.0 && per[1] > 50.0, "{per:?}");
        assert!((per.iter().sum::<f64>() - structure(&residual, &noise)).abs() < 1e-9);
    }

    #[test]
    fn white_residuals_score_their_gaussian_likelihood() {
        // A white series: ρ̂ ≈ 0, so ℓ = −(n/2) ln(Σe²/n) to O(ρ̂²).
        let e = white(400, 0.1, 1);
        let residual = Mat::from_fn(400, 1, |k, _| e[k]);
        let noise = NoiseModel::of(&residual);
        assert!(noise.rho[0].abs() < 0.2);
        let power: f64 = e.iter().map(|v| v * v).sum();
        let white = -200.0 * (power / 400.0).ln();
        assert!((noise.log_likelihoods(&residual, None)[0] - white).abs() < 0.05 * white.abs());
        // Halving the residual gains n ln 2 exactly (the variance is profiled).
        let half = Mat::from_fn(400, 1, |k, _| 0.5 * e[k]);
        let gained = noise.log_likelihoods(&half, None)[0] - noise.log_likelihoods(&residual, None)[0];
        assert!((gained - 400.0 * 2f64.ln()).abs() < 1e-9);
        // Only the selected rows count.
        let rows: Vec<f64> = (0..400).map(|k| if k < 100 { 1.0 } else { 0.0 }).collect();
        let part = Mat::from_fn(100, 1, |k, _| e[k]);
        let a = noise.log_likelihoods(&residual, Some(&rows))[0];
        assert!((a - noise.log_likelihoods(&part, None)[0]).abs() < 1e-9);
    }

    #[test]
    fn a_smooth_misfit_left_in_the_residual_costs_likelihood_under_a_fixed_rho() {
        // Noise alone, and the same noise plus a slow misfit: with ρ fixed by the noise, the
        // misfit's innovations count against the model that leaves it (a per-model ρ would call
        // the misfit correlated noise and hide it).
        let noise = white(400, 0.01, 2);
        let clean = Mat::from_fn(400, 1, |k, _| noise[k]);
        let misfit = Mat::from_fn(400, 1, |k, _| noise[k] + 0.2 * (k as f64 * 0.02).sin());
        let model = NoiseModel::of(&clean);
        let gain = model.log_likelihoods(&clean, None)[0] - model.log_likelihoods(&misfit, None)[0];
        assert!(gain > 100.0, "{gain}");
    }

    #[test]
    fn the_fit_weights_are_the_inverse_innovation_scales_the_likelihood_profiles() {
        // The weight 1/s_o of a likelihood fit: s_o² = U_o/n, the innovation variance the
        // log-likelihood −(n/2) ln(U_o/n) profiles; with the weights, Σ (w u)² = n per output.
        let (a, b) = (white(500, 0.1, 3), white(500, 3.0, 4));
        let mut lagged = vec![0.0; 500];
        for k in 0..500 {
            lagged[k] = b[k] + if k > 0 { 0.8 * lagged[k - 1] } else { 0.0 };
        }
        let residual = Mat::from_fn(500, 2, |k, o| if o == 0 { a[k] } else { lagged[k] });
        let noise = NoiseModel::of(&residual);
        assert!(noise.rho[0].abs() < 0.2 && (noise.rho[1] - 0.8).abs() < 0.1, "{:?}", noise.rho);
        let fit = noise.fit_weights(&residual);
        assert_eq!(fit.rho, noise.rho);
        for o in 0..2 {
            let rho = noise.rho[o];
            let u: f64 = (0..500)
                .map(|k| {
                    let e = residual[(k, o)];
                    if k == 0 { (1.0 - rho * rho) * e * e } else { (e - rho * residual[(k - 1, o)]).powi(2) }
                })
                .sum();
            assert!((u * fit.weights[o].powi(2) / 500.0 - 1.0).abs() < 1e-12, "output {o}");
            let profiled = -250.0 * (u / 500.0).ln();
            assert!((noise.log_likelihoods(&residual, None)[o] - profiled).abs() < 1e-9);
        }
        // Innovation scales about 0.1 and 3 (the second series' driving noise).
        assert!(
            (1.0 / fit.weights[0] / 0.1 - 1.0).abs() < 0.1 && (1.0 / fit.weights[1] / 3.0 - 1.0).abs() < 0.1
        );
        // A zero residual still gets a finite weight.
        let zero = Mat::<f64>::zeros(50, 1);
        assert!(NoiseModel::of(&zero).fit_weights(&zero).weights[0].is_finite());
    }
}
