//! The characteristic equation and its roots.
//!
//! Δ(λ, κ) = λ(sin λ cosh λ − cos λ sinh λ) − κ(1 + cos λ cosh λ) = 0.
//! It is evaluated in two sign-preserving forms: ½Δ by Krylov–Duncan series for λ < 3
//! (no cancellation as λ → 0, where Δ ≈ 2λ⁴/3 − 2κ), and Δ/cosh λ with tanh and sech for
//! λ ≥ 3 (no overflow for high modes). Every root lies in its own bracket: the i-th root
//! λ_i(κ) increases monotonically with κ from the pinned-free root p_{i−1} (p_0 = 0) to the
//! clamped-free root c_i, and c_i < p_i, so [p_{i−1}, c_i] holds exactly one root.

use crate::krylov::krylov;
use num_dual::DualNum;
use roots::{Convergency, find_root_brent};

/// Below this λ the series form is used.
pub(crate) const SERIES_LIMIT: f64 = 3.0;

/// e^{−λ}-based sech, safe for large λ.
fn sech<D: DualNum<Primitive = f64> + Copy>(lambda: D) -> D {
    let e = (-lambda).exp();
    e * 2.0 / (e * e + 1.0)
}

/// The characteristic function, with a positive factor that depends on the form (see above).
pub fn characteristic<D: DualNum<Primitive = f64> + Copy>(lambda: D, kappa: D) -> D {
    if lambda.re() < SERIES_LIMIT {
        let [s1, s2, s3, s4] = krylov(lambda);
        lambda * (s3 * s2 - s4 * s1) + kappa * (s4 * s2 - s1 * s1)
    } else {
        let (s, c) = lambda.sin_cos();
        lambda * (s - c * lambda.tanh()) - kappa * (sech(lambda) + c)
    }
}

/// Converged when the bracket is a few ulps wide; never on |f| alone (f has no natural scale).
struct Bracket;

impl Convergency<f64> for Bracket {
    fn is_root_found(&mut self, y: f64) -> bool {
        y == 0.0
    }
    fn is_converged(&mut self, x1: f64, x2: f64) -> bool {
        (x1 - x2).abs() <= 4.0 * f64::EPSILON * x1.abs().max(x2.abs()) + f64::MIN_POSITIVE
    }
    fn is_iteration_limit_reached(&mut self, iter: usize) -> bool {
        iter > 500
    }
}

/// Brent's method on a bracket that is known to hold one sign change.
pub(crate) fn brent(f: impl Fn(f64) -> f64, lower: f64, upper: f64) -> Option<f64> {
    find_root_brent(lower, upper, &f, &mut Bracket).ok()
}

/// Newton's method safeguarded by bisection (Press et al., *Numerical Recipes*, `rtsafe`) on
/// a bracket with one sign change; `f` returns the value and the derivative. A Newton step
/// that would leave the bracket, or that does not halve the step before last, is replaced by
/// bisection, so the iteration never diverges and converges quadratically near the root.
/// Converged when the step is a few ulps of the root.
pub(crate) fn safeguarded_newton(f: impl Fn(f64) -> (f64, f64), lower: f64, upper: f64) -> Option<f64> {
    let (f_lower, f_upper) = (f(lower).0, f(upper).0);
    if f_lower == 0.0 {
        return Some(lower);
    }
    if f_upper == 0.0 {
        return Some(upper);
    }
    if f_lower * f_upper > 0.0 || !(f_lower.is_finite() && f_upper.is_finite()) {
        return None;
    }
    // `negative` and `positive` are the bracket's ends where f < 0 and f > 0.
    let (mut negative, mut positive) = if f_lower < 0.0 { (lower, upper) } else { (upper, lower) };
    let mut x = 0.5 * (lower + upper);
    let mut step_before = (upper - lower).abs();
    let mut step = step_before;
    let (mut fx, mut slope) = f(x);
    for _ in 0..200 {
        let leaves_bracket = ((x - positive) * slope - fx) * ((x - negative) * slope - fx) > 0.0;
        if leaves_bracket || (2.0 * fx).abs() > (step_before * slope).abs() {
            step_before = step;
            step = 0.5 * (positive - negative);
            x = negative + step;
        } else {
            step_before = step;
            step = fx / slope;
            x -= step;
        }
        if step.abs() <= 4.0 * f64::EPSILON * x.abs() + f64::MIN_POSITIVE {
            return Some(x);
        }
        (fx, slope) = f(x);
        if fx == 0.0 {
            return Some(x);
        }
        if !fx.is_finite() {
            return None;
        }
        if fx < 0.0 {
            negative = x;
        } else {
            positive = x;
        }
    }
    None
}

/// Roots below this index are computed once per process and kept (they are constants).
const TABULATED: usize = 64;

/// The j-th positive root of the pinned-free equation tan λ = tanh λ (j ≥ 1), in
/// (jπ, jπ + π/2); `pinned_free_root(0)` is the rigid-body root 0.
pub fn pinned_free_root(j: usize) -> f64 {
    static TABLE: std::sync::OnceLock<Vec<f64>> = std::sync::OnceLock::new();
    match TABLE.get_or_init(|| (0..TABULATED).map(solve_pinned_free).collect()).get(j) {
        Some(root) => *root,
        None => solve_pinned_free(j),
    }
}

fn solve_pinned_free(j: usize) -> f64 {
    if j == 0 {
        return 0.0;
    }
    let lo = j as f64 * std::f64::consts::PI;
    let f = |l: f64| l.sin() - l.cos() * l.tanh();
    brent(f, lo, lo + std::f64::consts::FRAC_PI_2).expect("bracket holds a sign change")
}

/// The j-th root (j ≥ 1) of the clamped-free equation 1 + cos λ cosh λ = 0, in ((j−1)π, jπ).
pub fn clamped_free_root(j: usize) -> f64 {
    assert!(j >= 1, "clamped-free roots are numbered from 1");
    static TABLE: std::sync::OnceLock<Vec<f64>> = std::sync::OnceLock::new();
    match TABLE.get_or_init(|| (1..TABULATED).map(solve_clamped_free).collect()).get(j - 1) {
        Some(root) => *root,
        None => solve_clamped_free(j),
    }
}

fn solve_clamped_free(j: usize) -> f64 {
    let pi = std::f64::consts::PI;
    let f = |l: f64| sech(l) + l.cos();
    brent(f, (j - 1) as f64 * pi, j as f64 * pi).expect("bracket holds a sign change")
}
