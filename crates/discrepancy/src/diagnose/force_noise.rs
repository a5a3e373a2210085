//! A forced record's recorded force is measured too, and its noise drives the model
//! ([`crate::frf::input_noise`]): an effect that acts through the dynamics must remove more of the
//! residual than a share of what that noise puts there.
//!
//! The share is [`FORCE_NOISE_SHARE`]. Of what the force's noise puts into the residual, an
//! effect that only damps or detunes the model's response to it removes a part — the part it
//! can reach; a missing effect removes what it put there itself, however large. A sensor's
//! offset, drift, scale or crosstalk is not screened: an offset or a drift adds to its readings
//! whatever the response, and a scale or a crosstalk takes up almost none of the noise's own
//! response (it multiplies the modelled response, of which the noise's is a small part;
//! [`takes_up_the_response`]).
//!
//! The noise's response is also part of the measurement model ([`predictors`]): coloured by
//! the model's own resonances, it is predictable from its past, and a candidate that matches a
//! part of its realisation gains nothing beyond chance under its own spectrum (docs/diagnose.md,
//! "The force's noise in the measurement model"). The read is held below twice the recorded
//! force's own spectral floor ([`crate::frf::RecordedInputs::ceilings`]).
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
use super::evidence::{NoiseModel, Predictor, autocovariance};
use super::{Candidate, Verdict};
use crate::frf::{InputNoise, NoiseResponse, RecordedInputs};
use faer::Mat;
use mem::Measurement;
use models::FitOutcome;
use plant::EffectKind;

/// The least share of what the recorded force's noise accounts for in a refit's residual
/// ([`InputNoise::residual_power`]) which an effect acting through the dynamics must remove.
pub const FORCE_NOISE_SHARE: f64 = 0.5;

/// The held-out gain (nats) above which the screen sets nothing aside: an effect that predicts
/// held-out blocks this much better than the reference is not taking up the model's response to
/// the force's noise, whatever share of that response it leaves.
///
/// The screen compares powers, the evidence likelihoods. A strong appendage at 17.9 Hz (draw
/// 20261316, `A_appendage_strong_s1`, the fixture `study_appendage_noisy_force`) removed less
/// than half of what the noise accounts for in the residual it leaves — the noise's response at
/// the structure's own modes is large beside the appendage's narrow band — and gained 324 nats
/// held out, where its band is quiet under the noise's spectrum. On the 60 nulls of the two
/// development draws 20261315–16 the stand-ins the screen set aside gained at most 54 nats held
/// out, and wrong stand-ins on effect records at most 88 (drags beside a strong scale on
/// 20261315). The exemption is twice the nulls' largest, rounded up.
///
/// It is a number of nats, set on records of 2,001 samples of two outputs. A stand-in's gain from
/// the model's systematic answer to the noise grows with the record, as a true effect's does;
/// on a much longer record the same screen may let stand-ins through. That is not measured: the
/// study draws one record length.
pub const FORCE_NOISE_EXEMPT: f64 = 110.0;

/// A fit's weighted simulated outputs and residual (K × p), as [`RecordedInputs::noise`]
/// reads them, the residual's weighted sum of squares, and the fits whose exact response to
/// white noise on the inputs the read takes ([`Weighted::noise`]).
struct Weighted<'a> {
    simulated: Mat<f64>,
    residual: Mat<f64>,
    error: f64,
    outcome: &'a FitOutcome,
    fallback: &'a FitOutcome,
}

impl<'a> Weighted<'a> {
    fn of(outcome: &'a FitOutcome, fallback: &'a FitOutcome) -> Self {
        let first = outcome.first();
        let (k, p) = (first.final_sensed.nrows(), first.final_sensed.ncols());
        let raw = first.residual();
        let residual = Mat::from_fn(k, p, |t, o| first.weights[o] * raw[(t, o)]);
        let simulated = Mat::from_fn(k, p, |t, o| first.weights[o] * first.final_sensed[(t, o)]);
        let error = residual.squared_norm_l2();
        Self { simulated, residual, error, outcome, fallback }
    }

