//! Fitting a model to one or more measured records, whichever path (exponential or ODE) it needs.
//!
//! Several experiments share the physical parameters; parameters named in
//! [`FitRequest::per_experiment`] (typically initial displacements or velocities) are estimated
//! once per experiment, named `name@k` for experiment k (1-based) in the report.

use crate::{Integrator, Model, ModelError};
use faer::Mat;
use mem::{
    Covariance, DerivativeCheck, Experiment, Fit, FitReport, Measurement, Parameter, Problem, ResponseModel,
    Safeguard, interval_residual, sampled_response,
};

/// What to fit.
#[derive(Clone, Debug)]
pub struct FitRequest {
    /// Names of the parameters to tune (shared by every experiment).
    pub free: Vec<String>,
    /// Names of parameters estimated separately for each experiment (e.g. initial states).
    pub per_experiment: Vec<String>,
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
    /// Per experiment, a weight per sample (0 leaves a sample out, e.g. a held-out block);
    /// empty: every sample of every experiment counts.
    pub sample_weights: Vec<Vec<f64>>,
    /// How a nonlinear model is integrated.
    pub integrator: Integrator,
    /// Stop when the predicted relative decrease of the error is below this (None: the MEM
    /// default, 10⁻¹²).
    pub cost_tolerance: Option<f64>,
    /// Output weights for every experiment, overriding `normalize` (e.g. 1/s_o, the noise's
    /// standard deviation per output, for a likelihood fit); None: as `normalize` says.
    pub output_weights: Option<Vec<f64>>,
    /// AR(1) lag-one coefficients of the noise per output, the same for every experiment:
    /// residuals and sensitivities are whitened before the weights
    /// ([`mem::Experiment::with_noise_correlation`]); None: white noise.
    pub noise_correlation: Option<Vec<f64>>,
    /// The noise of each output as a stationary process of known spectrum, the same for every
    /// experiment ([`mem::Experiment::with_noise_predictors`]); it replaces `noise_correlation`
    /// (setting both is an error). None: as `noise_correlation` says.
    pub noise_predictors: Option<Vec<mem::NoisePredictor>>,
}

impl FitRequest {
    /// Levenberg–Marquardt, normalised outputs, 100 iterations, derivative check on,
    /// automatic covariance, nothing per experiment.
    pub fn new(free: &[&str]) -> Self {
        Self {
            free: free.iter().map(|s| s.to_string()).collect(),
            per_experiment: Vec::new(),
            normalize: true,
            safeguard: Safeguard::LevenbergMarquardt,
            derivative_check: DerivativeCheck::Error,
            covariance: Covariance::Auto,
            max_iterations: 100,
            sample_weights: Vec::new(),
            integrator: Integrator::default(),
            cost_tolerance: None,
            output_weights: None,
            noise_correlation: None,
            noise_predictors: None,
        }
    }
}

/// One experiment of a fit: its record and the curves around the fit.
#[derive(Clone, Debug)]
pub struct ExperimentOutcome {
    /// The record, aligned with the model's outputs (and decimated, if it was).
    pub data: Measurement,
    /// Outputs of the initial model on the record's rows (K × p).
    pub initial_outputs: Mat<f64>,
    /// Outputs of the fitted model on the record's rows, quantized where its sensors are.
    pub final_outputs: Mat<f64>,
    /// The continuous quantities the fitted model's sensors read, before quantization.
    pub final_sensed: Mat<f64>,
    /// Half the quantization step per output (0 for a continuous sensor).
    pub half_widths: Vec<f64>,
    /// Output weights used.
    pub weights: Vec<f64>,
    /// This experiment's own parameters (name, fitted value).
    pub own: Vec<(String, f64)>,
}

impl ExperimentOutcome {
    /// Unweighted residual measured − fitted (K × p). On a quantized output a reading y is the
    /// interval [y − Δ/2, y + Δ/2], and the residual is the distance of the model's continuous
    /// output to it — what the fit minimised.
    pub fn residual(&self) -> Mat<f64> {
        Mat::from_fn(self.data.n_samples(), self.data.n_outputs(), |k, o| {
            interval_residual(self.data.values()[(k, o)] - self.final_sensed[(k, o)], self.half_widths[o])
        })
    }
}

