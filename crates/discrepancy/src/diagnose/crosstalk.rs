//! The crosstalk a named effect is set against (step 7 of [module `diagnose`](mod@super)): one
//! sensor's channel picking up another's signal, y_i′ = y_i + g·y_j — a wiring, grounding or
//! amplifier fault, not physics, and not in the catalog. It changes the readings of one output
//! by the shape of another's, which a delay or a force can imitate on that output while the
//! model's own parameters take up the rest; one gain that explains the record as well as an
//! effect is the simpler answer.
//!
//! Of the p(p − 1) ordered pairs one is refitted ([`screened`]): the pair whose reading best
//! explains the reference's residual on the other output, by the least squares of the residual
//! r_i, whitened under the noise model's AR(1) (w_0 = √(1 − ρ²)·e_0, w_k = e_k − ρe_{k−1}, as
//! the likelihood reads it), on the reference's fitted y_j whitened alike. That gain,
//! −(n/2) ln(U_g/U_0), is a lower bound on the refit's: the refit frees the reference's
//! parameters beside g.
//!
//! The pair refitted is the best of K = p(p − 1): it is charged ln K nats
//! ([`Rival::penalty`](super::Rival::penalty)) before it is set against the effect, so that
//! crosstalk, as a class, weighs as one alternative (each pair with prior 1/K). On the slewing
//! rig a loop delay acts, to first order in τ, as a torque ∝ θ̇ whose share the servo's own
//! damping does not take up reaches the strain gauge; a pickup of the tachometer by the strain
//! channel is then the same residual, and on one record the two differ by a few nats either
//! way. The charge decides a tie, a fraction of a nat, for the catalog's effect.

use super::answer::AddedTerm;
use super::evidence::NoiseModel;
use super::mismatch::RivalTrial;
use faer::Mat;
use models::{FitOutcome, Model, ModelEffect};

/// The whitened least squares of `residual`'s column i on `regressor`'s column j under AR(1)
/// coefficient ρ: the gain −(n/2) ln(U_g/U_0) (nats) of the best g, and that g.
pub(super) fn regression(
    residual: &Mat<f64>,
    regressor: &Mat<f64>,
    i: usize,
    j: usize,
    rho: f64,
) -> (f64, f64) {
    let whiten = |m: &Mat<f64>, c: usize, k: usize| {
        if k == 0 { (1.0 - rho * rho).sqrt() * m[(0, c)] } else { m[(k, c)] - rho * m[(k - 1, c)] }
    };
    let (mut rr, mut rs, mut ss) = (0.0, 0.0, 0.0);
    for k in 0..residual.nrows() {
        let (r, s) = (whiten(residual, i, k), whiten(regressor, j, k));
        (rr, rs, ss) = (rr + r * r, rs + r * s, ss + s * s);
    }
    if !(rr > 0.0 && ss > 0.0) {
        return (0.0, 0.0);
    }
    let left = (rr - rs * rs / ss).max(f64::MIN_POSITIVE);
    (-0.5 * residual.nrows() as f64 * (left / rr).ln(), rs / ss)
}