    /// The noise on `inputs` as this fit shows it ([`RecordedInputs::noise`]), through the
    /// fitted model's exact response to white noise on its inputs where it has one
    /// ([`exact_response`]) — or, where it has none (an added mode refitted without damping,
    /// which does not decay), the `fallback` model's, the reference's linear one. The response
    /// is computed here, for the fits whose noise is read, not for every candidate screened.
    fn noise(&self, inputs: &RecordedInputs) -> Option<InputNoise> {
        let lags = inputs.segment_length().max(MAX_PREDICTOR_ORDER);
        // A force the fit added bends the model's response to the noise about the response to
        // the force (a strong spring's tangent stiffness): its linear part's exact response is
        // not the noise's, and H₁ of the fit's own simulation reads it.
        let linear = self.outcome.fitted.as_structure().is_none_or(structure::StructureModel::is_linear);
        let response = linear
            .then(|| exact_response(self.outcome, lags).or_else(|| exact_response(self.fallback, lags)))
            .flatten();
        inputs.noise(&self.simulated, &self.residual, response.as_ref())
    }
}

/// The fitted model's exact response to unit white noise on its recorded inputs, its outputs
/// weighted as the fit's, up to `lags` ([`NoiseResponse`]); `None` for a model without a linear
/// state space with inputs (the slewing rig), a decimated record (its inputs are averaged over
/// each interval), inputs recorded in another order than the model's, or a model without a
/// stationary response (a mode that does not decay). The state space is the linear part of the
/// fitted model, its added modes included; an added force or a sensor effect is left out — the
/// noise is small, and it passes through the model about its response to the force.
fn exact_response(outcome: &FitOutcome, lags: usize) -> Option<NoiseResponse> {
    let first = outcome.first();
    let data = &first.data;
    if data.decimation().is_some_and(|d| d.factor() > 1) {
        return None;
    }
    let inputs = data.inputs()?;
    let model = outcome.fitted.as_structure()?;
    if inputs.names() != model.input_names().as_slice() {
        return None;
    }
    let space = model.state_space::<f64>(&model.values()).ok()?;
    NoiseResponse::new(&space, inputs.hold(), data.interval(), &first.weights, lags)
}

/// The noise on `data`'s recorded inputs, read from the best-fitting of the reference and the
/// candidates (the residual closest to the noise itself, as for the measurement model); then
/// each candidate still standing whose effect acts through the dynamics, removes less than
/// [`FORCE_NOISE_SHARE`] of what that noise accounts for and gains at most
/// [`FORCE_NOISE_EXEMPT`] held out is set aside
/// ([`Verdict::WithinForceNoise`]). `None` (and nothing set aside) for a record without inputs.
pub(super) fn screen(
    candidates: &mut [Candidate],
    trials: &[Trial],
    reference: &FitOutcome,
    data: &Measurement,
) -> Option<InputNoise> {
    let inputs = RecordedInputs::of(data, data.n_samples())?;
    let before = Weighted::of(reference, reference);
    let fits: Vec<Option<Weighted>> =
        candidates.iter().map(|c| c.outcome.as_ref().map(|o| Weighted::of(o, reference))).collect();
    let best =
        fits.iter().flatten().chain(std::iter::once(&before)).min_by(|a, b| a.error.total_cmp(&b.error))?;
    let noise = best.noise(&inputs)?;
    let within: Vec<bool> = candidates
        .iter()
        .zip(trials)
        .zip(&fits)
        .map(|((candidate, trial), fit)| {
            let Some(fit) = fit else { return false };
            // What the force's noise accounts for in what this refit leaves: a refit that only
            // takes up part of the model's response to that noise leaves the rest of it.
            candidate.verdict == Verdict::Outscored
                && takes_up_the_response(trial.kind)
                && !candidate.evidence.held_out.is_some_and(|h| h > FORCE_NOISE_EXEMPT)
                && fit
                    .noise(&inputs)
                    .is_some_and(|left| before.error - fit.error < FORCE_NOISE_SHARE * left.residual_power)
        })
        .collect();
    drop(fits);
    for (candidate, within) in candidates.iter_mut().zip(within) {
        if within {
            candidate.verdict = Verdict::WithinForceNoise;
        }
    }
    Some(noise)
}

