//! Is a sensor quantized? A lattice in its raw readings, seen while the signal moves.
//!
//! Two forms are told apart, as a quantizer can sit before or after the noise:
//! - **exact**: every reading is y = c + jΔ to rounding precision (noise added before the
//!   quantizer, as in an ADC). A continuous measurement model gives such a record probability
//!   zero, so the lattice itself is the evidence; it must span several levels, not only the
//!   settled tail.
//! - **blurred**: readings y = c + jΔ + e (noise after the quantizer). Over the samples taken
//!   while the signal moves (the settled tail excluded, where values crowd near rest and any
//!   step would look like a lattice), R(Δ) = |mean exp(2πi y/Δ)| is ≈ exp(−2π²σ²/Δ²) on a
//!   lattice blurred by noise σ and ≈ 1/√n otherwise. The step and phase are found on the first
//!   half of those samples and confirmed on the second ([`blurred`]).
//!
//! - **sawtooth**: the same noise-after quantizer seen through the model. The residual about
//!   the fitted response x̂ is r = Q(x̂) − x̂ + e, a sawtooth of x̂ with period Δ whose
//!   fundamental has amplitude Δ/π (x − round(x) = (Δ/π) Σ_k (−1)^{k+1} sin(2πkx/Δ)/k).
//!   Regressing r on the phase of x̂ does not suffer the noise's blur of the readings'
//!   own phase, so it sees a step that [`blurred`] cannot (about 2.5× the z at Δ = 3.6σ). The
//!   period is found on the first half of the moving samples and the sinusoid confirmed on the
//!   second, where its amplitude must also be a rounding's, Δ/π ([`sawtooth`]).
//!
//! Either way the step matters only if it is comparable to the noise or larger (a record
//! printed with six decimals lies on a 10⁻⁶ lattice too); [`Lattice::matters`] says so.

use serde::Serialize;

/// How the lattice shows.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(rename_all = "snake_case", tag = "form")]
pub enum LatticeForm {
    /// Every reading lies on the lattice to rounding precision; `levels` distinct values.
    Exact {
        /// Distinct levels the readings take.
        levels: usize,
    },
    /// The moving samples crowd around the lattice: found on the first half of them, its phase
    /// holds on the second half by `z` standard errors.
    Blurred {
        /// The confirmation's z (batch-means standard error).
        z: f64,
        /// The samples it was confirmed on.
        samples: usize,
    },
    /// The residual about the fitted response is a rounding's sawtooth of the response: its
    /// period found on the first half of the moving samples, its fundamental held on the second
    /// half by `z` standard errors with `amplitude_ratio` × the Δ/π a rounding gives.
    Sawtooth {
        /// The confirmation's z (batch-means standard error).
        z: f64,
        /// The samples it was confirmed on.
        samples: usize,
        /// The fundamental's amplitude on the second half over Δ/π.
        amplitude_ratio: f64,
    },
}

/// A lattice found in one sensor's readings.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Lattice {
    /// Step Δ.
    pub step: f64,
    /// How it shows.
    pub form: LatticeForm,
    /// The sensor noise σ (before or after the quantizer) it leaves: from the blur of a blurred
    /// lattice, from the residual variance less Δ²/12 for an exact one.
    pub noise: f64,
}

impl Lattice {
    /// The step is comparable to the noise or larger (Δ ≥ σ/2): the rounding is a visible part
    /// of the measurement, not a printing precision far below the noise.
    pub fn matters(&self) -> bool {
        self.step >= 0.5 * self.noise
    }
}

