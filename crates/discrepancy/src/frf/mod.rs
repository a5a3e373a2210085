//! Resonances of a forced record, by a scan of trial modes driven by its measured inputs.
//!
//! A free decay is a response ERA reads as it is. A forced record's response follows its input,
//! so its resonances are looked for by the question the diagnosis will ask of them: how much of
//! the series would a mode driven by the record's own input explain? For every frequency of a
//! geometric grid over the band the inputs excite (their auto-spectrum at least [`EXCITED`] of
//! its largest; Welch, Hann-windowed segments of a quarter of the record, at most [`MAX_SEGMENT`]
//! samples, half overlapping; Bendat & Piersol, *Random Data*, §9.2), a trial mode
//! η̈ + 2ζω η̇ + ω² η = ω² u (ζ = [`SCAN_DAMPING`]) is driven from rest by each input, and the
//! series' projection on span{η, η̇/ω} is its gain (`scan`). Local maxima of the gain standing at
//! least [`PROMINENCE`] times above its median over the band, at least [`SEPARATION`] apart, are
//! the resonances, at most [`MAX_PEAKS`], each with the damping ratio of [`DAMPINGS`] that
//! explains most at its frequency. This is the matched filter of the driven-mode candidate: where
//! the input excites little, a white residual's expected gain is the same as anywhere (two
//! degrees of freedom an output), so the band's edges do not ring. The H₁ estimate
//! S_uy/S_uu that this replaced divides by the input's auto-spectrum: at the edge of a
//! band-limited input its variance grows without bound, and its peak picking found "modes" at
//! 50 and 52 Hz (refitted at 36 and 46 Hz) on a roof-driven record, low-passed at 40 Hz, whose
//! appendage rang at 21 Hz. (A least-squares impulse
//! response fed to ERA, tried before that, rang at a swept sine's last frequency.)
//!
//! Where the series' noise is coloured and its predictor known ([`resonances_under`]: a forced
//! record whose recorded force carries noise, which the model's resonances colour), the series
//! and each trial mode's response are whitened by that predictor before the projection: the
//! generalized matched filter (prewhitening; Kay, *Fundamentals of Statistical Signal Processing,
//! Vol. II: Detection Theory*, 1998, ch. 4), whose chance gain is the same at every frequency as
//! it is for the plain scan in white noise.
//!
//! A mode that belongs to a body hung on a structure also pushes back on its coordinate, as a
//! mass that grows towards its frequency, over the whole band; where its own ringing is too weak
//! for the scan above, that reaction is read by a scan of trial appendages at each coordinate
//! (`appendage.rs`, [`AppendageScan`]): the exact first-order change of the outputs per unit of a
//! vanishing appendage's mass, whitened alike, the free parameters' span projected off, set
//! against the same mass held rigid.

mod appendage;
mod input_noise;
mod noise_response;
mod scan;
mod spectra;

pub use appendage::{APPENDAGE_DAMPING, APPENDAGE_SPACING, AppendageResonance, AppendageScan, RIGID};
pub use input_noise::{InputNoise, InputNoiseLevel, RecordedInputs, input_noise};
pub use noise_response::NoiseResponse;

use era::EraMode;
use faer::Mat;
use mem::{Measurement, NoisePredictor};

/// The share of the inputs' largest auto-spectrum above which a frequency counts as excited.
pub const EXCITED: f64 = 1e-2;

/// How far a resonance's gain must stand above its median over the excited band.
pub const PROMINENCE: f64 = 4.0;

/// The longest segment (samples): a long record is averaged over more segments, and the direct
/// transform's cost stays O(K · MAX_SEGMENT).
pub const MAX_SEGMENT: usize = 1024;

/// The most resonances returned. A misfit of each modelled mode takes one; the rest are left for
/// modes the model lacks.
pub const MAX_PEAKS: usize = 6;

/// The relative spacing of the scan's frequencies: a quarter of the width 2ζ of a trial mode's
/// half-power band at [`SCAN_DAMPING`].
pub const SPACING: f64 = 0.005;

/// The damping ratio of the scan's trial mode.
pub const SCAN_DAMPING: f64 = 0.01;

