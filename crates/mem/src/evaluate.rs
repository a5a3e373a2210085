//! Residuals and sensitivities of all experiments at one P (Eqs. 11–12, stacked).

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

/// Simulates every experiment at P.
pub(crate) fn evaluate(experiments: &[Experiment<'_>], p: &[f64]) -> Result<Evaluation, MemError> {
    let n_rows: usize = experiments.iter().map(|e| e.data.n_samples() * e.data.n_outputs()).sum();
    let mut residual = Vec::with_capacity(n_rows);
    let mut sensitivity = Mat::<f64>::zeros(n_rows, p.len());
    let mut row = 0;
    for (index, e) in experiments.iter().enumerate() {
        let (k, n_out) = (e.data.n_samples(), e.data.n_outputs());
        let mut out = Response::zeros(k, n_out, p.len());
        e.model.respond(p, e.data.interval(), &mut out).map_err(|source| MemError::Model {
            experiment: index,
            parameters: p.to_vec(),
            source,
        })?;
        let measured = e.data.values();
        for step in 0..k {
            for o in 0..n_out {
                let w = e.weights[o];
                residual.push(w * (measured[(step, o)] - out.outputs[(step, o)]));
                for i in 0..p.len() {
                    sensitivity[(row, i)] = w * out.sensitivities[(step * n_out + o, i)];
                }
                row += 1;
            }
        }
    }
    let cost = residual.iter().map(|r| r * r).sum();
    Ok(Evaluation { residual, sensitivity, cost })
}
