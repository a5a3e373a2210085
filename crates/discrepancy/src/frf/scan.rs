//! The kernel of the resonance scan: one trial mode driven by one input, and how much of a
//! series it explains.
//!
//! The trial mode is η̈ + 2ζω η̇ + ω² η = ω² u from rest, u held over each sample interval, stepped
//! by the exact one-step map of [η, η̇/ω, u] (the exponential of the 3 × 3 augmented matrix over
//! one interval, computed once per trial, never per sample). A driven unmodeled mode adds
//! a_o η + b_o η̇/ω to output o, linear in its amplitudes, so the share of a series it can explain
//! at (ω, ζ) is the series' projection on span{η, η̇/ω}: Σ_o ‖Q₂ᵀ r_o‖², Q₂ an orthonormal basis
//! of the two columns (modified Gram–Schmidt; no normal equations are formed).

use faer::Mat;
use mem::NoisePredictor;

/// The response [η, η̇/ω] (K × 2) of the trial mode at `f` Hz and damping ratio `zeta` to the
/// input column `u` (K samples, held over each interval of `h` s), from rest; `None` when the
/// one-step map cannot be computed (a frequency or interval that is not finite and positive).
#[cfg(test)]
fn trial_response(f: f64, zeta: f64, h: f64, u: &[f64]) -> Option<Mat<f64>> {
    TrialMode::new(f, zeta, h)?.respond(u)
}

/// The trial mode at one frequency and damping: its one-step map, computed once and driven by
/// as many inputs as asked.
pub(super) struct TrialMode {
    phi: Mat<f64>,
}

impl TrialMode {
    /// The mode at `f` Hz and damping ratio `zeta`, stepped every `h` s; `None` when its one-step
    /// map cannot be computed (a frequency or interval that is not finite and positive).
    pub(super) fn new(f: f64, zeta: f64, h: f64) -> Option<Self> {
        let w = 2.0 * std::f64::consts::PI * f;
        if !(w.is_finite() && w > 0.0 && h.is_finite() && h > 0.0) {
            return None;
        }
        // States [η, η̇/ω]: d/dt η = ω (η̇/ω); d/dt (η̇/ω) = −ω η − 2ζω (η̇/ω) + ω u.
        let a = Mat::from_fn(3, 3, |r, c| {
            h * match (r, c) {
                (0, 1) => w,
                (1, 0) => -w,
                (1, 1) => -2.0 * zeta * w,
                (1, 2) => w,
                _ => 0.0,
            }
        });
        Some(Self { phi: expm::expm(a.as_ref()).ok()? })
    }

    /// Its response to `u` from rest; `None` where it is not finite.
    pub(super) fn respond(&self, u: &[f64]) -> Option<Mat<f64>> {
        let phi = &self.phi;
        let mut x = [0.0, 0.0];
        let mut response = Mat::zeros(u.len(), 2);
        for (t, &ut) in u.iter().enumerate() {
            response[(t, 0)] = x[0];
            response[(t, 1)] = x[1];
            x = [
                phi[(0, 0)] * x[0] + phi[(0, 1)] * x[1] + phi[(0, 2)] * ut,
                phi[(1, 0)] * x[0] + phi[(1, 1)] * x[1] + phi[(1, 2)] * ut,
            ];
        }
        x.iter().all(|v| v.is_finite()).then_some(response)
    }
}

/// An orthonormal basis Q₂ of the columns of `regressors` (K × 2), by modified Gram–Schmidt; a
/// column that adds less than 1e-12 of its own norm to the basis is left out (an input that
/// does not excite the trial mode explains nothing).
pub(super) fn basis(regressors: &Mat<f64>) -> Vec<Vec<f64>> {
    let k = regressors.nrows();
    let mut basis: Vec<Vec<f64>> = Vec::with_capacity(regressors.ncols());
    for c in 0..regressors.ncols() {
        let mut v: Vec<f64> = (0..k).map(|t| regressors[(t, c)]).collect();
        let norm0 = v.iter().map(|x| x * x).sum::<f64>().sqrt();
        for q in &basis {
            let d: f64 = q.iter().zip(&v).map(|(a, b)| a * b).sum();
            v.iter_mut().zip(q).for_each(|(x, qi)| *x -= d * qi);
        }
        let norm = v.iter().map(|x| x * x).sum::<f64>().sqrt();
        if norm0 > 0.0 && norm > 1e-12 * norm0 && norm.is_finite() {
            v.iter_mut().for_each(|x| *x /= norm);
            basis.push(v);
        }
    }
    basis
}

/// Σ_o ‖Q₂ᵀ r_o‖² for the columns r_o of `series` (K × p) and an orthonormal `basis` Q₂
/// ([`basis`]).
#[cfg(test)]
fn explained(series: &Mat<f64>, basis: &[Vec<f64>]) -> f64 {
    (0..series.ncols())
        .map(|o| explained_column(&(0..series.nrows()).map(|t| series[(t, o)]).collect::<Vec<f64>>(), basis))
        .sum()
}

/// ‖Q₂ᵀ r‖² for one series `column` and an orthonormal `basis` Q₂ ([`basis`]).
pub(super) fn explained_column(column: &[f64], basis: &[Vec<f64>]) -> f64 {
    basis.iter().map(|q| q.iter().zip(column).map(|(a, b)| a * b).sum::<f64>().powi(2)).sum()
}

