//! What a response computation fills: outputs and their sensitivities at K samples.

use faer::Mat;

/// Outputs and output sensitivities at K samples.
///
/// `outputs[(k, o)]` is y_o(t_k); `sensitivities[(k·p + o, i)]` is ∂y_o(t_k)/∂P_i, so that
/// `sensitivities` is exactly the matrix S of the paper's Eq. (11)–(12) with rows ordered by
/// time, then output.
#[derive(Clone, Debug)]
pub struct Response {
    /// K × p model outputs.
    pub outputs: Mat<f64>,
    /// (K·p) × j output sensitivities.
    pub sensitivities: Mat<f64>,
}

impl Response {
    /// An empty response for `n_samples` samples of `n_outputs` outputs and `n_params` parameters.
    pub fn zeros(n_samples: usize, n_outputs: usize, n_params: usize) -> Self {
        Self {
            outputs: Mat::zeros(n_samples, n_outputs),
            sensitivities: Mat::zeros(n_samples * n_outputs, n_params),
        }
    }

    /// Number of samples K.
    pub fn n_samples(&self) -> usize {
        self.outputs.nrows()
    }
}