/// Whether an effect of this kind is screened: every effect acting through the dynamics. A
/// sensor's effect is not: an offset or a drift adds to the readings whatever the response, and
/// a scale (1 + s)·y or a crosstalk y + g·y′ multiplies the modelled response, which the noise's
/// own response is a small part of (at 1 % noise on the recorded force, of the order of a part
/// in 10⁴ of its power).
///
/// Scales were screened until the thirty-fifth session, as a proxy: a scale above 1 gave back,
/// on the noisy-force draw 20261304, the response an output-error fit of the reference had
/// given up (+0.4 % and +0.8 % on a white null and a weak drag). The measurement model since
/// holds the noise's response ([`predictors`]), and the screen set aside true scales of 1 %
/// resolved at 10 σ (draw 20261341, `A_scale_medium_s0`: 0.96 % ± 0.10 %, held out 50 nats) —
/// and on the three noisy-force draws 20261341–43 none of the six medium scales was named with
/// it, four without it and with the other changes of that session (docs/diagnose.md, "The
/// force's noise predicted to its modes' length").
fn takes_up_the_response(kind: EffectKind) -> bool {
    !matches!(
        kind,
        EffectKind::OutputOffset
            | EffectKind::SensorDrift
            | EffectKind::SensorQuantization
            | EffectKind::SensorScale
            | EffectKind::SensorCrosstalk
    )
}

/// The noise on `data`'s recorded force as `best`, the best-fitting model, shows it (the
/// residual closest to the noise itself, as for ρ; the fitted `reference` stands in for `best`'s
/// model where that has no stationary response); `None` for a record without inputs.
pub(super) fn read(best: &FitOutcome, reference: &FitOutcome, data: &Measurement) -> Option<InputNoise> {
    let inputs = RecordedInputs::of(data, best.first().final_sensed.nrows())?;
    Weighted::of(best, reference).noise(&inputs)
}

/// The least order of the noise's predictor on a forced record ([`NoiseModel::predictors`]).
pub const PREDICTOR_ORDER: usize = 20;

/// The largest order of the noise's predictor: the lags of the read's spectrum (half its Welch
/// segment) bound it too.
pub const MAX_PREDICTOR_ORDER: usize = 160;

/// The predictor's order is the least at which its prediction error lies within this share of
/// the largest order's (`predictor_of`).
pub const PREDICTOR_CONVERGED: f64 = 1e-3;

/// The linear predictor of the noise whose one-sided spectrum is `total` (Welch bins), of the
/// least order from [`PREDICTOR_ORDER`] at which its error variance is within
/// [`PREDICTOR_CONVERGED`] of the largest order's (Levinson–Durbin gives every order's at once).
///
/// The model's response to the force's noise rings at lightly damped modes, and its
/// autocovariance lasts as long as they do: a predictor of 20 lags, the maximum-entropy extension
/// of those lags alone, mistook the spectrum far from the modes — most at the lowest frequencies,
/// where a sensor's drift lies. On draw 20261341's `A_drift_medium_s1` (a drift of 4·10⁻⁶ m/s on
/// q1, 1 % noise on the recorded force) the drift gained 50 nats under order 20 and 221 under the
/// true per-output covariance (an independent scipy check with the generator's own noise
/// levels; 206 at order 60, 200 at order 100); the order-20 error variance stood 5–7 % above
/// the limit, order 80 within 0.05 % (docs/diagnose.md, "The force's noise predicted to its
/// modes' length").
fn predictor_of(total: &[f64]) -> Option<Predictor> {
    let lags = MAX_PREDICTOR_ORDER.min(total.len() / 2).max(PREDICTOR_ORDER);
    converged(&autocovariance(total, lags))
}

/// The predictor of the autocovariance `gamma` (lags 0, 1, …) of the least order from
/// [`PREDICTOR_ORDER`] whose error variance lies within [`PREDICTOR_CONVERGED`] of that of the
/// largest order `gamma` holds and is positive definite for (halved down to
/// [`PREDICTOR_ORDER`] until it is); `None` if even that is not.
fn converged(gamma: &[f64]) -> Option<Predictor> {
    let mut lags = gamma.len().checked_sub(1)?;
    // The largest order whose autocovariance is still positive definite.
    let full = loop {
        match Predictor::of_autocovariance(&gamma[..=lags]) {
            Some(p) => break p,
            None if lags > PREDICTOR_ORDER => lags = (lags / 2).max(PREDICTOR_ORDER),
            None => return None,
        }
    };
    let limit = full.error_variance(lags);
    let order = (PREDICTOR_ORDER..=lags)
        .find(|&m| full.error_variance(m) <= (1.0 + PREDICTOR_CONVERGED) * limit)
        .unwrap_or(lags);
    Predictor::of_autocovariance(&gamma[..=order])
}

