//! Fitting a slewing model to measured data, whichever path (exponential or ODE) it needs.

use crate::ModelError;
use crate::ode::NonlinearResponse;
use crate::slewing::SlewingFitModel;
use faer::Mat;
use mem::{
    Covariance, DerivativeCheck, Experiment, Fit, FitReport, Measurement, Problem, ResponseModel, Safeguard,
    interval_residual, sampled_response,
};
use plant::SlewingModel;

/// What to fit.
#[derive(Clone, Debug)]
pub struct FitRequest {
    /// Names of the parameters to tune.
    pub free: Vec<String>,
    /// Weight outputs by 1/RMS (otherwise unit weights: the paper's Eq. 22).
    pub normalize: bool,
    /// Step safeguard.
    pub safeguard: Safeguard,
    /// The derivative check at the start.
    pub derivative_check: DerivativeCheck,
    /// The covariance of the uncertainty.
    pub covariance: Covariance,
    /// Iteration cap.
    pub max_iterations: usize,
}

impl FitRequest {
    /// Levenberg–Marquardt, normalised outputs, 100 iterations, derivative check on,
    /// automatic covariance.
    pub fn new(free: &[&str]) -> Self {
        Self {
            free: free.iter().map(|s| s.to_string()).collect(),
            normalize: true,
            safeguard: Safeguard::LevenbergMarquardt,
            derivative_check: DerivativeCheck::Error,
            covariance: Covariance::Auto,
            max_iterations: 100,
        }
    }
}

/// A fit and the models and responses around it.
#[derive(Clone, Debug)]
pub struct FitOutcome {
    /// The MEM report.
    pub report: FitReport,
    /// The model the fit started from.
    pub initial: SlewingModel,
    /// The model with the fitted values.
    pub fitted: SlewingModel,
    /// Outputs of the initial model on the data's rows (K × p).
    pub initial_outputs: Mat<f64>,
    /// Outputs of the fitted model on the data's rows (K × p), quantized where its sensors are.
    pub final_outputs: Mat<f64>,
    /// The continuous quantities the fitted model's sensors read (K × p), before quantization.
    pub final_sensed: Mat<f64>,
    /// Half the quantization step per output (0 for a continuous sensor).
    pub half_widths: Vec<f64>,
    /// Output weights used.
    pub weights: Vec<f64>,
}

impl FitOutcome {
    /// Unweighted residual measured − fitted (K × p). On a quantized output a reading y is the
    /// interval [y − Δ/2, y + Δ/2], and the residual is the distance of the model's continuous
    /// output to it — what the fit minimised (`mem::Experiment::with_quantization`).
    pub fn residual(&self, data: &Measurement) -> Mat<f64> {
        Mat::from_fn(data.n_samples(), data.n_outputs(), |k, o| {
            interval_residual(data.values()[(k, o)] - self.final_sensed[(k, o)], self.half_widths[o])
        })
    }
}

/// The response model for `model` with `free` parameters: the exact exponential path when the
/// model is linear, the ODE path otherwise.
///
/// # Errors
/// Unknown parameter names.
pub fn response_model(
    model: &SlewingModel,
    free: &[&str],
) -> Result<Box<dyn ResponseModel + Send + Sync>, ModelError> {
    Ok(if model.is_linear() {
        Box::new(SlewingFitModel::new(model.clone(), free)?.response())
    } else {
        Box::new(NonlinearResponse::new(model.clone(), free)?)
    })
}

/// Checks that the data's columns are the model's outputs (any order) and returns the data
/// reordered to the model's output order.
///
/// # Errors
/// [`ModelError::Columns`] naming both lists.
pub fn align(model: &SlewingModel, data: &Measurement) -> Result<Measurement, ModelError> {
    let wanted = model.output_names();
    let have = data.names();
    let mismatch =
        || ModelError::Columns { data: have.to_vec(), model: wanted.iter().map(|s| s.to_string()).collect() };
    if wanted.len() != have.len() || wanted.iter().any(|w| !have.iter().any(|h| h == w)) {
        return Err(mismatch());
    }
    Ok(data.select(&wanted)?)
}

/// The model's outputs on the data's rows (through the data's decimation), quantized where
/// the model's sensors are, and the continuous quantities before quantization.
fn outputs_on(model: &SlewingModel, data: &Measurement) -> Result<(Mat<f64>, Mat<f64>), ModelError> {
    let response = response_model(model, &[])?;
    let sensed = sampled_response(response.as_ref(), data, &[])?.outputs;
    let mut quantized = sensed.clone();
    for (o, step) in model.quantization().into_iter().enumerate() {
        if let Some(step) = step {
            for k in 0..quantized.nrows() {
                quantized[(k, o)] = step * (quantized[(k, o)] / step).round();
            }
        }
    }
    Ok((quantized, sensed))
}

/// Fits `model` to `data` (columns aligned by name).
///
/// # Errors
/// Column mismatch, unknown names, or failures of the model or the iteration.
pub fn fit(model: &SlewingModel, data: &Measurement, request: &FitRequest) -> Result<FitOutcome, ModelError> {
    let data = align(model, data)?;
    let free: Vec<&str> = request.free.iter().map(|s| s.as_str()).collect();
    let adapter = SlewingFitModel::new(model.clone(), &free)?;
    let response = response_model(model, &free)?;
    let experiment = if request.normalize {
        Experiment::normalized(response.as_ref(), &data)
    } else {
        Experiment::new(response.as_ref(), &data)
    };
    let experiment = experiment.with_quantization(&model.quantization());
    let (weights, half_widths) = (experiment.weights.clone(), experiment.half_widths.clone());
    let problem = Problem::new(vec![experiment], adapter.parameters())?;
    let report = Fit::new()
        .with_safeguard(request.safeguard)
        .with_derivative_check(request.derivative_check)
        .with_covariance(request.covariance)
        .with_max_iterations(request.max_iterations)?
        .run(&problem)?;
    let fitted = adapter.model_at(&report.parameters)?;
    let (initial_outputs, _) = outputs_on(model, &data)?;
    let (final_outputs, final_sensed) = outputs_on(&fitted, &data)?;
    Ok(FitOutcome {
        report,
        initial: model.clone(),
        fitted,
        initial_outputs,
        final_outputs,
        final_sensed,
        half_widths,
        weights,
    })
}