/// A fit and the models and responses around it.
#[derive(Clone, Debug)]
pub struct FitOutcome {
    /// The MEM report.
    pub report: FitReport,
    /// The model the fit started from.
    pub initial: Model,
    /// The model with the fitted shared values (and the first experiment's own values).
    pub fitted: Model,
    /// Per experiment.
    pub experiments: Vec<ExperimentOutcome>,
}

impl FitOutcome {
    /// The first (or only) experiment.
    pub fn first(&self) -> &ExperimentOutcome {
        &self.experiments[0]
    }
}

/// Checks that the data's columns hold the model's outputs and inputs (by name, in any order;
/// other columns are not used) and returns the record with the outputs in the model's order and
/// the inputs attached (held as the model says).
///
/// # Errors
/// [`ModelError::Columns`] naming both lists.
pub fn align(model: &Model, data: &Measurement) -> Result<Measurement, ModelError> {
    let outputs = model.output_names();
    let inputs = model.input_names();
    let mismatch = || {
        let given: Vec<String> = data
            .names()
            .iter()
            .cloned()
            .chain(data.inputs().iter().flat_map(|i| i.names().to_vec()))
            .collect();
        let model: Vec<String> = outputs.iter().chain(&inputs).cloned().collect();
        let missing = model.iter().filter(|c| !given.contains(c)).cloned().collect();
        ModelError::Columns { data: given, model, missing }
    };
    let data = match (data.inputs(), inputs.is_empty()) {
        (None, false) => {
            if inputs.iter().any(|i| !data.names().contains(i)) {
                return Err(mismatch());
            }
            let refs: Vec<&str> = inputs.iter().map(|s| s.as_str()).collect();
            data.clone().with_inputs(&refs, model.hold())?
        }
        (Some(given), _) if given.names() != inputs.as_slice() => return Err(mismatch()),
        _ => data.clone(),
    };
    // Every output must be there (by name, in any order); other columns are not used.
    if outputs.iter().any(|w| !data.names().contains(w)) {
        return Err(mismatch());
    }
    let refs: Vec<&str> = outputs.iter().map(|s| s.as_str()).collect();
    Ok(data.select(&refs)?)
}

/// The model's outputs on the data's rows (through the data's decimation, driven by its
/// inputs), quantized where the model's sensors are, and the continuous quantities before.
fn outputs_on(model: &Model, data: &Measurement) -> Result<(Mat<f64>, Mat<f64>), ModelError> {
    let response = model.response(&[])?;
    let sensed = sampled_response(response.as_ref(), data, &[])?.outputs;
    let mut quantized = sensed.clone();
    for (o, step) in reading_steps(model, data).into_iter().enumerate() {
        if let Some(step) = step {
            for k in 0..quantized.nrows() {
                quantized[(k, o)] = step * (quantized[(k, o)] / step).round();
            }
        }
    }
    Ok((quantized, sensed))
}

/// The quantization steps that apply to a record's rows: the model's, on raw readings; none on a
/// decimated record, whose rows are filtered averages of readings (the rounding is part of
/// their noise, not an interval each row lies in).
fn reading_steps(model: &Model, data: &Measurement) -> Vec<Option<f64>> {
    let steps = model.quantization();
    if data.decimation().is_some() { vec![None; steps.len()] } else { steps }
}

/// Fits `model` to one record.
///
/// # Errors
/// As [`fit_experiments`].
pub fn fit(model: &Model, data: &Measurement, request: &FitRequest) -> Result<FitOutcome, ModelError> {
    fit_experiments(model, std::slice::from_ref(data), request)
}

