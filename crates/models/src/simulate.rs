//! Plain simulation of any slewing model (with or without effects).

use crate::ode::{NonlinearError, NonlinearResponse};
use expm::{Response, SensitivityPropagator};
use faer::Mat;
use plant::SlewingModel;

/// The model's free decay at t_k = k·h, k < n_samples, as K × p outputs: by the exact matrix
/// exponential when the model is linear, by the ODE solver otherwise. Sensor quantization
/// (a measurement-only effect) is applied to the outputs.
///
/// # Errors
/// Plant or solver failures.
pub fn simulate_model(model: &SlewingModel, h: f64, n_samples: usize) -> Result<Mat<f64>, NonlinearError> {
    let mut y = simulate_sensors(model, h, n_samples)?;
    for (o, step) in model.quantization().into_iter().enumerate() {
        if let Some(step) = step {
            for k in 0..y.nrows() {
                y[(k, o)] = step * (y[(k, o)] / step).round();
            }
        }
    }
    Ok(y)
}

/// As [`simulate_model`] without the sensors' quantization: the continuous quantities the
/// sensors read.
///
/// # Errors
/// Plant or solver failures.
pub fn simulate_sensors(model: &SlewingModel, h: f64, n_samples: usize) -> Result<Mat<f64>, NonlinearError> {
    let mut out = Response::zeros(n_samples, model.sensors().len(), 0);
    if model.is_linear() {
        let ss = model.state_space()?;
        SensitivityPropagator::new(ss.a.as_ref(), &[], ss.c.as_ref(), h)
            .and_then(|p| p.propagate_into(&ss.x0, None, &mut out))
            .map_err(|e| NonlinearError::Solver(e.to_string()))?;
    } else {
        NonlinearResponse::new(model.clone(), &[])?.simulate(&[], 0.0, h, &mut out)?;
    }
    Ok(out.outputs)
}

/// As [`simulate_model`], for a model given as RON text.
///
/// # Errors
/// Parse, plant or solver failures.
pub fn simulate(ron: &str, h: f64, n_samples: usize) -> Result<Mat<f64>, NonlinearError> {
    simulate_model(&SlewingModel::from_ron(ron, "<string>")?, h, n_samples)
}
