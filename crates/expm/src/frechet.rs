//! The Fréchet derivative L(A, E) of the exponential, by differentiating the Padé and
//! squaring recurrences (Al-Mohy & Higham 2009b, Algorithm 6.4).
//!
//! With X = 2⁻ˢA and F = 2⁻ˢE, the derivative of r_m(X) = (V − U)⁻¹(V + U) in direction F
//! solves (V − U) L_r = L_U + L_V + (L_U − L_V) r_m(X), where L_U and L_V follow from the
//! product rule on the even powers: M₂ = X F + F X, M₄ = X² M₂ + M₂ X², ….  The squaring
//! phase R_{k+1} = R_k² has the derivative L_{k+1} = R_k L_k + L_k R_k.  Everything that
//! does not depend on E — the powers, U, V, the LU factors of V − U and the squares R_k — is
//! computed once in [`ExpmFrechet::new`] and shared by every direction.

use crate::pade::{self, PadeParts, Scaled, Target};
use crate::square::Square;
use crate::{ExpmError, check};
use faer::{Mat, MatRef};

/// The E-independent part of Algorithm 6.4 for any [`Square`] storage.
pub(crate) struct Frechet<M: Square> {
    /// ‖A‖₁, for overflow reports.
    norm: f64,
    scaled: Scaled<M>,
    /// The odd-part polynomial W of r_m (U = X W).
    w: M,
    /// m = 13 only: Z₁ and Z₂ of [`PadeParts`].
    z: Option<(M, M)>,
    lu: M::Lu,
    /// R_0 = r_m(X), R_1 = R_0², …, R_s = e^A.
    squares: Vec<M>,
}

impl<M: Square> Frechet<M> {
    /// e^A and the shared factors (A already checked to be square and finite).
    pub(crate) fn new(a: &M) -> Result<Self, ExpmError> {
        let norm = a.norm1();
        let scaled = pade::choose(a, Target::FrechetDerivative)?;
        let PadeParts { u, v, w, z } = pade::evaluate(&scaled);
        let (r0, lu) = pade::quotient(&u, &v);
        let mut squares = Vec::with_capacity(scaled.squarings as usize + 1);
        squares.push(r0);
        for k in 0..scaled.squarings as usize {
            let next = squares[k].product(&squares[k]);
            squares.push(next);
        }
        if !squares.last().expect("at least R_0").all_finite() {
            return Err(ExpmError::Overflow { norm, squarings: scaled.squarings });
        }
        Ok(Self { norm, scaled, w, z, lu, squares })
    }

    /// e^A.
    pub(crate) fn exp(&self) -> &M {
        self.squares.last().expect("at least R_0")
    }

