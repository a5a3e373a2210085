//! Krylov–Duncan functions by their Taylor series, for small arguments (u ≤ 3):
//! S₁ = (cosh u + cos u)/2 = Σ u^{4k}/(4k)!, S₂ = (sinh u + sin u)/2 = Σ u^{4k+1}/(4k+1)!,
//! S₃ = (cosh u − cos u)/2 = Σ u^{4k+2}/(4k+2)!, S₄ = (sinh u − sin u)/2 = Σ u^{4k+3}/(4k+3)!.
//! The series have positive terms, so there is no cancellation as u → 0 (the closed forms lose
//! all digits of S₃ and S₄ there). With ′ = d/du: S₁′ = S₄, S₂′ = S₁, S₃′ = S₂, S₄′ = S₃.

use num_dual::DualNum;

/// Number of series terms per function: for u ≤ 3 the first omitted term is below
/// 3⁴⁸/48! ≈ 6e-39, far below double precision.
const TERMS: usize = 12;

/// [S₁(u), S₂(u), S₃(u), S₄(u)].
pub(crate) fn krylov<D: DualNum<Primitive = f64> + Copy>(u: D) -> [D; 4] {
    let mut out = [D::from(0.0); 4];
    let mut term = D::from(1.0); // u^m / m!
    for m in 0..4 * TERMS {
        out[m % 4] += term;
        term = term * u / ((m + 1) as f64);
    }
    out
}
