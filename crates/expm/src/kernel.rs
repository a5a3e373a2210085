//! Matrix products through faer's GEMM (its nano-gemm kernels beat a plain loop even at 8×8),
//! single-threaded below 128³ multiply-adds. The accumulating forms let the Padé and Fréchet
//! recurrences build sums of products in one buffer instead of allocating a temporary per term.

use faer::{Accum, Mat, MatMut, MatRef, Par};

fn parallelism(m: usize, k: usize, n: usize) -> Par {
    if m * k * n >= 128 * 128 * 128 { faer::get_global_parallelism() } else { Par::Seq }
}

fn product_into(out: MatMut<'_, f64>, accum: Accum, a: MatRef<'_, f64>, b: MatRef<'_, f64>) {
    let par = parallelism(a.nrows(), a.ncols(), b.ncols());
    faer::linalg::matmul::matmul(out, accum, a, b, 1.0, par);
}

/// A·B.
pub(crate) fn mul(a: &Mat<f64>, b: &Mat<f64>) -> Mat<f64> {
    let mut out = Mat::<f64>::zeros(a.nrows(), b.ncols());
    product_into(out.as_mut(), Accum::Replace, a.as_ref(), b.as_ref());
    out
}

/// out ← out + A·B.
pub(crate) fn mul_add(out: &mut Mat<f64>, a: &Mat<f64>, b: &Mat<f64>) {
    product_into(out.as_mut(), Accum::Add, a.as_ref(), b.as_ref());
}