    /// L(A, E) (E already checked to be of the same order and finite).
    pub(crate) fn derivative(&self, e: &M) -> Result<M, ExpmError> {
        let s = &self.scaled;
        let b = pade::coefficients(s.degree);
        let p = &s.powers;
        let x = &s.x;
        let mut f = e.clone();
        f.scale(s.scale);
        // m[k − 1] = M_k = d(X^{2k}) in direction F.
        let mut m: Vec<M> = Vec::with_capacity(p.len() - 1);
        m.push(M::two_products(x, &f, &f, x));
        if p.len() > 2 {
            m.push(M::two_products(&p[1], &m[0], &m[0], &p[1]));
        }
        if p.len() > 3 {
            m.push(M::two_products(&p[2], &m[0], &m[1], &p[1]));
        }
        if p.len() > 4 {
            m.push(M::two_products(&p[2], &m[1], &m[1], &p[2]));
        }
        let (lu_u, lu_v) = match &self.z {
            Some((z1, z2)) => {
                let lz1 = M::combination(&[(b[13], &m[2]), (b[11], &m[1]), (b[9], &m[0])]);
                let lz2 = M::combination(&[(b[12], &m[2]), (b[10], &m[1]), (b[8], &m[0])]);
                let mut lw = M::combination(&[(b[7], &m[2]), (b[5], &m[1]), (b[3], &m[0])]);
                lw.add_product(&p[3], &lz1);
                lw.add_product(&m[2], z1);
                let lu_u = M::two_products(x, &lw, &f, &self.w);
                let mut lu_v = M::combination(&[(b[6], &m[2]), (b[4], &m[1]), (b[2], &m[0])]);
                lu_v.add_product(&p[3], &lz2);
                lu_v.add_product(&m[2], z2);
                (lu_u, lu_v)
            }
            None => {
                let odd: Vec<(f64, &M)> = m.iter().enumerate().map(|(k, mk)| (b[2 * k + 3], mk)).collect();
                let even: Vec<(f64, &M)> = m.iter().enumerate().map(|(k, mk)| (b[2 * k + 2], mk)).collect();
                (M::two_products(x, &M::combination(&odd), &f, &self.w), M::combination(&even))
            }
        };
        // (V − U) L_r = (L_U + L_V) + (L_U − L_V) r_m(X)
        let difference = M::combination(&[(1.0, &lu_u), (-1.0, &lu_v)]);
        let mut l = M::combination(&[(1.0, &lu_u), (1.0, &lu_v)]);
        l.add_product(&difference, &self.squares[0]);
        M::solve_in_place(&self.lu, &mut l);
        for r in &self.squares[..self.squares.len() - 1] {
            l = M::two_products(r, &l, &l, r);
        }
        if !l.all_finite() {
            return Err(ExpmError::Overflow { norm: self.norm, squarings: s.squarings });
        }
        Ok(l)
    }

    /// The Padé degree m and the number of squarings s that were chosen.
    pub(crate) fn choice(&self) -> (usize, u32) {
        (self.scaled.degree, self.scaled.squarings)
    }
}

/// e^A together with everything needed to evaluate L(A, E) for any number of directions E.
///
/// ```
/// use faer::mat;
/// let a = mat![[-1.0, 2.0], [0.0, -3.0]];
/// let work = expm::ExpmFrechet::new(a.as_ref()).unwrap();
/// // L(A, A) = A e^A, because A commutes with itself.
/// let l = work.derivative(a.as_ref()).unwrap();
/// let expected = &a * work.exp();
/// assert!((&l - &expected).norm_max() < 1e-14);
/// ```
pub struct ExpmFrechet {
    n: usize,
    core: Frechet<Mat<f64>>,
}

impl ExpmFrechet {
    /// Computes e^A and the E-independent part of the Fréchet derivative.
    ///
    /// # Errors
    /// As [`crate::expm`].
    pub fn new(a: MatRef<'_, f64>) -> Result<Self, ExpmError> {
        let n = check::square("a", a)?;
        check::finite("a", a)?;
        Ok(Self { n, core: Frechet::new(&a.to_owned())? })
    }

    /// The order of A.
    pub fn n(&self) -> usize {
        self.n
    }

    /// e^A.
    pub fn exp(&self) -> MatRef<'_, f64> {
        self.core.exp().as_ref()
    }

    /// The Padé degree m that was chosen.
    pub fn degree(&self) -> usize {
        self.core.choice().0
    }

    /// The number of squarings s that was chosen.
    pub fn squarings(&self) -> u32 {
        self.core.choice().1
    }

    /// L(A, E), the Fréchet derivative of e^A in direction E.
    ///
    /// # Errors
    /// [`ExpmError::ShapeMismatch`] if E is not n×n, [`ExpmError::NonFinite`] for NaN or
    /// infinite entries, [`ExpmError::Overflow`] if the derivative does not fit in `f64`.
    pub fn derivative(&self, e: MatRef<'_, f64>) -> Result<Mat<f64>, ExpmError> {
        check::shape("e", e, self.n, self.n)?;
        check::finite("e", e)?;
        self.core.derivative(&e.to_owned())
    }
}

