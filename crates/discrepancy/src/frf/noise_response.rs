//! A linear model's exact response to white noise on its inputs: per output and input, the
//! autocovariance of the sampled output when that input carries white noise of unit variance,
//! held over each interval as the record's inputs are.
//!
//! Sampled with the record's hold, the model is x_{k+1} = Φ x_k + Γ_now e_k + Γ_next e_{k+1},
//! y_k = C x_k + D e_k ([`expm::step_gains`]; Γ_next = 0 for a zero-order hold, whose gain is
//! Γ_now + Γ_next of the first-order split). With z_k = x_k − Γ_next e_k it is the innovations
//! form z_{k+1} = Φ z_k + B′ e_k, y_k = C z_k + D′ e_k, B′ = Φ Γ_next + Γ_now, D′ = C Γ_next + D.
//! For white e of unit variance the stationary covariance P = Φ P Φᵀ + B′B′ᵀ (the discrete
//! Lyapunov equation, solved by Smith's doubling: P = Σ_n Φⁿ B′B′ᵀ (Φⁿ)ᵀ summed over 2ʲ terms at
//! step j) gives γ(0) = C P Cᵀ + D′D′ᵀ and γ(l) = C Φˡ P Cᵀ + C Φˡ⁻¹ B′ D′ᵀ for l ≥ 1
//! (Anderson & Moore, *Optimal Filtering*, 1979, §4.4).
//!
//! The Welch estimate of [`super::input_noise()`] reads a residual's spectrum on bins a quarter of
//! the record wide, far wider than a lightly damped mode's half-power band: the expected windowed
//! periodogram of a series of autocovariance γ is Σ_l c_l γ(l) e^{−iω_b l}, c_l = Σ_n w_n w_{n+|l|}
//! the window's own autocorrelation (Percival & Walden, *Spectral Analysis for Physical
//! Applications*, 1993, §6.3), which [`NoiseResponse::expected_levels`] gives exactly, where
//! H₁ of the simulation gives the window-averaged frequency response, not the window-averaged
//! power. And the noise's predictor is then built from the exact autocovariance, not from a
//! spectrum sampled on those bins.

use faer::Mat;
use mem::nalgebra::DMatrix;
use mem::{Hold, StateSpace};

/// Smith's doubling steps at most (2⁶⁴ terms of the series: a mode must decay within them).
const DOUBLINGS: usize = 64;

/// One model's response to unit white noise on each input: `autocovariance[o][i][l]`, output o
/// (in the weighted units its caller gave), input i, lag l = 0…`lags`.
#[derive(Clone, Debug)]
pub struct NoiseResponse {
    autocovariance: Vec<Vec<Vec<f64>>>,
}

