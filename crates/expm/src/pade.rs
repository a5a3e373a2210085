//! Choice of the Padé degree m and the number of squarings s (Al-Mohy & Higham 2009a,
//! Algorithm 5.1), and the E-independent part of evaluating r_m(2⁻ˢA).
//!
//! The diagonal Padé approximant is r_m(X) = (V − U)⁻¹(V + U) with
//! U = X Σ_k b_{2k+1} X^{2k} and V = Σ_k b_{2k} X^{2k}.  Its backward error for e^X is
//! bounded through a power series with nonnegative coefficients, which may be evaluated at
//! α_p(X) = max(‖X^p‖^{1/p}, ‖X^{p+1}‖^{1/(p+1)}) instead of ‖X‖ (Theorem 4.2 of the paper);
//! this is what avoids the over-scaling of the 2005 algorithm on non-normal matrices.  The
//! extra term ℓ(X, m) adds squarings when the rounding errors of evaluating r_m would
//! otherwise dominate (Eq. 5.1 of the paper).
//!
//! For the Fréchet derivative the thresholds θ_m are replaced by the smaller ℓ_m of
//! Al-Mohy & Higham (2009b, Table 6.1), which bound the backward error of L(X, E) as well;
//! the same Theorem 4.2 lets them be compared with α_p(X).

use crate::ExpmError;
use crate::square::{EXACT_POWER_NORMS, Square};

/// Unit roundoff of `f64`, 2⁻⁵³.
pub(crate) const UNIT_ROUNDOFF: f64 = 1.110_223_024_625_156_5e-16;

/// Padé coefficients b_0..b_m for m = 3, 5, 7, 9, 13 (Higham 2005, Eq. 2.1 scaled to integers).
pub(crate) fn coefficients(m: usize) -> &'static [f64] {
    match m {
        3 => &[120.0, 60.0, 12.0, 1.0],
        5 => &[30240.0, 15120.0, 3360.0, 420.0, 30.0, 1.0],
        7 => &[17297280.0, 8648640.0, 1995840.0, 277200.0, 25200.0, 1512.0, 56.0, 1.0],
        9 => &[
            17643225600.0,
            8821612800.0,
            2075673600.0,
            302702400.0,
            30270240.0,
            2162160.0,
            110880.0,
            3960.0,
            90.0,
            1.0,
        ],
        13 => &[
            64764752532480000.0,
            32382376266240000.0,
            7771770303897600.0,
            1187353796428800.0,
            129060195264000.0,
            10559470521600.0,
            670442572800.0,
            33522128640.0,
            1323241920.0,
            40840800.0,
            960960.0,
            16380.0,
            182.0,
            1.0,
        ],
        _ => unreachable!("only degrees 3, 5, 7, 9 and 13 are used"),
    }
}

/// What the approximation must be accurate for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Target {
    /// e^X alone: θ_m of Higham (2005), Table 2.3.
    Exponential,
    /// e^X and L(X, E): ℓ_m of Al-Mohy & Higham (2009b), Table 6.1.
    FrechetDerivative,
}

impl Target {
    fn threshold(self, m: usize) -> f64 {
        match (self, m) {
            (Target::Exponential, 3) => 1.495_585_217_958_292e-2,
            (Target::Exponential, 5) => 2.539_398_330_063_23e-1,
            (Target::Exponential, 7) => 9.504_178_996_162_932e-1,
            (Target::Exponential, 9) => 2.097_847_961_257_068,
            (Target::Exponential, 13) => 5.371_920_351_148_152,
            (Target::FrechetDerivative, 3) => 1.08e-2,
            (Target::FrechetDerivative, 5) => 2.00e-1,
            (Target::FrechetDerivative, 7) => 7.83e-1,
            (Target::FrechetDerivative, 9) => 1.78,
            (Target::FrechetDerivative, 13) => 4.74,
            _ => unreachable!("only degrees 3, 5, 7, 9 and 13 are used"),
        }
    }
}

/// 1/|c_{2m+1}| with c_{2m+1} = (m!)² / ((2m)! (2m+1)!), the leading coefficient of the
/// backward-error series of r_m.
fn reciprocal_leading_coefficient(m: usize) -> f64 {
    match m {
        3 => 100800.0,
        5 => 10059033600.0,
        7 => 4487938430976000.0,
        9 => 5914384781877411840000.0,
        13 => 113250775606021113483283660800000000.0,
        _ => unreachable!("only degrees 3, 5, 7, 9 and 13 are used"),
    }
}