/// Per output, the predictor of the noise the recorded force's noise and the sensor's leave
/// together ([`NoiseModel::predictors`]): [`Predictor`] of the autocovariance of
/// [`noise_spectrum`] read from the best-fitting model. `None` for an output whose spectrum holds
/// none of the force's noise (its noise is then the AR(1) of ρ_o) or is degenerate.
///
/// This is the measurement model of errors in variables: the residual holds −G(e), the model's
/// response to the force's noise, coloured by its resonances. Under AR(1) noise a candidate that
/// matches part of that response's realisation — a narrow band at a resonance, a handful of
/// degrees of freedom in a record of seconds, and far above the sensor's floor — gains hundreds
/// of nats (a drag with its exponent and the refitted damping, 227 nats on the fixture
/// `offset_q3_noisy_force`, where the model's W = E‖G e‖² differs from the reference's by under
/// a nat); under the noise's own spectrum the same match is what that noise does by chance.
///
/// Where the read holds the fitted model's exact response ([`InputNoise::response_autocovariance`],
/// a structure's linear model), the autocovariance is that response's own beside the sensor's
/// floor, coloured as the likelihood of `residual` (the residual the noise was read from) says
/// ([`floor_colour`], [`floor_lags`]). A spectrum sampled on Welch bins a quarter of the record
/// wide stands for a lightly damped mode's response only roughly, and a floor coloured so that
/// the two together are correlated at lag one as the residual is takes up every error of the
/// read: a residual of nothing but that noise was then predicted better by its own AR(20) than
/// by the predictor, by tens of nats (a sensor offset on draw 20261319 was set aside as
/// removing 20 % of its output's structure; under the exact response and the floor's colour
/// the noise alone leaves about none). The floor's colour is chosen under the first
/// [`PREDICTOR_ORDER`] lags; the predictor then runs to the order at which its error converges
/// ([`converged`]; at most [`MAX_PREDICTOR_ORDER`] and a quarter of the record), as the
/// spectrum's does.
pub(super) fn predictors(
    read: &InputNoise,
    noise: &NoiseModel,
    residual: &Mat<f64>,
) -> Vec<Option<Predictor>> {
    (0..read.spectra.len())
        .map(|o| {
            if let Some(exact) = read.response_autocovariance.as_ref().and_then(|r| r.get(o)) {
                let floor = read.floors.get(o).copied().unwrap_or(0.0);
                let longest = MAX_PREDICTOR_ORDER.min(residual.nrows() / 4).max(PREDICTOR_ORDER);
                let lags = &exact[..exact.len().min(longest + 1)];
                if !lags.first().is_some_and(|g| *g > 0.0) || o >= residual.ncols() {
                    return None;
                }
                let series: Vec<f64> = (0..residual.nrows()).map(|t| residual[(t, o)]).collect();
                // The floor's colour by the likelihood under the first lags (the search scores
                // some sixty colours); the predictor then runs to its converged order.
                let rho_v = floor_colour(&lags[..lags.len().min(PREDICTOR_ORDER + 1)], floor, &series);
                return converged(&floor_lags(lags, floor, rho_v));
            }
            let total = noise_spectrum(read, noise, o)?;
            let floor = read.floors.get(o).copied().unwrap_or(0.0);
            let coloured = read.spectra[o].iter().any(|l| l - floor > 0.0);
            coloured.then(|| predictor_of(&total)).flatten()
        })
        .collect()
}

fn rho(noise: &NoiseModel, o: usize) -> f64 {
    noise.rho.get(o).copied().unwrap_or(0.0)
}

/// Output o's spectrum of the noise alone, on `read`'s Welch bins: the force's noise through the
/// model's response (`read`'s fitted spectrum less the sensor's level) beside the sensor's noise,
/// whose level was read as white. The sensor's noise is given the AR(1) colour ρ_v that makes the
/// two together correlated at lag one by the measurement model's ρ_o, as the residual ρ was read
/// from is — ρ_v = (ρ(γ_v + γ_g,0) − γ_g,1)/γ_v, held in ±0.99 — so that a sensor coloured of
/// itself is not counted as the force's noise: without the force's noise the spectrum is the
/// AR(1) of ρ_o. `None` where `read` has no such output.
fn noise_spectrum(read: &InputNoise, noise: &NoiseModel, o: usize) -> Option<Vec<f64>> {
    let (levels, floor) = (read.spectra.get(o)?, *read.floors.get(o)?);
    let response: Vec<f64> = levels.iter().map(|l| (l - floor).max(0.0)).collect();
    Some(coloured_floor(&response, floor, rho(noise, o)))
}