impl NoiseResponse {
    /// The response of `space` (ẋ = A x + B u, y = C x + D u; its x(0) is not used) sampled
    /// every `h` with `hold`, its outputs scaled by `weights`, to unit white noise on each input,
    /// up to lag `lags`. `None` for a model without inputs, one whose sampled form has no
    /// stationary response (a mode that does not decay — a rigid-body mode, an unstable or
    /// undamped one — or a non-finite value), or `weights` not one per output.
    pub fn new(space: &StateSpace<f64>, hold: Hold, h: f64, weights: &[f64], lags: usize) -> Option<Self> {
        let faer = |x: &DMatrix<f64>| Mat::from_fn(x.nrows(), x.ncols(), |r, c| x[(r, c)]);
        let (a, b, c) = (faer(&space.a), faer(space.b.as_ref()?), faer(&space.c));
        let d = space.d.as_ref().map(faer);
        let (n, m, p) = (a.nrows(), b.ncols(), c.nrows());
        if n == 0 || a.ncols() != n || b.nrows() != n || c.ncols() != n || weights.len() != p {
            return None;
        }
        if d.as_ref().is_some_and(|d| d.nrows() != p || d.ncols() != m) {
            return None;
        }
        let gains = expm::step_gains(a.as_ref(), &[], b.as_ref(), &[], h).ok()?;
        let phi = gains.phi;
        let (b_prime, d_prime) = match hold {
            Hold::Zero => (&gains.now + &gains.next, d.unwrap_or_else(|| Mat::zeros(p, m))),
            Hold::FirstOrder => {
                let d0 = d.unwrap_or_else(|| Mat::zeros(p, m));
                (&phi * &gains.next + &gains.now, &c * &gains.next + d0)
            }
        };
        let weighted_c = Mat::from_fn(p, n, |o, j| weights[o] * c[(o, j)]);
        let weighted_d = Mat::from_fn(p, m, |o, i| weights[o] * d_prime[(o, i)]);
        let mut autocovariance = vec![vec![vec![0.0; lags + 1]; m]; p];
        for i in 0..m {
            let column = b_prime.as_ref().col(i).as_mat().to_owned();
            let covariance = stationary_covariance(&phi, &column)?;
            // Rows C Φˡ, from l = 0 on, beside the lag-l covariances.
            let mut rows = weighted_c.clone();
            let pc = &covariance * weighted_c.transpose();
            for l in 0..=lags {
                for o in 0..p {
                    let state: f64 = (0..n).map(|j| rows[(o, j)] * pc[(j, o)]).sum();
                    let direct = if l == 0 { weighted_d[(o, i)].powi(2) } else { 0.0 };
                    autocovariance[o][i][l] += state + direct;
                }
                if l < lags {
                    // The feedthrough's share of lag l + 1, C Φˡ B′ D′ᵀ, while `rows` hold C Φˡ.
                    for o in 0..p {
                        let through: f64 = (0..n).map(|j| rows[(o, j)] * column[(j, 0)]).sum();
                        autocovariance[o][i][l + 1] += through * weighted_d[(o, i)];
                    }
                    rows = &rows * &phi;
                }
            }
        }
        let finite = autocovariance.iter().flatten().flatten().all(|g| g.is_finite());
        finite.then_some(Self { autocovariance })
    }

    /// The number of outputs.
    pub fn outputs(&self) -> usize {
        self.autocovariance.len()
    }

    /// The number of inputs.
    pub fn inputs(&self) -> usize {
        self.autocovariance.first().map_or(0, Vec::len)
    }

    /// The largest lag held.
    pub fn lags(&self) -> usize {
        self.autocovariance.first().and_then(|o| o.first()).map_or(0, |g| g.len().saturating_sub(1))
    }

    /// γ_{o,i}(l), l = 0…[`lags`](Self::lags): output o's autocovariance under unit white noise
    /// on input i.
    pub fn autocovariance(&self, o: usize, i: usize) -> &[f64] {
        &self.autocovariance[o][i]
    }

    /// Output o's expected Hann-windowed periodogram under unit white noise on input i, at bins
    /// 0…`length`/2 − 1 of a segment of `length`, divided by the window's power Σ w_n² (the
    /// level white noise of unit variance has in every bin); `None` if fewer than `length` − 1
    /// lags are held.
    pub fn expected_levels(&self, o: usize, i: usize, length: usize, window: &[f64]) -> Option<Vec<f64>> {
        let gamma = &self.autocovariance[o][i];
        if length < 2 || gamma.len() < length || window.len() != length {
            return None;
        }
        let lag_window: Vec<f64> =
            (0..length).map(|l| (0..length - l).map(|n| window[n] * window[n + l]).sum()).collect();
        let power = lag_window[0];
        if power <= 0.0 {
            return None;
        }
        let weighted: Vec<f64> = (0..length).map(|l| lag_window[l] * gamma[l]).collect();
        let cos: Vec<f64> =
            (0..length).map(|j| (2.0 * std::f64::consts::PI * j as f64 / length as f64).cos()).collect();
        Some(
            (0..length / 2)
                .map(|b| {
                    let tail: f64 = (1..length).map(|l| weighted[l] * cos[(b * l) % length]).sum();
                    (weighted[0] + 2.0 * tail) / power
                })
                .collect(),
        )
    }
}

