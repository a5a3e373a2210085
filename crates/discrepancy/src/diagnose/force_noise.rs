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
use crate::frf::{InputNoise, RecordedInputs};
use faer::Mat;
use mem::Measurement;
use models::FitOutcome;

/// The least share of what the recorded force's noise accounts for in a refit's residual
/// ([`InputNoise::residual_power`]) which an effect acting through the dynamics must remove.
pub const FORCE_NOISE_SHARE: f64 = 0.5;

/// A fit's weighted simulated outputs and residual (K × p), as [`RecordedInputs::noise`]
/// reads them, and the residual's weighted sum of squares.
struct Weighted {
    simulated: Mat<f64>,
    residual: Mat<f64>,
    error: f64,
}

impl Weighted {
    fn of(outcome: &FitOutcome) -> Self {
        let first = outcome.first();
        let (k, p) = (first.final_sensed.nrows(), first.final_sensed.ncols());
        let raw = first.residual();
        let residual = Mat::from_fn(k, p, |t, o| first.weights[o] * raw[(t, o)]);
        let simulated = Mat::from_fn(k, p, |t, o| first.weights[o] * first.final_sensed[(t, o)]);
        let error = residual.squared_norm_l2();
        Self { simulated, residual, error }
    }
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
    let inputs = RecordedInputs::of(data, data.n_samples())?;
    let before = Weighted::of(reference);
    let fits: Vec<Option<Weighted>> =
        candidates.iter().map(|c| c.outcome.as_ref().map(Weighted::of)).collect();
    let best =
        fits.iter().flatten().chain(std::iter::once(&before)).min_by(|a, b| a.error.total_cmp(&b.error))?;
    let noise = inputs.noise(&best.simulated, &best.residual)?;
    for ((candidate, trial), fit) in candidates.iter_mut().zip(trials).zip(&fits) {
        let Some(fit) = fit else { continue };
        if candidate.verdict != Verdict::Outscored || trial.output.is_some() {
            continue;
        }
        // What the force's noise accounts for in what this refit leaves: a refit that only
        // takes up part of the model's response to that noise leaves the rest of it.
        let Some(left) = inputs.noise(&fit.simulated, &fit.residual) else { continue };
        if before.error - fit.error < FORCE_NOISE_SHARE * left.residual_power {
            candidate.verdict = Verdict::WithinForceNoise;
        }
    }
    Some(noise)
}
