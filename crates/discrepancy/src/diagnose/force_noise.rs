//! A forced record's recorded force is measured too, and its noise drives the model
//! ([`crate::frf::input_noise`]): an effect that acts through the dynamics must remove more of the
//! residual than a share of what that noise puts there.
//!
//! The share is [`FORCE_NOISE_SHARE`]. Of what the force's noise puts into the residual, an
//! effect that only damps or detunes the model's response to it removes a part — the part it
//! can reach; a missing effect removes what it put there itself, however large. A sensor's
//! effect acts on its readings, not through the dynamics, and cannot take up a response; it is
//! not screened.
//!
//! What the noise accounts for is read from the residual each refit leaves, not the
//! reference's: a missing effect at the driven floor leaves a residual shaped like the force's
//! noise in the reference (both pass through the same frequency response), and only its refit
//! shows what is left once it is explained.
//!
//! The share was set on two development draws of `studies/structure --forced`, with 1 % and
//! 2 % noise on the recorded force (docs/diagnose.md, "Noise on the recorded force"): the
//! frictions, drags and springs named on their nulls removed 0.01–0.48 of what the noise
//! accounts for; the catalog effects named right removed above 1, but for two weak drags (0.81,
//! kept, and 0.41, lost).

use super::catalog::Trial;
use super::{Candidate, Verdict};
use crate::frf::{InputNoise, input_noise};
use mem::Measurement;
use models::FitOutcome;

/// The least share of what the recorded force's noise accounts for in a refit's residual
/// ([`InputNoise::residual_power`]) which an effect acting through the dynamics must remove.
pub const FORCE_NOISE_SHARE: f64 = 0.5;

/// The weighted sum of squares of a fit's residual.
fn weighted_error(outcome: &FitOutcome) -> f64 {
    let first = outcome.first();
    let residual = first.residual();
    (0..residual.ncols()).map(|o| first.weights[o].powi(2) * residual.col(o).squared_norm_l2()).sum()
}

/// The noise on `data`'s recorded inputs, read from the best-fitting of the reference and the
/// candidates (the residual closest to the noise itself, as for the measurement model); then
/// each candidate still standing whose effect acts through the dynamics and removes less than
/// [`FORCE_NOISE_SHARE`] of what that noise accounts for is set aside
/// ([`Verdict::WithinForceNoise`]). `None` (and nothing set aside) for a record without inputs.
pub(super) fn screen(
    candidates: &mut [Candidate],
    trials: &[Trial],
    reference: &FitOutcome,
    data: &Measurement,
) -> Option<InputNoise> {
    data.inputs()?;
    let best = candidates
        .iter()
        .filter_map(|c| c.outcome.as_ref())
        .chain(std::iter::once(reference))
        .map(|o| (o, weighted_error(o)))
        .min_by(|a, b| a.1.total_cmp(&b.1))?
        .0;
    let noise = noise_in(best, data)?;
    let before = weighted_error(reference);
    for (candidate, trial) in candidates.iter_mut().zip(trials) {
        let Some(outcome) = candidate.outcome.as_ref() else { continue };
        if candidate.verdict != Verdict::Outscored || trial.output.is_some() {
            continue;
        }
        // What the force's noise accounts for in what this refit leaves: a refit that only
        // takes up part of the model's response to that noise leaves the rest of it.
        let Some(left) = noise_in(outcome, data) else { continue };
        let removed = before - weighted_error(outcome);
        if removed < FORCE_NOISE_SHARE * left.residual_power {
            candidate.verdict = Verdict::WithinForceNoise;
        }
    }
    Some(noise)
}

/// The inputs' noise as a fit's weighted residual shows it.
fn noise_in(outcome: &FitOutcome, data: &Measurement) -> Option<InputNoise> {
    let first = outcome.first();
    let (k, p) = (first.final_sensed.nrows(), first.final_sensed.ncols());
    let residual = first.residual();
    let simulated = faer::Mat::from_fn(k, p, |t, o| first.weights[o] * first.final_sensed[(t, o)]);
    let weighted = faer::Mat::from_fn(k, p, |t, o| first.weights[o] * residual[(t, o)]);
    input_noise(data, &simulated, &weighted)
}
