//! Discretisation at a constant sample interval: Φ, Ψ_i and the input gains, by one exponential
//! of an augmented matrix and its Fréchet derivatives (Van Loan 1978).
//!
//! Free decay: Φ = e^{Ah}, Ψ_i = L(Ah, h∂A/∂P_i) — the blocks of exp(h[[A, 0], [∂A/∂P_i, A]])
//! of the paper's Eq. 9.
//!
//! Zero-order hold (u(t) = u_k on [t_k, t_{k+1})): exp(h[[A, B], [0, 0]]) = [[Φ, Γ], [0, I]] with
//! Γ = ∫₀ʰ e^{Aτ}dτ B, so x_{k+1} = Φx_k + Γu_k; the Fréchet derivative of the same exponential
//! in the direction h[[∂A/∂P_i, ∂B/∂P_i], [0, 0]] gives ∂Φ/∂P_i and ∂Γ/∂P_i together.
//!
//! First-order hold (u linear between samples): exp([[Ah, Bh, 0], [0, 0, I], [0, 0, 0]]) =
//! [[Φ, Γ₁, Γ₂], [0, I, I], [0, 0, I]], Γ₁ = ∫₀ʰ e^{Aσ}dσ B, Γ₂ = ∫₀ʰ e^{Aσ}(h − σ)/h dσ B, so
//! x_{k+1} = Φx_k + Γ₁u_k + Γ₂(u_{k+1} − u_k) = Φx_k + (Γ₁ − Γ₂)u_k + Γ₂u_{k+1}.

use crate::fixed::Fixed;
use crate::frechet::Frechet;
use crate::square::Square;
use crate::{ExpmError, Hold, check};
use faer::{Mat, MatRef};

/// Input gains of one step: x_{k+1} = Φx_k + Γ_now u_k + Γ_next u_{k+1}.
#[derive(Clone, Debug)]
pub(crate) struct InputGains {
    /// Γ_now (N × m).
    pub now: Mat<f64>,
    /// Γ_next (N × m), first-order hold only.
    pub next: Option<Mat<f64>>,
    /// ∂Γ_now/∂P_i stacked ((j·N) × m).
    pub d_now: Mat<f64>,
    /// ∂Γ_next/∂P_i stacked ((j·N) × m), first-order hold only.
    pub d_next: Option<Mat<f64>>,
}

/// Φ, the stacked Ψ_i ((j·N) × N) and the input gains.
#[derive(Clone, Debug)]
pub(crate) struct Discrete {
    pub phi: Mat<f64>,
    pub psi: Mat<f64>,
    pub gains: Option<InputGains>,
}

/// B and its derivatives, with the hold.
#[derive(Clone, Copy, Debug)]
pub(crate) struct InputMatrices<'a> {
    pub b: MatRef<'a, f64>,
    pub db: &'a [MatRef<'a, f64>],
    pub hold: Hold,
}