/// ℓ(X, m) of Al-Mohy & Higham (2009a), Eq. 5.1: extra squarings needed so that the rounding
/// errors in evaluating r_m(X) stay below the unit roundoff.
fn extra_squarings<M: Square>(x: &M, m: usize) -> u32 {
    let norm = x.norm1();
    if norm == 0.0 {
        return 0;
    }
    let alpha = x.abs_power_norm1(2 * m + 1) / (reciprocal_leading_coefficient(m) * norm);
    if alpha.is_nan() || alpha <= 0.0 {
        return 0;
    }
    let value = ((alpha / UNIT_ROUNDOFF).log2() / (2 * m) as f64).ceil();
    if value.is_finite() && value > 0.0 { value as u32 } else { 0 }
}

/// Above this one-norm, A is halved before its powers are formed (A⁸ would overflow).
const HUGE_NORM: f64 = 1e30;

/// The even powers of the scaled matrix that the chosen degree needs, and the choice itself.
pub(crate) struct Scaled<M> {
    /// Padé degree m.
    pub degree: usize,
    /// Number of squarings s.
    pub squarings: u32,
    /// 2⁻ˢ (the factor applied to A and to every direction E).
    pub scale: f64,
    /// X = 2⁻ˢ A.
    pub x: M,
    /// [I, X², X⁴, X⁶, X⁸] as far as the degree needs (X⁸ only for m = 9).
    pub powers: Vec<M>,
}

/// Highest power whose norm the derivative guard looks at: 2·13, for the degree-13 remainder.
const GUARD_POWERS: usize = 26;

/// Upper bounds of ‖A^i‖₁ for i = 0..=26 from the norms that are known (`known[i]` for ‖A^i‖),
/// the others bounded by sub-multiplicativity ‖A^i‖ ≤ ‖A^l‖‖A^{i−l}‖.
fn power_bounds(known: &[(usize, f64)]) -> [f64; GUARD_POWERS + 1] {
    let mut a = [f64::INFINITY; GUARD_POWERS + 1];
    a[0] = 1.0;
    for &(i, v) in known {
        if i <= GUARD_POWERS {
            a[i] = a[i].min(v);
        }
    }
    for i in 2..=GUARD_POWERS {
        for l in 1..i {
            a[i] = a[i].min(a[l] * a[i - l]);
        }
    }
    a
}

/// δ_k = (S_k/k)^{1/(k−1)} with S_k = Σ_{i+j=k−1} ‖X^i‖‖X^j‖, for X = scale·A (`norms` of A).
///
/// The Padé approximant's backward error for the Fréchet derivative in direction F is the
/// derivative of the remainder series, ΔF = Σ_{k ≥ 2m+1} c_k Σ_{i+j=k−1} X^i F X^j, so
/// ‖ΔF‖/‖F‖ ≤ Σ c_k S_k ≤ Σ c_k k δ^{k−1} = h′(δ) when every S_k ≤ k δ^{k−1}: δ ≤ ℓ_m keeps it
/// below the unit roundoff (Al-Mohy & Higham 2009b, whose ℓ_m bound exactly h′). Evaluated at
/// k = 2m + 1, the remainder's leading term. The powers of X alone cannot see these terms: a
/// nilpotent X (X⁴ = 0) has ‖X^k‖ = 0 for k ≥ 4, but X³FX³ ≠ 0.
fn cross_delta(norms: &[f64; GUARD_POWERS + 1], scale: f64, k: usize) -> f64 {
    let s_k: f64 = (0..k).map(|i| norms[i] * norms[k - 1 - i] * scale.powi((k - 1) as i32)).sum();
    (s_k / k as f64).powf(1.0 / (k - 1) as f64)
}

/// Exact ‖A^i‖₁ for i = 1..=26, by forming the powers of `scale`·A (None if they overflow);
/// returned as norms of A (divided back by scaleⁱ).
fn exact_power_norms<M: Square>(a: &M, scale: f64) -> Option<[f64; GUARD_POWERS + 1]> {
    let mut x = a.clone();
    x.scale(scale);
    let mut norms = [0.0; GUARD_POWERS + 1];
    norms[0] = 1.0;
    let mut power = x.clone();
    for i in 1..=GUARD_POWERS {
        if i > 1 {
            power = power.product(&x);
        }
        let v = power.norm1();
        if !v.is_finite() {
            return None;
        }
        norms[i] = v / scale.powi(i as i32);
    }
    Some(norms)
}

