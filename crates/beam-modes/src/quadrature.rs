//! Composite Gauss–Legendre quadrature, used to cross-check the closed-form integrals.

use num_dual::DualNum;

/// Nodes and weights of the n-point Gauss–Legendre rule on [−1, 1] (Newton on P_n, started
/// from Chebyshev-like guesses; accurate to a few ulps for n ≤ 64).
pub fn gauss_legendre(n: usize) -> Vec<(f64, f64)> {
    let mut rule = Vec::with_capacity(n);
    for i in 0..n {
        let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
        let mut dp = 1.0;
        for _ in 0..100 {
            let (mut p0, mut p1) = (1.0, x);
            for k in 2..=n {
                let p2 = ((2 * k - 1) as f64 * x * p1 - (k - 1) as f64 * p0) / k as f64;
                p0 = p1;
                p1 = p2;
            }
            dp = n as f64 * (x * p1 - p0) / (x * x - 1.0);
            let dx = p1 / dp;
            x -= dx;
            if dx.abs() < 1e-16 {
                break;
            }
        }
        rule.push((x, 2.0 / ((1.0 - x * x) * dp * dp)));
    }
    rule
}

/// ∫ₐᵇ f(x) dx by `panels` equal panels of the `points`-point rule.
pub fn integrate<D: DualNum<Primitive = f64> + Copy>(
    f: impl Fn(D) -> D,
    a: D,
    b: D,
    panels: usize,
    points: usize,
) -> D {
    let rule = gauss_legendre(points);
    let width = (b - a) / panels as f64;
    let mut total = D::from(0.0);
    for p in 0..panels {
        let left = a + width * p as f64;
        for &(x, w) in &rule {
            total += f(left + width * ((x + 1.0) * 0.5)) * (w * 0.5);
        }
    }
    total * width
}
