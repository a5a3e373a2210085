//! # era — the Eigensystem Realization Algorithm on a free decay
//!
//! Juang & Pappa (1985, *An eigensystem realization algorithm for modal parameter
//! identification and model reduction*, J. Guid. Control Dyn. 8(5)): the paper's Table 2
//! "Measurements" row comes from ERA.
//!
//! A free decay y_k = C Aᵏ x₀ (p outputs, k = 0..K−1) plays the role of the Markov parameters.
//! With the block Hankel matrices H(k)_{ij} = y_{k+i+j} (r block rows, s columns) and the
//! truncated SVD H(0) ≈ U_n Σ_n V_nᵀ of order n, the realization is
//!
//! ```text
//! A_d = Σ_n^{-1/2} U_nᵀ H(1) V_n Σ_n^{-1/2},  C_d = [first p rows of U_n Σ_n^{1/2}],
//! x̂₀ = [first column of Σ_n^{1/2} V_nᵀ].
//! ```
//!
//! Eigenvalues z_j of A_d give s_j = ln(z_j)/h, frequency |s_j|/2π \[Hz\] (undamped) and damping
//! ratio −Re(s_j)/|s_j|. Two indicators flag spurious (noise) modes:
//! * **consistency** (an extended modal amplitude coherence): the modal time history identified
//!   from the data, row j of Φ⁻¹Σ_n^{1/2}V_nᵀ, against its ideal z_jᵏ·q_j(0); 1 for a mode that
//!   decays as an exponential over the whole record;
//! * **MPC** (modal phase collinearity) of the output shape C_dφ_j, 1 for a real (normal) mode;
//!   reported only with two or more outputs.
//!
//! Outputs of different units should be normalised first ([`identify`] divides each by its RMS).

use faer::{Mat, MatRef, c64};

/// What can go wrong.
#[derive(Debug, thiserror::Error)]
pub enum EraError {
    /// Too few samples for the requested order.
    #[error(
        "ERA needs more samples: {samples} samples cannot support order {order} (need at least {needed})"
    )]
    TooShort {
        /// Samples given.
        samples: usize,
        /// Order requested.
        order: usize,
        /// Samples needed.
        needed: usize,
    },
    /// The order must be positive.
    #[error("the model order must be at least 1")]
    ZeroOrder,
    /// A linear-algebra step failed.
    #[error("ERA's {0} did not converge")]
    Numerical(&'static str),
}

/// One identified mode (Im s ≥ 0).
#[derive(Clone, Debug, serde::Serialize)]
pub struct EraMode {
    /// Undamped natural frequency \[Hz\].
    pub frequency_hz: f64,
    /// Damping ratio.
    pub damping_ratio: f64,
    /// Consistency indicator in \[0, 1\].
    pub consistency: f64,
    /// Modal phase collinearity in \[0, 1\] (None with one output).
    pub mpc: Option<f64>,
    /// Share of the response this mode carries (‖C_dφ_j‖·|q_j(0)|, normalised to sum 1).
    pub contribution: f64,
    /// Whether the indicators mark it as physical (consistency ≥ 0.9 and contribution ≥ 0.1 %).
    pub physical: bool,
}

/// The result of ERA.
#[derive(Clone, Debug, serde::Serialize)]
pub struct EraResult {
    /// Modes sorted by frequency.
    pub modes: Vec<EraMode>,
    /// Singular values of H(0), largest first (to choose the order).
    pub singular_values: Vec<f64>,
    /// Order used.
    pub order: usize,
}

