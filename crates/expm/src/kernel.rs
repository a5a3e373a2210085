//! Matrix products: faer's GEMM for sizes where it pays, a plain loop for tiny matrices where
//! its dispatch costs more than the arithmetic (8×8 is 512 multiply-adds).

use faer::{Accum, Mat, MatRef, Par};

/// Below this many multiply-adds the plain loop is used.
const SMALL: usize = 48 * 48 * 48;

/// A·B.
pub(crate) fn mul(a: &Mat<f64>, b: &Mat<f64>) -> Mat<f64> {
    mul_ref(a.as_ref(), b.as_ref())
}

/// A·B for views.
pub(crate) fn mul_ref(a: MatRef<'_, f64>, b: MatRef<'_, f64>) -> Mat<f64> {
    let (m, k, n) = (a.nrows(), a.ncols(), b.ncols());
    let mut out = Mat::<f64>::zeros(m, n);
    if m * k * n <= SMALL {
        // Columns of A as contiguous slices (a view may be strided: copy it once then).
        let a_cols: Vec<f64>;
        let a_slices: Vec<&[f64]> = if (0..k).all(|l| a.col(l).try_as_col_major().is_some()) {
            (0..k).map(|l| a.col(l).try_as_col_major().expect("checked").as_slice()).collect()
        } else {
            a_cols = (0..k).flat_map(|l| (0..m).map(move |i| a[(i, l)])).collect();
            a_cols.chunks_exact(m.max(1)).collect()
        };
        for j in 0..n {
            let col =
                out.col_mut(j).try_as_col_major_mut().expect("a fresh Mat is column-major").as_slice_mut();
            for (l, acol) in a_slices.iter().enumerate() {
                let blj = b[(l, j)];
                if blj == 0.0 {
                    continue;
                }
                for (c, av) in col.iter_mut().zip(acol.iter()) {
                    *c += av * blj;
                }
            }
        }
    } else {
        let par = if m * k * n >= 128 * 128 * 128 { faer::get_global_parallelism() } else { Par::Seq };
        faer::linalg::matmul::matmul(out.as_mut(), Accum::Replace, a, b, 1.0, par);
    }
    out
}
