//! A noise-after quantizer seen through the model: the residual about the fitted response is
//! the rounding's sawtooth of that response (see the module notes of `quantization`).

use super::{Lattice, LatticeForm, batch_z, golden_max, moving_end, rest_value};

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
    let n = residual.len().min(fitted.len());
    let blocks = n / 4 * 4;
    scan_lanes::<4>(&residual[..blocks], &fitted[..blocks], f0, df, &mut c, &mut s);
    scan_lanes::<1>(&residual[blocks..n], &fitted[blocks..n], f0, df, &mut c, &mut s);
    let n = residual.len().max(1) as f64;
    c.iter().zip(&s).map(|(c, s)| 2.0 * (c * c + s * s).sqrt() / n).collect()
}

/// Adds the samples' terms to the grid's sums `c`, `s`, L samples' phasors turning side by
/// side: their chains are independent, and each grid point still adds them in sample order, so
/// the sums are those of one sample at a time. The sample count is a multiple of L.
fn scan_lanes<const L: usize>(
    residual: &[f64],
    fitted: &[f64],
    f0: f64,
    df: f64,
    c: &mut [f64],
    s: &mut [f64],
) {
    let tau = 2.0 * std::f64::consts::PI;
    for (r, x) in residual.chunks_exact(L).zip(fitted.chunks_exact(L)) {
        let (mut ps, mut pc, mut ws, mut wc) = ([0.0; L], [0.0; L], [0.0; L], [0.0; L]);
        for l in 0..L {
            (ps[l], pc[l]) = (tau * f0 * x[l]).sin_cos();
            (ws[l], wc[l]) = (tau * df * x[l]).sin_cos();
        }
        for j in 0..c.len() {
            for l in 0..L {
                c[j] += r[l] * pc[l];
                s[j] += r[l] * ps[l];
                (pc[l], ps[l]) = (pc[l] * wc[l] - ps[l] * ws[l], pc[l] * ws[l] + ps[l] * wc[l]);
            }
            if j % 64 == 63 {
                for l in 0..L {
                    let norm = (pc[l] * pc[l] + ps[l] * ps[l]).sqrt();
                    (pc[l], ps[l]) = (pc[l] / norm, ps[l] / norm);
                }
            }
        }
    }
}

/// The end (exclusive) of the samples the sawtooth is read over: the later of the readings' own
/// [`moving_end`] and the last sample where the fitted response is farther from its rest value
/// (its median over the last tenth of the record) than `SWING_SIGMAS` residual σ. Chosen by
/// time, as the readings' end is; past it the response sits within a few σ of rest and its phase
/// stands still, so a misfit there would project on one phase alone.
pub(super) fn swinging_end(values: &[f64], fitted: &[f64]) -> usize {
    let Some(rest) = rest_value(fitted) else { return 0 };
    let n = fitted.len();
    let sigma = (values.iter().zip(fitted).map(|(y, x)| (y - x).powi(2)).sum::<f64>() / n as f64).sqrt();
    let end = fitted.iter().rposition(|x| (x - rest).abs() > SWING_SIGMAS * sigma).map_or(0, |k| k + 1);
    end.max(moving_end(values))
}

/// The local quadratic least-squares smooth of `v` over ±`h` samples (Savitzky–Golay, the
/// centre weight w₀ = 3(3h² + 3h − 1)/((2h − 1)(2h + 1)(2h + 3)) returned beside it); zero on
/// the first and last `h` samples, which keep the model's response.
fn local_quadratic(v: &[f64], h: usize) -> (Vec<f64>, f64) {
    let n = v.len();
    let hf = h as f64;
    let norm = (2.0 * hf - 1.0) * (2.0 * hf + 1.0) * (2.0 * hf + 3.0);
    let weights: Vec<f64> = (0..=2 * h)
        .map(|i| {
            let j = i as f64 - hf;
            (3.0 * (3.0 * hf * hf + 3.0 * hf - 1.0) - 15.0 * j * j) / norm
        })
        .collect();
    let smooth = (0..n)
        .map(|k| {
            if k < h || k + h >= n {
                return 0.0;
            }
            weights.iter().enumerate().map(|(i, w)| w * v[k + i - h]).sum()
        })
        .collect();
    (smooth, weights[h])
}

/// Half the window (samples) of the local smooth that corrects the fitted response for a second
/// reading: 15 samples, w₀ = 0.15, so the corrected response carries 0.39 σ of noise.
const SMOOTHING_HALF_WIDTH: usize = 7;

