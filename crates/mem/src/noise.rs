//! Stationary Gaussian noise of a known spectrum, as the linear predictors of its autocovariance.
//!
//! A zero-mean stationary series with autocovariance γ₀…γ_q is predicted from its last
//! 1, 2, …, q values by the Levinson–Durbin recursion (Brockwell & Davis, *Time Series: Theory
//! and Methods*, 2nd ed., 1991, §5.2): order m has coefficients a_m,1…a_m,m and prediction error
//! variance v_m (v₀ = γ₀). Predicting each sample from as many predecessors as it has, up to q,
//! and dividing each error by √v_m is the Cholesky factorisation of the series' Toeplitz
//! covariance (the innovations algorithm), so the sum of the squared scaled errors is the exact
//! Gaussian quadratic form of an AR(q) series — of any segment of it. AR(1) noise of lag-one
//! coefficient ρ is the case q = 1, γ = (1, ρ).
//!
//! `NoisePredictor::whiten` maps a series to its innovations in units of the order-q error,
//! (e_k − Σ_i a_m,i e_{k−i})·(v_q/v_m)^½, which a fit under that noise minimises
//! ([`Experiment::with_noise_predictors`](crate::Experiment::with_noise_predictors)).

/// The linear predictors of a stationary series of orders 1…q, from its autocovariance.
#[derive(Clone, Debug, PartialEq)]
pub struct NoisePredictor {
    /// a_m,1…a_m,m for m = 1…q.
    coefficients: Vec<Vec<f64>>,
    /// v₀…v_q.
    errors: Vec<f64>,
}

impl NoisePredictor {
    /// From γ₀…γ_q (q ≥ 0); `None` for a degenerate autocovariance (γ₀ ≤ 0, a non-finite value,
    /// or a prediction error that vanishes: not positive definite).
    pub fn of_autocovariance(gamma: &[f64]) -> Option<Self> {
        let first = *gamma.first()?;
        if !(first > 0.0 && gamma.iter().all(|g| g.is_finite())) {
            return None;
        }
        let q = gamma.len() - 1;
        let (mut a, mut error) = (Vec::<f64>::new(), first);
        let (mut coefficients, mut errors) = (Vec::with_capacity(q), vec![first]);
        for m in 1..=q {
            let k = (gamma[m] - (1..m).map(|j| a[j - 1] * gamma[m - j]).sum::<f64>()) / error;
            let mut next: Vec<f64> = (1..m).map(|j| a[j - 1] - k * a[m - j - 1]).collect();
            next.push(k);
            a = next;
            error *= 1.0 - k * k;
            if error.is_nan() || error <= 0.0 {
                return None;
            }
            coefficients.push(a.clone());
            errors.push(error);
        }
        Some(Self { coefficients, errors })
    }

    /// AR(1) noise e_k = ρ e_{k−1} + u_k of unit variance; `None` unless |ρ| < 1.
    pub fn ar1(rho: f64) -> Option<Self> {
        (rho.is_finite() && rho.abs() < 1.0).then(|| Self::of_autocovariance(&[1.0, rho])).flatten()
    }

    /// The largest order q.
    pub fn order(&self) -> usize {
        self.coefficients.len()
    }

    /// The prediction error variance v_m of order m ≤ q (v₀ = γ₀).
    pub fn error_variance(&self, m: usize) -> f64 {
        self.errors[m.min(self.order())]
    }

    /// The coefficients a_m,1…a_m,m of order m (1 ≤ m ≤ q; empty for m = 0).
    pub fn coefficients(&self, m: usize) -> &[f64] {
        match m.min(self.order()) {
            0 => &[],
            m => &self.coefficients[m - 1],
        }
    }

    /// The scaled innovation of `e` predicted from `past` (its predecessors, the nearest first;
    /// as many as there are, at most q used): (e − Σ_i a_m,i past_i)·(v_q/v_m)^½.
    pub fn scaled_innovation(&self, e: f64, past: &[f64]) -> f64 {
        let (m, predicted) = self.prediction(past);
        let (q, v) = (self.order(), &self.errors);
        (e - predicted) * if q == m { 1.0 } else { (v[q] / v[m]).sqrt() }
    }

    /// The squared scaled innovation, (e − Σ_i a_m,i past_i)²·v_q/v_m (as
    /// [`NoisePredictor::scaled_innovation`], squared without the square root).
    pub fn squared_innovation(&self, e: f64, past: &[f64]) -> f64 {
        let (m, predicted) = self.prediction(past);
        (e - predicted).powi(2) * (self.errors[self.order()] / self.errors[m])
    }

