//! The fitted response corrected by the model's own modes before a sawtooth is read about it
//! (see the module notes of `quantization`).

use super::sawtooth::swinging_end;
use faer::Mat;

/// `fitted` corrected by the model's own modal decays: over the samples the sawtooth reads
/// (`swinging_end`), the residual's least-squares fit by a constant and, for each pole
/// s = σ + iω of the fitted model's linear dynamics (`poles`, upper half plane, s⁻¹), the decays
/// e^{σt}cos ωt, e^{σt}sin ωt and the same times t — a small error of a mode's amplitude, phase,
/// frequency or decay, to first order — added to the response at every sample. A decimated fit
/// never sees the modes above its Nyquist frequency, and a misfit of a high mode's decay in the
/// raw record is a fast oscillation no local smooth follows; the correction removes it with
/// four numbers a mode, far too few to follow a sawtooth that changes with every step crossed.
/// Solved by the MEM's own truncated SVD (`mem::truncated_svd_solve`, singular values below
/// 10⁻¹⁰ of the largest cut: close poles give near-equal columns); `fitted` is returned as it is
/// when the sizes disagree, a column is not finite (an unstable pole over a long record) or the
/// SVD fails.
pub fn modal_corrected(values: &[f64], fitted: &[f64], times: &[f64], poles: &[(f64, f64)]) -> Vec<f64> {
    let n = fitted.len();
    if values.len() != n || times.len() != n || n == 0 {
        return fitted.to_vec();
    }
    let end = swinging_end(values, fitted);
    let t0 = times[0];
    let nyquist = std::f64::consts::PI / ((times[n - 1] - t0) / (n - 1).max(1) as f64);
    // Each column t^power · e^{σt} · (cos or sin) ωt, as (σ, ω, power, sine); the constant first.
    let mut columns = vec![(0.0, 0.0, 0, false)];
    for &(sigma, omega) in poles.iter().filter(|(s, w)| s.is_finite() && w.is_finite() && *w < nyquist) {
        let phases: &[bool] = if omega > 0.0 { &[false, true] } else { &[false] };
        for &sine in phases {
            columns.extend([0, 1].map(|power| (sigma, omega, power, sine)));
        }
    }
    let m = columns.len();
    if end < 4 * m {
        return fitted.to_vec();
    }
    let basis = Mat::<f64>::from_fn(n, m, |k, j| {
        let (sigma, omega, power, sine) = columns[j];
        let t = times[k] - t0;
        let wave = if sine { (omega * t).sin() } else { (omega * t).cos() };
        t.powi(power) * (sigma * t).exp() * wave
    });
    if !(0..m).all(|j| (0..n).all(|k| basis[(k, j)].is_finite())) {
        return fitted.to_vec();
    }
    let residual: Vec<f64> = (0..end).map(|k| values[k] - fitted[k]).collect();
    let Ok(coefficients) = mem::truncated_svd_solve(basis.subrows(0, end).to_owned(), &residual, 1e-10)
    else {
        return fitted.to_vec();
    };
    (0..n).map(|k| fitted[k] + (0..m).map(|j| basis[(k, j)] * coefficients[j]).sum::<f64>()).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A decaying 1.7 Hz response at 128 Hz for 20 s, and its times.
    fn response() -> (Vec<f64>, Vec<f64>) {
        let times: Vec<f64> = (0..2560).map(|k| k as f64 / 128.0).collect();
        let tau = 2.0 * std::f64::consts::PI;
        let x = times.iter().map(|t| 0.8 * (-t / 4.0).exp() * (tau * 1.7 * t).cos()).collect();
        (x, times)
    }

    #[test]
    fn a_misfit_made_of_the_models_own_decays_is_removed_exactly() {
        let (fitted, times) = response();
        let tau = 2.0 * std::f64::consts::PI;
        let (sigma, omega) = (-0.3, tau * 10.9);
        // An offset, and the 10.9 Hz mode's amplitude and decay off (the t·e^{σt} term).
        let values: Vec<f64> = fitted
            .iter()
            .zip(&times)
            .map(|(x, t)| {
                x + 0.01
                    + 0.05 * (sigma * t).exp() * (omega * t).cos()
                    + 0.02 * t * (sigma * t).exp() * (omega * t).sin()
            })
            .collect();
        let corrected = modal_corrected(&values, &fitted, &times, &[(-0.25, tau * 1.7), (sigma, omega)]);
        let worst = corrected.iter().zip(&values).map(|(c, y)| (c - y).abs()).fold(0.0, f64::max);
        assert!(worst < 1e-9, "{worst}");
        // Without the poles only the constant is fitted: the offset goes, the mode stays.
        let constant = modal_corrected(&values, &fitted, &times, &[]);
        let left = constant.iter().zip(&values).map(|(c, y)| (c - y).abs()).fold(0.0, f64::max);
        assert!(left > 0.04, "{left}");
    }

    #[test]
    fn mismatched_sizes_or_an_overflowing_pole_leave_the_response_as_it_is() {
        let (fitted, times) = response();
        let values: Vec<f64> = fitted.iter().map(|x| x + 0.01).collect();
        assert_eq!(modal_corrected(&values[1..], &fitted, &times, &[]), fitted);
        assert_eq!(modal_corrected(&values, &fitted, &times[1..], &[]), fitted);
        assert!(modal_corrected(&[], &[], &[], &[]).is_empty());
        // e^{50 t} overflows within the record: no column, no correction, no NaN.
        assert_eq!(modal_corrected(&values, &fitted, &times, &[(50.0, 3.0)]), fitted);
        // A pole above the Nyquist frequency (64 Hz here) is left out, not aliased: the constant
        // alone is fitted.
        let high = modal_corrected(&values, &fitted, &times, &[(-1.0, 2.0 * std::f64::consts::PI * 70.0)]);
        assert!(high.iter().zip(&values).all(|(c, y)| (c - y).abs() < 1e-12));
    }
}
