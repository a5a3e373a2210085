//! [`Fixed`]: an N×N matrix on the stack, N a compile-time constant, for the small systems of
//! the MEM (the paper's model has 8 states). Loops of constant length unroll and vectorize, and
//! nothing is allocated: at N = 8 a product is 512 multiply–adds, less work than a heap
//! allocation and its release.

use crate::square::Square;
use faer::{MatMut, MatRef};

/// Column-major N×N matrix: `self.0[j][i]` is entry (i, j).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Fixed<const N: usize>(pub [[f64; N]; N]);

/// LU factors with partial pivoting: L (unit, strictly below the diagonal) and U share `lu`;
/// `swaps[k]` is the row exchanged with row k at step k.
#[derive(Clone, Copy, Debug)]
pub(crate) struct FixedLu<const N: usize> {
    lu: [[f64; N]; N],
    swaps: [usize; N],
}

impl<const N: usize> Fixed<N> {
    #[inline(always)]
    fn add_product_kernel(&mut self, a: &Self, b: &Self) {
        for j in 0..N {
            self.0[j] = mat_vec_add(&a.0, &b.0[j], self.0[j]);
        }
    }

    #[inline(always)]
    fn lu_kernel(&self) -> FixedLu<N> {
        let mut lu = self.0;
        let mut swaps = [0; N];
        for k in 0..N {
            let pivot = (k..N).fold(k, |best, r| if lu[k][r].abs() > lu[k][best].abs() { r } else { best });
            swaps[k] = pivot;
            if pivot != k {
                for column in lu.iter_mut() {
                    column.swap(k, pivot);
                }
            }
            let diagonal = lu[k][k];
            for r in k + 1..N {
                lu[k][r] /= diagonal;
            }
            for c in k + 1..N {
                let factor = lu[c][k];
                for r in k + 1..N {
                    lu[c][r] -= lu[k][r] * factor;
                }
            }
        }
        FixedLu { lu, swaps }
    }
    #[inline(always)]
    fn solve_kernel(lu: &FixedLu<N>, rhs: &mut Self) {
        for column in rhs.0.iter_mut() {
            for k in 0..N {
                column.swap(k, lu.swaps[k]);
            }
            // L y = b (unit lower), then U x = y.
            for k in 0..N {
                let yk = column[k];
                for r in k + 1..N {
                    column[r] -= lu.lu[k][r] * yk;
                }
            }
            for k in (0..N).rev() {
                column[k] /= lu.lu[k][k];
                let xk = column[k];
                for r in 0..k {
                    column[r] -= lu.lu[k][r] * xk;
                }
            }
        }
    }

    /// max(1ᵀ|A|ᵖ): the row vector vᵀ ← vᵀ|A| is |A|ᵀv, a matrix–vector product with the
    /// columns of |A|ᵀ (the rows of |A|).
    #[inline(always)]
    fn abs_power_norm_kernel(&self, p: usize) -> f64 {
        let rows: [[f64; N]; N] = std::array::from_fn(|i| std::array::from_fn(|j| self.0[j][i].abs()));
        let mut v = [1.0; N];
        for _ in 0..p {
            v = mat_vec_add(&rows, &v, [0.0; N]);
        }
        v.into_iter().fold(0.0, f64::max)
    }

    #[inline(always)]
    fn combination_kernel(terms: &[(f64, &Self)]) -> Self {
        let mut out = Fixed([[0.0; N]; N]);
        for (c, m) in terms {
            if *c == 0.0 {
                continue;
            }
            for j in 0..N {
                for i in 0..N {
                    out.0[j][i] = c.mul_add(m.0[j][i], out.0[j][i]);
                }
            }
        }
        out
    }
}

/// acc + M v for a column-major R×N matrix (`m[l]` is column l), accumulated in two independent
/// chains (even and odd columns) that are added at the end: half the dependent multiply–adds.
/// Written so that each column operation is one SIMD multiply–add with a broadcast scalar.
#[inline(always)]
pub(crate) fn mat_vec_add<const R: usize, const N: usize>(
    m: &[[f64; R]; N],
    v: &[f64; N],
    acc: [f64; R],
) -> [f64; R] {
    let mut even = acc;
    let mut odd = [0.0; R];
    for l in (0..N).step_by(2) {
        for r in 0..R {
            even[r] = m[l][r].mul_add(v[l], even[r]);
        }
        if l + 1 < N {
            for r in 0..R {
                odd[r] = m[l + 1][r].mul_add(v[l + 1], odd[r]);
            }
        }
    }
    std::array::from_fn(|r| even[r] + odd[r])
}