    /// The unscaled prediction error e − Σ_i a_m,i past_i of order m = min(len(past), q): the
    /// error of the order-m predictor itself, not the order-q innovation
    /// [`NoisePredictor::scaled_innovation`] scales it to.
    pub fn prediction_error(&self, e: f64, past: &[f64]) -> f64 {
        e - self.prediction(past).1
    }

    /// The order m used for `past` and the prediction Σ_i a_m,i past_i.
    fn prediction(&self, past: &[f64]) -> (usize, f64) {
        let m = past.len().min(self.order());
        (m, self.coefficients(m).iter().zip(past).map(|(a, x)| a * x).sum())
    }

    /// The scaled innovations of one unbroken series (as the crate's segment-wise `whiten` with a
    /// single segment): a linear, time-invariant map once past the first q samples, so a
    /// regression whitened by it is the generalised least squares of this noise.
    pub fn whitened(&self, series: &[f64]) -> Vec<f64> {
        let mut out = series.to_vec();
        self.whiten(&mut out, 0, 1, series.len(), |_| false);
        out
    }

    /// Whitens `values`, a series of `len` samples read at `offset + k·stride` (several series
    /// interleaved), to its scaled innovations in place: sample k is predicted from the samples
    /// since the last that starts a segment (`starts(k)`; sample 0 always does), at most q of
    /// them, kept as read.
    pub(crate) fn whiten(
        &self,
        values: &mut [f64],
        offset: usize,
        stride: usize,
        len: usize,
        starts: impl Fn(usize) -> bool,
    ) {
        let q = self.order();
        // The samples as read, the nearest first: buffer[head..head + depth]. New ones go in
        // front; when the front is reached, the q − 1 still needed move to the back.
        let mut buffer = vec![0.0; 2 * q + 1];
        let (mut head, mut depth) = (buffer.len(), 0usize);
        for k in 0..len {
            if starts(k) {
                depth = 0;
            }
            let v = &mut values[offset + k * stride];
            let read = *v;
            *v = self.scaled_innovation(read, &buffer[head..head + depth]);
            if q == 0 {
                continue;
            }
            let keep = depth.min(q - 1);
            if head == 0 {
                let end = buffer.len();
                buffer.copy_within(0..keep, end - keep);
                head = end - keep;
            }
            head -= 1;
            buffer[head] = read;
            depth = keep + 1;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::NoisePredictor;

    #[test]
    fn an_ar1_predictor_whitens_as_the_ar1_formulas_say() {
        let rho = 0.7;
        let p = NoisePredictor::ar1(rho).expect("|ρ| < 1");
        let e = [1.0, -0.5, 0.25, 2.0, 0.0];
        let mut w = e;
        // Sample 3 starts a segment (its predecessor left out).
        p.whiten(&mut w, 0, 1, e.len(), |k| k == 3);
        let expected = [
            (1.0 - rho * rho).sqrt() * e[0],
            e[1] - rho * e[0],
            e[2] - rho * e[1],
            (1.0 - rho * rho).sqrt() * e[3],
            e[4] - rho * e[3],
        ];
        // The very arithmetic of the AR(1) whitening this replaced: the same bits.
        assert_eq!(w, expected);
        assert!(NoisePredictor::ar1(1.0).is_none() && NoisePredictor::ar1(f64::NAN).is_none());
    }

    /// The order-m error is the order-m predictor's own: unscaled, and the order-q innovation
    /// is it scaled by v_q/v_m.
    #[test]
    fn a_short_past_gives_the_short_predictors_own_error() {
        let p = NoisePredictor::of_autocovariance(&[2.0, 1.2, 0.3, -0.2]).expect("positive definite");
        let (e, past) = (0.7, [0.4, -0.9]);
        let a = p.coefficients(2);
        let expected = e - a[0] * past[0] - a[1] * past[1];
        assert!((p.prediction_error(e, &past) - expected).abs() < 1e-15);
        let scaled = expected * expected * p.error_variance(3) / p.error_variance(2);
        assert!((p.squared_innovation(e, &past) - scaled).abs() < 1e-14);
        assert!(p.error_variance(3) < p.error_variance(2));
    }

    /// One series whitened whole is its innovations scaled as the likelihood sums them.
    #[test]
    fn a_whole_series_whitens_to_the_innovations_the_likelihood_squares() {
        let p = NoisePredictor::of_autocovariance(&[2.0, 1.2, 0.3]).expect("positive definite");
        let e = [0.3, -1.0, 0.8, 0.1, -0.4, 1.1];
        let w = p.whitened(&e);
        let mut past: Vec<f64> = Vec::new();
        for (k, &x) in e.iter().enumerate() {
            assert!((w[k].powi(2) - p.squared_innovation(x, &past)).abs() < 1e-12, "sample {k}");
            past.insert(0, x);
            past.truncate(p.order());
        }
    }

    #[test]
    fn interleaved_series_are_whitened_apart() {
        let p = NoisePredictor::of_autocovariance(&[2.0, 1.2, 0.3]).expect("positive definite");
        let a = [0.3, -1.0, 0.8, 0.1, -0.4];
        let b = [1.5, 0.2, -0.7, 0.9, 0.0];
        let mut both: Vec<f64> = a.iter().zip(&b).flat_map(|(x, y)| [*x, *y]).collect();
        let (mut wa, mut wb) = (a, b);
        p.whiten(&mut wa, 0, 1, 5, |_| false);
        p.whiten(&mut wb, 0, 1, 5, |_| false);
        p.whiten(&mut both, 0, 2, 5, |_| false);
        p.whiten(&mut both, 1, 2, 5, |_| false);
        for k in 0..5 {
            assert_eq!(both[2 * k], wa[k]);
            assert_eq!(both[2 * k + 1], wb[k]);
        }
    }

    /// The whitened series is (v_q)^½ L⁻¹e for Σ = LLᵀ the Toeplitz covariance of the AR(2)
    /// process e_k = 0.5e_{k−1} − 0.3e_{k−2} + u_k, its autocovariance from the Yule–Walker
    /// equations in closed form and extended by the recursion (a dense Cholesky by faer).
    #[test]
    fn whitening_is_the_inverse_cholesky_factor_of_the_toeplitz_covariance() {
        let (a1, a2, n) = (0.5_f64, -0.3_f64, 9usize);
        // ρ₁ = a₁/(1 − a₂), ρ_l = a₁ρ_{l−1} + a₂ρ_{l−2}; γ₀ = 1/(1 − a₁ρ₁ − a₂ρ₂) for unit u.
        let mut rho = vec![1.0, a1 / (1.0 - a2)];
        for l in 2..n {
            rho.push(a1 * rho[l - 1] + a2 * rho[l - 2]);
        }
        let g0 = 1.0 / (1.0 - a1 * rho[1] - a2 * rho[2]);
        let gamma: Vec<f64> = rho.iter().map(|r| g0 * r).collect();
        let p = NoisePredictor::of_autocovariance(&gamma[..=2]).expect("an AR(2) autocovariance");
        assert!((p.coefficients(2)[0] - a1).abs() < 1e-12 && (p.coefficients(2)[1] - a2).abs() < 1e-12);
        assert!((p.error_variance(2) - 1.0).abs() < 1e-12);
        let sigma = faer::Mat::<f64>::from_fn(n, n, |i, j| gamma[i.abs_diff(j)]);
        let e = faer::Mat::<f64>::from_fn(n, 1, |k, _| ((k * 7 + 3) % 5) as f64 - 2.0 + 0.1 * k as f64);
        let l = sigma.llt(faer::Side::Lower).expect("positive definite").L().to_owned();
        // L⁻¹e by forward substitution, times (v_q)^½.
        let mut expected = vec![0.0; n];
        for k in 0..n {
            let known: f64 = (0..k).map(|j| l[(k, j)] * expected[j]).sum();
            expected[k] = (e[(k, 0)] - known) / l[(k, k)];
        }
        expected.iter_mut().for_each(|x| *x *= p.error_variance(2).sqrt());
        let mut w: Vec<f64> = (0..n).map(|k| e[(k, 0)]).collect();
        p.whiten(&mut w, 0, 1, n, |_| false);
        for k in 0..n {
            assert!((w[k] - expected[k]).abs() < 1e-12, "sample {k}: {} against {}", w[k], expected[k]);
        }
    }

    #[test]
    fn a_degenerate_autocovariance_has_no_predictor() {
        assert!(NoisePredictor::of_autocovariance(&[]).is_none());
        assert!(NoisePredictor::of_autocovariance(&[0.0, 0.0]).is_none());
        assert!(NoisePredictor::of_autocovariance(&[1.0, 1.0]).is_none());
        assert!(NoisePredictor::of_autocovariance(&[1.0, f64::INFINITY]).is_none());
        assert_eq!(NoisePredictor::of_autocovariance(&[4.0]).map(|p| p.order()), Some(0));
    }
}