/// `u` through `predictor`'s full-order prediction-error filter from rest:
/// v_k = u_k − Σ_{i=1..q} a_q,i u_{k−i}, with u zero before the record.
pub(super) fn error_filtered(u: &[f64], predictor: &NoisePredictor) -> Vec<f64> {
    let a = predictor.coefficients(predictor.order());
    (0..u.len()).map(|k| u[k] - a.iter().zip(u[..k].iter().rev()).map(|(c, x)| c * x).sum::<f64>()).collect()
}

/// The trial mode's response `x` (K × 2) whitened by `predictor` ([`NoisePredictor::whitened`],
/// column by column), from `driven`, the same mode's response to the input through the
/// predictor's error filter ([`error_filtered`]). Both the mode and the filter are linear,
/// time-invariant and start from rest, so they commute: from sample q on the whitening is that
/// filter, and `driven` is the whitened response there; the first q samples, where the
/// whitening is of lower orders, are whitened from `x` itself. One recursion of the mode per
/// output instead of a q-tap filter over every sample of both columns for every trial.
pub(super) fn whitened_response(x: &Mat<f64>, mut driven: Mat<f64>, predictor: &NoisePredictor) -> Mat<f64> {
    let head = predictor.order().min(x.nrows());
    for c in 0..x.ncols() {
        let start: Vec<f64> = (0..head).map(|t| x[(t, c)]).collect();
        for (t, v) in predictor.whitened(&start).into_iter().enumerate() {
            driven[(t, c)] = v;
        }
    }
    driven
}

/// The columns of `regressors` whitened by `predictor`, directly: the reference
/// [`whitened_response`] is checked against.
#[cfg(test)]
fn whitened(regressors: &Mat<f64>, predictor: &NoisePredictor) -> Mat<f64> {
    let k = regressors.nrows();
    let mut out = Mat::zeros(k, regressors.ncols());
    for c in 0..regressors.ncols() {
        let column: Vec<f64> = (0..k).map(|t| regressors[(t, c)]).collect();
        for (t, v) in predictor.whitened(&column).into_iter().enumerate() {
            out[(t, c)] = v;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The one-step map against the closed-form step response of a lightly damped oscillator:
    /// η(t) = 1 − e^(−ζωt)(cos ω_d t + ζ/√(1−ζ²) sin ω_d t) for a unit step from rest.
    #[test]
    fn the_trial_mode_follows_the_closed_form_step_response() {
        let (f, zeta, h) = (3.0, 0.05, 0.01);
        let u = vec![1.0; 400];
        let r = trial_response(f, zeta, h, &u).unwrap();
        let w = 2.0 * std::f64::consts::PI * f;
        let wd = w * (1.0 - zeta * zeta).sqrt();
        for t in 0..400 {
            let s = t as f64 * h;
            let exact = 1.0
                - (-zeta * w * s).exp()
                    * ((wd * s).cos() + zeta / (1.0 - zeta * zeta).sqrt() * (wd * s).sin());
            assert!((r[(t, 0)] - exact).abs() < 1e-12, "t = {s}: {} against {exact}", r[(t, 0)]);
        }
        assert!(trial_response(f64::NAN, zeta, h, &u).is_none());
        assert!(trial_response(f, zeta, 0.0, &u).is_none());
    }

    /// A series in the regressors' span is explained whole; one orthogonal to them not at all;
    /// a zero regressor column adds nothing.
    #[test]
    fn the_projection_explains_what_lies_in_the_span_and_nothing_else() {
        let k = 50;
        let x =
            Mat::from_fn(k, 2, |t, c| if c == 0 { (t as f64 * 0.3).sin() } else { (t as f64 * 0.3).cos() });
        let inside = Mat::from_fn(k, 1, |t, _| 2.0 * x[(t, 0)] - 0.5 * x[(t, 1)]);
        let total: f64 = (0..k).map(|t| inside[(t, 0)].powi(2)).sum();
        assert!((explained(&inside, &basis(&x)) - total).abs() < 1e-9 * total);
        let zero = Mat::from_fn(k, 2, |t, c| if c == 0 { x[(t, 0)] } else { 0.0 });
        let orthogonal = Mat::from_fn(k, 1, |t, _| {
            x[(t, 1)]
                - x[(t, 0)] * {
                    let d: f64 = (0..k).map(|s| x[(s, 0)] * x[(s, 1)]).sum();
                    d / (0..k).map(|s| x[(s, 0)].powi(2)).sum::<f64>()
                }
        });
        assert!(explained(&orthogonal, &basis(&zero)) < 1e-18);
    }

    /// The trial mode driven by the filtered input, its first q samples whitened from the mode's
    /// own response, is the mode's response whitened directly (to round-off), for a predictor of
    /// 30 lags, past and before sample q.
    #[test]
    fn the_mode_driven_by_the_filtered_input_is_its_whitened_response() {
        let predictor = NoisePredictor::of_autocovariance(
            &test_problems::Ar2::resonance(0.99, 0.3).autocovariance(30, 1.0),
        )
        .expect("positive definite");
        let u: Vec<f64> =
            (0..600).map(|k| ((k * 37 % 101) as f64 / 50.0 - 1.0) + (0.01 * k as f64).sin()).collect();
        let x = trial_response(12.0, 0.02, 0.005, &u).unwrap();
        let driven = trial_response(12.0, 0.02, 0.005, &error_filtered(&u, &predictor)).unwrap();
        let fast = whitened_response(&x, driven, &predictor);
        let direct = whitened(&x, &predictor);
        let scale = direct.norm_max();
        for t in 0..u.len() {
            for c in 0..2 {
                assert!((fast[(t, c)] - direct[(t, c)]).abs() < 1e-10 * scale, "sample {t}, column {c}");
            }
        }
    }
}
