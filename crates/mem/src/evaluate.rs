//! Residuals and sensitivities of all experiments at one P (Eqs. 11–12, stacked).
//!
//! Each experiment's model is simulated on its record's model grid — the raw grid of a
//! decimated record — and, for a decimated record, its outputs and every sensitivity column go
//! through the record's own decimation operator, so model and data are treated identically.
//! Rows are weighted per output (and per decimated row by the inverse noise gain of the edge
//! rows); local parameters are scattered into the problem's columns.

use crate::vector::sum_squares;
use crate::{Grid, Measurement, MemError, NoisePredictor, Problem, ResponseModel, interval_residual};
use expm::Response;
use faer::Mat;

/// E and S of Eq. 12 for every experiment, stacked and weighted, and ‖E‖² (Eq. 22).
pub(crate) struct Evaluation {
    /// Weighted residual w·(y_meas − y_model), all experiments, rows (experiment, k, output).
    pub residual: Vec<f64>,
    /// Weighted sensitivities w·∂y/∂P, same rows, one column per problem parameter.
    pub sensitivity: Mat<f64>,
    /// ‖residual‖².
    pub cost: f64,
}

/// Where each experiment's rows start and how they are laid out (for per-series statistics).
#[derive(Clone, Debug)]
pub(crate) struct RowLayout {
    /// (first row, samples, outputs) per experiment.
    pub blocks: Vec<(usize, usize, usize)>,
}

impl RowLayout {
    pub fn of(problem: &Problem<'_>) -> Self {
        let mut row = 0;
        let blocks = problem
            .experiments
            .iter()
            .map(|e| {
                let block = (row, e.data.n_samples(), e.data.n_outputs());
                row += e.data.n_samples() * e.data.n_outputs();
                block
            })
            .collect();
        Self { blocks }
    }

    /// The series (rows of one output of one experiment), as (experiment, output, rows).
    pub fn series(&self) -> impl Iterator<Item = (usize, usize, Vec<usize>)> + '_ {
        self.blocks.iter().enumerate().flat_map(|(e, &(first, k, p))| {
            (0..p).map(move |o| (e, o, (0..k).map(|t| first + t * p + o).collect()))
        })
    }
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

/// Whitens interleaved rows (k, o) — entry k·p + o — output by output by its noise predictor
/// ([`NoisePredictor::whiten`]; AR(1): row k becomes v_k − ρ_o v_{k−1}, a row that starts a
/// segment (1 − ρ_o²)^½ v_k). Row 0 starts a segment, and so does a row whose predecessor has
/// sample weight 0 (see
/// [`Experiment::with_noise_predictors`](crate::Experiment::with_noise_predictors)).
fn whiten_rows(values: &mut [f64], predictors: &[NoisePredictor], sample_weights: Option<&[f64]>) {
    let p = predictors.len();
    if p == 0 {
        return;
    }
    let k = values.len() / p;
    let starts = |row: usize| row == 0 || sample_weights.is_some_and(|w| w[row - 1] == 0.0);
    for (o, predictor) in predictors.iter().enumerate() {
        predictor.whiten(values, o, p, k, starts);
    }
}

/// What an evaluation computes: the residual alone (the cost of a trial point the iteration
/// may reject) or the residual and S.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Wanted {
    /// Outputs only: [`Evaluation::sensitivity`] has no columns.
    Cost,
    /// Outputs and sensitivities.
    Sensitivities,
}

/// The model's response for one experiment on its data's rows (decimated if the data are).
pub(crate) fn respond(
    problem: &Problem<'_>,
    index: usize,
    p: &[f64],
    wanted: Wanted,
) -> Result<Response, MemError> {
    let e = &problem.experiments[index];
    sampled(e.model, e.data, &e.local(p), wanted).map_err(|error| match error {
        MemError::Model { source, .. } => {
            MemError::Model { experiment: index, parameters: problem.describe(p), source }
        }
        other => other,
    })
}

/// The outputs and sensitivities of `model` at `p` on the rows of the record `data`: simulated
/// on the record's model grid (with its inputs) and, for a decimated record, put through the
/// record's own decimation operator — exactly what a fit compares with the data.
///
/// # Errors
/// [`MemError::Model`] if the model fails or its response is not finite.
pub fn sampled_response(
    model: &dyn ResponseModel,
    data: &Measurement,
    p: &[f64],
) -> Result<Response, MemError> {
    sampled(model, data, p, Wanted::Sensitivities)
}

