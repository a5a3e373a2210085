//! The square-matrix operations the Padé and Fréchet recurrences are written against.
//!
//! The algorithms of [`crate::pade`] and [`crate::frechet`] are generic over [`Square`] so that
//! one implementation serves two storages: faer's heap-allocated [`Mat`] for any order, and
//! [`crate::fixed::Fixed`], a stack array of compile-time order N ≤ 16 used by the sensitivity
//! propagator, where a heap allocation per intermediate costs more than the arithmetic.

use crate::kernel;
use crate::norm::{abs_power_norm1, estimate_product_norm1, norm1};
use faer::linalg::solvers::{PartialPivLu, Solve};
use faer::{Mat, MatMut, MatRef};

/// Up to this order the norms of matrix powers are computed exactly (by forming the product).
pub(crate) const EXACT_POWER_NORMS: usize = 64;

/// A real square matrix with the operations of scaling and squaring and of Algorithm 6.4.
pub(crate) trait Square: Clone {
    /// LU factors with partial pivoting, for solves with (V − U).
    type Lu;
    /// A copy of an n×n view (its order must suit the storage).
    fn from_ref(a: MatRef<'_, f64>) -> Self;
    /// Writes the matrix into an n×n view.
    fn write_to(&self, out: MatMut<'_, f64>);
    /// The order n.
    fn order(&self) -> usize;
    /// The identity of order n.
    fn identity(n: usize) -> Self;
    /// self · b.
    fn product(&self, b: &Self) -> Self;
    /// self ← self + a·b.
    fn add_product(&mut self, a: &Self, b: &Self);
    /// Σ cₖ Mₖ (terms with cₖ = 0 are skipped; at least one term).
    fn combination(terms: &[(f64, &Self)]) -> Self;
    /// self ← factor · self.
    fn scale(&mut self, factor: f64);
    /// The induced one-norm.
    fn norm1(&self) -> f64;
    /// ‖ |self|ᵖ ‖₁, exactly.
    fn abs_power_norm1(&self, p: usize) -> f64;
    /// ‖F₁ F₂ ⋯ F_q‖₁: exact up to order [`EXACT_POWER_NORMS`], estimated above.
    fn product_norm1(factors: &[&Self]) -> f64;
    /// Whether every entry is finite.
    fn all_finite(&self) -> bool;
    /// The largest entry in magnitude.
    fn max_abs(&self) -> f64;
    /// LU factors of self.
    fn lu(&self) -> Self::Lu;
    /// rhs ← self⁻¹ rhs from the factors.
    fn solve_in_place(lu: &Self::Lu, rhs: &mut Self);

    /// a₁b₁ + a₂b₂.
    fn two_products(a1: &Self, b1: &Self, a2: &Self, b2: &Self) -> Self {
        let mut out = a1.product(b1);
        out.add_product(a2, b2);
        out
    }
}

impl Square for Mat<f64> {
    type Lu = PartialPivLu<f64>;

    fn from_ref(a: MatRef<'_, f64>) -> Self {
        a.to_owned()
    }
    fn write_to(&self, mut out: MatMut<'_, f64>) {
        out.copy_from(self);
    }
    fn order(&self) -> usize {
        self.nrows()
    }
    fn identity(n: usize) -> Self {
        Mat::identity(n, n)
    }
    fn product(&self, b: &Self) -> Self {
        kernel::mul(self, b)
    }
    fn add_product(&mut self, a: &Self, b: &Self) {
        kernel::mul_add(self, a, b);
    }
    fn combination(terms: &[(f64, &Self)]) -> Self {
        let (nrows, ncols) = (terms[0].1.nrows(), terms[0].1.ncols());
        let mut out = Mat::<f64>::zeros(nrows, ncols);
        for (c, m) in terms {
            if *c == 0.0 {
                continue;
            }
            for j in 0..ncols {
                let target = out
                    .col_mut(j)
                    .try_as_col_major_mut()
                    .expect("a fresh Mat is column-major")
                    .as_slice_mut();
                let source = m.col(j).try_as_col_major().expect("an owned Mat is column-major").as_slice();
                for (t, v) in target.iter_mut().zip(source) {
                    *t += c * v;
                }
            }
        }
        out
    }
    fn scale(&mut self, factor: f64) {
        for j in 0..self.ncols() {
            for v in
                self.col_mut(j).try_as_col_major_mut().expect("an owned Mat is column-major").as_slice_mut()
            {
                *v *= factor;
            }
        }
    }
    fn norm1(&self) -> f64 {
        norm1(self.as_ref())
    }
    fn abs_power_norm1(&self, p: usize) -> f64 {
        abs_power_norm1(self.as_ref(), p)
    }
    fn product_norm1(factors: &[&Self]) -> f64 {
        if factors[0].nrows() <= EXACT_POWER_NORMS {
            let mut product = factors[0].product(factors[1]);
            for f in &factors[2..] {
                product = product.product(f);
            }
            product.norm1()
        } else {
            estimate_product_norm1(&factors.iter().map(|f| f.as_ref()).collect::<Vec<_>>())
        }
    }
    fn all_finite(&self) -> bool {
        self.is_all_finite()
    }
    fn max_abs(&self) -> f64 {
        self.norm_max()
    }
    fn lu(&self) -> Self::Lu {
        self.partial_piv_lu()
    }
    fn solve_in_place(lu: &Self::Lu, rhs: &mut Self) {
        lu.solve_in_place(rhs);
    }
}