/// The damping ratios tried at a resonance's frequency; the one that explains most is its seed.
pub const DAMPINGS: [f64; 7] = [0.002, 0.005, 0.01, 0.02, 0.05, 0.1, 0.2];

/// The least relative distance between two resonances returned.
pub const SEPARATION: f64 = 0.1;

/// The cycles a resonance must complete within the record.
const MIN_CYCLES: f64 = 3.0;

/// The resonances of `series` (K × p on the record's grid, the outputs already weighted) driven
/// by `data`'s measured inputs, strongest first, as modes with consistency 1 and a contribution
/// that is the resonance's share of the returned resonances' summed gain; `None` without inputs
/// or with fewer than 64 samples. The inputs are taken on the record's grid (averaged over each
/// interval where it was decimated); the gain does not depend on an input's units.
pub fn resonances(data: &Measurement, series: &Mat<f64>) -> Option<Vec<EraMode>> {
    resonances_of(data, &[series]).map(|mut each| each.remove(0))
}

/// [`resonances`] of several series of one record (a residual and the record itself, say): the
/// trial modes depend on the inputs alone, so each is driven once and projected on every series.
/// One list per series, in their order; `None` as for [`resonances`].
pub fn resonances_of(data: &Measurement, series: &[&Mat<f64>]) -> Option<Vec<Vec<EraMode>>> {
    let plain: Vec<Scanned<'_>> = series.iter().map(|s| Scanned { series: s, noise: None }).collect();
    resonances_under(data, &plain)
}

/// A series to scan, and the noise it is read under: per output, the predictor whose
/// innovations are white (`None` for the whole series, or for an output: white noise).
#[derive(Clone, Copy)]
pub struct Scanned<'a> {
    /// The series (K × p, the outputs already weighted).
    pub series: &'a Mat<f64>,
    /// Per output, the noise's predictor ([`NoisePredictor`]).
    pub noise: Option<&'a [Option<NoisePredictor>]>,
}