/// Makes an α-based choice (m, s) safe for the Fréchet derivative: keeps it if
/// max(δ_{m+1}, δ_{2m+1}) ≤ ℓ_m (see [`cross_delta`]) with the bounds from the known norms; otherwise with the
/// exact norms of the powers (formed only then, and only for n ≤ 64); otherwise raises s, or
/// moves to m = 13, until the condition holds. Returns (m, s).
fn guard_derivative<M: Square>(a: &M, known: &[(usize, f64)], degree: usize, squarings: u32) -> (usize, u32) {
    let target = Target::FrechetDerivative;
    // δ at k = 2m + 1 bounds the remainder (truncation); at k = m + 1, the degree of the
    // polynomials U and V, it keeps their evaluation from cancelling (rounding).
    let delta = |norms: &[f64; GUARD_POWERS + 1], m: usize, s: u32| {
        let scale = 0.5f64.powi(s as i32);
        cross_delta(norms, scale, m + 1).max(cross_delta(norms, scale, 2 * m + 1))
    };
    let safe = |norms: &[f64; GUARD_POWERS + 1], m: usize, s: u32| delta(norms, m, s) <= target.threshold(m);
    let bounds = power_bounds(known);
    if safe(&bounds, degree, squarings) {
        return (degree, squarings);
    }
    let norms = if a.order() <= EXACT_POWER_NORMS {
        exact_power_norms(a, 0.5f64.powi(squarings as i32)).unwrap_or(bounds)
    } else {
        bounds
    };
    if safe(&norms, degree, squarings) {
        return (degree, squarings);
    }
    // The fewest squarings with m = 13 (δ is homogeneous of degree one in the scale).
    let needed = delta(&norms, 13, squarings);
    let extra = if needed.is_finite() && needed > 0.0 {
        (needed / target.threshold(13)).log2().ceil().max(0.0) as u32
    } else if needed == 0.0 {
        0
    } else {
        64
    };
    (13, squarings + extra)
}

/// Algorithm 5.1 of Al-Mohy & Higham (2009a): choose m and s, form the needed powers; for the
/// Fréchet derivative, the choice is then made safe for the cross terms X^iFX^j
/// ([`guard_derivative`]).
///
/// # Errors
/// [`ExpmError::NormOverflow`] if ‖A‖₁ itself overflows.
pub(crate) fn choose<M: Square>(a: &M, target: Target) -> Result<Scaled<M>, ExpmError> {
    // Powers of a matrix with a huge norm would overflow before they are scaled: halve first.
    let norm = a.norm1();
    if !norm.is_finite() {
        return Err(ExpmError::NormOverflow { largest: a.max_abs() });
    }
    if norm > HUGE_NORM {
        // norm ≤ f64::MAX, so at most 1024 halvings bring it below 1 (one level of recursion).
        let extra = norm.log2().ceil() as u32;
        let mut smaller = a.clone();
        smaller.scale(0.5f64.powi(extra as i32));
        let mut s = choose(&smaller, target)?;
        s.squarings += extra;
        s.scale *= 0.5f64.powi(extra as i32);
        return Ok(s);
    }
    let (degree, squarings, powers, known) = alpha_choice(a, target);
    let (degree, squarings) = match target {
        Target::Exponential => (degree, squarings),
        Target::FrechetDerivative => guard_derivative(a, &known, degree, squarings),
    };
    let n = a.order();
    // The even powers the degree needs (formed already for the α choice, or now).
    let mut powers = powers;
    if powers.is_empty() {
        powers.push(M::identity(n));
    }
    let needed = match degree {
        3 => 2,
        5 => 3,
        7 | 13 => 4,
        _ => 5,
    };
    while powers.len() < needed {
        let next =
            if powers.len() == 1 { a.product(a) } else { powers[powers.len() - 1].product(&powers[1]) };
        powers.push(next);
    }
    powers.truncate(needed);
    let scale = 0.5f64.powi(squarings as i32);
    let mut x = a.clone();
    if squarings > 0 {
        x.scale(scale);
        for (k, p) in powers.iter_mut().enumerate().skip(1) {
            p.scale(scale.powi(2 * k as i32));
        }
    }
    Ok(Scaled { degree, squarings, scale, x, powers })
}