/// out ← out + a·b as a pulp operation (a closure would not be inlined into the dispatched
/// function, and its `mul_add` would become a library call).
struct AddProduct<'a, const N: usize> {
    out: &'a mut Fixed<N>,
    a: &'a Fixed<N>,
    b: &'a Fixed<N>,
}

impl<const N: usize> pulp::WithSimd for AddProduct<'_, N> {
    type Output = ();
    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _simd: S) {
        self.out.add_product_kernel(self.a, self.b);
    }
}

/// LU factors as a pulp operation.
struct Factor<'a, const N: usize>(&'a Fixed<N>);

impl<const N: usize> pulp::WithSimd for Factor<'_, N> {
    type Output = FixedLu<N>;
    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _simd: S) -> FixedLu<N> {
        self.0.lu_kernel()
    }
}

/// Forward and back substitution as a pulp operation.
struct Substitute<'a, const N: usize> {
    lu: &'a FixedLu<N>,
    rhs: &'a mut Fixed<N>,
}

impl<const N: usize> pulp::WithSimd for Substitute<'_, N> {
    type Output = ();
    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _simd: S) {
        Fixed::solve_kernel(self.lu, self.rhs);
    }
}

/// ‖ |A|ᵖ ‖₁ as a pulp operation.
struct AbsPowerNorm<'a, const N: usize> {
    matrix: &'a Fixed<N>,
    power: usize,
}

impl<const N: usize> pulp::WithSimd for AbsPowerNorm<'_, N> {
    type Output = f64;
    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _simd: S) -> f64 {
        self.matrix.abs_power_norm_kernel(self.power)
    }
}

/// Σ cₖ Mₖ as a pulp operation.
struct Combination<'a, 'b, const N: usize>(&'a [(f64, &'b Fixed<N>)]);

impl<const N: usize> pulp::WithSimd for Combination<'_, '_, N> {
    type Output = Fixed<N>;
    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _simd: S) -> Fixed<N> {
        Fixed::combination_kernel(self.0)
    }
}

impl<const N: usize> Square for Fixed<N> {
    type Lu = FixedLu<N>;