/// Fits `model` to several records at once: shared parameters, and per-experiment ones.
///
/// # Errors
/// Column mismatch, unknown names, or failures of the model or the iteration.
pub fn fit_experiments(
    model: &Model,
    records: &[Measurement],
    request: &FitRequest,
) -> Result<FitOutcome, ModelError> {
    let data = records.iter().map(|d| align(model, d)).collect::<Result<Vec<_>, _>>()?;
    let shared: Vec<&str> = request.free.iter().map(|s| s.as_str()).collect();
    let own: Vec<&str> = request.per_experiment.iter().map(|s| s.as_str()).collect();
    if let Some(both) = own.iter().find(|o| shared.contains(o)) {
        return Err(ModelError::SharedAndOwn { name: both.to_string() });
    }
    let local: Vec<&str> = shared.iter().chain(&own).copied().collect();
    let responses: Vec<Box<dyn ResponseModel + Send + Sync>> =
        data.iter().map(|_| model.response_with(&local, request.integrator)).collect::<Result<_, _>>()?;
    let mut parameters: Vec<Parameter> = model.parameters(&shared)?;
    let own_parameters = model.parameters(&own)?;
    let several = data.len() > 1;
    if !request.sample_weights.is_empty() && request.sample_weights.len() != data.len() {
        return Err(mem::MemError::Shape(format!(
            "sample weights for {} experiments, but {} records",
            request.sample_weights.len(),
            data.len()
        ))
        .into());
    }
    let mut experiments = Vec::with_capacity(data.len());
    for (e, (record, response)) in data.iter().zip(&responses).enumerate() {
        let mut indices: Vec<usize> = (0..shared.len()).collect();
        for p in &own_parameters {
            indices.push(parameters.len());
            let name = if several { format!("{}@{}", p.name, e + 1) } else { p.name.clone() };
            parameters.push(Parameter { name, ..p.clone() });
        }
        let experiment = if request.normalize {
            Experiment::normalized(response.as_ref(), record)
        } else {
            Experiment::new(response.as_ref(), record)
        };
        let mut experiment =
            experiment.with_quantization(&reading_steps(model, record)).with_parameters(indices);
        if let Some(w) = request.sample_weights.get(e) {
            experiment = experiment.with_sample_weights(w.clone());
        }
        if let Some(w) = &request.output_weights {
            experiment.weights = w.clone();
        }
        if let Some(rho) = &request.noise_correlation {
            experiment = experiment.with_noise_correlation(rho.clone());
        }
        if let Some(predictors) = &request.noise_predictors {
            experiment = experiment.with_noise_predictors(predictors.clone());
        }
        experiments.push(experiment);
    }
    let settings: Vec<(Vec<f64>, Vec<f64>)> =
        experiments.iter().map(|e| (e.weights.clone(), e.half_widths.clone())).collect();
    let indices: Vec<Vec<usize>> =
        experiments.iter().map(|e| e.parameters.clone().unwrap_or_default()).collect();
    let problem = Problem::new(experiments, parameters)?;
    let mut fit = Fit::new();
    if let Some(tol) = request.cost_tolerance {
        fit = fit.with_cost_tolerance(tol)?;
    }
    let report = fit
        .with_safeguard(request.safeguard)
        .with_derivative_check(request.derivative_check)
        .with_covariance(request.covariance)
        .with_max_iterations(request.max_iterations)?
        .run(&problem)?;
    let mut outcomes = Vec::with_capacity(data.len());
    let mut fitted = None;
    for (e, record) in data.into_iter().enumerate() {
        let values: Vec<f64> = indices[e].iter().map(|&i| report.parameters[i]).collect();
        let at = model.with_values(&local, &values)?;
        let (initial_outputs, _) = outputs_on(model, &record)?;
        let (final_outputs, final_sensed) = outputs_on(&at, &record)?;
        let (weights, half_widths) = settings[e].clone();
        let own_values = own.iter().zip(&values[shared.len()..]).map(|(n, v)| (n.to_string(), *v)).collect();
        if fitted.is_none() {
            fitted = Some(at);
        }
        outcomes.push(ExperimentOutcome {
            data: record,
            initial_outputs,
            final_outputs,
            final_sensed,
            half_widths,
            weights,
            own: own_values,
        });
    }
    Ok(FitOutcome {
        report,
        initial: model.clone(),
        fitted: fitted.expect("at least one experiment"),
        experiments: outcomes,
    })
}
