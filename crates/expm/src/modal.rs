//! Outputs and sensitivities in modal coordinates, for a diagonalisable, well-conditioned A.
//!
//! With A = V Λ V⁻¹, μ_j = e^{λ_j h}, z₀ = V⁻¹x₀, the Fréchet derivative in modal coordinates
//! is Daleckii–Krein's Ψ̃_i = (h V⁻¹ ∂A/∂P_i V) ∘ Δ, Δ_jl = (e^{λ_j h} − e^{λ_l h})/(λ_j h − λ_l h).
//! The sensitivity recursion w_{k+1} = M w_k + Ψ̃ (μᵏ ∘ z₀) sums in closed form (a geometric
//! series): with G_jl = Ψ̃_jl z₀_l and D_jl = G_jl/(μ_j − μ_l) (j ≠ l),
//!
//! ```text
//! w_k[j] = μ_jᵏ (w₀[j] + Σ_l D_jl) − Σ_l D_jl μ_lᵏ + G_jj k μ_jᵏ⁻¹,
//! ```
//!
//! so every output and sensitivity is `Re(P₁ [μ_jᵏ] + P₂ [k μ_jᵏ⁻¹])`: two complex matrix products
//! of (j+1)p × N coefficients with the N × K matrices of powers — O(N³j) to set up and
//! O(p j N K) to evaluate, against O(j N² K) for the propagation.
//!
//! Accuracy: the divided differences cancel when two μ are close and V amplifies rounding by
//! κ(V); the method is used only when κ₁(V)·(1 + max|μ|/min|μ_j − μ_l|) ≤ 1e8 (relative error
//! ≲ 1e-8), otherwise the caller propagates.

use crate::ExpmError;
use crate::response::Response;
use faer::linalg::solvers::Solve;
use faer::{Accum, Mat, MatRef, c64};

/// Largest accepted amplification κ₁(V)·(1 + max|μ|/min gap).
const MAX_AMPLIFICATION: f64 = 1e8;
/// Samples per chunk of powers.
const CHUNK: usize = 1024;

fn complex(m: MatRef<'_, f64>) -> Mat<c64> {
    Mat::from_fn(m.nrows(), m.ncols(), |i, j| c64::new(m[(i, j)], 0.0))
}

fn norm1(m: MatRef<'_, c64>) -> f64 {
    (0..m.ncols()).map(|j| (0..m.nrows()).map(|i| m[(i, j)].norm()).sum::<f64>()).fold(0.0, f64::max)
}

/// (e^a − e^b)/(a − b), e^a when a = b, without cancellation for close a, b.
fn exp_divided_difference(a: c64, b: c64) -> c64 {
    let d = a - b;
    let eb = b.exp();
    if d.norm() < 1e-4 {
        // e^b (e^d − 1)/d = e^b (1 + d/2 + d²/6 + d³/24 + d⁴/120)
        eb * (c64::new(1.0, 0.0)
            + d * (c64::new(0.5, 0.0)
                + d * (c64::new(1.0 / 6.0, 0.0) + d * (c64::new(1.0 / 24.0, 0.0) + d / 120.0))))
    } else {
        (a.exp() - eb) / d
    }
}

