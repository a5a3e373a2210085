//! Small linear test models with a known answer: a two-mass spring chain and an oscillator whose
//! stiffness is a product of two parameters (not identifiable), and the noisy record of either.

use faer::Mat;

use crate::{rng, with_noise};

/// A two-mass spring chain (not the slewing plant): masses m₁ = 1, m₂ = 0.5, springs k₁ (to
/// ground) and k₂ (between the masses), light damping c on each mass; P = [k₁, k₂, c];
/// outputs: both displacements; starts from a deflection of the outer mass.
#[derive(Clone, Debug)]
pub struct SpringChain {
    /// Initial displacements of the two masses.
    pub x0: [f64; 2],
}

impl SpringChain {
    /// The true parameters used by the tests.
    pub const TRUE: [f64; 3] = [40.0, 15.0, 0.3];
}

impl mem::LinearModel for SpringChain {
    type Error = std::convert::Infallible;
    fn n_states(&self) -> usize {
        4
    }
    fn n_params(&self) -> usize {
        3
    }
    fn output_names(&self) -> Vec<String> {
        vec!["y0".into(), "y1".into()]
    }
    fn linearize(&self, p: &[f64]) -> Result<mem::Linearized, Self::Error> {
        let (m1, m2) = (1.0, 0.5);
        let (k1, k2, c) = (p[0], p[1], p[2]);
        let a = faer::mat![
            [0.0, 0.0, 1.0, 0.0],
            [0.0, 0.0, 0.0, 1.0],
            [-(k1 + k2) / m1, k2 / m1, -c / m1, 0.0],
            [k2 / m2, -k2 / m2, 0.0, -c / m2],
        ];
        let entry = |i: usize, j: usize, v: f64| {
            Mat::<f64>::from_fn(4, 4, |r, c| if (r, c) == (i, j) { v } else { 0.0 })
        };
        let dk1 = entry(2, 0, -1.0 / m1);
        let dk2 = faer::mat![
            [0.0, 0.0, 0.0, 0.0],
            [0.0, 0.0, 0.0, 0.0],
            [-1.0 / m1, 1.0 / m1, 0.0, 0.0],
            [1.0 / m2, -1.0 / m2, 0.0, 0.0],
        ];
        let dc = entry(2, 2, -1.0 / m1) + entry(3, 3, -1.0 / m2);
        Ok(mem::Linearized::new(
            a,
            vec![dk1, dk2, dc],
            faer::mat![[1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0]],
            vec![self.x0[0], self.x0[1], 0.0, 0.0],
        ))
    }
}

/// A damped oscillator whose stiffness is the product P₁·P₂ (damping P₃): the pair (P₁, P₂)
/// is not identifiable, only its product is.
#[derive(Clone, Debug)]
pub struct ProductOscillator;

impl mem::LinearModel for ProductOscillator {
    type Error = std::convert::Infallible;
    fn n_states(&self) -> usize {
        2
    }
    fn n_params(&self) -> usize {
        3
    }
    fn output_names(&self) -> Vec<String> {
        vec!["y0".into()]
    }
    fn linearize(&self, p: &[f64]) -> Result<mem::Linearized, Self::Error> {
        Ok(mem::Linearized::new(
            faer::mat![[0.0, 1.0], [-p[0] * p[1], -p[2]]],
            vec![
                faer::mat![[0.0, 0.0], [-p[1], 0.0]],
                faer::mat![[0.0, 0.0], [-p[0], 0.0]],
                faer::mat![[0.0, 0.0], [0.0, -1.0]],
            ],
            faer::mat![[1.0, 0.0]],
            vec![1.0, 0.0],
        ))
    }
}

/// Simulates `model` at `p` for `n_samples` samples of interval `h` and returns the outputs as
/// a measurement, with white Gaussian noise of standard deviation `noise_fraction` × (each
/// output's RMS) added (seeded).
pub fn simulate_measurement(
    model: &dyn mem::ResponseModel,
    p: &[f64],
    h: f64,
    n_samples: usize,
    noise_fraction: f64,
    seed: u64,
) -> mem::Measurement {
    let clean = mem::Measurement::simulate(model, p, h, n_samples).expect("the test model evaluates");
    let values = with_noise(clean.values(), noise_fraction, &mut rng(seed));
    mem::Measurement::new(model.output_names(), 0.0, h, values).expect("finite simulated data")
}