/// Runs ERA on `data` (K × p) sampled at interval `h`, realization order `order`.
///
/// # Errors
/// [`EraError::TooShort`], [`EraError::ZeroOrder`], [`EraError::Numerical`].
pub fn identify(data: MatRef<'_, f64>, h: f64, order: usize) -> Result<EraResult, EraError> {
    if order == 0 {
        return Err(EraError::ZeroOrder);
    }
    let (k_samples, p) = (data.nrows(), data.ncols());
    let needed = 2 * order + 2;
    if k_samples < needed {
        return Err(EraError::TooShort { samples: k_samples, order, needed });
    }
    // Normalise each output by its RMS so that units do not weigh (computed on the output
    // divided by its peak, so that data of any magnitude, 1e-300 or 1e300, neither underflow
    // nor overflow when squared).
    let scale: Vec<f64> = (0..p)
        .map(|o| {
            let peak = (0..k_samples).map(|k| data[(k, o)].abs()).fold(0.0, f64::max);
            if !(peak > 0.0 && peak.is_finite()) {
                return 1.0;
            }
            let ms = (0..k_samples).map(|k| (data[(k, o)] / peak).powi(2)).sum::<f64>() / k_samples as f64;
            peak * ms.sqrt()
        })
        .collect();
    let y = |k: usize, o: usize| data[(k, o)] / scale[o];
    let s_cols = ((k_samples - 1) / 2).min(300);
    let r_rows = (k_samples - 1 - s_cols).min((300 / p).max(order + 1));
    if r_rows * p < order || s_cols < order {
        return Err(EraError::TooShort { samples: k_samples, order, needed: 2 * order * p + 2 });
    }
    let hankel = |shift: usize| Mat::from_fn(r_rows * p, s_cols, |i, j| y(shift + i / p + j, i % p));
    let h0 = hankel(0);
    let h1 = hankel(1);
    let svd = h0.thin_svd().map_err(|_| EraError::Numerical("SVD"))?;
    let sv: Vec<f64> = (0..svd.S().dim()).map(|i| svd.S()[i]).collect();
    let n = order.min(sv.iter().filter(|v| **v > 1e-14 * sv[0]).count());
    let u = svd.U().subcols(0, n);
    let v = svd.V().subcols(0, n);
    let root: Vec<f64> = sv[..n].iter().map(|s| s.sqrt()).collect();
    // A = Σ^{-1/2} Uᵀ H(1) V Σ^{-1/2}: the products once, O(rows × cols × n).
    let h1v = &h1 * v;
    let projected = u.transpose() * &h1v;
    let a_d = Mat::from_fn(n, n, |i, j| projected[(i, j)] / (root[i] * root[j]));
    let c_d = Mat::from_fn(p, n, |o, j| u[(o, j)] * root[j]);
    // Modal time histories: Σ^{1/2} Vᵀ, n × s.
    let controllability = Mat::from_fn(n, s_cols, |i, b| root[i] * v[(b, i)]);
    let eig = a_d.eigen().map_err(|_| EraError::Numerical("eigen-decomposition"))?;
    let z = eig.S();
    let phi = eig.U();
    let phi_inv = complex_inverse(phi).ok_or(EraError::Numerical("modal matrix inversion"))?;
    let mut modes = Vec::new();
    let mut total = 0.0;
    let mut raw = Vec::new();
    for j in 0..n {
        let zj = z[j];
        if zj.im < 0.0 {
            continue;
        }
        let (modulus, angle) = ((zj.re * zj.re + zj.im * zj.im).sqrt(), zj.im.atan2(zj.re));
        let s = c64::new(modulus.ln() / h, angle / h);
        let s_abs = (s.re * s.re + s.im * s.im).sqrt();
        let frequency_hz = s_abs / (2.0 * std::f64::consts::PI);
        let damping_ratio = if s_abs > 0.0 { -s.re / s_abs } else { 1.0 };
        // Identified modal history q_j(b) and its ideal z_j^b q_j(0).
        let history: Vec<c64> =
            (0..s_cols).map(|b| (0..n).map(|i| phi_inv[(j, i)] * controllability[(i, b)]).sum()).collect();
        let mut ideal = Vec::with_capacity(s_cols);
        let mut power = c64::new(1.0, 0.0);
        for _ in 0..s_cols {
            ideal.push(power * history[0]);
            power *= zj;
        }
        let consistency = mac(&history, &ideal);
        let shape: Vec<c64> = (0..p).map(|o| (0..n).map(|i| phi[(i, j)] * c_d[(o, i)]).sum()).collect();
        let mpc = (p >= 2).then(|| phase_collinearity(&shape));
        let size = shape.iter().map(|c| c.norm_sqr()).sum::<f64>().sqrt() * history[0].norm();
        // A complex pair carries twice the response of one eigenvalue.
        let weight = if zj.im > 0.0 { 2.0 * size } else { size };
        total += weight;
        raw.push((frequency_hz, damping_ratio, consistency, mpc, weight));
    }
    for (frequency_hz, damping_ratio, consistency, mpc, weight) in raw {
        let contribution = if total > 0.0 { weight / total } else { 0.0 };
        modes.push(EraMode {
            frequency_hz,
            damping_ratio,
            consistency,
            mpc,
            contribution,
            physical: consistency >= 0.9 && contribution >= 1e-3,
        });
    }
    modes.sort_by(|a, b| a.frequency_hz.total_cmp(&b.frequency_hz));
    Ok(EraResult { modes, singular_values: sv, order: n })
}

