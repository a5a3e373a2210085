//! The Fréchet derivative L(A, E) of the exponential, by differentiating the Padé and
//! squaring recurrences (Al-Mohy & Higham 2009b, Algorithm 6.4).
//!
//! With X = 2⁻ˢA and F = 2⁻ˢE, the derivative of r_m(X) = (V − U)⁻¹(V + U) in direction F
//! solves (V − U) L_r = L_U + L_V + (L_U − L_V) r_m(X), where L_U and L_V follow from the
//! product rule on the even powers: M₂ = X F + F X, M₄ = X² M₂ + M₂ X², ….  The squaring
//! phase R_{k+1} = R_k² has the derivative L_{k+1} = R_k L_k + L_k R_k.  Everything that
//! does not depend on E — the powers, U, V, the LU factors of V − U and the squares R_k — is
//! computed once in [`ExpmFrechet::new`] and shared by every direction.

use crate::exponential::{overflow_check, pade_quotient};
use crate::kernel::{mul, mul_add, two_products};
use crate::pade::{self, PadeParts, Scaled, Target, combine};
use crate::{ExpmError, check};
use faer::linalg::solvers::{PartialPivLu, Solve};
use faer::{Mat, MatRef};

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
    norm: f64,
    scaled: Scaled,
    /// The odd-part polynomial W of r_m (U = X W).
    w: Mat<f64>,
    /// m = 13 only: Z₁ and Z₂ of [`PadeParts`].
    z: Option<(Mat<f64>, Mat<f64>)>,
    lu: PartialPivLu<f64>,
    /// R_0 = r_m(X), R_1 = R_0², …, R_s = e^A.
    squares: Vec<Mat<f64>>,
}

impl ExpmFrechet {
    /// Computes e^A and the E-independent part of the Fréchet derivative.
    ///
    /// # Errors
    /// As [`crate::expm`].
    pub fn new(a: MatRef<'_, f64>) -> Result<Self, ExpmError> {
        let n = check::square("a", a)?;
        check::finite("a", a)?;
        let scaled = pade::choose(a, Target::FrechetDerivative);
        let PadeParts { u, v, w, z } = pade::evaluate(&scaled);
        let (r0, lu) = pade_quotient(&u, &v);
        let mut squares = Vec::with_capacity(scaled.squarings as usize + 1);
        squares.push(r0);
        for k in 0..scaled.squarings as usize {
            let next = mul(&squares[k], &squares[k]);
            squares.push(next);
        }
        let last = squares.pop().expect("at least R_0");
        squares.push(overflow_check(last, a, scaled.squarings)?);
        Ok(Self { n, norm: crate::norm1(a), scaled, w, z, lu, squares })
    }

    /// The order of A.
    pub fn n(&self) -> usize {
        self.n
    }

    /// e^A.
    pub fn exp(&self) -> MatRef<'_, f64> {
        self.squares.last().expect("at least R_0").as_ref()
    }

    /// The Padé degree m that was chosen.
    pub fn degree(&self) -> usize {
        self.scaled.degree
    }

    /// The number of squarings s that was chosen.
    pub fn squarings(&self) -> u32 {
        self.scaled.squarings
    }

    /// L(A, E), the Fréchet derivative of e^A in direction E.
    ///
    /// # Errors
    /// [`ExpmError::ShapeMismatch`] if E is not n×n, [`ExpmError::NonFinite`] for NaN or
    /// infinite entries, [`ExpmError::Overflow`] if the derivative does not fit in `f64`.
    pub fn derivative(&self, e: MatRef<'_, f64>) -> Result<Mat<f64>, ExpmError> {
        check::shape("e", e, self.n, self.n)?;
        check::finite("e", e)?;
        let s = &self.scaled;
        let b = pade::coefficients(s.degree);
        let p = &s.powers;
        let x = &s.x;
        let f = Mat::from_fn(self.n, self.n, |r, c| e[(r, c)] * s.scale);
        // m[k − 1] = M_k = d(X^{2k}) in direction F.
        let mut m: Vec<Mat<f64>> = Vec::with_capacity(p.len() - 1);
        m.push(two_products(x, &f, &f, x));
        if p.len() > 2 {
            m.push(two_products(&p[1], &m[0], &m[0], &p[1]));
        }
        if p.len() > 3 {
            m.push(two_products(&p[2], &m[0], &m[1], &p[1]));
        }
        if p.len() > 4 {
            m.push(two_products(&p[2], &m[1], &m[1], &p[2]));
        }
        let (lu_u, lu_v) = match &self.z {
            Some((z1, z2)) => {
                let lz1 = combine(&[(b[13], &m[2]), (b[11], &m[1]), (b[9], &m[0])]);
                let lz2 = combine(&[(b[12], &m[2]), (b[10], &m[1]), (b[8], &m[0])]);
                let mut lw = combine(&[(b[7], &m[2]), (b[5], &m[1]), (b[3], &m[0])]);
                mul_add(&mut lw, &p[3], &lz1);
                mul_add(&mut lw, &m[2], z1);
                let lu_u = two_products(x, &lw, &f, &self.w);
                let mut lu_v = combine(&[(b[6], &m[2]), (b[4], &m[1]), (b[2], &m[0])]);
                mul_add(&mut lu_v, &p[3], &lz2);
                mul_add(&mut lu_v, &m[2], z2);
                (lu_u, lu_v)
            }
            None => {
                let odd: Vec<(f64, &Mat<f64>)> =
                    m.iter().enumerate().map(|(k, mk)| (b[2 * k + 3], mk)).collect();
                let even: Vec<(f64, &Mat<f64>)> =
                    m.iter().enumerate().map(|(k, mk)| (b[2 * k + 2], mk)).collect();
                (two_products(x, &combine(&odd), &f, &self.w), combine(&even))
            }
        };
        // (V − U) L_r = (L_U + L_V) + (L_U − L_V) r_m(X)
        let difference = combine(&[(1.0, &lu_u), (-1.0, &lu_v)]);
        let mut l = combine(&[(1.0, &lu_u), (1.0, &lu_v)]);
        mul_add(&mut l, &difference, &self.squares[0]);
        self.lu.solve_in_place(&mut l);
        for r in &self.squares[..self.squares.len() - 1] {
            l = two_products(r, &l, &l, r);
        }
        if check::finite("result", l.as_ref()).is_err() {
            return Err(ExpmError::Overflow { norm: self.norm, squarings: s.squarings });
        }
        Ok(l)
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
