//! Plain simulation of a slewing model (with or without effects), for studies and tests.

use crate::{Model, ModelError};
use faer::Mat;
use plant::SlewingModel;

/// The model's free decay at t_k = k·h, k < n_samples, as K × p outputs as its sensors read them
/// (sensor effects applied, quantized where a sensor is): by the exact matrix exponential when
/// the model is linear, by the ODE solver otherwise.
///
/// # Errors
/// Plant or solver failures.
pub fn simulate_model(model: &SlewingModel, h: f64, n_samples: usize) -> Result<Mat<f64>, ModelError> {
    Model::Slewing(model.clone()).simulate(&mem::Grid::free(h), n_samples)
}

/// As [`simulate_model`], for a model given as RON text.
///
/// # Errors
/// Parse, plant or solver failures.
pub fn simulate(ron: &str, h: f64, n_samples: usize) -> Result<Mat<f64>, ModelError> {
    simulate_model(&SlewingModel::from_ron(ron, "<string>")?, h, n_samples)
}