/// P = Φ P Φᵀ + g gᵀ by Smith's doubling; `None` if the series does not converge within
/// [`DOUBLINGS`] steps (Φ has an eigenvalue on or outside the unit circle) or is not finite.
fn stationary_covariance(phi: &Mat<f64>, g: &Mat<f64>) -> Option<Mat<f64>> {
    let mut power = phi.clone();
    let mut sum = g * g.transpose();
    for _ in 0..DOUBLINGS {
        let step = &power * &sum * power.transpose();
        let (added, held) = (step.norm_max(), sum.norm_max());
        sum += &step;
        if !(added.is_finite() && held.is_finite()) {
            return None;
        }
        if added <= f64::EPSILON * held {
            return Some(sum);
        }
        power = &power * &power;
    }
    None
}

#[cfg(test)]
mod tests {
    use super::super::tests::space;
    use super::NoiseResponse;
    use faer::Mat;
    use mem::Hold;

    /// A damped oscillator ẍ + 2ζω ẋ + ω² x = u, read as x and ẋ, sampled every h: the exact
    /// response's autocovariance against the one a long simulation driven by white noise
    /// gives (independent: a sum over the impulse response, computed by stepping the exact
    /// sampled model), for both holds, and for an output with feedthrough.
    fn oscillator() -> (Mat<f64>, Mat<f64>, Mat<f64>, Mat<f64>) {
        let (a, b) = super::super::tests::oscillator(3.0, 0.03);
        let c = Mat::from_fn(2, 2, |r, cc| if r == cc { 1.0 } else { 0.0 });
        let d = Mat::from_fn(2, 1, |r, _| if r == 1 { 0.25 } else { 0.0 });
        (a, b, c, d)
    }

    /// γ(l) = Σ_j y_j y_{j+l} of the impulse response y_j of the sampled system, stepped
    /// directly from x_{k+1} = Φ x_k + Γ_now e_k + Γ_next e_{k+1}, y_k = C x_k + D e_k with a
    /// unit impulse e_0 = 1 (and x₀ = Γ_next e₀: the ramp into it).
    fn by_impulse(hold: Hold, h: f64, lags: usize, with_d: bool) -> Vec<Vec<f64>> {
        let (a, b, c, d) = oscillator();
        let g = expm::step_gains(a.as_ref(), &[], b.as_ref(), &[], h).unwrap();
        let (now, next) = match hold {
            Hold::Zero => (&g.now + &g.next, Mat::<f64>::zeros(2, 1)),
            Hold::FirstOrder => (g.now.clone(), g.next.clone()),
        };
        let steps = 40_000;
        // Under a first-order hold the impulse already acts over the interval before it:
        // x₀ = Γ_next e₀.
        let mut x = &next * 1.0;
        let mut y = vec![vec![0.0; steps]; 2];
        for k in 0..steps {
            let e = |j: usize| if j == 0 { 1.0 } else { 0.0 };
            for o in 0..2 {
                y[o][k] = (0..2).map(|j| c[(o, j)] * x[(j, 0)]).sum::<f64>()
                    + if with_d { d[(o, 0)] * e(k) } else { 0.0 };
            }
            x = &g.phi * &x + &now * e(k) + &next * e(k + 1);
        }
        (0..2)
            .map(|o| (0..=lags).map(|l| (0..steps - l).map(|j| y[o][j] * y[o][j + l]).sum()).collect())
            .collect()
    }