/// The step of an exact lattice, with the number of distinct levels, if every value is
/// c + jΔ to 10⁻⁶Δ (plus 10⁻¹² of the largest magnitude) and there are at least `min_levels`
/// levels among at most 90 % distinct values.
pub fn exact(values: &[f64], min_levels: usize) -> Option<(f64, usize)> {
    let scale = values.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    if values.len() < 10 || !(scale > 0.0 && scale.is_finite()) {
        return None;
    }
    let mut sorted = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    let tie = 1e-12 * scale;
    let mut levels: Vec<f64> = Vec::new();
    for v in sorted {
        if levels.last().is_none_or(|l| v - l > tie) {
            levels.push(v);
        }
    }
    if levels.len() < min_levels.max(3) || levels.len() as f64 > 0.9 * values.len() as f64 {
        return None;
    }
    let smallest = levels.windows(2).map(|w| w[1] - w[0]).fold(f64::INFINITY, f64::min);
    let origin = levels[0];
    (1..=8).map(|d| smallest / d as f64).find_map(|step| {
        let tolerance = 1e-6 * step + tie;
        let on = levels.iter().all(|v| {
            let j = (v - origin) / step;
            (j - j.round()).abs() * step <= tolerance
        });
        on.then_some((step, levels.len()))
    })
}

/// The mean of exp(2πi y/Δ).
fn phasor(values: &[f64], step: f64) -> (f64, f64) {
    let (mut c, mut s) = (0.0, 0.0);
    for v in values {
        let phase = 2.0 * std::f64::consts::PI * v / step;
        c += phase.cos();
        s += phase.sin();
    }
    let n = values.len().max(1) as f64;
    (c / n, s / n)
}

fn rayleigh(values: &[f64], step: f64) -> f64 {
    let (c, s) = phasor(values, step);
    (c * c + s * s).sqrt()
}

/// The samples taken while the signal moves: from the start to the last sample farther from
/// the rest value (the median of the last tenth of the record) than a tenth of the largest
/// excursion. Chosen by time, not by value, so that no cut in value shapes their distribution.
pub fn moving(values: &[f64]) -> Vec<f64> {
    values[..moving_end(values)].to_vec()
}

/// The end (exclusive) of the samples [`moving`] keeps.
fn moving_end(values: &[f64]) -> usize {
    let n = values.len();
    if n == 0 {
        return 0;
    }
    let mut tail: Vec<f64> = values[n - (n / 10).max(1)..].to_vec();
    tail.sort_by(f64::total_cmp);
    let rest = tail[tail.len() / 2];
    let reach = values.iter().fold(0.0f64, |a, v| a.max((v - rest).abs()));
    values.iter().rposition(|v| (v - rest).abs() > 0.1 * reach).map_or(0, |k| k + 1)
}

/// The mean of `projections` and its z over the batch-means standard error (20 batches, so
/// that coloured noise does not pass for evidence).
fn batch_z(projections: &[f64]) -> (f64, f64) {
    let batches = 20;
    let size = (projections.len() / batches).max(1);
    let means: Vec<f64> = (0..batches)
        .map(|b| {
            let chunk = projections.get(b * size..((b + 1) * size).min(projections.len())).unwrap_or(&[]);
            chunk.iter().sum::<f64>() / chunk.len().max(1) as f64
        })
        .collect();
    let mean = means.iter().sum::<f64>() / batches as f64;
    let spread = (means.iter().map(|m| (m - mean).powi(2)).sum::<f64>() / (batches - 1) as f64).sqrt();
    (mean, mean / (spread / (batches as f64).sqrt()).max(f64::MIN_POSITIVE))
}

