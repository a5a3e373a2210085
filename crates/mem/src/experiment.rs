//! One experiment: a model, the record it must reproduce, output weights, quantized readings,
//! and which of the shared parameters it sees.

use crate::{Measurement, MemError, NoisePredictor, ResponseModel};
use std::borrow::Cow;

/// One experiment: a model and the measurement it must reproduce, with output weights.
pub struct Experiment<'a> {
    /// The model (with this experiment's initial condition and sensors).
    pub model: &'a (dyn ResponseModel + Sync),
    /// The measured record.
    pub data: &'a Measurement,
    /// Weight per output (residuals are multiplied by it); see [`Measurement::rms_weights`].
    pub weights: Vec<f64>,
    /// Half-width of the reading's interval per output (0: an exact reading); see
    /// [`Experiment::with_quantization`].
    pub half_widths: Vec<f64>,
    /// The positions in the problem's parameter vector of this model's parameters (None: the
    /// model takes the whole vector). Several experiments share physical parameters and keep
    /// their own, e.g. each its own initial state.
    pub parameters: Option<Vec<usize>>,
    /// A weight per sample (row of the record), multiplying its residuals and sensitivities;
    /// 0 leaves a sample out (a held-out block). None: every sample counts.
    pub sample_weights: Option<Vec<f64>>,
    /// The lag-one coefficient ρ_o of each output's AR(1) noise, e_k = ρ_o e_{k−1} + u_k
    /// (None: white noise). Each output's residuals and sensitivities are whitened to the
    /// innovations u_k = e_k − ρ_o e_{k−1} (u₀ = (1 − ρ_o²)^½ e₀) before the weights, so the
    /// error is the Gaussian AR(1) log-likelihood's sum of squares at these ρ_o and weights
    /// 1/s_o; see [`Experiment::with_noise_correlation`].
    pub noise_correlation: Option<Vec<f64>>,
    /// The noise of each output as a stationary process of known spectrum ([`NoisePredictor`];
    /// None: white, or the AR(1) of `noise_correlation`). Each output's residuals and
    /// sensitivities are whitened to its scaled innovations before the weights; see
    /// [`Experiment::with_noise_predictors`]. At most one of the two is set.
    pub noise_predictors: Option<Vec<NoisePredictor>>,
}

impl<'a> Experiment<'a> {
    /// An experiment with unit weights (the paper's Eq. 22 error).
    pub fn new(model: &'a (dyn ResponseModel + Sync), data: &'a Measurement) -> Self {
        Self {
            model,
            data,
            weights: vec![1.0; data.n_outputs()],
            half_widths: vec![0.0; data.n_outputs()],
            parameters: None,
            sample_weights: None,
            noise_correlation: None,
            noise_predictors: None,
        }
    }

    /// Uses weights 1/RMS(measured output), so outputs of different units count alike.
    pub fn normalized(model: &'a (dyn ResponseModel + Sync), data: &'a Measurement) -> Self {
        Self { weights: data.rms_weights(), ..Self::new(model, data) }
    }

    /// Declares quantized outputs: `steps[o] = Some(Δ)` means output o was read by a quantizer
    /// of step Δ, so a reading y only says that the value lies in [y − Δ/2, y + Δ/2]. Its
    /// residual is then the distance from the model's output to that interval,
    /// r = sign(y − ŷ)·max(0, |y − ŷ| − Δ/2) — interval-censored least squares — and rows
    /// inside the interval carry no sensitivity.
    pub fn with_quantization(mut self, steps: &[Option<f64>]) -> Self {
        self.half_widths = steps.iter().map(|s| s.map_or(0.0, |d| 0.5 * d)).collect();
        self
    }

    /// Weights per sample (0 leaves a sample out of the fit, e.g. to score a prediction of it).
    pub fn with_sample_weights(mut self, weights: Vec<f64>) -> Self {
        self.sample_weights = Some(weights);
        self
    }

    /// Fits under AR(1) noise of lag-one coefficients `rho` (one per output, |ρ| < 1): the
    /// error becomes Σ_o w_o² U_o, U_o = (1 − ρ_o²)e₀² + Σ_k (e_k − ρ_o e_{k−1})², which with
    /// w_o = 1/s_o (the innovations' standard deviation) is −2 × the Gaussian log-likelihood up
    /// to a constant — generalised least squares, the maximum-likelihood fit when the noise is
    /// that model. A sample weight then weights the innovation u_k, and a sample left out (weight 0)
    /// ends a segment: the next starts anew, (1 − ρ_o²)^½ e_k, as a held-out score of the same
    /// likelihood on alternate blocks counts it.
    pub fn with_noise_correlation(mut self, rho: Vec<f64>) -> Self {
        self.noise_correlation = Some(rho);
        self
    }

