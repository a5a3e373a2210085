//! Where and how model and measurement disagree.

use crate::FitOutcome;
use crate::stats::ljung_box;
use mem::Measurement;

/// How one output's residual looks.
#[derive(Clone, Debug, serde::Serialize)]
pub struct OutputDiscrepancy {
    /// Output name.
    pub name: String,
    /// Share of the weighted error ‖Y_error‖ this output carries.
    pub share: f64,
    /// RMS of the unweighted residual, in the output's unit.
    pub rms: f64,
    /// RMS of the residual in the first third of the record over that in the last third.
    pub early_to_late: f64,
    /// Ljung–Box p-value (lags 1–20): ≈ 0 when the residual has structure, large when white.
    pub whiteness_p: f64,
}

/// The localisation of a discrepancy.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Localisation {
    /// The Nyquist frequency of the grid the model is simulated on (the raw record's) \[Hz\]: no
    /// mode above it is looked for.
    pub nyquist_hz: f64,
    /// Per output.
    pub outputs: Vec<OutputDiscrepancy>,
    /// (start s, end s, share of the weighted error) for ten equal windows of the record.
    pub windows: Vec<(f64, f64, f64)>,
    /// (amplitude, half-cycle log decrement) of the measured first output, largest amplitude first
    /// (none for a forced record, whose half cycles follow its input).
    pub decrement_vs_amplitude: Vec<(f64, f64)>,
    /// Least-squares slope of the decrement against amplitude, divided by the mean decrement
    /// (per unit amplitude): ≈ 0 for viscous damping, > 0 when damping grows with amplitude
    /// (drag), < 0 when it grows as the motion dies out (dry friction).
    pub decrement_trend: f64,
    /// Physical modes ERA finds in the residual (a peak the model lacks), strongest first.
    pub residual_modes: Vec<era::EraMode>,
    /// Physical modes ERA finds in the measured data, strongest first.
    pub data_modes: Vec<era::EraMode>,
    /// On a forced structure's record, the bodies the residual shows hanging on its coordinates
    /// ([`crate::frf::AppendageScan`]), best first; filled by the diagnosis, empty elsewhere.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub appendages: Vec<crate::frf::AppendageResonance>,
    /// Findings in words.
    pub findings: Vec<String>,
}

fn smoothed(values: &[f64], half: usize) -> Vec<f64> {
    (0..values.len())
        .map(|k| {
            let (a, b) = (k.saturating_sub(half), (k + half + 1).min(values.len()));
            values[a..b].iter().sum::<f64>() / (b - a) as f64
        })
        .collect()
}

/// Half-cycle peaks (|extrema| between zero crossings) of a smoothed signal.
fn half_cycle_peaks(values: &[f64]) -> Vec<f64> {
    let s = smoothed(values, 2);
    let mean = s[s.len() * 3 / 4..].iter().sum::<f64>() / (s.len() - s.len() * 3 / 4) as f64;
    let mut peaks = Vec::new();
    let mut current: f64 = 0.0;
    let mut sign = (s[0] - mean).signum();
    for v in &s {
        let d = v - mean;
        if d.signum() != sign && d != 0.0 {
            peaks.push(current);
            current = 0.0;
            sign = d.signum();
        }
        current = current.max(d.abs());
    }
    peaks
}

/// Localises the residual of a fit.
pub fn localise(data: &Measurement, outcome: &FitOutcome) -> Localisation {
    localise_under(data, outcome, None)
}