/// A blurred lattice, found on the first half of the moving samples and confirmed on the
/// second: the step Δ maximising R over the first half (from `min_step` to a fortieth of their
/// range, so that the signal's own distribution is smooth on the scale of a step; then the
/// largest multiple of it that keeps R), and the lattice's phase φ; on the second half, the
/// mean of cos(2πy/Δ − φ), which is 0 without a lattice, over its standard error by batch means
/// (20 batches, so that coloured noise does not pass for evidence). A lattice that is a trace
/// of the signal's distribution in one half (its turning points, its approach to rest) does
/// not hold its phase in the other, where the amplitudes differ.
///
/// Returns (step, z, samples confirmed on, blur σ) if z ≥ `threshold`.
pub fn blurred(values: &[f64], min_step: f64, threshold: f64) -> Option<(f64, f64, usize, f64)> {
    let samples = moving(values);
    let n = samples.len();
    let (first, second) = samples.split_at(n / 2);
    let (lo, hi) =
        samples.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| (a.min(*v), b.max(*v)));
    let max_step = (hi - lo) / 40.0;
    if n < 200 || !(max_step > min_step && min_step > 0.0) {
        return None;
    }
    let grid = 800;
    let ratio = (max_step / min_step).powf(1.0 / grid as f64);
    let mut best = (0.0, min_step);
    let mut step = min_step;
    for _ in 0..=grid {
        let r = rayleigh(first, step);
        if r > best.0 {
            best = (r, step);
        }
        step *= ratio;
    }
    // Refine by golden-section search around the best grid point.
    let (mut a, mut b) = (best.1 / ratio, best.1 * ratio);
    for _ in 0..60 {
        let m1 = b - (b - a) / 1.618_033_988_75;
        let m2 = a + (b - a) / 1.618_033_988_75;
        if rayleigh(first, m1) > rayleigh(first, m2) {
            b = m2;
        } else {
            a = m1;
        }
    }
    let mut step = 0.5 * (a + b);
    let r = rayleigh(first, step);
    // A sub-multiple of the true step shows the same R: take the largest multiple that keeps it.
    if let Some(k) = (2..=8)
        .rev()
        .find(|&k| k as f64 * step <= (hi - lo) / 8.0 && rayleigh(first, k as f64 * step) >= 0.9 * r)
    {
        step *= k as f64;
    }
    let (c, s) = phasor(first, step);
    let phase = s.atan2(c);
    let projections: Vec<f64> =
        second.iter().map(|v| (2.0 * std::f64::consts::PI * v / step - phase).cos()).collect();
    let (mean, z) = batch_z(&projections);
    let blur = step / (2.0 * std::f64::consts::PI) * (-2.0 * mean.clamp(1e-300, 1.0).ln()).sqrt();
    (z >= threshold).then_some((step, z, second.len(), blur))
}

/// The fundamental of r against the phase of x at frequency f (cycles per unit of x):
/// 2·mean(r·exp(−2πi f x)), as (cos, sin) parts.
fn fundamental(residual: &[f64], fitted: &[f64], frequency: f64) -> (f64, f64) {
    let (mut c, mut s) = (0.0, 0.0);
    for (r, x) in residual.iter().zip(fitted) {
        let (sin, cos) = (2.0 * std::f64::consts::PI * frequency * x).sin_cos();
        c += r * cos;
        s += r * sin;
    }
    let n = residual.len().max(1) as f64;
    (2.0 * c / n, 2.0 * s / n)
}

/// The amplitudes of the fundamental of r against the phase of x on the frequency grid
/// f_j = f₀ + j·df, j < count, each sample's phasor turned by exp(2πi x·df) from one grid point
/// to the next instead of recomputed (renormalised every 64 steps).
fn fundamental_scan(residual: &[f64], fitted: &[f64], f0: f64, df: f64, count: usize) -> Vec<f64> {
    let mut c = vec![0.0; count];
    let mut s = vec![0.0; count];
    let tau = 2.0 * std::f64::consts::PI;
    for (r, x) in residual.iter().zip(fitted) {
        let (mut ps, mut pc) = (tau * f0 * x).sin_cos();
        let (ws, wc) = (tau * df * x).sin_cos();
        for j in 0..count {
            c[j] += r * pc;
            s[j] += r * ps;
            (pc, ps) = (pc * wc - ps * ws, pc * ws + ps * wc);
            if j % 64 == 63 {
                let norm = (pc * pc + ps * ps).sqrt();
                (pc, ps) = (pc / norm, ps / norm);
            }
        }
    }
    let n = residual.len().max(1) as f64;
    c.iter().zip(&s).map(|(c, s)| 2.0 * (c * c + s * s).sqrt() / n).collect()
}