/// Fills `out` by the modal method, or returns `Ok(false)` (leaving `out` untouched) if A is
/// not diagonalisable well enough for it.
#[allow(clippy::too_many_arguments)]
pub(crate) fn modal_response(
    a: MatRef<'_, f64>,
    da: &[MatRef<'_, f64>],
    c: MatRef<'_, f64>,
    dc: Option<&[MatRef<'_, f64>]>,
    x0: &[f64],
    dx0: Option<MatRef<'_, f64>>,
    h: f64,
    out: &mut Response,
) -> Result<bool, ExpmError> {
    let (n, j, p) = (a.nrows(), da.len(), c.nrows());
    let k_samples = out.outputs.nrows();
    let Ok(eig) = a.eigen() else { return Ok(false) };
    let lambda: Vec<c64> = (0..n).map(|i| eig.S()[i] * h).collect();
    let v = eig.U().to_owned();
    let v_inv = v.partial_piv_lu().solve(Mat::<c64>::identity(n, n));
    if (0..n).any(|i| (0..n).any(|k| !v_inv[(i, k)].re.is_finite() || !v_inv[(i, k)].im.is_finite())) {
        return Ok(false);
    }
    let mu: Vec<c64> = lambda.iter().map(|l| l.exp()).collect();
    let max_mu = mu.iter().map(|m| m.norm()).fold(0.0, f64::max);
    let mut gap = f64::INFINITY;
    for a_ in 0..n {
        for b in a_ + 1..n {
            gap = gap.min((mu[a_] - mu[b]).norm());
        }
    }
    let kappa = norm1(v.as_ref()) * norm1(v_inv.as_ref());
    let amplification = kappa * (1.0 + max_mu / gap);
    if amplification.is_nan() || amplification > MAX_AMPLIFICATION {
        return Ok(false);
    }
    let z0: Vec<c64> = (0..n).map(|r| (0..n).map(|l| v_inv[(r, l)] * x0[l]).sum()).collect();
    let cv = complex(c) * &v; // p × n
    // Coefficients: rows (col·p + o) for col 0 = outputs, col i+1 = ∂/∂P_i.
    let mut p1 = Mat::<c64>::zeros((j + 1) * p, n);
    let mut p2 = Mat::<c64>::zeros(j * p, n);
    for o in 0..p {
        for l in 0..n {
            p1[(o, l)] = cv[(o, l)] * z0[l];
        }
    }
    for (i, dai) in da.iter().enumerate() {
        let f = &v_inv * (complex(*dai) * &v);
        // G_jl = h F_jl Δ_jl z0_l; D_jl = G_jl/(μ_j − μ_l).
        let mut d = Mat::<c64>::zeros(n, n);
        let mut row_sum = vec![c64::new(0.0, 0.0); n];
        let mut diag = vec![c64::new(0.0, 0.0); n];
        for r in 0..n {
            for l in 0..n {
                let g = f[(r, l)] * h * exp_divided_difference(lambda[r], lambda[l]) * z0[l];
                if r == l {
                    diag[r] = g;
                } else {
                    let dl = g / (mu[r] - mu[l]);
                    d[(r, l)] = dl;
                    row_sum[r] += dl;
                }
            }
        }
        let w0: Vec<c64> = match dx0 {
            Some(dx) => (0..n).map(|r| (0..n).map(|l| v_inv[(r, l)] * dx[(l, i)]).sum()).collect(),
            None => vec![c64::new(0.0, 0.0); n],
        };
        let cvd = &cv * &d;
        let dcv = dc.map(|dc| complex(dc[i]) * &v);
        for o in 0..p {
            for l in 0..n {
                let mut e = cv[(o, l)] * (w0[l] + row_sum[l]) - cvd[(o, l)];
                if let Some(dcv) = &dcv {
                    e += dcv[(o, l)] * z0[l];
                }
                p1[((i + 1) * p + o, l)] = e;
                p2[(i * p + o, l)] = cv[(o, l)] * diag[l];
            }
        }
    }
    // Evaluate over chunks of samples: powers μᵏ and k μᵏ⁻¹, then two complex GEMMs.
    let chunk = CHUNK.min(k_samples.max(1));
    let mut powers = Mat::<c64>::zeros(n, chunk);
    let mut ramps = Mat::<c64>::zeros(n, chunk);
    let mut y1 = Mat::<c64>::zeros((j + 1) * p, chunk);
    let mut y2 = Mat::<c64>::zeros(j * p, chunk);
    let mut current: Vec<c64> = vec![c64::new(1.0, 0.0); n]; // μ^k
    let mut previous: Vec<c64> = vec![c64::new(0.0, 0.0); n]; // μ^{k−1} (0 for k = 0)
    let par = faer::get_global_parallelism();
    let mut start = 0;
    while start < k_samples {
        let len = chunk.min(k_samples - start);
        for t in 0..len {
            let k = (start + t) as f64;
            for r in 0..n {
                powers[(r, t)] = current[r];
                ramps[(r, t)] = previous[r] * k;
                previous[r] = current[r];
                current[r] *= mu[r];
            }
        }
        faer::linalg::matmul::matmul(
            y1.as_mut().subcols_mut(0, len),
            Accum::Replace,
            p1.as_ref(),
            powers.as_ref().subcols(0, len),
            c64::new(1.0, 0.0),
            par,
        );
        if j > 0 {
            faer::linalg::matmul::matmul(
                y2.as_mut().subcols_mut(0, len),
                Accum::Replace,
                p2.as_ref(),
                ramps.as_ref().subcols(0, len),
                c64::new(1.0, 0.0),
                par,
            );
        }
        for t in 0..len {
            let k = start + t;
            for o in 0..p {
                out.outputs[(k, o)] = y1[(o, t)].re;
                for i in 0..j {
                    out.sensitivities[(k * p + o, i)] = y1[((i + 1) * p + o, t)].re + y2[(i * p + o, t)].re;
                }
            }
        }
        start += len;
    }
    Ok(true)
}