/// Discretises at interval `h` (A, the ∂A/∂P_i and the inputs already validated).
pub(crate) fn discretise(
    a: MatRef<'_, f64>,
    da: &[MatRef<'_, f64>],
    inputs: Option<InputMatrices<'_>>,
    h: f64,
) -> Result<Discrete, ExpmError> {
    let n = a.nrows();
    let m = inputs.map_or(0, |i| i.b.ncols());
    let blocks = match inputs.map(|i| i.hold) {
        None => 0,
        Some(Hold::Zero) => 1,
        Some(Hold::FirstOrder) => 2,
    };
    let order = n + blocks * m;
    // The augmented generator h·[[A, B, 0], [0, 0, I], [0, 0, 0]] (its leading part only for
    // free decay or zero-order hold).
    let mut generator = Mat::<f64>::zeros(order, order);
    generator.as_mut().submatrix_mut(0, 0, n, n).copy_from(a);
    if let Some(i) = inputs {
        generator.as_mut().submatrix_mut(0, n, n, m).copy_from(i.b);
        if blocks == 2 {
            for c in 0..m {
                generator[(n + c, n + m + c)] = 1.0 / h;
            }
        }
    }
    let directions: Vec<Option<Mat<f64>>> = (0..da.len())
        .map(|i| {
            let db = inputs.map(|inp| inp.db[i]);
            let nonzero = da[i].norm_max() > 0.0 || db.is_some_and(|d| d.norm_max() > 0.0);
            nonzero.then(|| {
                let mut d = Mat::<f64>::zeros(order, order);
                d.as_mut().submatrix_mut(0, 0, n, n).copy_from(da[i]);
                if let Some(db) = db {
                    d.as_mut().submatrix_mut(0, n, n, m).copy_from(db);
                }
                d
            })
        })
        .collect();
    macro_rules! fixed {
        ($($k:literal)*) => {
            match order {
                $($k => exponentials::<Fixed<$k>>(&generator, &directions, h)?,)*
                _ => exponentials::<Mat<f64>>(&generator, &directions, h)?,
            }
        };
    }
    let (exp, derivatives) = fixed!(1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16);
    let j = da.len();
    let phi = exp.as_ref().submatrix(0, 0, n, n).to_owned();
    let mut psi = Mat::<f64>::zeros(j * n, n);
    for (i, d) in derivatives.iter().enumerate() {
        if let Some(d) = d {
            psi.as_mut().submatrix_mut(i * n, 0, n, n).copy_from(d.as_ref().submatrix(0, 0, n, n));
        }
    }
    let gains = inputs.map(|_| {
        let block = |e: &Mat<f64>, b: usize| e.as_ref().submatrix(0, n + b * m, n, m).to_owned();
        let stacked = |b: usize| {
            let mut out = Mat::<f64>::zeros(j * n, m);
            for (i, d) in derivatives.iter().enumerate() {
                if let Some(d) = d {
                    out.as_mut().submatrix_mut(i * n, 0, n, m).copy_from(d.as_ref().submatrix(
                        0,
                        n + b * m,
                        n,
                        m,
                    ));
                }
            }
            out
        };
        if blocks == 2 {
            // Γ_now = Γ₁ − Γ₂, Γ_next = Γ₂ (and the same for the derivatives).
            let (g1, g2) = (block(&exp, 0), block(&exp, 1));
            let (d1, d2) = (stacked(0), stacked(1));
            InputGains { now: &g1 - &g2, next: Some(g2), d_now: &d1 - &d2, d_next: Some(d2) }
        } else {
            InputGains { now: block(&exp, 0), next: None, d_now: stacked(0), d_next: None }
        }
    });
    Ok(Discrete { phi, psi, gains })
}

/// e^{hG} and L(hG, hE_i) (None for a zero direction).
type Exponentials = (Mat<f64>, Vec<Option<Mat<f64>>>);

/// e^{hG} and L(hG, hE_i) for the non-zero directions, in the storage `M`.
fn exponentials<M: Square>(
    generator: &Mat<f64>,
    directions: &[Option<Mat<f64>>],
    h: f64,
) -> Result<Exponentials, ExpmError> {
    let order = generator.nrows();
    let mut g = M::from_ref(generator.as_ref());
    g.scale(h);
    let work = Frechet::new(&g)?;
    let mut exp = Mat::zeros(order, order);
    work.exp().write_to(exp.as_mut());
    let derivatives = directions
        .iter()
        .map(|d| {
            d.as_ref()
                .map(|d| {
                    let mut e = M::from_ref(d.as_ref());
                    e.scale(h);
                    let l = work.derivative(&e)?;
                    let mut out = Mat::zeros(order, order);
                    l.write_to(out.as_mut());
                    Ok(out)
                })
                .transpose()
        })
        .collect::<Result<Vec<_>, ExpmError>>()?;
    Ok((exp, derivatives))
}

/// The free state and its sensitivities at time `t` ≥ 0: x(t) = e^{At}x₀ and
/// s_i(t) = e^{At}s_i(0) + L(At, t∂A/∂P_i)x₀ (the blocks of Eq. 9's exponential at step t).
pub(crate) fn advance(
    a: MatRef<'_, f64>,
    da: &[MatRef<'_, f64>],
    x0: &[f64],
    s0: MatRef<'_, f64>,
    t: f64,
) -> Result<(Vec<f64>, Mat<f64>), ExpmError> {
    let n = a.nrows();
    let d = discretise(a, da, None, t)?;
    let x0m = MatRef::from_column_major_slice(x0, n, 1);
    let x = &d.phi * x0m;
    let mut s = &d.phi * s0;
    for i in 0..da.len() {
        let psi_i = d.psi.as_ref().submatrix(i * n, 0, n, n);
        let add = psi_i * x0m;
        for r in 0..n {
            s[(r, i)] += add[(r, 0)];
        }
    }
    Ok(((0..n).map(|r| x[(r, 0)]).collect(), s))
}

/// One step of ẋ = A x + B u with u linear over the step, and its parameter derivatives:
/// x(t + h) = Φ x(t) + Γ_now u(t) + Γ_next u(t + h) (first-order hold; Γ_now + Γ_next is the
/// zero-order-hold gain ∫₀ʰ e^{Aσ}dσ B). For exponential integrators of ẋ = A x + B τ(x), which
/// treat the nonlinear forcing τ as such an input over a step.
#[derive(Clone, Debug)]
pub struct StepGains {
    /// Φ = e^{Ah} (N × N).
    pub phi: Mat<f64>,
    /// Γ_now (N × m).
    pub now: Mat<f64>,
    /// Γ_next (N × m).
    pub next: Mat<f64>,
    /// ∂Φ/∂P_i, one per parameter.
    pub d_phi: Vec<Mat<f64>>,
    /// ∂Γ_now/∂P_i.
    pub d_now: Vec<Mat<f64>>,
    /// ∂Γ_next/∂P_i.
    pub d_next: Vec<Mat<f64>>,
}

/// [`StepGains`] at interval `h`, by one augmented exponential and its Fréchet derivatives in the
/// directions h[[∂A/∂P_i, ∂B/∂P_i, 0], [0, 0, 0], [0, 0, 0]] (Van Loan 1978).
///
/// # Errors
/// [`ExpmError`] for non-square, mismatched or non-finite matrices, or h not finite and > 0.
pub fn step_gains(
    a: MatRef<'_, f64>,
    da: &[MatRef<'_, f64>],
    b: MatRef<'_, f64>,
    db: &[MatRef<'_, f64>],
    h: f64,
) -> Result<StepGains, ExpmError> {
    let n = check::square("a", a)?;
    if n == 0 {
        return Err(ExpmError::Empty { name: "a" });
    }
    check::finite("a", a)?;
    let m = b.ncols();
    check::shape("b", b, n, m)?;
    check::finite("b", b)?;
    check::count("db", db.len(), da.len())?;
    for d in da {
        check::shape("da", *d, n, n)?;
        check::finite("da", *d)?;
    }
    for d in db {
        check::shape("db", *d, n, m)?;
        check::finite("db", *d)?;
    }
    if !(h.is_finite() && h > 0.0) {
        return Err(ExpmError::InvalidInterval { h });
    }
    let d = discretise(a, da, Some(InputMatrices { b, db, hold: Hold::FirstOrder }), h)?;
    let gains = d.gains.expect("a hold gives gains");
    let split = |stacked: &Mat<f64>, cols: usize| -> Vec<Mat<f64>> {
        (0..da.len()).map(|i| stacked.as_ref().submatrix(i * n, 0, n, cols).to_owned()).collect()
    };
    Ok(StepGains {
        d_phi: split(&d.psi, n),
        d_now: split(&gains.d_now, m),
        d_next: split(gains.d_next.as_ref().expect("first-order hold"), m),
        phi: d.phi,
        now: gains.now,
        next: gains.next.expect("first-order hold"),
    })
}
