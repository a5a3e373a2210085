//! Residuals and sensitivities of all experiments at one P (Eqs. 11–12, stacked).

use crate::vector::sum_squares;
use crate::{Experiment, MemError, interval_residual};
use expm::Response;
use faer::Mat;

/// E and S of Eq. 12 for every experiment, stacked and weighted, and ‖E‖² (Eq. 22).
pub(crate) struct Evaluation {
    /// Weighted residual w·(y_meas − y_model), all experiments, rows (experiment, k, output).
    pub residual: Vec<f64>,
    /// Weighted sensitivities w·∂y/∂P, same rows.
    pub sensitivity: Mat<f64>,
    /// ‖residual‖².
    pub cost: f64,
}

/// Multiplies interleaved rows (k, o) — entry k·p + o — by `weights[o]`: eight rows at a time
/// against the weights repeated eight times, so that the loop vectorizes for any p ≤ 8.
fn scale_rows(values: &mut [f64], weights: &[f64]) {
    const ROWS: usize = 8;
    let p = weights.len();
    if p == 0 {
        return;
    }
    if p > ROWS {
        for row in values.chunks_exact_mut(p) {
            row.iter_mut().zip(weights).for_each(|(v, w)| *v *= w);
        }
        return;
    }
    let mut pattern = [0.0; ROWS * ROWS];
    for (t, v) in pattern[..ROWS * p].iter_mut().enumerate() {
        *v = weights[t % p];
    }
    let pattern = &pattern[..ROWS * p];
    let mut blocks = values.chunks_exact_mut(ROWS * p);
    for block in &mut blocks {
        block.iter_mut().zip(pattern).for_each(|(v, w)| *v *= w);
    }
    blocks.into_remainder().iter_mut().zip(pattern).for_each(|(v, w)| *v *= w);
}

/// Simulates every experiment at P (in parallel when there are several).
pub(crate) fn evaluate(experiments: &[Experiment<'_>], p: &[f64]) -> Result<Evaluation, MemError> {
    let n_rows: usize = experiments.iter().map(|e| e.data.n_samples() * e.data.n_outputs()).sum();
    let mut residual: Vec<f64> = Vec::with_capacity(n_rows);
    let simulate = |(index, e): (usize, &Experiment<'_>)| {
        let mut out = Response::zeros(e.data.n_samples(), e.data.n_outputs(), p.len());
        e.model.respond(p, e.data.interval(), &mut out).map_err(|source| MemError::Model {
            experiment: index,
            parameters: p.to_vec(),
            source,
        })?;
        Ok::<_, MemError>(out)
    };
    let mut responses: Vec<Response> = if experiments.len() > 1 {
        use rayon::prelude::*;
        experiments.par_iter().enumerate().map(simulate).collect::<Result<_, _>>()?
    } else {
        experiments.iter().enumerate().map(simulate).collect::<Result<_, _>>()?
    };
    // One experiment's weighted S is the stacked S: no copy.
    let mut stacked = (experiments.len() > 1).then(|| Mat::<f64>::zeros(n_rows, p.len()));
    let mut row = 0;
    for (e, out) in experiments.iter().zip(responses.iter_mut()) {
        let (k, n_out) = (e.data.n_samples(), e.data.n_outputs());
        let measured = e.data.values();
        // Residual rows (k, o) from the column-major measurement and model outputs.
        residual.resize(row + k * n_out, 0.0);
        let rows = &mut residual[row..];
        for o in 0..n_out {
            let half_width = e.half_widths[o];
            let meas = measured.col(o).try_as_col_major().expect("an owned Mat is column-major").as_slice();
            let model =
                out.outputs.col(o).try_as_col_major().expect("an owned Mat is column-major").as_slice();
            for (chunk, (m, y)) in rows.chunks_exact_mut(n_out).zip(meas.iter().zip(model)) {
                chunk[o] = interval_residual(m - y, half_width);
            }
        }
        scale_rows(&mut rows[..k * n_out], &e.weights);
        // Weighted sensitivities, in place, column by column on contiguous slices.
        let rows = &residual[row..row + k * n_out];
        let intervals = e.half_widths.iter().any(|h| *h > 0.0);
        for i in 0..p.len() {
            let column =
                out.sensitivities.col_mut(i).try_as_col_major_mut().expect("an owned Mat is column-major");
            let column = column.as_slice_mut();
            if intervals {
                // Inside a reading's interval the residual is flat in P.
                for (d, r) in column.chunks_exact_mut(n_out).zip(rows.chunks_exact(n_out)) {
                    for ((d, r), h) in d.iter_mut().zip(r).zip(&e.half_widths) {
                        if *h > 0.0 && *r == 0.0 {
                            *d = 0.0;
                        }
                    }
                }
            }
            scale_rows(column, &e.weights);
            if let Some(stacked) = stacked.as_mut() {
                stacked.col_mut(i).subrows_mut(row, k * n_out).copy_from(out.sensitivities.col(i));
            }
        }
        row += k * n_out;
    }
    let sensitivity = match stacked {
        Some(s) => s,
        None => responses.pop().expect("one experiment").sensitivities,
    };
    let cost = sum_squares(&residual);
    Ok(Evaluation { residual, sensitivity, cost })
}