/// The largest frequency grid [`sawtooth`] scans (points): it bounds the cost when the range of
/// the response is very many smallest steps.
const SAWTOOTH_GRID: usize = 20_000;

/// A noise-after quantizer seen through the model: the residual r = y − x̂ of the readings
/// about the fitted response is a sawtooth of x̂ of period Δ (see the module notes).
///
/// Over the moving samples: on the first half, the Δ from `min_step` to a fortieth of x̂'s
/// range whose fundamental is largest (a grid in 1/Δ at a quarter of the resolution 1/range,
/// then a golden-section refinement), and its phase φ; on the second half, the mean of
/// 2r·cos(2πx̂/Δ − φ), its z by batch means, and its ratio to the Δ/π a rounding gives. A
/// periodicity that is not a rounding's (a cogging-like ripple, a trace of the misfit) does not
/// hold its phase, or has the wrong amplitude for its period.
///
/// Returns the lattice if z ≥ `threshold` and the ratio is within 0.5–1.5; its noise is the
/// moving samples' residual variance less the rounding's Δ²/12.
pub fn sawtooth(values: &[f64], fitted: &[f64], min_step: f64, threshold: f64) -> Option<Lattice> {
    if values.len() != fitted.len() {
        return None;
    }
    let end = moving_end(values);
    let (x, r): (Vec<f64>, Vec<f64>) =
        fitted[..end].iter().zip(&values[..end]).map(|(x, y)| (*x, y - x)).unzip();
    let n = x.len();
    if n < 200 || !x.iter().chain(&r).all(|v| v.is_finite()) {
        return None;
    }
    let half = n / 2;
    let (x1, x2) = x.split_at(half);
    let (r1, r2) = r.split_at(half);
    let (lo, hi) = x1.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| (a.min(*v), b.max(*v)));
    let range = hi - lo;
    let max_step = range / 40.0;
    if !(max_step > min_step && min_step > 0.0) {
        return None;
    }
    let (f_lo, f_hi) = (1.0 / max_step, 1.0 / min_step);
    let df = (0.25 / range).max((f_hi - f_lo) / SAWTOOTH_GRID as f64);
    let count = ((f_hi - f_lo) / df).ceil() as usize + 1;
    let amplitudes = fundamental_scan(r1, x1, f_lo, df, count);
    let best = amplitudes.iter().enumerate().max_by(|a, b| a.1.total_cmp(b.1)).map(|(j, _)| j)?;
    let amplitude = |f: f64| {
        let (c, s) = fundamental(r1, x1, f);
        c.hypot(s)
    };
    let (mut a, mut b) = (f_lo + (best as f64 - 1.0) * df, f_lo + (best as f64 + 1.0) * df);
    for _ in 0..40 {
        let m1 = b - (b - a) / 1.618_033_988_75;
        let m2 = a + (b - a) / 1.618_033_988_75;
        if amplitude(m1) > amplitude(m2) {
            b = m2;
        } else {
            a = m1;
        }
    }
    let frequency = 0.5 * (a + b);
    let step = 1.0 / frequency;
    let (c, s) = fundamental(r1, x1, frequency);
    let phase = s.atan2(c);
    let projections: Vec<f64> = r2
        .iter()
        .zip(x2)
        .map(|(r, x)| 2.0 * r * (2.0 * std::f64::consts::PI * frequency * x - phase).cos())
        .collect();
    let (mean, z) = batch_z(&projections);
    let amplitude_ratio = mean / (step / std::f64::consts::PI);
    let variance = r.iter().map(|v| v * v).sum::<f64>() / n as f64;
    (z >= threshold && (0.5..=1.5).contains(&amplitude_ratio)).then(|| Lattice {
        step,
        form: LatticeForm::Sawtooth { z, samples: r2.len(), amplitude_ratio },
        noise: (variance - step * step / 12.0).max(0.0).sqrt(),
    })
}

