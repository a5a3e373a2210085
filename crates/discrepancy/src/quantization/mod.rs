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
//!   second, where its amplitude must also be a rounding's, Δ/π ([`sawtooth()`]). Its samples run
//!   while the fitted response is more than ten residual σ from rest, not only while the
//!   readings swing beyond a tenth of their range: a large signal crosses many steps long after
//!   that. Where the model misses by more than Δ/2π (it lacks another effect, say), the phase of
//!   x̂ is scrambled; a second reading corrects x̂ by a local quadratic smooth of the residual,
//!   which follows the smooth misfit but not the sawtooth that changes with every step crossed.
//!   If neither finds it, both are made again about x̂ corrected by the fitted model's own
//!   modal decays ([`modal_corrected`], [`detect_about`]): a decimated fit never sees the modes
//!   above its Nyquist frequency, and their misfit in the raw record is too fast for the local
//!   smooth.
//!
//! Either way the step matters only if it is comparable to the noise or larger (a record
//! printed with six decimals lies on a 10⁻⁶ lattice too); [`Lattice::matters`] says so.

mod correction;
mod lattice;
mod sawtooth;

pub use correction::modal_corrected;
pub use lattice::{blurred, exact};
pub use sawtooth::sawtooth;

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

/// The samples taken while the signal moves: from the start to the last sample farther from
/// the rest value (the median of the last tenth of the record) than a tenth of the largest
/// excursion (its ⌈n/200⌉-th largest, so that a glitch does not set it) whose neighbour is
/// farther too. Motion lasts; a stray reading in the settled tail — a glitch, a noise spike —
/// stands alone, and would otherwise stretch the window over the tail. Chosen by time, not by
/// value, so that no cut in value shapes their distribution.
pub fn moving(values: &[f64]) -> Vec<f64> {
    values[..moving_end(values)].to_vec()
}

/// The end (exclusive) of the samples [`moving`] keeps (the last excursion, if none has an
/// excursion beside it; 0 if the record does not move).
fn moving_end(values: &[f64]) -> usize {
    let Some(rest) = rest_value(values) else { return 0 };
    let excursions: Vec<f64> = values.iter().map(|v| (v - rest).abs()).collect();
    let reach = extent(&excursions).map_or(0.0, |(_, high)| high);
    let moves: Vec<bool> = excursions.iter().map(|e| *e > 0.1 * reach).collect();
    let sustained = (0..moves.len())
        .rev()
        .find(|&k| moves[k] && ((k > 0 && moves[k - 1]) || moves.get(k + 1).copied().unwrap_or(false)));
    sustained.or_else(|| moves.iter().rposition(|m| *m)).map_or(0, |k| k + 1)
}

/// The range of a record's readings without its few most extreme ones: the ⌈n/200⌉-th smallest
/// and largest values (the 0.5th and 99.5th percentiles). A glitch — a reading far outside the
/// signal, a spike or a dropout — then neither sets the scale a lattice is looked for on nor
/// decides where the signal stops moving (`None` if `values` is empty).
fn extent(values: &[f64]) -> Option<(f64, f64)> {
    let n = values.len();
    if n == 0 {
        return None;
    }
    let k = n.div_ceil(200) - 1;
    let mut sorted = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    Some((sorted[k], sorted[n - 1 - k]))
}

/// The rest value of a record: the median of its last tenth (`None` if it is empty).
fn rest_value(values: &[f64]) -> Option<f64> {
    let n = values.len();
    if n == 0 {
        return None;
    }
    let mut tail: Vec<f64> = values[n - (n / 10).max(1)..].to_vec();
    tail.sort_by(f64::total_cmp);
    Some(tail[tail.len() / 2])
}

/// The maximiser of a unimodal `f` on [a, b] by `iterations` steps of golden-section search
/// (the midpoint of the last bracket).
fn golden_max(f: impl Fn(f64) -> f64, mut a: f64, mut b: f64, iterations: usize) -> f64 {
    for _ in 0..iterations {
        let m1 = b - (b - a) / 1.618_033_988_75;
        let m2 = a + (b - a) / 1.618_033_988_75;
        if f(m1) > f(m2) {
            b = m2;
        } else {
            a = m1;
        }
    }
    0.5 * (a + b)
}

/// The batch means the blurred and sawtooth statistics are taken over: without a lattice their
/// z is Student's t with `BATCHES − 1` degrees of freedom.
pub const BATCHES: usize = 20;

/// The z a batch-means statistic needs for a false-alarm probability `alpha` (one-sided),
/// from Student's t with `BATCHES − 1` degrees of freedom (8, the blurred test's bar, if the
/// distribution cannot be had).
pub fn batch_threshold(alpha: f64) -> f64 {
    use statrs::distribution::{ContinuousCDF, StudentsT};
    StudentsT::new(0.0, 1.0, (BATCHES - 1) as f64).map_or(8.0, |t| t.inverse_cdf(1.0 - alpha))
}

/// The z each reading of a lattice needs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Thresholds {
    /// The blurred lattice's confirmation.
    pub blurred: f64,
    /// The sawtooth's confirmation, for each response it is read about.
    pub sawtooth: f64,
}

/// The mean of `projections` and its z over the batch-means standard error ([`BATCHES`]
/// batches, so that coloured noise does not pass for evidence).
fn batch_z(projections: &[f64]) -> (f64, f64) {
    let batches = BATCHES;
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

/// The lattice of one sensor's raw readings, if there is one: exact first, else blurred, else
/// the sawtooth of the residual about `fitted` (the fitted model's output at the same samples).
/// `threshold` is the z the blurred and sawtooth statistics need.
pub fn detect(values: &[f64], fitted: &[f64], threshold: f64) -> Option<Lattice> {
    detect_about(values, &[fitted], Thresholds { blurred: threshold, sawtooth: threshold })
}

/// [`detect`] with several responses the sawtooth may be read about, tried in turn (the fitted
/// response, then the same corrected by [`modal_corrected`]): each correction fits the noise a
/// little too, so a response that finds the sawtooth is not traded for a later one. The
/// smallest step searched is half the residual's RMS about the response it is smallest about:
/// about the fitted response alone it also holds the model's misfit (the modes above a
/// decimated fit's Nyquist, say), which would put the floor above a lattice the noise leaves
/// plain. The tests' bars were calibrated from half the true noise σ (`examples/lattice_null.rs`),
/// no higher than this floor.
pub fn detect_about(values: &[f64], responses: &[&[f64]], thresholds: Thresholds) -> Option<Lattice> {
    let n = values.len().max(1) as f64;
    let variances: Vec<f64> = responses
        .iter()
        .map(|r| values.iter().zip(r.iter()).map(|(y, x)| (y - x).powi(2)).sum::<f64>() / n)
        .collect();
    let residual_variance = *variances.first()?;
    if let Some((step, levels)) = exact(values, 10) {
        let noise = (residual_variance - step * step / 12.0).max(0.0).sqrt();
        return Some(Lattice { step, form: LatticeForm::Exact { levels }, noise });
    }
    let range = values.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    let misfit = variances.iter().copied().fold(residual_variance, f64::min);
    let min_step = (0.5 * misfit.sqrt()).max(1e-6 * range);
    if let Some((step, z, samples, noise)) = blurred(values, min_step, thresholds.blurred) {
        return Some(Lattice { step, form: LatticeForm::Blurred { z, samples }, noise });
    }
    responses.iter().find_map(|response| sawtooth(values, response, min_step, thresholds.sawtooth))
}
