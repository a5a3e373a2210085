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

/// Algorithm 5.1 of Al-Mohy & Higham (2009a): choose m and s, form the needed powers.
pub(crate) fn choose<M: Square>(a: &M, target: Target) -> Scaled<M> {
    // Powers of a matrix with a huge norm would overflow before they are scaled: halve first.
    let norm = a.norm1();
    if norm > HUGE_NORM {
        let extra = norm.log2().ceil() as u32;
        let mut smaller = a.clone();
        smaller.scale(0.5f64.powi(extra as i32));
        let mut s = choose(&smaller, target);
        s.squarings += extra;
        s.scale *= 0.5f64.powi(extra as i32);
        return s;
    }
    let n = a.order();
    let finish = |degree: usize, squarings: u32, mut powers: Vec<M>| {
        let scale = 0.5f64.powi(squarings as i32);
        let mut x = a.clone();
        if squarings > 0 {
            x.scale(scale);
            for (k, p) in powers.iter_mut().enumerate().skip(1) {
                p.scale(scale.powi(2 * k as i32));
            }
        }
        Scaled { degree, squarings, scale, x, powers }
    };
    let identity = M::identity(n);
    let a2 = a.product(a);
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
    let eta1 = d4_estimate.max(d6_estimate);
    if eta1 <= target.threshold(3) && extra_squarings(a, 3) == 0 {
        return finish(3, 0, vec![identity, a2]);
    }
    let a4 = a4_early.unwrap_or_else(|| a2.product(&a2));
    let d4 = a4.norm1().powf(0.25);
    let eta2 = d4.max(d6_estimate);
    if eta2 <= target.threshold(5) && extra_squarings(a, 5) == 0 {
        return finish(5, 0, vec![identity, a2, a4]);
    }
    let a6 = a6_early.unwrap_or_else(|| a2.product(&a4));
    let d6 = a6.norm1().powf(1.0 / 6.0);
    let d8 = M::product_norm1(&[&a4, &a4]).powf(0.125);
    let eta3 = d6.max(d8);
    if eta3 <= target.threshold(7) && extra_squarings(a, 7) == 0 {
        return finish(7, 0, vec![identity, a2, a4, a6]);
    }
    if eta3 <= target.threshold(9) && extra_squarings(a, 9) == 0 {
        let a8 = a4.product(&a4);
        return finish(9, 0, vec![identity, a2, a4, a6, a8]);
    }
    let d10 = M::product_norm1(&[&a4, &a6]).powf(0.1);
    let eta4 = d8.max(d10);
    let eta5 = eta3.min(eta4);
    let mut squarings =
        if eta5 > 0.0 { (eta5 / target.threshold(13)).log2().ceil().max(0.0) as u32 } else { 0 };
    let mut scaled = a.clone();
    scaled.scale(0.5f64.powi(squarings as i32));
    squarings += extra_squarings(&scaled, 13);
    finish(13, squarings, vec![identity, a2, a4, a6])
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