/// The response spectrum `response` with a sensor floor of white level `floor` added, coloured
/// as [`noise_spectrum`] says; `response` alone for a floor that is not positive.
fn coloured_floor(response: &[f64], floor: f64, rho: f64) -> Vec<f64> {
    let bins = response.len();
    let g = autocovariance(response, 1);
    // γ₀ of the white floor: w₀ + 2(bins − 1) times its level ([`autocovariance`] at lag 0).
    let v = floor * (2 * bins).saturating_sub(1) as f64;
    if v.is_nan() || v <= 0.0 {
        return response.to_vec();
    }
    let rho_v = ((rho * (v + g[0]) - g[1]) / v).clamp(-0.99, 0.99);
    let shape: Vec<f64> = (0..bins)
        .map(|b| {
            let w = std::f64::consts::PI * b as f64 / bins as f64;
            (1.0 - rho_v * rho_v) / (1.0 - 2.0 * rho_v * w.cos() + rho_v * rho_v)
        })
        .collect();
    let scale = v / autocovariance(&shape, 0)[0];
    shape.iter().zip(response).map(|(s, r)| scale * s + r).collect()
}

/// The autocovariance `response` (lags 0, 1, …) of the force's noise through the model with a
/// sensor floor of variance `floor` and AR(1) colour `rho_v` added; `response` alone for a
/// floor that is not positive.
fn floor_lags(response: &[f64], floor: f64, rho_v: f64) -> Vec<f64> {
    if floor.is_nan() || floor <= 0.0 {
        return response.to_vec();
    }
    let mut power = 1.0;
    response
        .iter()
        .map(|g| {
            let v = g + floor * power;
            power *= rho_v;
            v
        })
        .collect()
}

/// The sensor floor's AR(1) colour ρ_v in [−[`MAX_FLOOR_COLOUR`], [`MAX_FLOOR_COLOUR`]] that
/// maximises the likelihood of `series`, the residual the noise was read from, under the
/// force's noise `response` beside that floor ([`floor_lags`]); 0 for a floor that is not
/// positive. A grid of [`FLOOR_COLOUR_GRID`] steps, then golden sections about its best.
///
/// A sensor may be coloured of itself, and the floor's colour is what tells that apart from the
/// force's noise. Set instead so that the floor and the response together are correlated at lag
/// one as the residual is (the rule on Welch spectra, [`noise_spectrum`]), it takes up every
/// error of the read of the noise's level: on draw 20261319 (`A_offset_medium_s1`, white
/// sensors, the force's noise read at 0.86 % against 1 %) it came out −0.12 and left 25 nats of
/// structure in the reference and 12 in the residual of the true offset; at the likelihood's
/// ρ_v (0.01) they are 10 and none.
fn floor_colour(response: &[f64], floor: f64, series: &[f64]) -> f64 {
    if floor.is_nan() || floor <= 0.0 {
        return 0.0;
    }
    let score = |rho_v: f64| {
        Predictor::of_autocovariance(&floor_lags(response, floor, rho_v))
            .map_or(f64::NEG_INFINITY, |p| profile_likelihood(&p, series))
    };
    let step = 2.0 * MAX_FLOOR_COLOUR / FLOOR_COLOUR_GRID as f64;
    let grid = (0..=FLOOR_COLOUR_GRID).map(|j| -MAX_FLOOR_COLOUR + step * j as f64);
    let (best, _) =
        grid.map(|r| (r, score(r))).fold((0.0, f64::NEG_INFINITY), |a, b| if b.1 > a.1 { b } else { a });
    let (mut low, mut high) = ((best - step).max(-MAX_FLOOR_COLOUR), (best + step).min(MAX_FLOOR_COLOUR));
    let ratio = 0.5 * (5f64.sqrt() - 1.0);
    for _ in 0..24 {
        let (a, b) = (high - ratio * (high - low), low + ratio * (high - low));
        if score(a) >= score(b) {
            high = b;
        } else {
            low = a;
        }
    }
    0.5 * (low + high)
}