/// [`sampled_response`], with the sensitivities only if `wanted` (none are computed otherwise:
/// the response then has no sensitivity columns).
fn sampled(
    model: &dyn ResponseModel,
    data: &Measurement,
    p: &[f64],
    wanted: Wanted,
) -> Result<Response, MemError> {
    let (start, interval, samples) = data.model_grid();
    let n_out = data.n_outputs();
    let j = if wanted == Wanted::Sensitivities { p.len() } else { 0 };
    let mut out = Response::zeros(samples, n_out, j);
    let grid = Grid { start, interval, inputs: data.inputs() };
    let failure =
        |source: crate::BoxedError| MemError::Model { experiment: 0, parameters: format!("{p:?}"), source };
    match wanted {
        Wanted::Sensitivities => model.respond(p, &grid, &mut out),
        Wanted::Cost => model.respond_outputs(p, &grid, &mut out),
    }
    .map_err(failure)?;
    if !(out.outputs.as_ref().is_all_finite() && out.sensitivities.as_ref().is_all_finite()) {
        return Err(failure("the model's response or its sensitivities are not finite".into()));
    }
    let Some(decimation) = data.decimation() else { return Ok(out) };
    let k = decimation.samples();
    let mut reduced = Response::zeros(k, n_out, j);
    for o in 0..n_out {
        let raw = out.outputs.col(o).try_as_col_major().expect("an owned Mat is column-major").as_slice();
        let target = reduced.outputs.col_mut(o).try_as_col_major_mut().expect("an owned Mat is column-major");
        decimation.apply_strided(raw, 0, 1, target.as_slice_mut(), 0, 1);
    }
    for i in 0..j {
        let raw =
            out.sensitivities.col(i).try_as_col_major().expect("an owned Mat is column-major").as_slice();
        let target =
            reduced.sensitivities.col_mut(i).try_as_col_major_mut().expect("an owned Mat is column-major");
        let target = target.as_slice_mut();
        for o in 0..n_out {
            decimation.apply_strided(raw, o, n_out, target, o, n_out);
        }
    }
    Ok(reduced)
}

/// Simulates every experiment at P (in parallel when there are several): E and S.
pub(crate) fn evaluate(problem: &Problem<'_>, p: &[f64]) -> Result<Evaluation, MemError> {
    evaluate_for(problem, p, Wanted::Sensitivities)
}

/// As [`evaluate`], with S only if `wanted`; the residual and the cost are the same bits
/// either way (the outputs are, [`ResponseModel::respond_outputs`]).
pub(crate) fn evaluate_for(problem: &Problem<'_>, p: &[f64], wanted: Wanted) -> Result<Evaluation, MemError> {
    let experiments = &problem.experiments;
    let n_rows: usize = experiments.iter().map(|e| e.data.n_samples() * e.data.n_outputs()).sum();
    let mut residual: Vec<f64> = Vec::with_capacity(n_rows);
    let simulate = |index: usize| respond(problem, index, p, wanted);
    let mut responses: Vec<Response> = if experiments.len() > 1 {
        use rayon::prelude::*;
        (0..experiments.len()).into_par_iter().map(simulate).collect::<Result<_, _>>()?
    } else {
        (0..experiments.len()).map(simulate).collect::<Result<_, _>>()?
    };
    let j = if wanted == Wanted::Sensitivities { p.len() } else { 0 };
    // One experiment whose model takes the whole vector: its weighted S is the stacked S.
    let in_place = experiments.len() == 1 && experiments[0].parameters.is_none();
    let mut stacked = (!in_place).then(|| Mat::<f64>::zeros(n_rows, j));
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
        // Per row: the decimation's edge weights times the sample weights.
        let row_scales: Option<Vec<f64>> = match (e.data.decimation(), &e.sample_weights) {
            (None, None) => None,
            (d, w) => {
                let mut scales: Vec<f64> = d.map_or_else(|| vec![1.0; k], |d| d.row_scales().collect());
                if let Some(w) = w {
                    scales.iter_mut().zip(w).for_each(|(s, w)| *s *= w);
                }
                Some(scales)
            }
        };
        let whitening = e.whitening();
        let scale = |values: &mut [f64]| {
            if let Some(predictors) = &whitening {
                whiten_rows(values, predictors, e.sample_weights.as_deref());
            }
            scale_rows(values, &e.weights);
            if let Some(scales) = &row_scales {
                for (chunk, s) in values.chunks_exact_mut(n_out).zip(scales) {
                    chunk.iter_mut().for_each(|v| *v *= s);
                }
            }
        };
        // Inside a reading's interval the residual is flat in P: where, before whitening.
        let intervals = e.half_widths.iter().any(|h| *h > 0.0);
        let flat: Option<Vec<bool>> = intervals.then(|| {
            rows[..k * n_out]
                .iter()
                .enumerate()
                .map(|(i, r)| e.half_widths[i % n_out] > 0.0 && *r == 0.0)
                .collect()
        });
        scale(&mut rows[..k * n_out]);
        // Weighted sensitivities, in place, column by column on contiguous slices.
        for i in 0..out.sensitivities.ncols() {
            let column =
                out.sensitivities.col_mut(i).try_as_col_major_mut().expect("an owned Mat is column-major");
            let column = column.as_slice_mut();
            if let Some(flat) = &flat {
                column.iter_mut().zip(flat).filter(|(_, f)| **f).for_each(|(d, _)| *d = 0.0);
            }
            scale(column);
            if let Some(stacked) = stacked.as_mut() {
                stacked.col_mut(e.column(i)).subrows_mut(row, k * n_out).copy_from(out.sensitivities.col(i));
            }
        }
        row += k * n_out;
    }
    let sensitivity = match stacked {
        Some(s) => s,
        None => responses.pop().expect("one experiment").sensitivities,
    };
    let cost = sum_squares(&residual);
    if !cost.is_finite() {
        return Err(MemError::Model {
            experiment: 0,
            parameters: problem.describe(p),
            source: "the error ‖Y_error‖ overflows: the model's response is far from the data".into(),
        });
    }
    Ok(Evaluation { residual, sensitivity, cost })
}
