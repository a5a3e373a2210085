//! Small statistics: whiteness of residuals, information criteria, the normal tail.

/// erfc(x) (Abramowitz & Stegun 7.1.26, absolute error < 1.5e-7; enough for a p-value).
pub fn erfc(x: f64) -> f64 {
    let z = x.abs();
    let t = 1.0 / (1.0 + 0.327_591_1 * z);
    let poly = t
        * (0.254_829_592
            + t * (-0.284_496_736 + t * (1.421_413_741 + t * (-1.453_152_027 + t * 1.061_405_429))));
    let value = poly * (-z * z).exp();
    if x >= 0.0 { value } else { 2.0 - value }
}

/// P(χ²_k > q) by the Wilson–Hilferty normal approximation (good to ~1e-3 for k ≥ 5).
pub fn chi_square_survival(q: f64, k: usize) -> f64 {
    let k = k as f64;
    let z = ((q / k).cbrt() - (1.0 - 2.0 / (9.0 * k))) / (2.0 / (9.0 * k)).sqrt();
    0.5 * erfc(z / std::f64::consts::SQRT_2)
}

/// Ljung–Box portmanteau test of a residual series for lags 1..=`lags`: (Q, p-value).
/// A white residual has a large p-value; structure the model misses gives p ≈ 0.
pub fn ljung_box(series: &[f64], lags: usize) -> (f64, f64) {
    let n = series.len();
    let mean = series.iter().sum::<f64>() / n as f64;
    let centred: Vec<f64> = series.iter().map(|v| v - mean).collect();
    let c0: f64 = centred.iter().map(|v| v * v).sum();
    if c0 == 0.0 || n <= lags + 1 {
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

/// Bayesian information criterion with the noise variance estimated from the fit:
/// BIC = m ln(‖E‖²/m) + k ln m.
pub fn bic(cost: f64, m: usize, k: usize) -> f64 {
    let m = m as f64;
    m * (cost / m).max(f64::MIN_POSITIVE).ln() + k as f64 * m.ln()
}
