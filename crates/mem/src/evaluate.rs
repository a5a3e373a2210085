//! Residuals and sensitivities of all experiments at one P (Eqs. 11–12, stacked).

use crate::vector::sum_squares;
use crate::{Experiment, MemError};
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
            let (w, half_width) = (e.weights[o], e.half_widths[o]);
            let meas = measured.col(o).try_as_col_major().expect("an owned Mat is column-major").as_slice();
            let model =
                out.outputs.col(o).try_as_col_major().expect("an owned Mat is column-major").as_slice();
            for (chunk, (m, y)) in rows.chunks_exact_mut(n_out).zip(meas.iter().zip(model)) {
                let r = m - y;
                // Interval readings: the distance to [y − Δ/2, y + Δ/2] (0 inside).
                chunk[o] = w * (r - r.clamp(-half_width, half_width));
            }
        }
        // Weighted sensitivities, in place, column by column on contiguous slices.
        let rows = &residual[row..row + k * n_out];
        let intervals = e.half_widths.iter().any(|h| *h > 0.0);
        for i in 0..p.len() {
            let column =
                out.sensitivities.col_mut(i).try_as_col_major_mut().expect("an owned Mat is column-major");
            let column = column.as_slice_mut();
            for (d, r) in column.chunks_exact_mut(n_out).zip(rows.chunks_exact(n_out)) {
                for (o, d) in d.iter_mut().enumerate() {
                    // Inside a reading's interval the residual is flat in P.
                    let flat = intervals && e.half_widths[o] > 0.0 && r[o] == 0.0;
                    *d = if flat { 0.0 } else { e.weights[o] * *d };
                }
            }
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