/// [`resonances_of`] with each series read under its noise: where an output's noise has a
/// predictor, both the series and the trial mode's response are whitened by it before the
/// projection, so the gain is the generalised least squares' (the matched filter in coloured
/// noise). On a forced record whose force is recorded with noise, the model's response to that
/// noise peaks at the modelled modes, and a trial mode there — driven by the same noisy force —
/// matches part of it; under the noise's own spectrum it gains only by chance, and an unmodelled
/// mode's resonance elsewhere stands out.
pub fn resonances_under(data: &Measurement, series: &[Scanned<'_>]) -> Option<Vec<Vec<EraMode>>> {
    let inputs = data.inputs()?;
    let k = series.iter().map(|s| s.series.nrows()).min()?;
    let m = inputs.names().len();
    if m == 0 || k < 64 {
        return None;
    }
    let held = spectra::held_inputs(data, k)?;
    let h = data.interval();
    let none = || Some(vec![Vec::new(); series.len()]);
    let Some((low, high)) = excited_band(&held, k, h) else {
        return none();
    };
    let columns: Vec<Vec<f64>> = (0..m).map(|i| (0..k).map(|t| held[(t, i)]).collect()).collect();
    // Each series' columns as scanned: whitened by their output's predictor where it has one.
    let whitened: Vec<Vec<Vec<f64>>> = series
        .iter()
        .map(|s| {
            (0..s.series.ncols())
                .map(|o| {
                    let column: Vec<f64> = (0..k).map(|t| s.series[(t, o)]).collect();
                    match predictor_of(s, o) {
                        Some(p) => p.whitened(&column),
                        None => column,
                    }
                })
                .collect()
        })
        .collect();
    // Per series and output with a predictor, each input through that predictor's error filter,
    // once: a trial mode driven by it is the mode's whitened response (`scan::whitened_response`).
    let filtered: Vec<Vec<Option<Vec<Vec<f64>>>>> = series
        .iter()
        .map(|s| {
            (0..s.series.ncols())
                .map(|o| {
                    predictor_of(s, o).map(|p| columns.iter().map(|u| scan::error_filtered(u, p)).collect())
                })
                .collect()
        })
        .collect();
    let plain_needed = filtered.iter().flatten().any(Option::is_none);
    // Each series' gain at (f, ζ), summed over the inputs' trial modes.
    let gains = |f: f64, zeta: f64| -> Vec<f64> {
        let mut g = vec![0.0; series.len()];
        let Some(mode) = scan::TrialMode::new(f, zeta, h) else { return g };
        for (i, u) in columns.iter().enumerate() {
            let Some(x) = mode.respond(u) else { continue };
            let plain = if plain_needed { scan::basis(&x) } else { Vec::new() };
            for (((gs, s), cols), inputs) in g.iter_mut().zip(series).zip(&whitened).zip(&filtered) {
                for (o, col) in cols.iter().enumerate() {
                    *gs += match (predictor_of(s, o), &inputs[o]) {
                        (Some(p), Some(by)) => match mode.respond(&by[i]) {
                            Some(driven) => scan::explained_column(
                                col,
                                &scan::basis(&scan::whitened_response(&x, driven, p)),
                            ),
                            None => 0.0,
                        },
                        _ => scan::explained_column(col, &plain),
                    };
                }
            }
        }
        g
    };
    let steps = ((high / low).ln() / SPACING.ln_1p()).floor() as usize;
    let grid: Vec<f64> = (0..=steps).map(|j| low * (SPACING.ln_1p() * j as f64).exp()).collect();
    if grid.len() < 5 {
        return none();
    }
    let scanned: Vec<Vec<f64>> = grid.iter().map(|&f| gains(f, SCAN_DAMPING)).collect();
    let at = |f0: f64, zeta: f64, which: usize| gains(f0, zeta)[which];
    Some(
        (0..series.len())
            .map(|which| {
                let g: Vec<f64> = scanned.iter().map(|v| v[which]).collect();
                peaks_of(&grid, &g)
                    .into_iter()
                    .map(|(j, share)| {
                        let f0 = grid[j];
                        let damping = DAMPINGS
                            .iter()
                            .map(|&z| (z, at(f0, z, which)))
                            .max_by(|a, b| a.1.total_cmp(&b.1))
                            .map_or(SCAN_DAMPING, |(z, _)| z);
                        EraMode {
                            frequency_hz: f0,
                            damping_ratio: damping,
                            consistency: 1.0,
                            mpc: None,
                            contribution: share,
                            physical: true,
                        }
                    })
                    .collect()
            })
            .collect(),
    )
}

/// Output o's noise predictor in a scanned series, if it has one.
fn predictor_of<'a>(s: &Scanned<'a>, o: usize) -> Option<&'a NoisePredictor> {
    s.noise.and_then(|n| n.get(o)).and_then(Option::as_ref)
}

/// The resonances of one gain curve `g` over `grid`: its local maxima standing [`PROMINENCE`]
/// times above its median, strongest first, [`SEPARATION`] apart, at most [`MAX_PEAKS`], each
/// with its share of their summed gain; none where a gain is not finite.
fn peaks_of(grid: &[f64], g: &[f64]) -> Vec<(usize, f64)> {
    let mut sorted: Vec<f64> = g.iter().copied().filter(|v| v.is_finite()).collect();
    if sorted.len() < grid.len() {
        return Vec::new();
    }
    sorted.sort_by(f64::total_cmp);
    let median = sorted[sorted.len() / 2];
    let mut maxima: Vec<usize> = (1..grid.len() - 1)
        .filter(|&j| g[j] > g[j - 1] && g[j] >= g[j + 1] && g[j] > 0.0 && g[j] >= PROMINENCE * median)
        .collect();
    maxima.sort_by(|&a, &b| g[b].total_cmp(&g[a]));
    let mut peaks: Vec<usize> = Vec::new();
    for j in maxima {
        if peaks.iter().all(|&p| (grid[p] / grid[j] - 1.0).abs() >= SEPARATION) {
            peaks.push(j);
        }
        if peaks.len() == MAX_PEAKS {
            break;
        }
    }
    let total: f64 = peaks.iter().map(|&j| g[j]).sum();
    peaks.into_iter().map(|j| (j, g[j] / total)).collect()
}

