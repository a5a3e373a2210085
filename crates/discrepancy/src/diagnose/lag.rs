//! A sensor read late, set against a named effect (step 7 of [module `diagnose`](mod@super)):
//! one output's channel reading its sensor τ_s behind the others, y_i(t − τ_s) — a multiplexed
//! converter that samples its channels in turn, an anti-alias filter on one channel (its group
//! delay), a time stamp taken before the conversion. Not physics, and not in the catalog. A
//! strain gauge read a few milliseconds late leaves a residual −τ_s·ẏ that is largest where
//! the beam moves fastest, at the release: a limit on the servo's first push, or a loop delay,
//! imitates it while the model's own parameters take up the rest; one lag that explains the
//! record as well is the simpler answer.
//!
//! Of the p outputs one is refitted ([`screened`]): the one whose rate of change best explains
//! the reference's residual, by the whitened least squares of module `crosstalk` (the rate from
//! central differences of the fitted output, a screen, not the refit) with a positive lag
//! (r ≈ −τ_s·ẏ; a reading cannot precede its signal). Refitted, the lag is the plant's
//! `SensorLag`, Padé(1,1) in the state space, from the screen's estimate, within (10⁻³, 1)
//! sample intervals (a skew of a sampled channel stays within its interval); the reference's
//! parameters are freed beside it. It is charged ln p for being the best of p.
//!
//! Only the slewing rig's model carries a lag (a structure's outputs have no `SensorLag`): for
//! a structure the rival is not tried.

use super::answer::AddedTerm;
use super::crosstalk::regression;
use super::evidence::NoiseModel;
use super::mismatch::RivalTrial;
use faer::Mat;
use models::{FitOutcome, Model};

/// The rate of change of each column of `y` sampled every `interval` seconds: central
/// differences inside, one-sided at the ends (zero for fewer than two samples).
fn rates(y: &Mat<f64>, interval: f64) -> Mat<f64> {
    let n = y.nrows();
    Mat::from_fn(n, y.ncols(), |k, c| {
        if n < 2 {
            return 0.0;
        }
        let (before, after) = (k.saturating_sub(1), (k + 1).min(n - 1));
        (y[(after, c)] - y[(before, c)]) / ((after - before) as f64 * interval)
    })
}

/// The lag to refit as a rival (see the module): the output whose rate best explains the
/// reference's residual with a positive lag, added at the screen's estimate (clamped into its
/// range) and refitted within (10⁻³, 1) sample intervals. None for a structure, for a record
/// of fewer than three samples, or when no output's residual leans on its rate with a lag.
/// (A model that already reads that sensor late cannot take a second lag there: the rival
/// search drops the trial when adding its effect fails.)
pub(super) fn screened(reference: &FitOutcome, noise: &NoiseModel, interval: f64) -> Option<RivalTrial> {
    let Model::Slewing(model) = &reference.fitted else { return None };
    let first = reference.first();
    let (residual, fitted) = (first.residual(), &first.final_outputs);
    if fitted.nrows() < 3 || !(interval.is_finite() && interval > 0.0) {
        return None;
    }
    let rate = rates(fitted, interval);
    let bounds = (1e-3 * interval, interval);
    let (i, lag, _) = (0..residual.ncols())
        .map(|i| {
            let (gain, g) = regression(&residual, &rate, i, i, noise.rho[i]);
            (i, -g, gain)
        })
        .filter(|&(_, lag, gain)| lag > 0.0 && gain > 0.0)
        .max_by(|a, b| a.2.total_cmp(&b.2))?;
    let sensor = *model.sensors().get(i)?;
    let start = lag.clamp(2.0 * bounds.0, 0.5 * bounds.1);
    Some(RivalTrial {
        name: plant::ParamId::Lag(sensor).name(),
        bounds,
        adds: Some((
            plant::Effect::SensorLag { sensor, lag: start }.into(),
            AddedTerm::Lag { output: sensor.output_name().into() },
        )),
        penalty: (residual.ncols() as f64).ln(),
    })
}

#[cfg(test)]
mod tests {
    use super::rates;
    use faer::Mat;

    /// Central differences are exact on a quadratic inside, one-sided at the ends.
    #[test]
    fn rates_are_the_differences_of_the_samples() {
        let y = Mat::from_fn(5, 1, |k, _| (k as f64 * 0.5).powi(2));
        let r = rates(&y, 0.5);
        // y = t², ẏ = 2t at t = 0.5, 1.0, 1.5 inside.
        for k in 1..4 {
            assert!((r[(k, 0)] - 2.0 * 0.5 * k as f64).abs() < 1e-12, "{k}: {}", r[(k, 0)]);
        }
        assert!((r[(0, 0)] - 0.5).abs() < 1e-12 && (r[(4, 0)] - 3.5).abs() < 1e-12);
    }
}