/// The α_p-based choice of Al-Mohy & Higham (2009a, Algorithm 5.1) with the thresholds of
/// `target`: (m, s, the powers [I, A², A⁴, …] formed on the way (unscaled), the power norms
/// known on the way as (i, ‖A^i‖₁)).
fn alpha_choice<M: Square>(a: &M, target: Target) -> (usize, u32, Vec<M>, Vec<(usize, f64)>) {
    let n = a.order();
    let identity = M::identity(n);
    let a2 = a.product(a);
    let mut known = vec![(1, a.norm1()), (2, a2.norm1())];
    // For small n, A⁴ and A⁶ are formed now (they are needed for m ≥ 5 anyway, and the exact
    // norms of the powers are cheaper than the estimator's bookkeeping).
    let small = n <= EXACT_POWER_NORMS;
    let a4_early = small.then(|| a2.product(&a2));
    let a6_early = a4_early.as_ref().map(|a4| a2.product(a4));
    let d4_estimate = match &a4_early {
        Some(a4) => a4.norm1(),
        None => M::product_norm1(&[&a2, &a2]),
    }
    .powf(0.25);
    let d6_estimate = match &a6_early {
        Some(a6) => a6.norm1(),
        None => M::product_norm1(&[&a2, &a2, &a2]),
    }
    .powf(1.0 / 6.0);
    if small {
        known.push((4, d4_estimate.powi(4)));
        known.push((6, d6_estimate.powi(6)));
    }
    let eta1 = d4_estimate.max(d6_estimate);
    if eta1 <= target.threshold(3) && extra_squarings(a, 3) == 0 {
        return (3, 0, vec![identity, a2], known);
    }
    let a4 = a4_early.unwrap_or_else(|| a2.product(&a2));
    let d4 = a4.norm1().powf(0.25);
    known.push((4, a4.norm1()));
    let eta2 = d4.max(d6_estimate);
    if eta2 <= target.threshold(5) && extra_squarings(a, 5) == 0 {
        return (5, 0, vec![identity, a2, a4], known);
    }
    let a6 = a6_early.unwrap_or_else(|| a2.product(&a4));
    let d6 = a6.norm1().powf(1.0 / 6.0);
    known.push((6, a6.norm1()));
    let d8 = M::product_norm1(&[&a4, &a4]).powf(0.125);
    let eta3 = d6.max(d8);
    if eta3 <= target.threshold(7) && extra_squarings(a, 7) == 0 {
        return (7, 0, vec![identity, a2, a4, a6], known);
    }
    if eta3 <= target.threshold(9) && extra_squarings(a, 9) == 0 {
        let a8 = a4.product(&a4);
        known.push((8, a8.norm1()));
        return (9, 0, vec![identity, a2, a4, a6, a8], known);
    }
    let d10 = M::product_norm1(&[&a4, &a6]).powf(0.1);
    let eta4 = d8.max(d10);
    let eta5 = eta3.min(eta4);
    let mut squarings =
        if eta5 > 0.0 { (eta5 / target.threshold(13)).log2().ceil().max(0.0) as u32 } else { 0 };
    let mut scaled = a.clone();
    scaled.scale(0.5f64.powi(squarings as i32));
    squarings += extra_squarings(&scaled, 13);
    (13, squarings, vec![identity, a2, a4, a6], known)
}

/// U and V of r_m(X), with the odd-part polynomial W (U = X W) kept for the Fréchet derivative.
pub(crate) struct PadeParts<M> {
    pub u: M,
    pub v: M,
    /// m ≤ 9: W = Σ b_{2k+1} X^{2k}.  m = 13: W = X⁶ Z₁ + b₇X⁶ + b₅X⁴ + b₃X² + b₁I.
    pub w: M,
    /// m = 13 only: Z₁ = b₁₃X⁶ + b₁₁X⁴ + b₉X² and Z₂ = b₁₂X⁶ + b₁₀X⁴ + b₈X².
    pub z: Option<(M, M)>,
}

/// Evaluates U and V of the chosen degree (Higham 2005, Eqs. 2.3–2.4 for m = 13).
pub(crate) fn evaluate<M: Square>(s: &Scaled<M>) -> PadeParts<M> {
    let b = coefficients(s.degree);
    let p = &s.powers;
    if s.degree == 13 {
        let z1 = M::combination(&[(b[13], &p[3]), (b[11], &p[2]), (b[9], &p[1])]);
        let z2 = M::combination(&[(b[12], &p[3]), (b[10], &p[2]), (b[8], &p[1])]);
        let mut w = M::combination(&[(b[7], &p[3]), (b[5], &p[2]), (b[3], &p[1]), (b[1], &p[0])]);
        w.add_product(&p[3], &z1);
        let mut v = M::combination(&[(b[6], &p[3]), (b[4], &p[2]), (b[2], &p[1]), (b[0], &p[0])]);
        v.add_product(&p[3], &z2);
        let u = s.x.product(&w);
        PadeParts { u, v, w, z: Some((z1, z2)) }
    } else {
        let odd: Vec<(f64, &M)> = p.iter().enumerate().map(|(k, m)| (b[2 * k + 1], m)).collect();
        let even: Vec<(f64, &M)> = p.iter().enumerate().map(|(k, m)| (b[2 * k], m)).collect();
        let w = M::combination(&odd);
        let v = M::combination(&even);
        let u = s.x.product(&w);
        PadeParts { u, v, w, z: None }
    }
}

/// r_m = (V − U)⁻¹ (V + U), and the factorisation of V − U for later solves.
pub(crate) fn quotient<M: Square>(u: &M, v: &M) -> (M, M::Lu) {
    let q = M::combination(&[(1.0, v), (-1.0, u)]);
    let mut p = M::combination(&[(1.0, v), (1.0, u)]);
    let lu = q.lu();
    M::solve_in_place(&lu, &mut p);
    (p, lu)
}
