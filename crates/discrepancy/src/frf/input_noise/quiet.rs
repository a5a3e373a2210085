//! A recorded input's noise read from its own quiet band ([`quiet_level`]).

use crate::frf::spectra;

/// A recorded input's bin is quiet where its level lies below this share of its largest
/// ([`super::RecordedInputs::quiet_levels`]): 30 dB under the band it excites.
pub const QUIET: f64 = 1e-3;

/// The least share of a recorded input's bins that must be quiet for their level to be read as
/// its noise's.
pub const QUIET_BINS: f64 = 0.125;

/// The quiet bins' level must be flat — the median of the lower-frequency half of them within
/// this factor of the upper half's — to be read as white noise, not a falling tail of the force.
pub const QUIET_FLATNESS: f64 = 1.5;

/// Quiet bins above this multiple of their median are the force's leakage, not its noise.
pub const QUIET_OUTLIER: f64 = 3.0;

/// A recorded input's noise variance read from its quiet band: from its auto-spectrum `suu` (Σ
/// over `segments` segments of |U_b|², bins 0…L/2 − 1 of a segment of `length`), the mean level
/// of its bins below [`QUIET`] of its largest (DC aside; those above [`QUIET_OUTLIER`] times
/// their median left out), over segments and window power — the variance of white noise with
/// that level in every bin. `None` unless at least [`QUIET_BINS`] of its bins are quiet and
/// their level is flat: the lower-frequency half of them within [`QUIET_FLATNESS`] of the upper
/// half, by their medians.
///
/// A transducer's noise is white across the record's band; the force a shaker applies is not. A
/// chirp's or a band-limited force's bins above its band hold the recorded force's noise alone,
/// flat, tens of dB under the band it excites — what an experimenter reads a transducer's noise
/// from. Read from the residual instead, the noise is what the model's response to it leaves
/// after the fit, and an output-error fit takes up part of it: at a lightly damped mode that
/// response has only a few degrees of freedom over a record of seconds, and the stiffnesses and
/// damping bend to match them where the force's own response there is brief (a chirp passes the
/// mode once). On draw 20261353 the noise so read on chirps had a median of 0.65 % against the
/// truth's 1 % (0.28–0.63 % on its seven white chirp nulls by H₁; 0.00–0.97 % through the
/// model's exact response); on one of them (`B_white_54`, read 0.00 % through the exact
/// response) the residual of the fitted model held, at 2–6 Hz where its first mode lies, 39–51 %
/// less than 1 % of noise on the force and the sensors' floor put there (an independent scipy
/// read of the fitted model's exact response, `studies/structure/quiet_read.py`). Read from the
/// quiet band, the seven read 0.97–1.03 %. A force as broad as the record's band, or one whose
/// band falls off without a flat floor (a low-passed noise's tail), has no quiet band,
/// and its noise is read from the residual.
pub(super) fn quiet_level(suu: &[f64], segments: usize, length: usize) -> Option<f64> {
    let largest = suu.iter().copied().filter(|l| l.is_finite()).fold(0.0, f64::max);
    if segments == 0 || suu.len() < 2 || largest <= 0.0 {
        return None;
    }
    let quiet: Vec<f64> =
        suu.iter().skip(1).copied().filter(|l| l.is_finite() && *l < QUIET * largest).collect();
    if (quiet.len() as f64) < QUIET_BINS * (suu.len() - 1) as f64 || quiet.len() < 4 {
        return None;
    }
    // Flat: the median of the lower-frequency half of the quiet bins within QUIET_FLATNESS of
    // the upper half's (medians, so that the force's leakage at its band's edges does not count).
    let median = |x: &[f64]| {
        let mut sorted = x.to_vec();
        sorted.sort_by(f64::total_cmp);
        sorted[sorted.len() / 2]
    };
    let half = quiet.len() / 2;
    let (low, high) = (median(&quiet[..half]), median(&quiet[half..]));
    if !(low > 0.0 && high > 0.0) || low.max(high) > QUIET_FLATNESS * low.min(high) {
        return None;
    }
    // The level: the mean of the quiet bins, the leakage left out — bins above QUIET_OUTLIER
    // times their median (white noise's Welch levels exceed three times their median about once
    // in 10⁴ bins).
    let cut = QUIET_OUTLIER * median(&quiet);
    let quiet: Vec<f64> = quiet.into_iter().filter(|l| *l <= cut).collect();
    let mean = |x: &[f64]| x.iter().sum::<f64>() / x.len() as f64;
    Some(mean(&quiet) / (segments as f64 * spectra::window_power(length)))
}