/// How far from rest, in residual σ, the fitted response must be for a sample to be read.
const SWING_SIGMAS: f64 = 10.0;

/// The largest frequency grid [`sawtooth`] scans (points): it bounds the cost when the range of
/// the response is very many smallest steps.
const SAWTOOTH_GRID: usize = 20_000;

/// A noise-after quantizer seen through the model: the residual r = y − x̂ of the readings
/// about the fitted response is a sawtooth of x̂ of period Δ (see the module notes).
///
/// Over the samples while the response swings (`swinging_end`): on the first half, the Δ from
/// `min_step` to a fortieth of x̂'s range whose fundamental is largest (a grid in 1/Δ at a
/// quarter of the resolution 1/range, then a golden-section refinement), and its phase φ; on
/// the second half, the mean of 2r·cos(2πx̂/Δ − φ), its z by batch means, and its ratio to the
/// Δ/π a rounding gives. A periodicity that is not a rounding's (a cogging-like ripple, a trace
/// of the misfit) does not hold its phase, or has the wrong amplitude for its period.
///
/// The phase of x̂ is only as good as the model: a misfit of Δ/2π scrambles it, and a model
/// that lacks another effect (a friction law of another form, say) misses by far more than a
/// small step. If the first reading finds nothing, a second reads about x̃ = x̂ + S(r), the
/// response corrected by a local quadratic smooth S of the residual over 15 samples: the misfit
/// is smooth in time and S follows it, while the sawtooth, which changes with every step the
/// signal crosses, mostly passes S by. S keeps the share w₀ of the noise (which blurs the
/// phase by exp(−2π²w₀σ²/Δ²)) and of the sawtooth; the ratio is taken to the amplitude a
/// rounding keeps after both.
///
/// Returns the lattice if z ≥ `threshold` and the ratio is within 0.5–1.5; its noise is the
/// residual variance (before the smooth) less the rounding's Δ²/12.
pub fn sawtooth(values: &[f64], fitted: &[f64], min_step: f64, threshold: f64) -> Option<Lattice> {
    if values.len() != fitted.len() {
        return None;
    }
    let end = swinging_end(values, fitted);
    read(values, fitted, end, min_step, threshold, None).or_else(|| {
        let r: Vec<f64> = values.iter().zip(fitted).map(|(y, x)| y - x).collect();
        let (smooth, centre) = local_quadratic(&r, SMOOTHING_HALF_WIDTH);
        let corrected: Vec<f64> = fitted.iter().zip(&smooth).map(|(x, l)| x + l).collect();
        read(values, &corrected, end, min_step, threshold, Some(centre))
    })
}

