//! Small statistics: information criteria on AR(1) residuals (whiteness and the χ² tail come
//! from `mem::stats`, which uses statrs).

pub use mem::stats::{chi_square_survival, ljung_box};

/// The innovation sum of squares of a residual series under a Gaussian AR(1) error model,
/// e_k = ρ e_{k−1} + u_k: (1 − ρ²)e₀² + Σ_{k≥1} (e_k − ρ e_{k−1})², with ρ the lag-one
/// autocorrelation (Yule–Walker), clamped to |ρ| ≤ 0.999. For white residuals (ρ ≈ 0) it is
/// ‖e‖²; for the smooth residual of a model that misses physics (ρ → 1) it is what the
/// sample-to-sample differences leave, so a candidate that only shrinks a smooth misfit a
/// little is not credited as if each of its K correlated samples were independent evidence.
pub fn ar1_innovations(e: &[f64]) -> f64 {
    let power: f64 = e.iter().map(|v| v * v).sum();
    if power == 0.0 || e.len() < 2 {
        return power;
    }
    let lagged: f64 = e.windows(2).map(|w| w[0] * w[1]).sum();
    let rho = (lagged / power).clamp(-0.999, 0.999);
    (1.0 - rho * rho) * e[0] * e[0] + e.windows(2).map(|w| (w[1] - rho * w[0]).powi(2)).sum::<f64>()
}

/// Smallest ratio of a channel's error to its baseline error that [`delta_bic`] credits: an
/// exactly fitted channel (e.g. every reading's interval holds the model) is strong evidence,
/// not infinite evidence.
const MIN_CHANNEL_RATIO: f64 = 1e-6;

/// ΔBIC of a candidate against the baseline, with one Gaussian AR(1) error process per output,
/// its innovation variance estimated from each fit: BIC = Σ_o K ln(U_o/K) + k ln m (U_o the
/// output's innovation sum of squares, [`ar1_innovations`]; K samples, m = K·p residuals, k
/// fitted parameters), so ΔBIC = Σ_o K ln(U_o,c/U_o,b) + Δk ln m. Per-output variances keep
/// an output that the model already fits closely (a potentiometer beside a strain gauge) from
/// being drowned by the others; the AR(1) term keeps a misfit's correlation from counting as
/// independent evidence. Negative is better; the per-output ρ and variance are in both models
/// and cancel in Δk.
pub fn delta_bic(candidate: &[f64], baseline: &[f64], samples: usize, added: usize) -> f64 {
    assert_eq!(candidate.len(), baseline.len(), "one error per output in both fits");
    let k = samples as f64;
    let m = k * baseline.len() as f64;
    let fit: f64 = candidate
        .iter()
        .zip(baseline)
        .filter(|(_, b)| **b > 0.0)
        .map(|(c, b)| k * (c / b).max(MIN_CHANNEL_RATIO).ln())
        .sum();
    fit + added as f64 * m.ln()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn delta_bic_is_the_per_output_log_likelihood_ratio_plus_the_penalty() {
        // Halving one output's error and keeping the other: 100·ln ½ + 1·ln 200.
        let value = delta_bic(&[0.5, 3.0], &[1.0, 3.0], 100, 1);
        assert!((value - (100.0 * 0.5f64.ln() + 200f64.ln())).abs() < 1e-12);
        // An exactly fitted output counts as a 10⁻⁶ ratio.
        // White residuals keep their sum of squares (to O(ρ̂) ~ 1/√K); a smooth one does not.
        let alternating: Vec<f64> = (0..400).map(|k| ((k * 7919) % 13) as f64 - 6.0).collect();
        let power: f64 = alternating.iter().map(|v| v * v).sum();
        assert!((ar1_innovations(&alternating) / power - 1.0).abs() < 0.2);
        let smooth: Vec<f64> = (0..400).map(|k| (k as f64 * 0.01).sin()).collect();
        let power: f64 = smooth.iter().map(|v| v * v).sum();
        assert!(ar1_innovations(&smooth) < 1e-3 * power);
        assert!((delta_bic(&[0.0], &[2.0], 10, 0) - 10.0 * 1e-6f64.ln()).abs() < 1e-9);
    }
}