    /// Fits under stationary Gaussian noise of a known spectrum per output, given as its linear
    /// predictors ([`NoisePredictor`], one per output): each output's residuals and
    /// sensitivities become the scaled innovations (e_k − Σ_i a_m,i e_{k−i})·(v_q/v_m)^½, m the
    /// samples before k in its segment up to q, so the error is the exact Gaussian quadratic form
    /// of that noise (its Toeplitz covariance's Cholesky factor) — generalised least squares.
    /// With weights 1/s_o (the innovations' standard deviation) it is −2 × the log-likelihood up
    /// to a constant. A sample left out (weight 0) ends a segment, as with
    /// [`Experiment::with_noise_correlation`], which is the case q = 1.
    pub fn with_noise_predictors(mut self, predictors: Vec<NoisePredictor>) -> Self {
        self.noise_predictors = Some(predictors);
        self
    }

    /// The predictors the residuals are whitened by: the given ones, or AR(1)'s of
    /// `noise_correlation`; None for white noise. Validated ([`Experiment::validate`]) before
    /// any evaluation.
    pub(crate) fn whitening(&self) -> Option<Cow<'_, [NoisePredictor]>> {
        match (&self.noise_predictors, &self.noise_correlation) {
            (Some(p), _) => Some(Cow::Borrowed(p)),
            (None, Some(rho)) => Some(Cow::Owned(
                rho.iter().map(|r| NoisePredictor::ar1(*r).expect("validated: |ρ| < 1")).collect(),
            )),
            (None, None) => None,
        }
    }

    /// The model's parameters are `indices` of the problem's parameter vector.
    pub fn with_parameters(mut self, indices: Vec<usize>) -> Self {
        self.parameters = Some(indices);
        self
    }

    /// This experiment's parameters taken from the problem's vector `p`.
    pub(crate) fn local(&self, p: &[f64]) -> Vec<f64> {
        match &self.parameters {
            Some(indices) => indices.iter().map(|i| p[*i]).collect(),
            None => p.to_vec(),
        }
    }

    /// The problem's column of local parameter i.
    pub(crate) fn column(&self, i: usize) -> usize {
        self.parameters.as_ref().map_or(i, |indices| indices[i])
    }

    /// Checks that model, data and weights fit together.
    pub(crate) fn validate(&self, index: usize, n_params: usize) -> Result<(), MemError> {
        let model_outputs = self.model.output_names();
        if model_outputs != self.data.names() {
            return Err(MemError::OutputNames {
                experiment: index,
                model: model_outputs,
                data: self.data.names().to_vec(),
            });
        }
        let model_inputs = self.model.input_names();
        let data_inputs = self.data.inputs().map(|i| i.names().to_vec()).unwrap_or_default();
        if model_inputs != data_inputs {
            return Err(MemError::InputNames { experiment: index, model: model_inputs, data: data_inputs });
        }
        let local = match &self.parameters {
            Some(indices) => {
                for (k, i) in indices.iter().enumerate() {
                    if *i >= n_params || indices[..k].contains(i) {
                        return Err(MemError::Shape(format!(
                            "experiment {index}: parameter index {i} is repeated or beyond the {n_params} parameters"
                        )));
                    }
                }
                indices.len()
            }
            None => n_params,
        };
        if self.model.n_params() != local {
            return Err(MemError::Shape(format!(
                "experiment {index}: the model has {} parameters, but it is given {local}",
                self.model.n_params()
            )));
        }
        if self.weights.len() != self.data.n_outputs()
            || self.weights.iter().any(|w| !(w.is_finite() && *w >= 0.0))
        {
            return Err(MemError::Shape(format!(
                "experiment {index}: need one finite weight ≥ 0 per output"
            )));
        }
        if self.half_widths.len() != self.data.n_outputs()
            || self.half_widths.iter().any(|w| !(w.is_finite() && *w >= 0.0))
        {
            return Err(MemError::Shape(format!(
                "experiment {index}: need one finite quantization step ≥ 0 per output"
            )));
        }
        if let Some(w) = &self.sample_weights
            && (w.len() != self.data.n_samples() || w.iter().any(|v| !(v.is_finite() && *v >= 0.0)))
        {
            return Err(MemError::Shape(format!(
                "experiment {index}: need one finite sample weight ≥ 0 per sample ({})",
                self.data.n_samples()
            )));
        }
        if let Some(rho) = &self.noise_correlation
            && (rho.len() != self.data.n_outputs() || rho.iter().any(|r| !(r.is_finite() && r.abs() < 1.0)))
        {
            return Err(MemError::Shape(format!(
                "experiment {index}: need one finite noise correlation ρ with |ρ| < 1 per output ({})",
                self.data.n_outputs()
            )));
        }
        if let Some(p) = &self.noise_predictors {
            if p.len() != self.data.n_outputs() {
                return Err(MemError::Shape(format!(
                    "experiment {index}: need one noise predictor per output ({}), got {}",
                    self.data.n_outputs(),
                    p.len()
                )));
            }
            if self.noise_correlation.is_some() {
                return Err(MemError::Shape(format!(
                    "experiment {index}: give the noise either as AR(1) coefficients or as predictors, not both"
                )));
            }
        }
        if self.data.start() < 0.0 {
            return Err(MemError::InvalidData(format!(
                "experiment {index}: the record starts at t = {} s, before the model's t = 0 where its \
                 initial state holds; shift the time column",
                self.data.start()
            )));
        }
        Ok(())
    }
}
