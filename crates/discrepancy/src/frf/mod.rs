//! Resonances of a forced record, by peak picking on its frequency response.
//!
//! A free decay is a response ERA reads as it is. A forced record's response follows its input,
//! so its resonances are read from the frequency response from the measured inputs instead: the
//! H₁ estimate H_oi(f) = S_{u_i y_o}(f) / S_{u_i u_i}(f) (Welch: Hann-windowed segments of a
//! quarter of the record, at most [`MAX_SEGMENT`] samples, half overlapping; Bendat & Piersol,
//! *Random Data*, §9.2), each input taken alone. Its peaks in the band the inputs excite (their
//! auto-spectrum at least [`EXCITED`] of its largest) are the resonances, at most [`MAX_PEAKS`],
//! each standing at least [`PROMINENCE`] times above the band's median, with the damping ratio of
//! its half-power width,
//! ζ = (f₂ − f₁)/(2f₀) (the classical peak-picking method; Ewins, *Modal Testing*, §4.3; the
//! window broadens a light peak, so this is an upper bound, good for a seed). A least-squares
//! impulse response would serve ERA only inside that band too, and rings at its edge like a
//! lightly damped mode (tried: ERA then seeded "modes" at a swept sine's last frequency).

mod input_noise;
mod spectra;

pub use input_noise::{InputNoise, InputNoiseLevel, RecordedInputs, input_noise};

use era::EraMode;
use faer::Mat;
use mem::Measurement;

/// The share of the inputs' largest auto-spectrum above which a frequency counts as excited.
pub const EXCITED: f64 = 1e-2;

/// How far a peak of the summed |H|² must stand above its median over the excited band.
pub const PROMINENCE: f64 = 4.0;

/// The longest segment (samples): a long record is averaged over more segments, and the direct
/// transform's cost stays O(K · MAX_SEGMENT).
pub const MAX_SEGMENT: usize = 1024;

/// The most peaks returned.
pub const MAX_PEAKS: usize = 3;

/// The resonances of `series` (K × p on the record's grid, the outputs already weighted) driven
/// by `data`'s measured inputs, strongest first, as modes with consistency 1 and a contribution
/// that is the peak's share of the peaks' summed |H|²; `None` without inputs or with fewer than
/// 64 samples. The inputs are taken on the record's grid (averaged over each interval where it
/// was decimated), and each one's |H| is weighted by its RMS, so inputs of other units add in
/// the outputs' units.
pub fn resonances(data: &Measurement, series: &Mat<f64>) -> Option<Vec<EraMode>> {
    let inputs = data.inputs()?;
    let (k, p, m) = (series.nrows(), series.ncols(), inputs.names().len());
    if m == 0 || k < 64 {
        return None;
    }
    let held = spectra::held_inputs(data, k)?;
    let length = (k / 4).min(MAX_SEGMENT);
    let bins = length / 2;
    let df = 1.0 / (length as f64 * data.interval());
    let spectra = |column: &dyn Fn(usize) -> f64| spectra::segments(column, k, length);
    let inputs_spectra: Vec<Vec<Vec<(f64, f64)>>> = (0..m).map(|i| spectra(&|t| held[(t, i)])).collect();
    let outputs_spectra: Vec<Vec<Vec<(f64, f64)>>> = (0..p).map(|o| spectra(&|t| series[(t, o)])).collect();
    let mut sum = vec![0.0; bins];
    let mut auto_total = vec![0.0; bins];
    for (i, ui) in inputs_spectra.iter().enumerate() {
        let rms = (0..k).map(|t| held[(t, i)].powi(2)).sum::<f64>().sqrt() / (k as f64).sqrt();
        for b in 1..bins {
            let suu: f64 = ui.iter().map(|s| s[b].0 * s[b].0 + s[b].1 * s[b].1).sum();
            auto_total[b] += suu / (rms * rms).max(f64::MIN_POSITIVE);
            if suu <= 0.0 {
                continue;
            }
            for yo in &outputs_spectra {
                // S_uy = Σ conj(U) Y over the segments.
                let (re, im) = ui.iter().zip(yo).fold((0.0, 0.0), |(re, im), (u, y)| {
                    (re + u[b].0 * y[b].0 + u[b].1 * y[b].1, im + u[b].0 * y[b].1 - u[b].1 * y[b].0)
                });
                sum[b] += (re * re + im * im) / (suu * suu) * rms * rms;
            }
        }
    }
    let largest = auto_total.iter().copied().fold(0.0, f64::max);
    let excited: Vec<usize> =
        (1..bins).filter(|&b| auto_total[b] >= EXCITED * largest && sum[b].is_finite()).collect();
    if excited.len() < 5 {
        return Some(Vec::new());
    }
    let mut in_band: Vec<f64> = excited.iter().map(|&b| sum[b]).collect();
    in_band.sort_by(f64::total_cmp);
    let median = in_band[in_band.len() / 2];
    let mut peaks: Vec<(usize, f64)> = excited
        .windows(3)
        .filter(|w| w[1] == w[0] + 1 && w[2] == w[1] + 1)
        .map(|w| w[1])
        .filter(|&b| sum[b] > sum[b - 1] && sum[b] >= sum[b + 1] && sum[b] >= PROMINENCE * median)
        .map(|b| (b, sum[b]))
        .collect();
    peaks.sort_by(|a, b| b.1.total_cmp(&a.1));
    peaks.truncate(MAX_PEAKS);
    let total: f64 = peaks.iter().map(|(_, g)| g).sum();
    Some(
        peaks
            .into_iter()
            .map(|(b, g)| {
                let (f0, width) = (b as f64 * df, half_power_width(&sum, b) * df);
                EraMode {
                    frequency_hz: f0,
                    damping_ratio: (width / (2.0 * f0)).max(0.5 * df / f0),
                    consistency: 1.0,
                    mpc: None,
                    contribution: g / total,
                    physical: true,
                }
            })
            .collect(),
    )
}

