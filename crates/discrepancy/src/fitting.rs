//! Fitting a slewing model to measured data, whichever path (exponential or ODE) it needs.

use crate::WorkflowError;
use faer::Mat;
use mem::{Experiment, Fit, FitReport, Measurement, ResponseModel, Safeguard, interval_residual};
use nonlinear::{NonlinearResponse, simulate_model, simulate_sensors};
use plant::SlewingModel;
use slewing::SlewingFitModel;

/// What to fit.
#[derive(Clone, Debug)]
pub struct FitRequest {
    /// Names of the parameters to tune.
    pub free: Vec<String>,
    /// Weight outputs by 1/RMS (otherwise unit weights: the paper's Eq. 22).
    pub normalize: bool,
    /// Step safeguard.
    pub safeguard: Safeguard,
    /// Compare S with finite differences after the fit.
    pub check_derivatives: bool,
    /// Iteration cap.
    pub max_iterations: usize,
}

impl FitRequest {
    /// Levenberg–Marquardt, normalised outputs, 100 iterations.
    pub fn new(free: &[&str]) -> Self {
        Self {
            free: free.iter().map(|s| s.to_string()).collect(),
            normalize: true,
            safeguard: Safeguard::LevenbergMarquardt,
            check_derivatives: false,
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
    /// Outputs of the initial model at the data's samples (K × p).
    pub initial_outputs: Mat<f64>,
    /// Outputs of the fitted model (K × p), quantized where the model's sensors are.
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
) -> Result<Box<dyn ResponseModel + Send + Sync>, WorkflowError> {
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
/// [`WorkflowError::Columns`] naming both lists.
pub fn align(model: &SlewingModel, data: &Measurement) -> Result<Measurement, WorkflowError> {
    let wanted = model.output_names();
    let have = data.names();
    let mismatch = || WorkflowError::Columns {
        data: have.to_vec(),
        model: wanted.iter().map(|s| s.to_string()).collect(),
    };
    if wanted.len() != have.len() {
        return Err(mismatch());
    }
    let order: Vec<usize> = wanted
        .iter()
        .map(|w| have.iter().position(|h| h == w).ok_or_else(mismatch))
        .collect::<Result<_, _>>()?;
    let values = Mat::from_fn(data.n_samples(), order.len(), |k, o| data.values()[(k, order[o])]);
    Ok(Measurement::new(
        wanted.iter().map(|s| s.to_string()).collect(),
        data.start(),
        data.interval(),
        values,
    )?)
}

/// Fits `model` to `data` (columns aligned by name).
///
/// # Errors
/// Column mismatch, unknown names, or failures of the model or the iteration.
pub fn fit(
    model: &SlewingModel,
    data: &Measurement,
    request: &FitRequest,
) -> Result<FitOutcome, WorkflowError> {
    let data = align(model, data)?;
    let free: Vec<&str> = request.free.iter().map(|s| s.as_str()).collect();
    let adapter = SlewingFitModel::new(model.clone(), &free)?;
    let p0 = adapter.values();
    let response = response_model(model, &free)?;
    let experiment = if request.normalize {
        Experiment::normalized(response.as_ref(), &data)
    } else {
        Experiment::new(response.as_ref(), &data)
    };
    let experiment = experiment.with_quantization(&model.quantization());
    let (weights, half_widths) = (experiment.weights.clone(), experiment.half_widths.clone());
    let report = Fit::new()
        .with_bounds(adapter.bounds())?
        .with_safeguard(request.safeguard)
        .with_derivative_check(request.check_derivatives)
        .with_parameter_names(adapter.names())
        .with_max_iterations(request.max_iterations)?
        .run(&[experiment], &p0)?;
    let fitted = adapter.model_at(&report.parameters)?;
    let initial_outputs = simulate_model(model, data.interval(), data.n_samples())?;
    let final_outputs = simulate_model(&fitted, data.interval(), data.n_samples())?;
    let final_sensed = simulate_sensors(&fitted, data.interval(), data.n_samples())?;
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