/// The lattice of one sensor's raw readings, if there is one: exact first, else blurred, else
/// the sawtooth of the residual about `fitted` (the fitted model's output at the same samples).
/// `threshold` is the z the blurred and sawtooth statistics need.
pub fn detect(values: &[f64], fitted: &[f64], threshold: f64) -> Option<Lattice> {
    let n = values.len().max(1) as f64;
    let residual_variance = values.iter().zip(fitted).map(|(y, x)| (y - x).powi(2)).sum::<f64>() / n;
    if let Some((step, levels)) = exact(values, 10) {
        let noise = (residual_variance - step * step / 12.0).max(0.0).sqrt();
        return Some(Lattice { step, form: LatticeForm::Exact { levels }, noise });
    }
    let range = values.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    let min_step = (0.5 * residual_variance.sqrt()).max(1e-6 * range);
    if let Some((step, z, samples, noise)) = blurred(values, min_step, threshold) {
        return Some(Lattice { step, form: LatticeForm::Blurred { z, samples }, noise });
    }
    sawtooth(values, fitted, min_step, threshold)
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};

    fn decay(n: usize) -> Vec<f64> {
        (0..n).map(|k| 0.5 * (-(k as f64) / 400.0).exp() * (k as f64 * 0.05).cos()).collect()
    }

    #[test]
    fn an_adc_record_is_an_exact_lattice_and_a_continuous_one_is_not() {
        let mut rng = rand::rngs::StdRng::seed_from_u64(3);
        let step = 0.004;
        let clean = decay(3000);
        let adc: Vec<f64> = clean
            .iter()
            .map(|v| step * ((v + 0.001 * rng.sample::<f64, _>(rand_distr::StandardNormal)) / step).round())
            .collect();
        let (found, levels) = exact(&adc, 10).expect("a lattice");
        assert!((found / step - 1.0).abs() < 1e-9, "{found}");
        assert!(levels > 100);
        let noisy: Vec<f64> =
            clean.iter().map(|v| v + 0.001 * rng.sample::<f64, _>(rand_distr::StandardNormal)).collect();
        assert!(exact(&noisy, 10).is_none());
        // Printing precision: a lattice of 10⁻⁶, far below the noise, does not matter.
        let printed: Vec<f64> = noisy.iter().map(|v| (v * 1e6).round() / 1e6).collect();
        let exact_fit: Vec<f64> = clean.clone();
        assert!(detect(&printed, &exact_fit, 8.0).is_none_or(|l| !l.matters()));
        let adc = detect(&adc, &clean, 8.0).expect("the ADC lattice");
        assert!(adc.matters());
    }

    #[test]
    fn a_settled_tail_is_not_a_lattice_but_a_blurred_lattice_while_moving_is() {
        let mut rng = rand::rngs::StdRng::seed_from_u64(5);
        // A decay that settles for two thirds of the record: noise crowding near rest.
        let clean: Vec<f64> = (0..3000)
            .map(|k| if k < 1000 { 0.5 * (k as f64 * 0.02).cos() * (1.0 - k as f64 / 1000.0) } else { 0.0 })
            .collect();
        let noisy: Vec<f64> =
            clean.iter().map(|v| v + 0.001 * rng.sample::<f64, _>(rand_distr::StandardNormal)).collect();
        assert!(blurred(&noisy, 5e-4, 8.0).is_none());
        let step = 0.01;
        let after: Vec<f64> = clean
            .iter()
            .map(|v| step * (v / step).round() + 0.001 * rng.sample::<f64, _>(rand_distr::StandardNormal))
            .collect();
        let (found, z, _, blur) = blurred(&after, 5e-4, 8.0).expect("a blurred lattice");
        assert!((found / step - 1.0).abs() < 0.01, "{found}");
        assert!(z > 20.0, "{z}");
        assert!((blur / 0.001 - 1.0).abs() < 0.3, "{blur}");
    }

    /// A lightly damped decay of 12.8 Hz-like sampling with 700 moving samples, then rest.
    fn swing(n: usize) -> Vec<f64> {
        (0..n)
            .map(|k| if k < 700 { 0.8 * (-(k as f64) / 300.0).exp() * (k as f64 * 0.11).cos() } else { 0.0 })
            .collect()
    }

    fn gaussian(rng: &mut rand::rngs::StdRng, n: usize, sigma: f64, rho: f64) -> Vec<f64> {
        let mut e = 0.0;
        let scale = sigma * (1.0 - rho * rho).sqrt();
        (0..n)
            .map(|_| {
                e = rho * e + scale * rng.sample::<f64, _>(rand_distr::StandardNormal);
                e
            })
            .collect()
    }

    #[test]
    fn noise_after_a_quantizer_is_seen_through_the_model_where_the_readings_blur() {
        let mut rng = rand::rngs::StdRng::seed_from_u64(11);
        let clean = swing(2000);
        let sigma = 0.004;
        let step = 3.6 * sigma;
        let noise = gaussian(&mut rng, clean.len(), sigma, 0.0);
        let y: Vec<f64> = clean.iter().zip(&noise).map(|(x, e)| step * (x / step).round() + e).collect();
        // The readings' own phase is blurred to e^{-2π²/3.6²} ≈ 0.22: not confirmed at z ≥ 8.
        assert!(blurred(&y, 0.5 * sigma, 8.0).is_none());
        let lattice = detect(&y, &clean, 8.0).expect("a lattice");
        assert!((lattice.step / step - 1.0).abs() < 0.01, "{} vs {step}", lattice.step);
        let LatticeForm::Sawtooth { z, samples, amplitude_ratio } = lattice.form else {
            panic!("{:?}", lattice.form)
        };
        assert!(z >= 8.0 && samples > 300, "{z} {samples}");
        assert!((amplitude_ratio - 1.0).abs() < 0.3, "{amplitude_ratio}");
        assert!(lattice.matters());
        assert!((lattice.noise / sigma - 1.0).abs() < 0.2, "{}", lattice.noise);
    }

    #[test]
    fn no_sawtooth_in_white_or_coloured_noise_a_misfit_or_a_ripple_of_the_wrong_amplitude() {
        let mut rng = rand::rngs::StdRng::seed_from_u64(12);
        let clean = swing(4000);
        let sigma = 0.004;
        for rho in [0.0, 0.5, 0.9] {
            for _ in 0..10 {
                let noise = gaussian(&mut rng, clean.len(), sigma, rho);
                let y: Vec<f64> = clean.iter().zip(&noise).map(|(x, e)| x + e).collect();
                assert!(sawtooth(&y, &clean, 0.5 * sigma, 8.0).is_none(), "rho {rho}");
                // A smooth misfit: the fitted response 2 % too small and 1 % slow.
                let misfit: Vec<f64> = (0..clean.len())
                    .map(|k| {
                        if k < 700 {
                            0.98 * 0.8 * (-(k as f64) / 300.0).exp() * (k as f64 * 0.111).cos()
                        } else {
                            0.0
                        }
                    })
                    .collect();
                assert!(sawtooth(&y, &misfit, 0.5 * sigma, 8.0).is_none(), "misfit, rho {rho}");
            }
        }
        // A ripple periodic in the response, three times a rounding's amplitude for its period.
        // The same ripple at a rounding's amplitude is found: the amplitude rule is what refuses it.
        let period = 0.02;
        let noise = gaussian(&mut rng, clean.len(), sigma, 0.0);
        let ripple = |times: f64| -> Vec<f64> {
            clean
                .iter()
                .zip(&noise)
                .map(|(x, e)| {
                    x + times * period / std::f64::consts::PI
                        * (2.0 * std::f64::consts::PI * x / period).sin()
                        + e
                })
                .collect()
        };
        assert!(sawtooth(&ripple(3.0), &clean, 0.5 * sigma, 8.0).is_none());
        let found = sawtooth(&ripple(1.0), &clean, 0.5 * sigma, 8.0).expect("a rounding's amplitude");
        assert!((found.step / period - 1.0).abs() < 0.01, "{}", found.step);
    }
}