/// The crosstalk to refit as a rival: the ordered pair (i picks up j) of the reference's
/// outputs whose whitened regression gains most (see the module), added at zero with g within
/// ± max|y_i| / max|y_j| (a pickup no larger than the output's own signal). None with one
/// output or when no pair gains. (A model that already carries a crosstalk on output i cannot
/// take a second: the rival search drops the trial when adding its effect fails.)
///
/// No pair is tried on `named_output`, the output a named sensor effect acts on: both then say
/// that channel misreads, and where the outputs move together — a free decay that one mode
/// dominates — another's signal is that output's own scaled, a tie that only restates the
/// effect.
pub(super) fn screened(
    reference: &FitOutcome,
    noise: &NoiseModel,
    named_output: Option<usize>,
) -> Option<RivalTrial> {
    let first = reference.first();
    let (residual, fitted) = (first.residual(), &first.final_outputs);
    let p = residual.ncols();
    let peak: Vec<f64> =
        (0..p).map(|c| (0..fitted.nrows()).map(|k| fitted[(k, c)].abs()).fold(0.0, f64::max)).collect();
    let (i, j, _) = (0..p)
        .filter(|&i| Some(i) != named_output)
        .flat_map(|i| (0..p).filter(move |&j| j != i).map(move |j| (i, j)))
        .filter(|&(i, j)| peak[i] > 0.0 && peak[j] > 0.0)
        .map(|(i, j)| (i, j, regression(&residual, fitted, i, j, noise.rho[i]).0))
        .filter(|&(_, _, gain)| gain > 0.0)
        .max_by(|a, b| a.2.total_cmp(&b.2))?;
    let bound = peak[i] / peak[j];
    let model = &reference.fitted;
    let outputs = model.output_names();
    let effect: ModelEffect = match model {
        Model::Slewing(m) => {
            let sensors = m.sensors();
            plant::Effect::SensorCrosstalk { sensor: sensors[i], from: sensors[j], gain: 0.0 }.into()
        }
        Model::Structure(_) => structure::Effect::SensorCrosstalk {
            output: outputs[i].clone(),
            from: outputs[j].clone(),
            gain: 0.0,
        }
        .into(),
    };
    let name = match &effect {
        ModelEffect::Slewing(e) => plant::ParamId::of_effect(e).first()?.name(),
        ModelEffect::Structure(e) => e.parameters(&outputs).first()?.0.clone(),
    };
    Some(RivalTrial {
        name,
        bounds: (-bound, bound),
        adds: Some((effect, AddedTerm::Crosstalk { output: outputs[i].clone(), from: outputs[j].clone() })),
        penalty: ((p * (p - 1)) as f64).ln(),
    })
}

#[cfg(test)]
mod tests {
    use super::regression;
    use faer::Mat;

    /// The whitened regression recovers a residual that is g times the regressor plus white
    /// noise: its gain is −(n/2) ln of the share the noise leaves, computed here directly.
    #[test]
    fn the_regression_gain_is_the_likelihood_of_the_share_left() {
        let n = 400;
        let regressor = Mat::from_fn(n, 1, |k, _| (0.05 * k as f64).sin());
        // A deterministic, zero-mean, uncorrelated-looking sequence for the noise.
        let noise = |k: usize| ((k * 7919 % 997) as f64 / 997.0 - 0.5) * 0.1;
        let residual = Mat::from_fn(n, 1, |k, _| 0.3 * regressor[(k, 0)] + noise(k));
        let (gain, fitted_g) = regression(&residual, &regressor, 0, 0, 0.0);
        // Direct: the least-squares g and the sums of squares before and after.
        let (mut rs, mut ss, mut rr) = (0.0, 0.0, 0.0);
        for k in 0..n {
            rs += residual[(k, 0)] * regressor[(k, 0)];
            ss += regressor[(k, 0)] * regressor[(k, 0)];
            rr += residual[(k, 0)] * residual[(k, 0)];
        }
        let g = rs / ss;
        assert!((g - 0.3).abs() < 0.02, "g = {g}");
        assert!((fitted_g - g).abs() < 1e-12, "{fitted_g} against {g}");
        let left: f64 = (0..n).map(|k| (residual[(k, 0)] - g * regressor[(k, 0)]).powi(2)).sum();
        let want = -0.5 * n as f64 * (left / rr).ln();
        assert!((gain - want).abs() < 1e-9 * want.abs(), "{gain} against {want}");
        // Nothing to explain in a regressor the residual does not hold.
        let flat = Mat::from_fn(n, 1, |k, _| noise(k));
        let orthogonal = Mat::from_fn(n, 1, |k, _| if k % 2 == 0 { 1.0 } else { -1.0 });
        assert!(regression(&flat, &orthogonal, 0, 0, 0.0).0 < 5.0);
    }
}