fn mac(a: &[c64], b: &[c64]) -> f64 {
    let cross: c64 = a.iter().zip(b).map(|(x, y)| x * y.conj()).sum();
    let na: f64 = a.iter().map(|x| x.norm_sqr()).sum();
    let nb: f64 = b.iter().map(|x| x.norm_sqr()).sum();
    if na == 0.0 || nb == 0.0 { 0.0 } else { cross.norm_sqr() / (na * nb) }
}

/// MPC of Pappa et al.: (λ₁ − λ₂)²/(λ₁ + λ₂)² of the 2×2 covariance of (Re ψ, Im ψ).
fn phase_collinearity(shape: &[c64]) -> f64 {
    let sxx: f64 = shape.iter().map(|c| c.re * c.re).sum();
    let syy: f64 = shape.iter().map(|c| c.im * c.im).sum();
    let sxy: f64 = shape.iter().map(|c| c.re * c.im).sum();
    let trace = sxx + syy;
    if trace == 0.0 {
        return 0.0;
    }
    let det = sxx * syy - sxy * sxy;
    let disc = (trace * trace / 4.0 - det).max(0.0).sqrt();
    let (l1, l2) = (trace / 2.0 + disc, trace / 2.0 - disc);
    ((l1 - l2) / (l1 + l2)).powi(2)
}

/// Inverse of a small complex matrix by Gauss–Jordan with partial pivoting.
fn complex_inverse(m: MatRef<'_, c64>) -> Option<Mat<c64>> {
    let n = m.nrows();
    let mut a = m.to_owned();
    let mut inv =
        Mat::<c64>::from_fn(n, n, |i, j| if i == j { c64::new(1.0, 0.0) } else { c64::new(0.0, 0.0) });
    for col in 0..n {
        let pivot = (col..n).max_by(|&x, &y| a[(x, col)].norm().total_cmp(&a[(y, col)].norm()))?;
        if a[(pivot, col)].norm() == 0.0 {
            return None;
        }
        for k in 0..n {
            let (t1, t2) = (a[(col, k)], inv[(col, k)]);
            a[(col, k)] = a[(pivot, k)];
            inv[(col, k)] = inv[(pivot, k)];
            a[(pivot, k)] = t1;
            inv[(pivot, k)] = t2;
        }
        let d = a[(col, col)];
        for k in 0..n {
            a[(col, k)] /= d;
            inv[(col, k)] /= d;
        }
        for r in 0..n {
            if r != col {
                let f = a[(r, col)];
                for k in 0..n {
                    let (ac, ic) = (a[(col, k)], inv[(col, k)]);
                    a[(r, k)] -= f * ac;
                    inv[(r, k)] -= f * ic;
                }
            }
        }
    }
    Some(inv)
}
