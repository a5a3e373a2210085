//! What a fit's residual holds beyond noise, and where: the words of an honest "none" (of the
//! reference fit, the baseline with the model's own parameters refitted).
//!
//! Per output: whether the residual is white (Ljung–Box, lags 1–20, at the 1 % level), the
//! frequency band that holds most of its power (periodogram, in octave bands from the
//! record's lowest resolvable frequency to Nyquist), the time window that holds most of it
//! (ten equal windows) and its amplitude relative to the output's RMS.

use crate::stats::ljung_box;
use models::FitOutcome;
use serde::Serialize;

/// A frequency band \[Hz\] and the share of the residual's power in it.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Band {
    /// Lower edge.
    pub low_hz: f64,
    /// Upper edge.
    pub high_hz: f64,
    /// Share of the residual's power.
    pub share: f64,
}

/// One output's residual.
#[derive(Clone, Debug, Serialize)]
pub struct OutputResidual {
    /// Output name.
    pub output: String,
    /// Ljung–Box p-value (lags 1–20).
    pub whiteness_p: f64,
    /// Structured (p < 0.01) or white.
    pub structured: bool,
    /// RMS of the residual over the RMS of the measured output; `None` when the output reads
    /// zero throughout (nothing to compare with).
    pub relative_rms: Option<f64>,
    /// The octave band holding most of the residual's power.
    pub band: Band,
    /// The window (start, end \[s\]) holding most of it, and its share.
    pub window: (f64, f64, f64),
}

/// The structure of a residual, output by output.
#[derive(Clone, Debug, Serialize)]
pub struct ResidualStructure {
    /// Per output.
    pub outputs: Vec<OutputResidual>,
    /// Whether any output's residual is structured.
    pub structured: bool,
}

impl ResidualStructure {
    /// Of a fit's (first experiment's) residual.
    pub fn of(outcome: &FitOutcome) -> Self {
        let e = outcome.first();
        let residual = e.residual();
        let (k, h) = (e.data.n_samples(), e.data.interval());
        let outputs: Vec<OutputResidual> = (0..residual.ncols())
            .map(|o| {
                let r: Vec<f64> = (0..k).map(|t| residual[(t, o)]).collect();
                let y: Vec<f64> = (0..k).map(|t| e.data.values()[(t, o)]).collect();
                let rms = |s: &[f64]| (s.iter().map(|v| v * v).sum::<f64>() / s.len().max(1) as f64).sqrt();
                let whiteness_p = ljung_box(&r, 20).1;
                let total: f64 = r.iter().map(|v| v * v).sum::<f64>().max(f64::MIN_POSITIVE);
                let window = (0..10)
                    .map(|w| {
                        let (a, b) = (w * k / 10, (w + 1) * k / 10);
                        let share = r[a..b].iter().map(|v| v * v).sum::<f64>() / total;
                        (e.data.start() + a as f64 * h, e.data.start() + b as f64 * h, share)
                    })
                    .max_by(|a, b| a.2.total_cmp(&b.2))
                    .unwrap_or((0.0, 0.0, 0.0));
                OutputResidual {
                    output: e.data.names()[o].clone(),
                    whiteness_p,
                    structured: whiteness_p < 0.01,
                    relative_rms: Some(rms(&y)).filter(|&y| y > 0.0).map(|y| rms(&r) / y),
                    band: dominant_band(&r, h),
                    window,
                }
            })
            .collect();
        let structured = outputs.iter().any(|o| o.structured);
        Self { outputs, structured }
    }

    /// The description in words.
    pub fn sentences(&self) -> Vec<String> {
        if !self.structured {
            return vec![
                "the baseline's residual is white on every output: nothing beyond noise to explain".into(),
            ];
        }
        self.outputs
            .iter()
            .filter(|o| o.structured)
            .map(|o| {
                let size = match o.relative_rms {
                    Some(relative) => format!("{:.2} % of the output's RMS", 100.0 * relative),
                    None => "on an output that reads zero throughout".into(),
                };
                format!(
                    "`{}`: structured residual (Ljung–Box p = {:.1e}), {size}, {:.0} % of its power \
                     in {:.2}–{:.2} Hz, most of it in {:.1}–{:.1} s",
                    o.output,
                    o.whiteness_p,
                    100.0 * o.band.share,
                    o.band.low_hz,
                    o.band.high_hz,
                    o.window.0,
                    o.window.1
                )
            })
            .collect()
    }
}

/// The octave band holding most of a series' power (plain DFT; records are short).
fn dominant_band(r: &[f64], h: f64) -> Band {
    let n = r.len();
    let nyquist = 0.5 / h;
    let resolution = 1.0 / (n as f64 * h);
    let power: Vec<(f64, f64)> = (1..=n / 2)
        .map(|j| {
            let f = j as f64 * resolution;
            let (mut c, mut s) = (0.0, 0.0);
            for (t, v) in r.iter().enumerate() {
                let phase = 2.0 * std::f64::consts::PI * (j * t) as f64 / n as f64;
                c += v * phase.cos();
                s += v * phase.sin();
            }
            (f, c * c + s * s)
        })
        .collect();
    let total: f64 = power.iter().map(|p| p.1).sum::<f64>().max(f64::MIN_POSITIVE);
    let mut best = Band { low_hz: 0.0, high_hz: nyquist, share: 0.0 };
    let mut low = 0.0;
    let mut high = 2.0 * resolution;
    while low < nyquist {
        let share = power.iter().filter(|(f, _)| *f > low && *f <= high).map(|p| p.1).sum::<f64>() / total;
        if share > best.share {
            best = Band { low_hz: low, high_hz: high.min(nyquist), share };
        }
        low = high;
        high *= 2.0;
    }
    best
}