/// [`localise`] with the residual's resonances read under the noise `noise` says (per output,
/// the predictor of its noise; [`crate::frf::resonances_under`]): on a forced record whose force
/// is recorded with noise, the model's response to that noise is not taken for a mode.
pub fn localise_under(
    data: &Measurement,
    outcome: &FitOutcome,
    noise: Option<&[Option<mem::NoisePredictor>]>,
) -> Localisation {
    let residual = outcome.first().residual();
    let (k, p) = (data.n_samples(), data.n_outputs());
    let weights = &outcome.first().weights;
    let total: f64 =
        (0..p).map(|o| (0..k).map(|t| (weights[o] * residual[(t, o)]).powi(2)).sum::<f64>()).sum();
    let third = k / 3;
    let outputs: Vec<OutputDiscrepancy> = (0..p)
        .map(|o| {
            let series: Vec<f64> = (0..k).map(|t| residual[(t, o)]).collect();
            let rms = |s: &[f64]| (s.iter().map(|v| v * v).sum::<f64>() / s.len().max(1) as f64).sqrt();
            let share =
                series.iter().map(|v| (weights[o] * v).powi(2)).sum::<f64>() / total.max(f64::MIN_POSITIVE);
            OutputDiscrepancy {
                name: data.names()[o].clone(),
                share,
                rms: rms(&series),
                early_to_late: rms(&series[..third]) / rms(&series[k - third..]).max(f64::MIN_POSITIVE),
                whiteness_p: ljung_box(&series, 20).1,
            }
        })
        .collect();
    let windows = (0..10)
        .map(|w| {
            let (a, b) = (w * k / 10, (w + 1) * k / 10);
            let share: f64 = (0..p)
                .map(|o| (a..b).map(|t| (weights[o] * residual[(t, o)]).powi(2)).sum::<f64>())
                .sum::<f64>()
                / total.max(f64::MIN_POSITIVE);
            (data.start() + a as f64 * data.interval(), data.start() + b as f64 * data.interval(), share)
        })
        .collect();
    let first: Vec<f64> = (0..k).map(|t| data.values()[(t, 0)]).collect();
    // A decrement is a free decay's: a forced record's half cycles follow its input.
    let driven = data.inputs().is_some();
    let peaks = if driven { Vec::new() } else { half_cycle_peaks(&first) };
    let noise_floor = 5.0 * outputs[0].rms.min(peaks.first().copied().unwrap_or(0.0) * 0.05);
    let decrement_vs_amplitude: Vec<(f64, f64)> = peaks
        .windows(2)
        .filter(|w| w[0] > noise_floor && w[1] > noise_floor)
        .map(|w| (0.5 * (w[0] + w[1]), (w[0] / w[1]).ln()))
        .collect();
    let decrement_trend = trend(&decrement_vs_amplitude);
    let modes_of = |series: faer::Mat<f64>, order: usize| -> Vec<era::EraMode> {
        match era::identify(series.as_ref(), data.interval(), order) {
            Ok(r) => {
                let mut modes: Vec<era::EraMode> = r
                    .modes
                    .into_iter()
                    .filter(|m| m.physical && m.damping_ratio < 0.5 && m.contribution > 0.05)
                    .collect();
                modes.sort_by(|a, b| b.contribution.total_cmp(&a.contribution));
                modes
            }
            Err(_) => Vec::new(),
        }
    };
    // A free decay is a response ERA reads as it is; a forced record's resonances are the peaks
    // of its frequency response from the measured inputs (`frf`).
    let weighted = |of: &dyn Fn(usize, usize) -> f64| faer::Mat::from_fn(k, p, |t, o| weights[o] * of(t, o));
    let (of_residual, of_data) =
        (weighted(&|t, o| residual[(t, o)]), weighted(&|t, o| data.values()[(t, o)]));
    let (residual_modes, data_modes) = match driven {
        // One scan of the inputs' trial modes serves both series.
        true => match crate::frf::resonances_under(
            data,
            &[
                crate::frf::Scanned { series: &of_residual, noise },
                crate::frf::Scanned { series: &of_data, noise: None },
            ],
        ) {
            Some(mut both) => {
                let of_data = both.pop().unwrap_or_default();
                (both.pop().unwrap_or_default(), of_data)
            }
            None => (Vec::new(), Vec::new()),
        },
        false => (modes_of(of_residual, 10), modes_of(of_data, 16)),
    };
    let mut findings = Vec::new();
    if let Some(o) = outputs.iter().max_by(|a, b| a.share.total_cmp(&b.share)) {
        findings.push(format!("output `{}` carries {:.0} % of the error", o.name, 100.0 * o.share));
    }
    for o in &outputs {
        if o.whiteness_p < 1e-3 {
            findings.push(format!(
                "the `{}` residual is not white (Ljung–Box p = {:.1e})",
                o.name, o.whiteness_p
            ));
        }
        // Where a forced record's residual lies follows where the input drives it.
        if driven {
            continue;
        }
        if o.early_to_late > 3.0 {
            findings.push(format!(
                "the `{}` residual is {:.1}× larger early in the record than late (amplitude-dependent)",
                o.name, o.early_to_late
            ));
        } else if o.early_to_late < 1.0 / 3.0 {
            findings.push(format!(
                "the `{}` residual grows toward the end of the record (small-amplitude effect)",
                o.name
            ));
        }
    }
    if decrement_vs_amplitude.len() >= 3 {
        if decrement_trend > 1.0 {
            findings.push("damping grows with amplitude (drag-like)".into());
        } else if decrement_trend < -1.0 {
            findings.push("damping grows as the motion dies out (dry-friction-like)".into());
        }
    }
    for m in residual_modes.iter().take(2) {
        findings.push(format!(
            "the residual holds a {:.3} Hz mode ({:.1} % damping)",
            m.frequency_hz,
            100.0 * m.damping_ratio
        ));
    }
    Localisation {
        nyquist_hz: 0.5 / data.model_grid().1,
        outputs,
        windows,
        decrement_vs_amplitude,
        decrement_trend,
        residual_modes,
        data_modes,
        appendages: Vec::new(),
        findings,
    }
}

/// Slope of y on x, divided by the mean of y.
fn trend(points: &[(f64, f64)]) -> f64 {
    let n = points.len() as f64;
    if points.len() < 3 {
        return 0.0;
    }
    let (mx, my) = (points.iter().map(|p| p.0).sum::<f64>() / n, points.iter().map(|p| p.1).sum::<f64>() / n);
    let sxy: f64 = points.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let sxx: f64 = points.iter().map(|p| (p.0 - mx).powi(2)).sum();
    if sxx == 0.0 || my == 0.0 { 0.0 } else { sxy / sxx / my }
}