    #[test]
    fn the_autocovariance_is_the_impulse_responses_own() {
        let (a, b, c, d) = oscillator();
        let h = 0.01;
        for hold in [Hold::Zero, Hold::FirstOrder] {
            for with_d in [false, true] {
                let exact =
                    NoiseResponse::new(&space(&a, &b, &c, with_d.then_some(&d)), hold, h, &[1.0, 2.0], 60)
                        .unwrap();
                let reference = by_impulse(hold, h, 60, with_d);
                for o in 0..2 {
                    let scale = [1.0, 4.0][o];
                    for l in 0..=60 {
                        let (got, want) = (exact.autocovariance(o, 0)[l], scale * reference[o][l]);
                        assert!(
                            (got - want).abs() <= 1e-9 * reference[o][0].abs() * scale,
                            "{hold:?} d {with_d} output {o} lag {l}: {got} against {want}"
                        );
                    }
                }
            }
        }
    }

    /// The expected periodogram of a series with that autocovariance, against the average of
    /// the periodograms of many simulated segments (an estimate within a few per cent).
    #[test]
    fn the_expected_levels_are_the_windowed_periodograms_mean() {
        let (a, b, c, _) = oscillator();
        let (h, length) = (0.01, 128);
        let window: Vec<f64> = (0..length)
            .map(|n| 0.5 - 0.5 * (2.0 * std::f64::consts::PI * n as f64 / length as f64).cos())
            .collect();
        let exact = NoiseResponse::new(&space(&a, &b, &c, None), Hold::Zero, h, &[1.0, 1.0], length).unwrap();
        let levels = exact.expected_levels(0, 0, length, &window).unwrap();
        // Simulate the sampled model driven by white noise (seeded), after a settling run.
        let g = expm::step_gains(a.as_ref(), &[], b.as_ref(), &[], h).unwrap();
        let gamma = &g.now + &g.next;
        let noise = super::super::tests::normals(31, 5_000 + 4_000 * length);
        let mut draws = noise.into_iter();
        let mut normal = move || draws.next().expect("enough draws");
        let mut x = Mat::<f64>::zeros(2, 1);
        for _ in 0..5_000 {
            x = &g.phi * &x + &gamma * normal();
        }
        let segments = 4_000;
        let power: f64 = window.iter().map(|w| w * w).sum();
        let mut mean = vec![0.0; length / 2];
        for _ in 0..segments {
            let mut series = vec![0.0; length];
            for s in &mut series {
                *s = x[(0, 0)];
                x = &g.phi * &x + &gamma * normal();
            }
            for (bin, m) in mean.iter_mut().enumerate() {
                let (mut re, mut im) = (0.0, 0.0);
                for (n, s) in series.iter().enumerate() {
                    let angle = 2.0 * std::f64::consts::PI * (bin * n) as f64 / length as f64;
                    re += window[n] * s * angle.cos();
                    im -= window[n] * s * angle.sin();
                }
                *m += (re * re + im * im) / power / segments as f64;
            }
        }
        let peak = levels.iter().copied().fold(0.0, f64::max);
        for (bin, (got, want)) in levels.iter().zip(&mean).enumerate().skip(1) {
            // 4,000 segments: a mean periodogram within ±6 % (4 σ of a χ² of 8,000 degrees),
            // or far below the peak where the leakage of the settling is seen.
            assert!(
                (got / want - 1.0).abs() < 0.06 || want.max(*got) < 1e-3 * peak,
                "bin {bin}: expected {got}, simulated {want}"
            );
        }
    }

    /// A model with a mode that does not decay (a free mass: ẍ = u) has no stationary response.
    #[test]
    fn a_mode_that_does_not_decay_has_no_stationary_response() {
        let a = Mat::from_fn(2, 2, |r, c| if (r, c) == (0, 1) { 1.0 } else { 0.0 });
        let b = Mat::from_fn(2, 1, |r, _| f64::from(u8::from(r == 1)));
        let c = Mat::from_fn(1, 2, |_, cc| f64::from(u8::from(cc == 0)));
        assert!(NoiseResponse::new(&space(&a, &b, &c, None), Hold::Zero, 0.01, &[1.0], 10).is_none());
    }
}
