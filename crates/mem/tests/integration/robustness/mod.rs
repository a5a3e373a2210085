//! Non-identifiability, the safeguard, bounds as constraints, the start checks, and the
//! validation of what a user gives (`identifiability.rs`, `iteration.rs`, `bounds.rs`,
//! `validation.rs`); the small test models they share are here.

use faer::{Mat, mat};
use mem::{
    BoxedError, DerivativeCheck, Exact, Experiment, Fit, Grid, Interval, LinearModel, LinearResponse,
    Linearized, MemError, Parameter, Problem, Response, ResponseModel, Safeguard, Side, Termination, Warning,
};
use std::sync::atomic::{AtomicUsize, Ordering};
use test_problems::{
    HandDerivedBuilding, ProductOscillator, ShearBuilding, SpringChain, add_noise, parameters,
    simulate_measurement,
};

mod bounds;
mod identifiability;
mod iteration;
mod validation;

/// x'' + c x' + k x = 0 from x(0) = 1 observed for 20 s: stiffness far off makes the first
/// Gauss–Newton step overshoot.
struct Oscillator;
impl LinearModel for Oscillator {
    type Error = std::convert::Infallible;
    fn n_states(&self) -> usize {
        2
    }
    fn n_params(&self) -> usize {
        2
    }
    fn output_names(&self) -> Vec<String> {
        vec!["y0".into()]
    }
    fn linearize(&self, p: &[f64]) -> Result<Linearized, Self::Error> {
        Ok(Linearized::new(
            mat![[0.0, 1.0], [-p[1], -p[0]]],
            vec![mat![[0.0, 0.0], [0.0, -1.0]], mat![[0.0, 0.0], [-1.0, 0.0]]],
            mat![[1.0, 0.0]],
            vec![1.0, 0.0],
        ))
    }
}

/// A response that counts how it is asked: with sensitivities or for the outputs alone.
struct Counting {
    inner: LinearResponse<Oscillator>,
    full: AtomicUsize,
    outputs: AtomicUsize,
}

impl ResponseModel for Counting {
    fn n_params(&self) -> usize {
        self.inner.n_params()
    }
    fn output_names(&self) -> Vec<String> {
        self.inner.output_names()
    }
    fn respond(&self, p: &[f64], grid: &Grid<'_>, out: &mut Response) -> Result<(), BoxedError> {
        self.full.fetch_add(1, Ordering::Relaxed);
        self.inner.respond(p, grid, out)
    }
    fn respond_outputs(&self, p: &[f64], grid: &Grid<'_>, out: &mut Response) -> Result<(), BoxedError> {
        assert_eq!(out.sensitivities.ncols(), 0, "the outputs alone are asked for without columns");
        self.outputs.fetch_add(1, Ordering::Relaxed);
        self.inner.respond_outputs(p, grid, out)
    }
}

/// The oscillator with its damping fixed: k alone is free.
struct OscillatorWithDamping(f64);
impl LinearModel for OscillatorWithDamping {
    type Error = std::convert::Infallible;
    fn n_states(&self) -> usize {
        2
    }
    fn n_params(&self) -> usize {
        1
    }
    fn output_names(&self) -> Vec<String> {
        Oscillator.output_names()
    }
    fn linearize(&self, p: &[f64]) -> Result<Linearized, Self::Error> {
        let mut full = Oscillator.linearize(&[self.0, p[0]])?;
        full.da.remove(0);
        Ok(full)
    }
}

/// A model whose linearize returns one ∂A/∂P too few.
struct ShortDerivatives;
impl LinearModel for ShortDerivatives {
    type Error = std::convert::Infallible;
    fn n_states(&self) -> usize {
        2
    }
    fn n_params(&self) -> usize {
        2
    }
    fn output_names(&self) -> Vec<String> {
        vec!["y0".into()]
    }
    fn linearize(&self, p: &[f64]) -> Result<Linearized, Self::Error> {
        let mut lin = Oscillator.linearize(p)?;
        lin.da.pop();
        Ok(lin)
    }
}

/// The oscillator with its initial displacement and velocity as parameters: ∂x(0)/∂P = [0, I].
struct OscillatorWithUnknownStart;
impl LinearModel for OscillatorWithUnknownStart {
    type Error = std::convert::Infallible;
    fn n_states(&self) -> usize {
        2
    }
    fn n_params(&self) -> usize {
        4
    }
    fn output_names(&self) -> Vec<String> {
        vec!["y0".into()]
    }
    fn linearize(&self, p: &[f64]) -> Result<Linearized, Self::Error> {
        let mut lin = Oscillator.linearize(&p[..2])?;
        lin.da.extend([Mat::zeros(2, 2), Mat::zeros(2, 2)]);
        lin.x0 = vec![p[2], p[3]];
        lin.dx0 = Some(mat![[0.0, 0.0, 1.0, 0.0], [0.0, 0.0, 0.0, 1.0]]);
        Ok(lin)
    }
}

/// A response that depends on no parameter (a model at rest, not driven).
struct AtRest;

impl mem::ResponseModel for AtRest {
    fn n_params(&self) -> usize {
        1
    }
    fn output_names(&self) -> Vec<String> {
        vec!["y0".into()]
    }
    fn respond(&self, _p: &[f64], _grid: &Grid<'_>, out: &mut mem::Response) -> Result<(), mem::BoxedError> {
        out.outputs.fill(0.0);
        out.sensitivities.fill(0.0);
        Ok(())
    }
}

/// The spring chain with its coupling spring k₂ fixed: k₁ and c free.
struct ChainWithCoupling(f64);
impl LinearModel for ChainWithCoupling {
    type Error = std::convert::Infallible;
    fn n_states(&self) -> usize {
        4
    }
    fn n_params(&self) -> usize {
        2
    }
    fn output_names(&self) -> Vec<String> {
        vec!["y0".into(), "y1".into()]
    }
    fn linearize(&self, p: &[f64]) -> Result<Linearized, Self::Error> {
        let mut full = SpringChain { x0: [0.0, 0.1] }.linearize(&[p[0], self.0, p[1]])?;
        full.da.remove(1);
        Ok(full)
    }
}

/// The oscillator with a third parameter the outputs do not depend on.
struct OscillatorWithInert;
impl LinearModel for OscillatorWithInert {
    type Error = std::convert::Infallible;
    fn n_states(&self) -> usize {
        2
    }
    fn n_params(&self) -> usize {
        3
    }
    fn output_names(&self) -> Vec<String> {
        Oscillator.output_names()
    }
    fn linearize(&self, p: &[f64]) -> Result<Linearized, Self::Error> {
        let mut full = Oscillator.linearize(&p[..2])?;
        full.da.push(Mat::zeros(2, 2));
        Ok(full)
    }
}