/// The band (Hz) the inputs `held` (K × m, every `h` s) excite: from the lowest to the highest
/// bin whose summed auto-spectrum (each input's divided by its mean square, so that inputs of
/// other units add) is at least [`EXCITED`] of its largest, and within [`MIN_CYCLES`] cycles in
/// the record and 0.95 of the Nyquist frequency; `None` with fewer than five such bins.
fn excited_band(held: &Mat<f64>, k: usize, h: f64) -> Option<(f64, f64)> {
    let length = (k / 4).min(MAX_SEGMENT);
    let bins = length / 2;
    let df = 1.0 / (length as f64 * h);
    let mut auto_total = vec![0.0; bins];
    for i in 0..held.ncols() {
        let mean_square = (0..k).map(|t| held[(t, i)].powi(2)).sum::<f64>() / k as f64;
        let segments = spectra::segments(&|t| held[(t, i)], k, length);
        for (b, total) in auto_total.iter_mut().enumerate().skip(1) {
            let suu: f64 = segments.iter().map(|s| s[b].0 * s[b].0 + s[b].1 * s[b].1).sum();
            *total += suu / mean_square.max(f64::MIN_POSITIVE);
        }
    }
    let largest = auto_total.iter().copied().filter(|v| v.is_finite()).fold(0.0, f64::max);
    let excited: Vec<usize> =
        (1..bins).filter(|&b| auto_total[b].is_finite() && auto_total[b] >= EXCITED * largest).collect();
    if excited.len() < 5 || largest <= 0.0 {
        return None;
    }
    let low = (excited[0] as f64 * df).max(MIN_CYCLES / (k as f64 * h));
    let high = (*excited.last()? as f64 * df).min(0.95 * 0.5 / h);
    (low < high).then_some((low, high))
}

#[cfg(test)]
pub(super) mod tests {
    use super::{Scanned, resonances, resonances_under};
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

    /// A and B of ÿ + 2ζω ẏ + ω² y = u (ω = 2πf) in the state [y, ẏ].
    pub(crate) fn oscillator(f: f64, zeta: f64) -> (Mat<f64>, Mat<f64>) {
        let w = 2.0 * std::f64::consts::PI * f;
        let a = Mat::from_fn(2, 2, |r, c| match (r, c) {
            (0, 1) => 1.0,
            (1, 0) => -w * w,
            (1, 1) => -2.0 * zeta * w,
            _ => 0.0,
        });
        (a, Mat::from_fn(2, 1, |r, _| f64::from(u8::from(r == 1))))
    }

    /// The state space ẋ = A x + B u, y = C x + D u of faer matrices (x(0) = 0).
    pub(crate) fn space(
        a: &Mat<f64>,
        b: &Mat<f64>,
        c: &Mat<f64>,
        d: Option<&Mat<f64>>,
    ) -> mem::StateSpace<f64> {
        let nalgebra =
            |x: &Mat<f64>| mem::nalgebra::DMatrix::from_fn(x.nrows(), x.ncols(), |r, cc| x[(r, cc)]);
        mem::StateSpace {
            a: nalgebra(a),
            c: nalgebra(c),
            x0: mem::nalgebra::DVector::zeros(a.nrows()),
            b: Some(nalgebra(b)),
            d: d.map(nalgebra),
        }
    }

    /// `n` seeded standard normals.
    pub(super) fn normals(seed: u64, n: usize) -> Vec<f64> {
        let mut rng = test_problems::rng(seed);
        (0..n).map(|_| rand::Rng::sample::<f64, _>(&mut rng, rand_distr::StandardNormal)).collect()
    }

