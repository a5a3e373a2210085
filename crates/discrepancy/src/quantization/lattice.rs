//! The lattice in the raw readings themselves: exact (noise before the quantizer) or blurred
//! (noise after it), found on the first half of the moving samples and confirmed on the second.

use super::{batch_z, extent, golden_max, moving};

/// The levels the moving samples must occupy for a blurred lattice to be confirmed on them
/// ([`occupied_levels`]).
const MIN_LEVELS: usize = 4;

/// The levels c + jΔ of a lattice of phase φ (c = φΔ/2π) that hold at least a two-hundredth of
/// `values` (and at least three of them), each reading counted at its nearest level.
fn occupied_levels(values: &[f64], step: f64, phase: f64) -> usize {
    let offset = phase / (2.0 * std::f64::consts::PI);
    let mut levels: Vec<i64> = values.iter().map(|v| (v / step - offset).round() as i64).collect();
    levels.sort_unstable();
    let enough = (values.len() / 200).max(3);
    levels.chunk_by(|a, b| a == b).filter(|run| run.len() >= enough).count()
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

/// A blurred lattice, found on the first half of the moving samples and confirmed on the
/// second: the step Δ maximising R over the first half (from `min_step` to a fortieth of their
/// range, so that the signal's own distribution is smooth on the scale of a step; then the
/// largest multiple of it that keeps R), and the lattice's phase φ; on the second half, the
/// mean of cos(2πy/Δ − φ), which is 0 without a lattice, over its standard error by batch means
/// (20 batches, so that coloured noise does not pass for evidence). A lattice that is a trace
/// of the signal's distribution in one half (its turning points, its approach to rest) does
/// not hold its phase in the other, where the amplitudes differ.
///
/// The range is taken without the few most extreme readings (the ⌈n/200⌉ at each end), and
/// the moving samples must occupy at least four levels, each holding a two-hundredth of them
/// (and at least three): a glitch far outside the signal, or a burst of them, would otherwise
/// stretch the range so that every other reading lies within one "step" of range/8, a lattice
/// of two levels that holds its phase anywhere.
///
/// Returns (step, z, samples confirmed on, blur σ) if z ≥ `threshold`.
pub fn blurred(values: &[f64], min_step: f64, threshold: f64) -> Option<(f64, f64, usize, f64)> {
    let samples = moving(values);
    let n = samples.len();
    let (first, second) = samples.split_at(n / 2);
    let (lo, hi) = extent(&samples)?;
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
    let mut step = golden_max(|s| rayleigh(first, s), best.1 / ratio, best.1 * ratio, 60);
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
    // A lattice is seen while the signal crosses its levels: readings that keep to a level or
    // two (all but some glitches, say) crowd there whatever the quantizer. (The confirming half
    // alone may hold only the last few levels of a coarse quantizer's approach to rest.)
    if occupied_levels(&samples, step, phase) < MIN_LEVELS {
        return None;
    }
    let projections: Vec<f64> =
        second.iter().map(|v| (2.0 * std::f64::consts::PI * v / step - phase).cos()).collect();
    let (mean, z) = batch_z(&projections);
    let blur = step / (2.0 * std::f64::consts::PI) * (-2.0 * mean.clamp(1e-300, 1.0).ln()).sqrt();
    (z >= threshold).then_some((step, z, second.len(), blur))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::quantization::{LatticeForm, Thresholds, detect, detect_about};
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
    fn a_glitch_is_not_a_lattice_and_does_not_hide_one() {
        // One reading of a continuous record replaced by a glitch far outside the signal: the
        // rest of the readings lie within one "step" of range/8, which would make them a
        // lattice of two levels. Readings that do not cross several steps are no lattice.
        let mut rng = rand::rngs::StdRng::seed_from_u64(11);
        let clean = decay(3000);
        let noisy: Vec<f64> =
            clean.iter().map(|v| v + 0.002 * rng.sample::<f64, _>(rand_distr::StandardNormal)).collect();
        for (at, glitch) in [(1400, 1000.0), (1400, 10.0), (2500, -30.0), (5, 50.0)] {
            let mut y = noisy.clone();
            y[at] = glitch;
            assert!(blurred(&y, 1e-3, 8.0).is_none(), "glitch {glitch} at {at}");
            assert!(detect(&y, &clean, 8.0).is_none_or(|l| !l.matters()), "glitch {glitch} at {at}");
        }
        // A burst: 1 % of the readings drop out to one value, too many to be left out of the
        // range; they and the signal occupy two levels.
        let mut y = noisy.clone();
        for k in 0..30 {
            y[17 + 100 * k] = 10.0;
        }
        assert!(blurred(&y, 1e-3, 8.0).is_none(), "a burst of dropouts");
        // A coarse ADC (noise before the rounding) on a slew from 0.5 to rest: nine levels, too
        // few for an exact lattice, and the confirming half holds only the last two or three;
        // the moving samples as a whole occupy all nine.
        let step = 0.0756;
        let slew: Vec<f64> = (0..3000)
            .map(|k| {
                let t = k as f64 / 128.0;
                let v = 0.5 * (-t / 0.6).exp() * (1.0 + 0.3 * (9.0 * t).sin());
                step * ((v + 0.001 * rng.sample::<f64, _>(rand_distr::StandardNormal)) / step).round()
            })
            .collect();
        assert!(exact(&slew, 10).is_none());
        let (found, ..) = blurred(&slew, 1e-3, 8.0).expect("the coarse lattice");
        let multiple = step / found;
        assert!((multiple - multiple.round()).abs() < 0.01, "{found}");
        // A true blurred lattice keeps being found with a glitch in it, wherever the glitch is.
        let step = 0.02;
        let after: Vec<f64> = clean
            .iter()
            .map(|v| step * (v / step).round() + 0.002 * rng.sample::<f64, _>(rand_distr::StandardNormal))
            .collect();
        for (at, glitch) in [(1400, 1000.0), (5, 50.0)] {
            let mut y = after.clone();
            y[at] = glitch;
            let (found, ..) = blurred(&y, 1e-3, 8.0).unwrap_or_else(|| panic!("glitch {glitch} at {at}"));
            assert!((found / step - 1.0).abs() < 0.01, "{found}");
        }
    }

    #[test]
    fn a_stray_reading_in_the_settled_tail_does_not_stretch_the_moving_window() {
        // The decay's peaks fall below a tenth of its reach (its 15th largest excursion, 0.43)
        // after k ≈ 950 and it sits at rest after that; a reading or two at a fifth of the reach,
        // each alone, late in the tail are not motion.
        let mut rng = rand::rngs::StdRng::seed_from_u64(17);
        let noisy: Vec<f64> = decay(3000)
            .iter()
            .map(|v| v + 0.002 * rng.sample::<f64, _>(rand_distr::StandardNormal))
            .collect();
        let settled = super::super::moving(&noisy).len();
        assert!((850..=1100).contains(&settled), "{settled}");
        for stray in [vec![2500], vec![2990], vec![1800, 2700]] {
            let mut y = noisy.clone();
            for &k in &stray {
                y[k] += 0.1;
            }
            let end = super::super::moving(&y).len();
            assert!((850..=1100).contains(&end), "{stray:?}: {end}");
        }
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

    #[test]
    fn a_misfit_the_modal_correction_removes_does_not_hide_a_finer_lattice() {
        // A fast mode (1.3 rad/sample, above a decimated fit's Nyquist) the fitted response
        // misses: the residual about the fit is 0.04 RMS, so a search from half of it would
        // start above the 0.01 step. The corrected response holds the mode; about it the
        // residual is the quantizer and the noise, and the step is searched from there.
        let mut rng = rand::rngs::StdRng::seed_from_u64(23);
        let step = 0.01;
        let slow = decay(3000);
        let exact_response: Vec<f64> = slow
            .iter()
            .enumerate()
            .map(|(k, v)| v + 0.1 * (-(k as f64) / 2000.0).exp() * (1.3 * k as f64).cos())
            .collect();
        let readings: Vec<f64> = exact_response
            .iter()
            .map(|v| step * (v / step).round() + 0.002 * rng.sample::<f64, _>(rand_distr::StandardNormal))
            .collect();
        let bars = Thresholds { blurred: 8.0, sawtooth: 8.0 };
        let alone = detect_about(&readings, &[&slow], bars);
        assert!(alone.is_none(), "about the fit alone the search starts above the step: {alone:?}");
        let lattice = detect_about(&readings, &[&slow, &exact_response], bars).expect("the lattice");
        assert!((lattice.step / step - 1.0).abs() < 0.01, "{}", lattice.step);
        assert!(matches!(lattice.form, LatticeForm::Blurred { .. }));
    }
}
