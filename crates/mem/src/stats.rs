//! Small statistics on residual series, with statrs's distributions: the Student-t quantile
//! of the intervals, Ljung–Box whiteness, lag-one autocorrelation.

use statrs::distribution::{ChiSquared, ContinuousCDF, StudentsT};

/// Two-sided 95 % quantile of Student's t with `dof` degrees of freedom (∞ for none).
pub fn t_quantile_975(dof: usize) -> f64 {
    if dof == 0 {
        return f64::INFINITY;
    }
    StudentsT::new(0.0, 1.0, dof as f64).map_or(f64::INFINITY, |t| t.inverse_cdf(0.975))
}

/// P(χ²_k > q).
pub fn chi_square_survival(q: f64, k: usize) -> f64 {
    if k == 0 || !q.is_finite() {
        return if q.is_finite() { 1.0 } else { 0.0 };
    }
    ChiSquared::new(k as f64).map_or(f64::NAN, |c| c.sf(q.max(0.0)))
}

/// Lag-one autocorrelation Σe_k e_{k−1}/Σe_k² (0 for a zero series), clamped to ±0.99.
pub fn lag_one(series: &[f64]) -> f64 {
    let power: f64 = series.iter().map(|v| v * v).sum();
    if power == 0.0 || series.len() < 2 {
        return 0.0;
    }
    (series.windows(2).map(|w| w[0] * w[1]).sum::<f64>() / power).clamp(-0.99, 0.99)
}

/// Ljung–Box portmanteau test of a series for lags 1..=`lags`: (Q, p-value). A white series
/// has a large p-value; structure gives p ≈ 0. A series too short for the lags, or constant,
/// gives (0, 1).
pub fn ljung_box(series: &[f64], lags: usize) -> (f64, f64) {
    let n = series.len();
    if n <= lags + 1 || lags == 0 {
        return (0.0, 1.0);
    }
    let mean = series.iter().sum::<f64>() / n as f64;
    let centred: Vec<f64> = series.iter().map(|v| v - mean).collect();
    let c0: f64 = centred.iter().map(|v| v * v).sum();
    if c0 == 0.0 || !c0.is_finite() {
        return (0.0, 1.0);
    }
    let q: f64 = (1..=lags)
        .map(|k| {
            let rk: f64 = (k..n).map(|t| centred[t] * centred[t - k]).sum::<f64>() / c0;
            rk * rk / (n - k) as f64
        })
        .sum::<f64>()
        * (n * (n + 2)) as f64;
    (q, chi_square_survival(q, lags))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Published values: t_{0.975} for 1, 10 and 30 degrees of freedom (Student's table), and
    /// the χ² tail at the 95 % point of 20 degrees of freedom (31.410).
    #[test]
    fn quantiles_match_tables() {
        assert!((t_quantile_975(1) - 12.7062).abs() < 1e-4);
        assert!((t_quantile_975(10) - 2.2281).abs() < 1e-4);
        assert!((t_quantile_975(30) - 2.0423).abs() < 1e-4);
        assert!((chi_square_survival(31.410, 20) - 0.05).abs() < 1e-4);
        assert_eq!(t_quantile_975(0), f64::INFINITY);
    }
}