    /// A single oscillator driven by a seeded broadband force is found at its frequency to the
    /// spectrum's resolution, strongest, with a damping ratio within 2× of its own.
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
        assert!((0.5 * zeta..=2.0 * zeta).contains(&peaks[0].damping_ratio), "{peaks:?}");
        // A free decay (no inputs) is not read this way.
        let free = Measurement::new(vec!["y".into()], 0.0, h, series.clone()).unwrap();
        assert!(resonances(&free, &series).is_none());
    }

    /// A weak resonance (its response a tenth of the noise's RMS) in a series driven by a
    /// band-limited input (four one-pole low-passes at 20 Hz: its auto-spectrum falls to 1 % of
    /// its largest near 29 Hz) is found first. The H₁ peak picking this scan replaced divides by
    /// that auto-spectrum: here it returned 26.0, 27.4 and 30.4 Hz, the band's edge, and not the
    /// mode.
    #[test]
    fn a_weak_resonance_is_found_ahead_of_the_band_edge_of_a_low_passed_input() {
        let (f, zeta, h, k) = (15.0, 0.01, 0.005, 4000);
        let a = 1.0 - (-2.0 * std::f64::consts::PI * 20.0 * h).exp();
        let mut u = normals(11, k);
        for _ in 0..4 {
            let mut y = 0.0;
            for v in u.iter_mut() {
                y += a * (*v - y);
                *v = y;
            }
        }
        let mode = driven_oscillator(f, zeta, h, &u);
        let rms = |x: &[f64]| (x.iter().map(|v| v * v).sum::<f64>() / x.len() as f64).sqrt();
        let scale = 1.0 / rms(&mode);
        let noise = normals(12, k);
        let y: Vec<f64> = mode.iter().zip(&noise).map(|(m, e)| 0.1 * scale * m + e).collect();
        let data = forced_record(&u, &y, h);
        let series = Mat::from_fn(k, 1, |t, _| y[t]);
        let peaks = resonances(&data, &series).unwrap();
        assert!(!peaks.is_empty());
        assert!((peaks[0].frequency_hz / f - 1.0).abs() < 0.01, "{peaks:?}");
    }

    /// The sample autocovariance γ₀…γ_lags of `x`.
    fn sample_autocovariance(x: &[f64], lags: usize) -> Vec<f64> {
        (0..=lags).map(|l| x.iter().zip(&x[l..]).map(|(a, b)| a * b).sum::<f64>() / x.len() as f64).collect()
    }

    /// Errors in variables: the recorded force u + e carries noise e, and the residual holds a
    /// modelled mode's response to it (6 Hz, 1 % damping) beside the sensor's white noise and a
    /// weak mode the model lacks (15 Hz) driven by the true force. A trial mode at 6 Hz driven by
    /// the recorded force matches part of the noise's response, and the plain scan puts it first;
    /// read under the noise's own predictor (of the sample autocovariance of a long realisation
    /// of that noise alone, another seed), the missing mode is first and 6 Hz is not found.
    #[test]
    fn under_the_noise_of_the_recorded_force_its_response_is_not_a_mode() {
        let (h, k) = (0.005, 4000);
        let rms = |x: &[f64]| (x.iter().map(|v| v * v).sum::<f64>() / x.len() as f64).sqrt();
        let unit = |x: Vec<f64>| {
            let r = rms(&x);
            x.into_iter().map(|v| v / r).collect::<Vec<f64>>()
        };
        let noise_of = |e: &[f64], v: &[f64]| -> Vec<f64> {
            let response = unit(driven_oscillator(6.0, 0.01, h, e));
            response.iter().zip(v).map(|(g, v)| 3.0 * g + v).collect()
        };
        let u = normals(21, k);
        let e: Vec<f64> = normals(22, k).iter().map(|v| 0.05 * v).collect();
        let recorded: Vec<f64> = u.iter().zip(&e).map(|(a, b)| a + b).collect();
        let missing = unit(driven_oscillator(15.0, 0.01, h, &u));
        let noise = noise_of(&e, &normals(23, k));
        let y: Vec<f64> = noise.iter().zip(&missing).map(|(n, m)| -n + 0.3 * m).collect();
        let data = forced_record(&recorded, &y, h);
        let series = Mat::from_fn(k, 1, |t, _| y[t]);
        let plain = resonances(&data, &series).unwrap();
        assert!((plain[0].frequency_hz / 6.0 - 1.0).abs() < 0.05, "{plain:?}");
        // The noise model: a long realisation of the noise alone, other seeds.
        let long = 40_000;
        let alone = noise_of(&normals(24, long), &normals(25, long));
        let predictor = mem::NoisePredictor::of_autocovariance(&sample_autocovariance(&alone, 60));
        let noise = [predictor];
        let under = resonances_under(&data, &[Scanned { series: &series, noise: Some(&noise) }]).unwrap();
        let first = &under[0];
        assert!(!first.is_empty());
        assert!((first[0].frequency_hz / 15.0 - 1.0).abs() < 0.01, "{first:?}");
        assert!(first.iter().all(|m| (m.frequency_hz / 6.0 - 1.0).abs() > 0.05), "{first:?}");
    }
}