/// [`sawtooth`] read about `fitted` over the first `end` samples; `smoothing` is the centre
/// weight of the local smooth that corrected it, if one did.
fn read(
    values: &[f64],
    fitted: &[f64],
    end: usize,
    min_step: f64,
    threshold: f64,
    smoothing: Option<f64>,
) -> Option<Lattice> {
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
    let frequency =
        golden_max(amplitude, f_lo + (best as f64 - 1.0) * df, f_lo + (best as f64 + 1.0) * df, 40);
    let step = 1.0 / frequency;
    let (c, s) = fundamental(r1, x1, frequency);
    let phase = s.atan2(c);
    let projections: Vec<f64> = r2
        .iter()
        .zip(x2)
        .map(|(r, x)| 2.0 * r * (2.0 * std::f64::consts::PI * frequency * x - phase).cos())
        .collect();
    let (mean, z) = batch_z(&projections);
    // The residual's variance is the noise's and the rounding's Δ²/12; a local smooth took the
    // share w₀ of both out of the residual and put the noise's into the response's phase.
    let kept = 1.0 - smoothing.unwrap_or(0.0);
    let variance = r.iter().map(|v| v * v).sum::<f64>() / n as f64 / kept;
    let noise = (variance - step * step / 12.0).max(0.0);
    let blur = smoothing.map_or(1.0, |w0| {
        let phase = 2.0 * std::f64::consts::PI / step;
        (-0.5 * phase * phase * noise * w0).exp()
    });
    let amplitude_ratio = mean / (step / std::f64::consts::PI) / (kept * blur);
    (z >= threshold && (0.5..=1.5).contains(&amplitude_ratio)).then(|| Lattice {
        step,
        form: LatticeForm::Sawtooth { z, samples: r2.len(), amplitude_ratio },
        noise: noise.sqrt(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::quantization::{batch_threshold, blurred, detect, modal_corrected};
    use rand::{Rng, SeedableRng};

    /// The scan's amplitudes agree with the fundamental computed directly at each grid point
    /// (the turned phasors drift by rounding only), for sample counts that fill the lanes and
    /// counts that leave a remainder.
    #[test]
    fn the_frequency_scan_matches_the_direct_fundamental() {
        let mut rng = rand::rngs::StdRng::seed_from_u64(5);
        for n in [203usize, 204, 1001] {
            let x: Vec<f64> =
                (0..n).map(|k| 3.0 * (k as f64 * 0.01).cos() + rng.random_range(-0.01..0.01)).collect();
            let r: Vec<f64> = x.iter().map(|v| 0.02 * (2.0 * std::f64::consts::PI * v / 0.1).sin()).collect();
            let (f0, df, count) = (2.0, 0.37, 300);
            let scan = fundamental_scan(&r, &x, f0, df, count);
            for (j, a) in scan.iter().enumerate() {
                let (c, s) = fundamental(&r, &x, f0 + j as f64 * df);
                assert!((a - c.hypot(s)).abs() < 1e-12, "n {n}, j {j}: {a} vs {}", c.hypot(s));
            }
            // The sawtooth's own frequency (10 per unit) stands out.
            let best = scan.iter().enumerate().max_by(|a, b| a.1.total_cmp(b.1)).unwrap().0;
            assert!((f0 + best as f64 * df - 10.0).abs() < df, "best at {}", f0 + best as f64 * df);
        }
    }

    /// The sawtooth's bar in diagnosis: t₁₉ at 10⁻⁵.
    fn bar() -> f64 {
        batch_threshold(1e-5)
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
        // The readings' own phase is blurred to e^{-2π²/3.6²} ≈ 0.22: held by z ≈ 5.7 here, on
        // the edge of the diagnosis's bar (t₁₉'s quantile at 10⁻⁵, 5.63); the sawtooth, read
        // through the model, holds it far above.
        let (_, blurred_z, _, _) = blurred(&y, 0.5 * sigma, f64::NEG_INFINITY).expect("a phase");
        assert!(blurred_z < 8.0, "{blurred_z}");
        let lattice = detect(&y, &clean, 8.0).expect("a lattice");
        assert!((lattice.step / step - 1.0).abs() < 0.01, "{} vs {step}", lattice.step);
        let LatticeForm::Sawtooth { z, samples, amplitude_ratio } = lattice.form else {
            panic!("{:?}", lattice.form)
        };
        assert!(z >= 8.0 && z > blurred_z + 2.0 && samples > 300, "{z} vs {blurred_z}, {samples}");
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
                assert!(sawtooth(&y, &clean, 0.5 * sigma, bar()).is_none(), "rho {rho}");
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
                assert!(sawtooth(&y, &misfit, 0.5 * sigma, bar()).is_none(), "misfit, rho {rho}");
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
        assert!(sawtooth(&ripple(3.0), &clean, 0.5 * sigma, bar()).is_none());
        let found = sawtooth(&ripple(1.0), &clean, 0.5 * sigma, 8.0).expect("a rounding's amplitude");
        assert!((found.step / period - 1.0).abs() < 0.01, "{}", found.step);
    }

    /// A decay sampled finely (a 1.7 Hz mode at 128 Hz, 3000 samples), amplitude 200σ-like.
    fn fine(n: usize, scale: f64, slow: f64) -> Vec<f64> {
        (0..n)
            .map(|k| {
                let t = k as f64 / 128.0;
                scale * (-t / 6.0).exp() * (2.0 * std::f64::consts::PI * 1.7 * slow * t).cos()
            })
            .collect()
    }

    #[test]
    fn a_model_that_misses_by_more_than_a_step_is_corrected_by_a_local_smooth() {
        let mut rng = rand::rngs::StdRng::seed_from_u64(13);
        let (sigma, n) = (0.004, 3000);
        let clean = fine(n, 0.8, 1.0);
        // The fitted response 2 % too small and 1 % slow: off by up to 4 steps.
        let model = fine(n, 0.98 * 0.8, 0.99);
        let step = 3.5 * sigma;
        let noise = gaussian(&mut rng, n, sigma, 0.0);
        let y: Vec<f64> = clean.iter().zip(&noise).map(|(x, e)| step * (x / step).round() + e).collect();
        let end = swinging_end(&y, &model);
        assert!(read(&y, &model, end, 0.5 * sigma, 8.0, None).is_none(), "the model alone");
        let lattice = sawtooth(&y, &model, 0.5 * sigma, 8.0).expect("the corrected reading");
        assert!((lattice.step / step - 1.0).abs() < 0.01, "{} vs {step}", lattice.step);
        let LatticeForm::Sawtooth { amplitude_ratio, .. } = lattice.form else {
            panic!("{:?}", lattice.form)
        };
        assert!((0.6..1.4).contains(&amplitude_ratio), "{amplitude_ratio}");
        assert!((lattice.noise / sigma - 1.0).abs() < 0.3, "{}", lattice.noise);
        // No quantizer: the same misfit with white or coloured noise shows no lattice.
        for rho in [0.0, 0.5, 0.9] {
            for _ in 0..10 {
                let noise = gaussian(&mut rng, n, sigma, rho);
                let y: Vec<f64> = clean.iter().zip(&noise).map(|(x, e)| x + e).collect();
                assert!(sawtooth(&y, &model, 0.5 * sigma, bar()).is_none(), "rho {rho}");
            }
        }
    }

    #[test]
    fn the_sawtooths_bar_is_students_t_with_19_degrees_of_freedom() {
        // scipy.stats.t.isf(1e-5, 19) = 5.626766232724045; isf(1e-7, 19) = 7.905112633688786.
        assert!((batch_threshold(1e-5) - 5.626_766_232_724_045).abs() < 1e-6, "{}", batch_threshold(1e-5));
        assert!((batch_threshold(1e-7) - 7.905_112_633_688_786).abs() < 1e-5, "{}", batch_threshold(1e-7));
    }

    /// A slow mode and a fast one, sampled at 128 Hz for `n` samples; `fast_decay` is the fast
    /// mode's σ (1/s).
    fn two_modes(n: usize, fast_decay: f64) -> Vec<f64> {
        (0..n)
            .map(|k| {
                let t = k as f64 / 128.0;
                let tau = 2.0 * std::f64::consts::PI;
                0.8 * (-t / 6.0).exp() * (tau * 1.7 * t).cos()
                    + 0.15 * (fast_decay * t).exp() * (tau * 10.9 * t).cos()
            })
            .collect()
    }

    #[test]
    fn a_high_modes_misfit_is_corrected_by_the_models_own_modes() {
        let mut rng = rand::rngs::StdRng::seed_from_u64(14);
        let n = 3000;
        let times: Vec<f64> = (0..n).map(|k| k as f64 / 128.0).collect();
        // The truth's 10.9 Hz mode decays at 0.5/s, the model's at 0.25/s: a fast oscillation
        // that a decimated fit never sees and no 15-sample smooth follows.
        let clean = two_modes(n, -0.5);
        let model = two_modes(n, -0.25);
        let tau = 2.0 * std::f64::consts::PI;
        let poles = [(-1.0 / 6.0, tau * 1.7), (-0.25, tau * 10.9)];
        let sigma = 0.004;
        let step = 3.2 * sigma;
        let noise = gaussian(&mut rng, n, sigma, 0.0);
        let y: Vec<f64> = clean.iter().zip(&noise).map(|(x, e)| step * (x / step).round() + e).collect();
        assert!(sawtooth(&y, &model, 0.5 * sigma, 8.0).is_none(), "the model and its smooth alone");
        let corrected = modal_corrected(&y, &model, &times, &poles);
        let lattice = sawtooth(&y, &corrected, 0.5 * sigma, 8.0).expect("the corrected reading");
        assert!((lattice.step / step - 1.0).abs() < 0.01, "{} vs {step}", lattice.step);
        // No quantizer: the corrected response shows no lattice in white or coloured noise.
        for rho in [0.0, 0.5, 0.9] {
            for _ in 0..10 {
                let noise = gaussian(&mut rng, n, sigma, rho);
                let y: Vec<f64> = clean.iter().zip(&noise).map(|(x, e)| x + e).collect();
                let corrected = modal_corrected(&y, &model, &times, &poles);
                assert!(sawtooth(&y, &corrected, 0.5 * sigma, bar()).is_none(), "rho {rho}");
            }
        }
    }
}