/// The largest |ρ_v| of the sensor floor's colour.
const MAX_FLOOR_COLOUR: f64 = 0.99;

/// Grid steps of [`floor_colour`] over [−0.99, 0.99].
const FLOOR_COLOUR_GRID: usize = 40;

/// −(n/2) ln(U/n) of `series` under `predictor`, U its scaled innovations' sum of squares (the
/// likelihood the evidence scores, [`NoiseModel::log_likelihoods`]).
fn profile_likelihood(predictor: &Predictor, series: &[f64]) -> f64 {
    let u: f64 = predictor.whitened(series).iter().map(|w| w * w).sum();
    let n = series.len() as f64;
    if u > 0.0 && n > 0.0 { -0.5 * n * (u / n).ln() } else { f64::NEG_INFINITY }
}

/// The structure (nats, [`structure_of_spectrum`]) `n` samples of the noise alone hold under
/// the measurement model's ρ: [`coloured_floor`] of the force's noise response and the sensor's
/// floor. Without the force's noise it is 0.
#[cfg(test)]
fn noise_structure(response: &[f64], floor: f64, rho: f64, n: usize) -> f64 {
    super::evidence::structure_of_spectrum(&coloured_floor(response, floor, rho), rho, n)
}

#[cfg(test)]
mod tests {
    use super::{
        PREDICTOR_CONVERGED, PREDICTOR_ORDER, Predictor, autocovariance, floor_colour, noise_structure,
        predictor_of,
    };
    use crate::frf::NoiseResponse;
    use faer::Mat;
    use mem::Hold;

    /// The force's noise through a lightly damped oscillator (3 Hz, ζ 0.03, sampled at 100 Hz)
    /// beside a sensor floor of AR(1) colour ρ (0, 0.6 and −0.4), each as much power as the
    /// other: the floor's colour the likelihood gives is ρ, to within the spread of 4,000
    /// samples.
    #[test]
    fn the_floors_colour_is_read_by_the_likelihood() {
        let (h, k) = (0.01, 4_000);
        let (a, b) = crate::frf::tests::oscillator(3.0, 0.03);
        let c = Mat::from_fn(1, 2, |_, j| f64::from(u8::from(j == 0)));
        let space = crate::frf::tests::space(&a, &b, &c, None);
        let response = NoiseResponse::new(&space, Hold::Zero, h, &[1.0], 20).unwrap();
        let gamma = response.autocovariance(0, 0).to_vec();
        let gains = expm::step_gains(a.as_ref(), &[], b.as_ref(), &[], h).unwrap();
        let drive = &gains.now + &gains.next;
        let normals = |seed: u64| -> Vec<f64> {
            let mut rng = test_problems::rng(seed);
            (0..k + 2_000)
                .map(|_| rand::Rng::sample::<f64, _>(&mut rng, rand_distr::StandardNormal))
                .collect()
        };
        let (force, sensor) = (normals(41), normals(42));
        let mut x = Mat::<f64>::zeros(2, 1);
        let mut through = Vec::with_capacity(k);
        for (t, e) in force.iter().enumerate() {
            if t >= 2_000 {
                through.push(x[(0, 0)]);
            }
            x = &gains.phi * &x + &drive * *e;
        }
        let floor = gamma[0];
        for rho in [0.0, 0.6, -0.4] {
            let mut v = sensor[0] * floor.sqrt();
            let series: Vec<f64> = through
                .iter()
                .zip(&sensor[1..])
                .map(|(g, n)| {
                    v = rho * v + (1.0 - rho * rho).sqrt() * floor.sqrt() * n;
                    g + v
                })
                .collect();
            let read = floor_colour(&gamma, floor, &series);
            assert!((read - rho).abs() < 0.05, "ρ {rho}: read {read}");
        }
    }

