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
    /// Per output, the order of its [`Predictor`] where the recorded force's noise colours the
    /// noise (0 where it is the AR(1) of ρ_o alone); empty where there is no recorded input.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub predictor_order: Vec<usize>,
    /// Per output, the noise's predictor where the recorded force's noise colours it (a forced
    /// record; [`Predictor`] of the spectrum that noise and the sensor's leave): the innovations
    /// the likelihood scores are then those of that predictor, not of ρ_o. Empty, or `None` for
    /// an output, where the noise is the AR(1) of ρ_o alone.
    #[serde(skip)]
    pub predictors: Vec<Option<Predictor>>,
}

/// The noise's linear predictors where it is coloured beyond AR(1) (mem's
/// [`NoisePredictor`](mem::NoisePredictor): Levinson–Durbin on the autocovariance, the exact Gaussian likelihood of
/// any segment).
pub use mem::NoisePredictor as Predictor;

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
        Self { rho, predictor_order: Vec::new(), predictors: Vec::new() }
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

    /// Output o's innovations' sum of squares U over the rows of positive weight (all if None),
    /// and how many rows that is: under its [`Predictor`] where it has one, under ρ_o otherwise.
    fn innovations(&self, residual: &Mat<f64>, o: usize, rows: Option<&[f64]>) -> (f64, usize) {
        match self.predictors.get(o) {
            Some(Some(predictor)) => predicted_innovations(predictor, residual, o, rows),
            _ => self.ar1_innovations(residual, o, rows),
        }
    }

    /// Output o's innovations' sum of squares under ρ_o alone (as [`Self::innovations`]).
    fn ar1_innovations(&self, residual: &Mat<f64>, o: usize, rows: Option<&[f64]>) -> (f64, usize) {
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

/// [`NoiseModel::innovations`] under a [`Predictor`]: each kept row predicted from the kept rows
/// just before it (up to the predictor's order; a row after a gap starts a new segment).
fn predicted_innovations(
    predictor: &Predictor,
    residual: &Mat<f64>,
    o: usize,
    rows: Option<&[f64]>,
) -> (f64, usize) {
    let keep = |k: usize| rows.is_none_or(|w| w[k] > 0.0);
    let q = predictor.order();
    let (mut u, mut n) = (0.0, 0usize);
    let mut past: Vec<f64> = Vec::with_capacity(q);
    for k in 0..residual.nrows() {
        if !keep(k) {
            past.clear();
            continue;
        }
        let e = residual[(k, o)];
        u += predictor.squared_innovation(e, &past);
        n += 1;
        past.insert(0, e);
        past.truncate(q);
    }
    (u, n)
}

/// The measurement model as a fit's weights: a refit that minimises
/// Σ_o Σ_k ((e_k − ρ_o e_{k−1})/s_o)² maximises the Gaussian AR(1) likelihood the evidence
/// scores, at the noise model's ρ_o and innovation scales s_o (generalised least squares); with
/// `predictors`, the innovations are those of each output's predictor instead
/// ([`NoiseModel::coloured_fit`]).
#[derive(Clone, Debug)]
pub struct LikelihoodFit {
    /// ρ_o per output.
    pub rho: Vec<f64>,
    /// 1/s_o per output.
    pub weights: Vec<f64>,
    /// Per output, the predictor the fit whitens by (its own, or AR(1) of ρ_o where it has
    /// none); None: AR(1) of `rho` for every output.
    pub predictors: Option<Vec<Predictor>>,
}

impl NoiseModel {
    /// The fit weights of this model under AR(1) of ρ_o alone, with innovation scales s_o from
    /// `residual` (the best-fitting model's): s_o² = U_o/n, floored at 10⁻¹² of the output's
    /// RMS so a perfect fit still weighs its output.
    pub fn fit_weights(&self, residual: &Mat<f64>) -> LikelihoodFit {
        // The refit whitens by ρ_o (`LikelihoodFit`), so its scales are ρ_o's too.
        let weights = self.weights_by(residual, |o| self.ar1_innovations(residual, o, None));
        LikelihoodFit { rho: self.rho.clone(), weights, predictors: None }
    }

    /// The fit that maximises the very likelihood the evidence scores where some output's noise
    /// has a [`Predictor`] (a forced record whose force is recorded with noise): each output
    /// whitened by its predictor (AR(1) of ρ_o where it has none), its scale s_o² = U_o/n from
    /// `residual` under the same. `None` where no output has a predictor ([`Self::fit_weights`]
    /// is then that likelihood's fit).
    pub fn coloured_fit(&self, residual: &Mat<f64>) -> Option<LikelihoodFit> {
        if !self.predictors.iter().any(Option::is_some) {
            return None;
        }
        let predictors = self.whitening(residual.ncols())?;
        let weights = self.weights_by(residual, |o| self.innovations(residual, o, None));
        Some(LikelihoodFit { rho: self.rho.clone(), weights, predictors: Some(predictors) })
    }

    /// Per output of `outputs`, the predictor its noise is whitened by: its own where it has one,
    /// AR(1) of ρ_o where it has none; `None` where a ρ_o is not a stationary AR(1).
    pub fn whitening(&self, outputs: usize) -> Option<Vec<Predictor>> {
        (0..outputs)
            .map(|o| match self.predictors.get(o) {
                Some(Some(p)) => Some(p.clone()),
                _ => Predictor::ar1(*self.rho.get(o)?),
            })
            .collect()
    }

    /// 1/s_o per output, s_o² = U_o/n from `innovations(o)` = (U_o, n), floored as
    /// [`Self::fit_weights`] says.
    fn weights_by(&self, residual: &Mat<f64>, innovations: impl Fn(usize) -> (f64, usize)) -> Vec<f64> {
        let n = residual.nrows().max(1) as f64;
        (0..residual.ncols())
            .map(|o| {
                let (u, _) = innovations(o);
                let power = residual.col(o).squared_norm_l2();
                let s2 = (u / n).max(1e-24 * power / n);
                if s2 > 0.0 { 1.0 / s2.sqrt() } else { 1.0 }
            })
            .collect()
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
/// the noise model's own prediction, less the 10 nats white noise gains by chance (half a χ²
/// with 20 degrees of freedom), summed over the outputs and floored at 0. The noise model's
/// prediction is the better (smaller sum of squared innovations) of AR(1), ρ_o e_{k−1}, and the
/// output's [`Predictor`] where it has one, taken at order 20 as the residual's autoregression is
/// (its error unscaled; the thirty-fifth session's longer predictors scaled it by their own
/// order's error, 5–7 % below order 20's, and took some 60 nats off every residual's
/// structure): the predictor's spectrum is read from the force's
/// noise, and where that read is above what a residual holds, a residual of sensor noise alone
/// would score as structure beyond it (seen on the forced draw 20261312: a softening spring's
/// refit left 2 % of the residual and was scored as explaining 27 % of its structure). A misfit
/// — smooth, an offset, a trend — is predictable from its past and scores high; noise that
/// follows the measurement model scores about 0.
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
            // The measurement model's own prediction: AR(1)'s, or its predictor's where it has
            // one and predicts better (the predictor's spectrum may be read above what this
            // residual holds).
            let ar1: f64 = (0..rows).map(|r| (y[(r, 0)] - rho * x[(r, 0)]).powi(2)).sum();
            let one = match noise.predictors.get(o) {
                Some(Some(predictor)) => {
                    let mut past = Vec::with_capacity(STRUCTURE_LAGS);
                    let predicted: f64 = (0..rows)
                        .map(|r| {
                            past.clear();
                            past.extend((0..predictor.order().min(STRUCTURE_LAGS)).map(|l| x[(r, l)]));
                            // The noise's own predictor of the same order as the residual's
                            // autoregression, its error unscaled: like against like.
                            predictor.prediction_error(y[(r, 0)], &past).powi(2)
                        })
                        .sum();
                    predicted.min(ar1)
                }
                _ => ar1,
            };
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
    let best = Predictor::of_autocovariance(&gamma)?;
    let error = best.error_variance(best.order());
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
        let (n, floor, bins) = (4000, 0.5, 512);
        let ((a1, a2), levels) = resonance(bins, floor);
        let mut scored = Vec::new();
        let mut rhos = Vec::new();
        for seed in 0..12 {
            let residual = resonant_noise((a1, a2), n, floor, (100 + seed, 200 + seed));
            let noise = NoiseModel::of(&residual);
            rhos.push(noise.rho[0]);
            scored.push(structure_per_output(&residual, &noise)[0]);
        }
        let rho = rhos.iter().sum::<f64>() / rhos.len() as f64;
        let mean = scored.iter().sum::<f64>() / scored.len() as f64;
        let implied = structure_of_spectrum(&levels, rho, n);
        assert!(mean > 200.0, "{mean}");
        assert!((implied / mean - 1.0).abs() < 0.1, "implied {implied}, scored {mean}");
        assert_eq!(structure_of_spectrum(&vec![1.0; bins], 0.0, n), 0.0);
    }

    /// The AR(2) resonance of [`the_structure_of_a_spectrum_is_what_its_noise_scores`]: its
    /// coefficients, and its one-sided spectrum on `bins` Welch bins with a white `floor` of
    /// standard deviation `floor` beside it.
    fn resonance(bins: usize, floor: f64) -> ((f64, f64), Vec<f64>) {
        let ar2 = test_problems::Ar2::resonance(0.97, 2.0 * std::f64::consts::PI * 0.05);
        ((ar2.a1, ar2.a2), ar2.spectrum(bins, 1.0, floor * floor))
    }

    /// White noise scored under a predictor read for a resonant spectrum (AR(2) poles at 0.98,
    /// about 5 % of the sampling rate) is not structure: the better noise model, AR(1) here,
    /// predicts it, and it scores about 0 (under the predictor alone, thousands of nats).
    #[test]
    fn white_noise_under_a_resonant_predictor_is_not_structure() {
        let n = 4000;
        let (a1, a2) = (2.0 * 0.98 * (2.0 * std::f64::consts::PI * 0.05).cos(), -0.98 * 0.98);
        // The AR(2) autocovariance by its Yule–Walker recursion (unit innovation variance).
        let r1 = a1 / (1.0 - a2);
        let mut gamma = vec![1.0, r1];
        for l in 2..=20 {
            gamma.push(a1 * gamma[l - 1] + a2 * gamma[l - 2]);
        }
        let predictor = Predictor::of_autocovariance(&gamma).unwrap();
        let samples = white(n, 1.0, 20261202);
        let white = Mat::<f64>::from_fn(n, 1, |r, _| samples[r]);
        let noise =
            NoiseModel { rho: vec![0.0], predictor_order: vec![20], predictors: vec![Some(predictor)] };
        let score = structure(&white, &noise);
        assert!(score < 15.0, "white noise scored {score} nats of structure");
    }

    /// `n` samples of the AR(2) `(a1, a2)` driven by unit white noise, with white noise of
    /// standard deviation `floor` beside it, from the two seeds.
    fn resonant_noise((a1, a2): (f64, f64), n: usize, floor: f64, (driven, beside): (u64, u64)) -> Mat<f64> {
        let (w, v) = (white(n, 1.0, driven), white(n, floor, beside));
        let mut x = vec![0.0; n];
        for k in 2..n {
            x[k] = a1 * x[k - 1] + a2 * x[k - 2] + w[k];
        }
        Mat::from_fn(n, 1, |k, _| x[k] + v[k])
    }

    /// Levinson–Durbin's predictors against the Gaussian likelihood computed directly: an AR(2)
    /// autocovariance (Yule–Walker, closed form) gives its own two coefficients and nothing
    /// beyond, and the innovations of a series and of its segments give xᵀΓ⁻¹x v_q with Γ the
    /// Toeplitz covariance, factored by faer's Cholesky.
    #[test]
    fn the_predictors_give_the_exact_gaussian_likelihood() {
        let (a1, a2, n) = (1.2, -0.5, 40);
        // γ₁ = a1 γ₀/(1 − a2), γ_l = a1 γ_{l−1} + a2 γ_{l−2}, γ₀ = 1.
        let mut gamma = vec![1.0, a1 / (1.0 - a2)];
        for l in 2..n {
            gamma.push(a1 * gamma[l - 1] + a2 * gamma[l - 2]);
        }
        let p = Predictor::of_autocovariance(&gamma[..=6]).expect("a valid autocovariance");
        assert_eq!(p.order(), 6);
        assert!((p.coefficients(2)[0] - a1).abs() < 1e-12 && (p.coefficients(2)[1] - a2).abs() < 1e-12);
        assert!(p.coefficients(6)[2..].iter().all(|c| c.abs() < 1e-12), "{:?}", p.coefficients(6));
        let x = white(n, 1.0, 3);
        let quadratic = |rows: &[usize]| {
            let g = Mat::from_fn(rows.len(), rows.len(), |i, j| gamma[rows[i].abs_diff(rows[j])]);
            let b = Mat::from_fn(rows.len(), 1, |i, _| x[rows[i]]);
            use faer::linalg::solvers::Solve;
            let solved = g.llt(faer::Side::Lower).expect("positive definite").solve(&b);
            (0..rows.len()).map(|i| b[(i, 0)] * solved[(i, 0)]).sum::<f64>()
        };
        let residual = Mat::from_fn(n, 1, |k, _| x[k]);
        let v = p.error_variance(p.order());
        let all = predicted_innovations(&p, &residual, 0, None);
        assert_eq!(all.1, n);
        let rows: Vec<usize> = (0..n).collect();
        assert!((all.0 - v * quadratic(&rows)).abs() < 1e-9 * all.0, "{} {}", all.0, v * quadratic(&rows));
        // Two segments (rows 0–9 and 25–39), each scored as a series of its own.
        let weights: Vec<f64> = (0..n).map(|k| if (10..25).contains(&k) { 0.0 } else { 1.0 }).collect();
        let split = predicted_innovations(&p, &residual, 0, Some(&weights));
        let (first, second): (Vec<usize>, Vec<usize>) = ((0..10).collect(), (25..40).collect());
        let direct = v * (quadratic(&first) + quadratic(&second));
        assert_eq!(split.1, 25);
        assert!((split.0 - direct).abs() < 1e-9 * direct, "{} {direct}", split.0);
        // An AR(1) autocovariance: its predictor's innovations are the noise model's under ρ.
        let rho: f64 = 0.6;
        let ar1 = Predictor::of_autocovariance(&(0..=4).map(|l| rho.powi(l)).collect::<Vec<_>>()).unwrap();
        let noise = NoiseModel { rho: vec![rho], predictor_order: Vec::new(), predictors: Vec::new() };
        let (u1, _) = noise.ar1_innovations(&residual, 0, Some(&weights));
        let (u2, _) = predicted_innovations(&ar1, &residual, 0, Some(&weights));
        // Both in units of the innovation variance v₁ = 1 − ρ²: the same sum.
        assert!((u1 - u2).abs() < 1e-9 * u2, "{u1} {u2}");
    }

    /// A candidate that matches part of a narrow-band noise — eight regressors at its resonance,
    /// a sine and a cosine under four windows of the record — gains 80–190 nats under AR(1)
    /// noise in these eight draws (> 50 asserted), and under that noise's own predictor no more than eight parameters gain by chance
    /// (χ²₈/2: 4 on average; < 15 in each of eight draws).
    #[test]
    fn a_match_to_a_narrow_band_noise_gains_only_by_chance_under_its_own_spectrum() {
        let (n, bins, floor) = (4000, 512, 0.5);
        let ((a1, a2), levels) = resonance(bins, floor);
        let predictor = Predictor::of_autocovariance(&autocovariance(&levels, 20)).expect("a spectrum");
        let omega = 2.0 * std::f64::consts::PI * 0.05;
        for seed in 0..8 {
            let residual = resonant_noise((a1, a2), n, floor, (300 + seed, 400 + seed));
            let design = Mat::from_fn(n, 8, |k, c| {
                let window = f64::from(u8::from(k * 4 / n == c / 2));
                let phase = omega * k as f64;
                window * if c % 2 == 0 { phase.sin() } else { phase.cos() }
            });
            use faer::linalg::solvers::SolveLstsq;
            let fitted = &design * design.qr().solve_lstsq(&residual);
            let matched = Mat::from_fn(n, 1, |k, _| residual[(k, 0)] - fitted[(k, 0)]);
            let ar1 = NoiseModel::of(&residual);
            let coloured = NoiseModel { predictors: vec![Some(predictor.clone())], ..ar1.clone() };
            let gain = |noise: &NoiseModel| {
                noise.log_likelihoods(&matched, None)[0] - noise.log_likelihoods(&residual, None)[0]
            };
            assert!(gain(&ar1) > 50.0, "seed {seed}: AR(1) {}", gain(&ar1));
            // Below chance's bar; it may be negative: the match leaves a notch where the noise's
            // spectrum has its peak, which its predictor mispredicts.
            assert!(gain(&coloured) < 15.0, "seed {seed}: coloured {}", gain(&coloured));
        }
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

    /// The coloured fit whitens each output as the evidence scores it: by its predictor where it
    /// has one (its scale s_o² = U_o/n under that predictor), by AR(1) of ρ_o where it has none;
    /// and there is none where no output has a predictor.
    #[test]
    fn the_coloured_fit_is_the_likelihood_the_evidence_scores() {
        let n = 2000;
        let ((a1, a2), _) = resonance(256, 0.5);
        let coloured = resonant_noise((a1, a2), n, 0.5, (11, 12));
        let plain = white(n, 2.0, 13);
        let residual = Mat::from_fn(n, 2, |k, o| if o == 0 { coloured[(k, 0)] } else { plain[k] });
        let mut noise = NoiseModel::of(&residual);
        assert!(noise.coloured_fit(&residual).is_none());
        let gamma = autocovariance(&resonance(256, 0.5).1, 20);
        let predictor = Predictor::of_autocovariance(&gamma).expect("a spectrum");
        noise.predictors = vec![Some(predictor.clone()), None];
        let fit = noise.coloured_fit(&residual).expect("a predictor");
        let predictors = fit.predictors.as_ref().expect("whitened by predictors");
        assert_eq!(predictors[0], predictor);
        assert_eq!(predictors[1], Predictor::ar1(noise.rho[1]).unwrap());
        for o in 0..2 {
            let (u, _) = noise.innovations(&residual, o, None);
            let s = (u / n as f64).sqrt();
            assert!((fit.weights[o] * s - 1.0).abs() < 1e-12, "output {o}: {} against 1/{s}", fit.weights[o]);
        }
        // The resonant output's scale is its predictor's, not AR(1)'s.
        let ar1 = noise.fit_weights(&residual);
        assert!(
            (fit.weights[0] / ar1.weights[0] - 1.0).abs() > 0.05,
            "{} {}",
            fit.weights[0],
            ar1.weights[0]
        );
        assert_eq!(fit.weights[1], ar1.weights[1]);
    }
}