/// The width in bins between the half-power points about peak `b` of `power`, interpolated
/// linearly between bins (to the spectrum's ends where it does not fall to half).
fn half_power_width(power: &[f64], b: usize) -> f64 {
    let half = 0.5 * power[b];
    let crossing = |step: isize| -> f64 {
        let mut j = b as isize;
        while j + step >= 0 && ((j + step) as usize) < power.len() {
            let next = (j + step) as usize;
            if power[next] <= half {
                let (a, c) = (power[j as usize], power[next]);
                let frac = if a > c { (a - half) / (a - c) } else { 1.0 };
                return (j as f64 + step as f64 * frac - b as f64).abs();
            }
            j += step;
        }
        (j as f64 - b as f64).abs()
    };
    crossing(-1) + crossing(1)
}

#[cfg(test)]
pub(super) mod tests {
    use super::resonances;
    use faer::Mat;
    use mem::{Hold, Measurement};

    /// The response y of ÿ + 2ζω ẏ + ω² y = u (f Hz, sampled every h s) to the zero-order-held
    /// input u from rest, by the exact one-step map of [y, ẏ] (a 20-term Taylor series of the
    /// augmented matrix's exponential, accurate to round-off at ωh ≈ 0.4).
    pub(super) fn driven_oscillator(f: f64, zeta: f64, h: f64, u: &[f64]) -> Vec<f64> {
        let w = 2.0 * std::f64::consts::PI * f;
        let a = [[0.0, 1.0, 0.0], [-w * w, -2.0 * zeta * w, 1.0], [0.0, 0.0, 0.0]];
        let mut phi = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        let mut term = phi;
        for n in 1..20 {
            let mut next = [[0.0; 3]; 3];
            for r in 0..3 {
                for c in 0..3 {
                    next[r][c] = (0..3).map(|j| term[r][j] * a[j][c] * h).sum::<f64>() / n as f64;
                }
            }
            term = next;
            for r in 0..3 {
                for c in 0..3 {
                    phi[r][c] += term[r][c];
                }
            }
        }
        let (mut y, mut v) = (0.0, 0.0);
        u.iter()
            .map(|&uk| {
                let out = y;
                (y, v) = (
                    phi[0][0] * y + phi[0][1] * v + phi[0][2] * uk,
                    phi[1][0] * y + phi[1][1] * v + phi[1][2] * uk,
                );
                out
            })
            .collect()
    }

    /// A record of one output `y` driven by one input `u`, held between samples every h s.
    pub(super) fn forced_record(u: &[f64], y: &[f64], h: f64) -> Measurement {
        let values = Mat::from_fn(u.len(), 2, |t, c| if c == 0 { u[t] } else { y[t] });
        Measurement::new(vec!["u".into(), "y".into()], 0.0, h, values)
            .unwrap()
            .with_inputs(&["u"], Hold::Zero)
            .unwrap()
    }

    /// `n` seeded standard normals.
    pub(super) fn normals(seed: u64, n: usize) -> Vec<f64> {
        let mut rng = test_problems::rng(seed);
        (0..n).map(|_| rand::Rng::sample::<f64, _>(&mut rng, rand_distr::StandardNormal)).collect()
    }

    /// A single oscillator driven by a seeded broadband force has its one peak at its frequency
    /// to the spectrum's resolution, with a damping ratio no smaller than its own (the Hann
    /// window only broadens a peak) and within 2× of it.
    #[test]
    fn a_driven_oscillator_peaks_at_its_frequency_and_damping() {
        let (f, zeta, h, k) = (12.5, 0.02, 0.005, 4000);
        let u = normals(7, k);
        let y = driven_oscillator(f, zeta, h, &u);
        let data = forced_record(&u, &y, h);
        let series = Mat::from_fn(k, 1, |t, _| data.values()[(t, 0)]);
        let peaks = resonances(&data, &series).unwrap();
        let df = 1.0 / ((k / 4) as f64 * h);
        assert!(!peaks.is_empty());
        assert!((peaks[0].frequency_hz - f).abs() <= df, "{peaks:?}");
        // The window broadens a peak: the half-power width is the mode's or wider, within 2×.
        assert!((zeta..2.0 * zeta).contains(&peaks[0].damping_ratio), "{peaks:?}");
        // A free decay (no inputs) is not read this way.
        let free = Measurement::new(vec!["y".into()], 0.0, h, series.clone()).unwrap();
        assert!(resonances(&free, &series).is_none());
    }
}