    /// A white sensor floor alone, or one coloured of itself (read under its own ρ), holds no
    /// structure; a resonance above it holds what the spectrum implies.
    #[test]
    fn the_noise_floor_counts_only_the_response_to_the_force_noise() {
        let (bins, n) = (512, 4000);
        let nothing = vec![0.0; bins];
        for rho in [0.0, 0.4, 0.8] {
            assert_eq!(noise_structure(&nothing, 1.0, rho, n), 0.0, "ρ {rho}");
        }
        // A resonance at a tenth of the Nyquist frequency, 20× the floor at its peak.
        let response: Vec<f64> = (0..bins)
            .map(|b| {
                let x = (b as f64 - 51.2) / 3.0;
                20.0 / (1.0 + x * x)
            })
            .collect();
        let alone = noise_structure(&response, 1.0, 0.5, n);
        assert!(alone > 50.0, "{alone}");
        // Ten times more floor hides most of it.
        assert!(noise_structure(&response, 10.0, 0.1, n) < alone / 2.0);
    }

    /// Order by convergence: for a white floor the least order; for a lightly damped resonance
    /// (3.5 Hz at 200 Hz, 0.5 % damping; 10⁴ times the floor at its peak and about the floor's
    /// level at zero frequency, as a displacement's response to a force's white noise is
    /// beside a sensor's) above a floor, more lags than 20, the error variance
    /// within [`PREDICTOR_CONVERGED`] of the longest's. A slow drift in that noise is scored by
    /// the converged predictor about as by a predictor of the noise's exact autocovariance (the
    /// AR(2) recursion in closed form, 400 lags), and by order 20 far less.
    #[test]
    fn the_predictor_runs_as_long_as_the_noise_rings() {
        let white = predictor_of(&vec![1.0; 250]).expect("a white spectrum");
        assert_eq!(white.order(), PREDICTOR_ORDER);
        let omega = 2.0 * std::f64::consts::PI * 3.5 / 200.0;
        let r = 1.0 - 0.005 * omega;
        let s2 = 1.5e-4;
        let ar2 = test_problems::Ar2::resonance(r, omega);
        let (a1, a2) = (ar2.a1, ar2.a2);
        let levels = ar2.spectrum(250, s2, 1.0);
        let chosen = predictor_of(&levels).expect("a resonant spectrum");
        assert!(chosen.order() > PREDICTOR_ORDER, "order {}", chosen.order());
        let longest = Predictor::of_autocovariance(&autocovariance(&levels, 120)).expect("positive definite");
        assert!(
            chosen.error_variance(chosen.order())
                <= (1.0 + PREDICTOR_CONVERGED) * longest.error_variance(120)
        );
        // The exact autocovariance of x_k = a1 x_{k−1} + a2 x_{k−2} + u_k (var u = s2) plus the
        // floor's white noise: the Welch bins' unit level is a variance of 1 (bins/bins).
        let mut gamma = ar2.autocovariance(400, s2);
        gamma[0] += 1.0;
        let exact = Predictor::of_autocovariance(&gamma).expect("positive definite");
        // A realisation, and a drift of 0.6 of the floor's RMS over the record.
        let n = 2001;
        let mut rng = test_problems::rng(41);
        let mut normal = || rand::Rng::sample::<f64, _>(&mut rng, rand_distr::StandardNormal);
        let (mut x1, mut x2) = (0.0, 0.0);
        let noise: Vec<f64> = (0..n + 5000)
            .map(|_| {
                let x = a1 * x1 + a2 * x2 + s2.sqrt() * normal();
                (x2, x1) = (x1, x);
                x + normal()
            })
            .skip(5000)
            .collect();
        let drifted: Vec<f64> =
            noise.iter().enumerate().map(|(k, e)| e + 0.6 * k as f64 / n as f64).collect();
        let profiled = |p: &Predictor, e: &[f64]| {
            let u: f64 = p.whitened(e).iter().map(|w| w * w).sum();
            -0.5 * n as f64 * (u / n as f64).ln()
        };
        let gain = |p: &Predictor| profiled(p, &noise) - profiled(p, &drifted);
        let twenty =
            Predictor::of_autocovariance(&autocovariance(&levels, PREDICTOR_ORDER)).expect("order 20");
        let (truth, converged, short) = (gain(&exact), gain(&chosen), gain(&twenty));
        assert!(truth > 10.0, "truth {truth}");
        assert!((converged / truth - 1.0).abs() < 0.3, "converged {converged}, truth {truth}");
        assert!(short < 0.5 * truth, "order 20 {short}, truth {truth}");
    }
}