    fn from_ref(a: MatRef<'_, f64>) -> Self {
        assert_eq!((a.nrows(), a.ncols()), (N, N), "a {N}×{N} matrix is required");
        Fixed(std::array::from_fn(|j| std::array::from_fn(|i| a[(i, j)])))
    }
    fn write_to(&self, mut out: MatMut<'_, f64>) {
        for j in 0..N {
            for i in 0..N {
                out[(i, j)] = self.0[j][i];
            }
        }
    }
    fn order(&self) -> usize {
        N
    }
    fn identity(_n: usize) -> Self {
        Fixed(std::array::from_fn(|j| std::array::from_fn(|i| if i == j { 1.0 } else { 0.0 })))
    }
    fn product(&self, b: &Self) -> Self {
        let mut out = Fixed([[0.0; N]; N]);
        out.add_product(self, b);
        out
    }
    fn add_product(&mut self, a: &Self, b: &Self) {
        // Compiled for the machine's best instruction set (AVX-512 or AVX2 with FMA) at run time.
        pulp::Arch::new().dispatch(AddProduct { out: self, a, b });
    }
    fn combination(terms: &[(f64, &Self)]) -> Self {
        pulp::Arch::new().dispatch(Combination(terms))
    }
    fn scale(&mut self, factor: f64) {
        self.0.iter_mut().flatten().for_each(|v| *v *= factor);
    }
    fn norm1(&self) -> f64 {
        self.0.iter().map(|c| c.iter().map(|v| v.abs()).sum::<f64>()).fold(0.0, f64::max)
    }
    fn abs_power_norm1(&self, p: usize) -> f64 {
        pulp::Arch::new().dispatch(AbsPowerNorm { matrix: self, power: p })
    }
    fn product_norm1(factors: &[&Self]) -> f64 {
        let mut product = factors[0].product(factors[1]);
        for f in &factors[2..] {
            product = product.product(f);
        }
        product.norm1()
    }
    fn all_finite(&self) -> bool {
        self.0.iter().flatten().all(|v| v.is_finite())
    }
    fn max_abs(&self) -> f64 {
        self.0.iter().flatten().fold(0.0, |m, v| m.max(v.abs()))
    }
    fn lu(&self) -> Self::Lu {
        pulp::Arch::new().dispatch(Factor(self))
    }
    fn solve_in_place(lu: &Self::Lu, rhs: &mut Self) {
        pulp::Arch::new().dispatch(Substitute { lu, rhs });
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::Mat;

    /// The fixed-size operations agree with faer's on a random 5×5 matrix.
    #[test]
    fn fixed_operations_match_faer() {
        // A small diagonal: partial pivoting has to exchange rows.
        let a = Mat::<f64>::from_fn(5, 5, |i, j| if i == j { 0.01 } else { ((3 * i + 7 * j) as f64).sin() });
        let b = Mat::<f64>::from_fn(5, 5, |i, j| ((2 * i + j) as f64).cos());
        let (fa, fb) = (Fixed::<5>::from_ref(a.as_ref()), Fixed::<5>::from_ref(b.as_ref()));
        let to_mat = |f: &Fixed<5>| {
            let mut m = Mat::zeros(5, 5);
            f.write_to(m.as_mut());
            m
        };
        // Tolerance: a few units of rounding on entries of size ≲ 10.
        let close = |x: &Mat<f64>, y: &Mat<f64>| (x - y).norm_max() < 1e-13;
        assert!(close(&to_mat(&fa.product(&fb)), &(&a * &b)));
        let mut x = fb;
        Fixed::solve_in_place(&fa.lu(), &mut x);
        assert!(close(&(&a * to_mat(&x)), &b));
        assert_eq!(fa.norm1(), Square::norm1(&a));
        assert!((fa.abs_power_norm1(3) - Square::abs_power_norm1(&a, 3)).abs() < 1e-12);
    }

    /// The whole Padé/Fréchet algorithm gives the same e^A and L(A, E) in both storages, for
    /// norms that select every degree and a few squarings. The faer path is itself checked
    /// against 60-digit references (tests/integration/reference); here the two differ only in the order
    /// of roundings, so they agree to a small multiple of u·‖e^A‖·(s + 1).
    #[test]
    fn fixed_and_faer_storage_give_the_same_frechet_derivative() {
        use crate::frechet::Frechet;
        for (case, norm) in [0.005, 0.15, 0.7, 1.5, 4.0, 40.0].into_iter().enumerate() {
            let raw = Mat::<f64>::from_fn(6, 6, |i, j| ((5 * i + 3 * j + case) as f64 * 0.7).sin());
            let a = &raw * faer::Scale(norm / Square::norm1(&raw));
            let e = Mat::<f64>::from_fn(6, 6, |i, j| ((i * j + case) as f64).cos());
            let dynamic = Frechet::new(&a).unwrap();
            let fixed = Frechet::new(&Fixed::<6>::from_ref(a.as_ref())).unwrap();
            assert_eq!(dynamic.choice(), fixed.choice());
            let to_mat = |f: &Fixed<6>| {
                let mut m = Mat::zeros(6, 6);
                f.write_to(m.as_mut());
                m
            };
            let exp = dynamic.exp();
            let tolerance = 1e-13 * exp.norm_max() * (dynamic.choice().1 as f64 + 1.0);
            assert!((&to_mat(fixed.exp()) - exp).norm_max() <= tolerance, "e^A, norm {norm}");
            let l_dynamic = dynamic.derivative(&e).unwrap();
            let l_fixed = to_mat(&fixed.derivative(&Fixed::<6>::from_ref(e.as_ref())).unwrap());
            let tolerance = 1e-13 * l_dynamic.norm_max() * (dynamic.choice().1 as f64 + 1.0);
            assert!((&l_fixed - &l_dynamic).norm_max() <= tolerance, "L(A, E), norm {norm}");
        }
    }
}