/// The Fréchet derivative's answer is not meaningful to working precision: the relative
/// condition number κ_exp(A) = ‖L(A)‖_F ‖A‖_F / ‖e^A‖_F is so large that κ·u exceeds the
/// accuracy a caller can use ([`ExpmFrechet::ill_conditioned`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IllConditioned {
    /// The estimate of κ_exp(A) (power method on L(A)*L(A), a lower bound within a small factor).
    pub condition: f64,
    /// κ·u: the relative error any backward-stable method may commit (u = 2⁻⁵³).
    pub error_bound: f64,
}

impl std::fmt::Display for IllConditioned {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "the exponential is ill-conditioned (κ ≈ {:.1e}): its value and derivatives may carry a relative \
             error up to {:.1e}",
            self.condition, self.error_bound
        )
    }
}

impl ExpmFrechet {
    /// An estimate of the relative condition number κ_exp(A) = ‖L(A)‖ ‖A‖/‖e^A‖ in the
    /// Frobenius norm (Higham, *Functions of Matrices*, §3.4): ‖L(A)‖ by `iterations` steps of the
    /// power method on L(A)*L(A), whose adjoint is L(Aᵀ, ·), from a fixed start.
    ///
    /// # Errors
    /// As [`ExpmFrechet::new`] for Aᵀ and [`ExpmFrechet::derivative`].
    pub fn condition(&self, a: MatRef<'_, f64>, iterations: usize) -> Result<f64, ExpmError> {
        check::shape("a", a, self.n, self.n)?;
        let adjoint = ExpmFrechet::new(a.transpose())?;
        let n = self.n;
        // A fixed, dense start (no randomness: the same answer on every run).
        let mut e = Mat::<f64>::from_fn(n, n, |i, j| 1.0 + 0.5 * ((3 * i + 7 * j) % 5) as f64);
        let mut gain = 0.0;
        for _ in 0..iterations.max(1) {
            let size = e.norm_l2();
            if size.is_nan() || size <= 0.0 {
                break;
            }
            e *= faer::Scale(1.0 / size);
            let l = self.derivative(e.as_ref())?;
            gain = l.norm_l2();
            e = adjoint.derivative(l.as_ref())?;
        }
        let exp = self.exp().norm_l2();
        Ok(if exp > 0.0 { gain * a.norm_l2() / exp } else { f64::INFINITY })
    }

    /// Whether κ_exp(A)·u exceeds `tolerance` (e.g. 1e-6): then the answer is not meaningful
    /// to that relative accuracy, and the caller should say so rather than use it silently.
    ///
    /// # Errors
    /// As [`Self::condition`].
    pub fn ill_conditioned(
        &self,
        a: MatRef<'_, f64>,
        tolerance: f64,
    ) -> Result<Option<IllConditioned>, ExpmError> {
        let condition = self.condition(a, 4)?;
        let error_bound = condition * f64::EPSILON / 2.0;
        Ok((error_bound > tolerance).then_some(IllConditioned { condition, error_bound }))
    }
}

/// (e^A, L(A, E)): the exponential and its Fréchet derivative in direction E.
///
/// # Errors
/// As [`ExpmFrechet::new`] and [`ExpmFrechet::derivative`].
pub fn expm_frechet(a: MatRef<'_, f64>, e: MatRef<'_, f64>) -> Result<(Mat<f64>, Mat<f64>), ExpmError> {
    let work = ExpmFrechet::new(a)?;
    let l = work.derivative(e)?;
    Ok((work.exp().to_owned(), l))
}

/// (e^A, [L(A, E_1), …, L(A, E_j)]): several directions sharing the E-independent work.
///
/// # Errors
/// As [`ExpmFrechet::new`] and [`ExpmFrechet::derivative`].
pub fn expm_frechet_many(
    a: MatRef<'_, f64>,
    directions: &[MatRef<'_, f64>],
) -> Result<(Mat<f64>, Vec<Mat<f64>>), ExpmError> {
    let work = ExpmFrechet::new(a)?;
    let ls = directions.iter().map(|e| work.derivative(*e)).collect::<Result<Vec<_>, _>>()?;
    Ok((work.exp().to_owned(), ls))
}
