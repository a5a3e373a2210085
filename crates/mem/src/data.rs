//! Measured free decays: uniform sampling, named outputs, decimation with anti-aliasing.

use crate::MemError;
use faer::Mat;

/// p outputs sampled at a uniform interval h, starting at the free decay's t = 0.
#[derive(Clone, Debug, PartialEq)]
pub struct Measurement {
    names: Vec<String>,
    interval: f64,
    start: f64,
    values: Mat<f64>,
}

/// Relative deviation of a time stamp from the uniform grid that still counts as uniform
/// (room for times printed with a few decimals).
const UNIFORM_TOLERANCE: f64 = 1e-4;

impl Measurement {
    /// Samples `values` (K × p) at t_k = start + k·interval.
    ///
    /// # Errors
    /// [`MemError::InvalidData`] for a non-positive interval, fewer than two samples, a name
    /// count that differs from p, or a NaN/infinite value (naming its sample and output).
    pub fn new(names: Vec<String>, start: f64, interval: f64, values: Mat<f64>) -> Result<Self, MemError> {
        if !(interval.is_finite() && interval > 0.0) {
            return Err(MemError::InvalidData(format!(
                "the sample interval must be finite and > 0, got {interval}"
            )));
        }
        if values.nrows() < 2 {
            return Err(MemError::InvalidData(format!("need at least 2 samples, got {}", values.nrows())));
        }
        if names.len() != values.ncols() {
            return Err(MemError::InvalidData(format!(
                "{} names for {} outputs",
                names.len(),
                values.ncols()
            )));
        }
        for o in 0..values.ncols() {
            for k in 0..values.nrows() {
                if !values[(k, o)].is_finite() {
                    return Err(MemError::Sample {
                        sample: k,
                        message: format!("output `{}` has the non-finite value {}", names[o], values[(k, o)]),
                    });
                }
            }
        }
        Ok(Self { names, interval, start, values })
    }

    /// From time stamps that must increase strictly and uniformly.
    ///
    /// # Errors
    /// As [`Self::new`], and [`MemError::InvalidData`] naming the first sample whose time is
    /// not increasing or off the uniform grid by more than 1e-4·h.
    pub fn from_times(times: &[f64], names: Vec<String>, values: Mat<f64>) -> Result<Self, MemError> {
        if times.len() != values.nrows() {
            return Err(MemError::InvalidData(format!(
                "{} time stamps for {} samples",
                times.len(),
                values.nrows()
            )));
        }
        if times.len() < 2 {
            return Err(MemError::InvalidData(format!("need at least 2 samples, got {}", times.len())));
        }
        for (k, w) in times.windows(2).enumerate() {
            if w[1].partial_cmp(&w[0]) != Some(std::cmp::Ordering::Greater) {
                return Err(MemError::Sample {
                    sample: k + 1,
                    message: format!("time is not increasing ({} after {})", w[1], w[0]),
                });
            }
        }
        let h = (times[times.len() - 1] - times[0]) / (times.len() - 1) as f64;
        for (k, t) in times.iter().enumerate() {
            let expected = times[0] + k as f64 * h;
            if (t - expected).abs() > UNIFORM_TOLERANCE * h {
                return Err(MemError::Sample {
                    sample: k,
                    message: format!(
                        "time is not uniformly sampled: {t} where {expected} was expected (h = {h})"
                    ),
                });
            }
        }
        Self::new(names, times[0], h, values)
    }

    /// Output names.
    pub fn names(&self) -> &[String] {
        &self.names
    }
    /// Number of outputs p.
    pub fn n_outputs(&self) -> usize {
        self.values.ncols()
    }
    /// Number of samples K.
    pub fn n_samples(&self) -> usize {
        self.values.nrows()
    }
    /// Sample interval h.
    pub fn interval(&self) -> f64 {
        self.interval
    }
    /// Time of the first sample.
    pub fn start(&self) -> f64 {
        self.start
    }
    /// K × p values.
    pub fn values(&self) -> &Mat<f64> {
        &self.values
    }
    /// The time stamps.
    pub fn times(&self) -> Vec<f64> {
        (0..self.n_samples()).map(|k| self.start + k as f64 * self.interval).collect()
    }

