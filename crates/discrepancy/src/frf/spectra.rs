//! The kernels of the frequency-response estimates: the inputs on the record's grid, and the
//! transforms of Hann-windowed, half-overlapping segments (Welch).

use faer::Mat;
use mem::Measurement;

/// The record's inputs (K × m) on its grid: averaged over each interval where it was decimated;
/// `None` without inputs.
pub(super) fn held_inputs(data: &Measurement, k: usize) -> Option<Mat<f64>> {
    let inputs = data.inputs()?;
    let factor = data.decimation().map_or(1, |d| d.factor());
    let raw = inputs.values();
    Some(Mat::from_fn(k, inputs.names().len(), |t, i| {
        let end = ((t + 1) * factor).min(raw.nrows());
        let start = (t * factor).min(end.saturating_sub(1));
        (start..end).map(|r| raw[(r, i)]).sum::<f64>() / (end - start).max(1) as f64
    }))
}

/// Σ_n w_n² of the Hann window of `length` samples: a white series of unit variance has that
/// expected |X_b|² in every bin of [`segments`].
pub(super) fn window_power(length: usize) -> f64 {
    (0..length).map(|n| hann(n, length).powi(2)).sum()
}

/// The Hann window of `length` samples that [`segments`] applies.
pub(super) fn window(length: usize) -> Vec<f64> {
    (0..length).map(|n| hann(n, length)).collect()
}

fn hann(n: usize, length: usize) -> f64 {
    0.5 - 0.5 * (2.0 * std::f64::consts::PI * n as f64 / length as f64).cos()
}

/// The discrete Fourier transforms (re, im) at bins 0 … length/2 − 1 of each Hann-windowed,
/// half-overlapping segment of `length` samples of the series `x` (K samples), its mean removed.
pub(super) fn segments(x: &dyn Fn(usize) -> f64, k: usize, length: usize) -> Vec<Vec<(f64, f64)>> {
    let mean = (0..k).map(x).sum::<f64>() / k as f64;
    let hop = (length / 2).max(1);
    let window = window(length);
    let (cos, sin): (Vec<f64>, Vec<f64>) = (0..length)
        .map(|n| {
            let a = 2.0 * std::f64::consts::PI * n as f64 / length as f64;
            (a.cos(), a.sin())
        })
        .unzip();
    (0..)
        .map(|s| s * hop)
        .take_while(|start| start + length <= k)
        .map(|start| {
            let w: Vec<f64> = (0..length).map(|n| window[n] * (x(start + n) - mean)).collect();
            (0..length / 2)
                .map(|b| {
                    w.iter().enumerate().fold((0.0, 0.0), |(re, im), (n, v)| {
                        let at = (b * n) % length;
                        (re + v * cos[at], im - v * sin[at])
                    })
                })
                .collect()
        })
        .collect()
}