    /// The named outputs only, in the given order.
    ///
    /// # Errors
    /// [`MemError::InvalidData`] for a name the measurement lacks.
    pub fn select(&self, names: &[&str]) -> Result<Self, MemError> {
        let columns = names
            .iter()
            .map(|n| {
                self.names.iter().position(|m| m == n).ok_or_else(|| {
                    MemError::InvalidData(format!(
                        "the data have no column `{n}` (columns: {})",
                        self.names.join(", ")
                    ))
                })
            })
            .collect::<Result<Vec<_>, _>>()?;
        let values = Mat::from_fn(self.n_samples(), columns.len(), |k, o| self.values[(k, columns[o])]);
        Self::new(names.iter().map(|n| n.to_string()).collect(), self.start, self.interval, values)
    }

    /// 1/RMS of each output (1 for an output that is identically zero), so that outputs in
    /// different units (rad, rad/s, strain) weigh alike in the fit.
    pub fn rms_weights(&self) -> Vec<f64> {
        (0..self.n_outputs())
            .map(|o| {
                let ms = (0..self.n_samples()).map(|k| self.values[(k, o)].powi(2)).sum::<f64>()
                    / self.n_samples() as f64;
                if ms > 0.0 { 1.0 / ms.sqrt() } else { 1.0 }
            })
            .collect()
    }

    /// Keeps every `factor`-th sample (starting with the first, so t = 0 stays) after a
    /// zero-phase low-pass FIR filter: a Blackman-windowed sinc with 20·factor + 1 taps and its
    /// cutoff at 80 % of the new Nyquist frequency (stop-band attenuation ≈ 74 dB). The ends
    /// are extended by odd reflection (x(−j) = 2x(0) − x(j)), which keeps each end's value and
    /// slope, so the decay's initial value is not pulled toward zero.
    ///
    /// # Errors
    /// [`MemError::InvalidData`] for factor 0 or a result with fewer than 2 samples.
    pub fn decimate(&self, factor: usize) -> Result<Self, MemError> {
        if factor == 0 {
            return Err(MemError::InvalidData("the decimation factor must be ≥ 1".into()));
        }
        if factor == 1 {
            return Ok(self.clone());
        }
        let half = 10 * factor;
        let cutoff = 0.8 * 0.5 / factor as f64; // cycles per input sample
        let taps: Vec<f64> = (0..=2 * half)
            .map(|i| {
                let m = i as f64 - half as f64;
                let sinc = if m == 0.0 {
                    2.0 * cutoff
                } else {
                    (2.0 * std::f64::consts::PI * cutoff * m).sin() / (std::f64::consts::PI * m)
                };
                let x = i as f64 / (2 * half) as f64;
                let window = 0.42 - 0.5 * (2.0 * std::f64::consts::PI * x).cos()
                    + 0.08 * (4.0 * std::f64::consts::PI * x).cos();
                sinc * window
            })
            .collect();
        let gain: f64 = taps.iter().sum();
        let k_in = self.n_samples();
        let k_out = (k_in - 1) / factor + 1;
        if k_out < 2 {
            return Err(MemError::InvalidData(format!(
                "decimating {k_in} samples by {factor} leaves fewer than 2"
            )));
        }
        let mut out = Mat::<f64>::zeros(k_out, self.n_outputs());
        for o in 0..self.n_outputs() {
            let x = |i: isize| -> f64 {
                let last = k_in as isize - 1;
                if i < 0 {
                    2.0 * self.values[(0, o)] - self.values[((-i).min(last) as usize, o)]
                } else if i > last {
                    2.0 * self.values[(last as usize, o)] - self.values[((2 * last - i).max(0) as usize, o)]
                } else {
                    self.values[(i as usize, o)]
                }
            };
            for k in 0..k_out {
                let centre = (k * factor) as isize;
                let acc: f64 =
                    taps.iter().enumerate().map(|(i, t)| t * x(centre + i as isize - half as isize)).sum();
                out[(k, o)] = acc / gain;
            }
        }
        Self::new(self.names.clone(), self.start, self.interval * factor as f64, out)
    }
}
