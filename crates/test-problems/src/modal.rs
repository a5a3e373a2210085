//! The seeded modal families of the benches: free ([`ModalFamily`]) and forced
//! ([`ForcedFamily`], [`simulate_forced`]).

use faer::Mat;
use rand::Rng;
use rand_distr::StandardNormal;

use crate::{gaussian, rng, with_noise};

/// The seeded modal test family of the benches: `n_modes` lightly coupled damped modes
/// (unit mass), whose parameters scale the stiffness (first half) and damping (second half) of
/// interleaved groups of modes; outputs are physical displacements at evenly spaced degrees of
/// freedom. A(P) = [[0, I], [−K(P), −D(P)]] with K, D linear in P, so ∂A/∂P_i is constant.
#[derive(Clone, Debug)]
pub struct ModalFamily {
    /// Number of modes n (states N = 2n).
    pub n_modes: usize,
    /// Stiffness terms K_i (one per stiffness parameter), physical coordinates.
    pub stiffness_terms: Vec<Mat<f64>>,
    /// Damping terms D_i (one per damping parameter), physical coordinates.
    pub damping_terms: Vec<Mat<f64>>,
    /// p × N output matrix (displacements).
    pub c: Mat<f64>,
    /// Initial state: a seeded static deflection, at rest.
    pub x0: Vec<f64>,
    /// The nominal parameters (all scale factors equal to one).
    pub p_nominal: Vec<f64>,
}

impl ModalFamily {
    /// Builds the family. Frequencies are spread over 0.1–5 Hz (below the 6.4 Hz Nyquist
    /// frequency of h = 1/12.8 s), damping ratios over 1–10 %.
    pub fn new(n_modes: usize, n_params: usize, n_outputs: usize, seed: u64) -> Self {
        assert!(n_params >= 1 && n_params <= 2 * n_modes, "1 ≤ n_params ≤ 2·n_modes");
        assert!(n_outputs >= 1 && n_outputs <= n_modes, "1 ≤ n_outputs ≤ n_modes");
        let mut r = rng(seed);
        let coupling = gaussian(n_modes, n_modes, seed.wrapping_add(1));
        let t = Mat::<f64>::from_fn(n_modes, n_modes, |i, j| {
            f64::from(u8::from(i == j)) + 0.05 * coupling[(i, j)] / (n_modes as f64).sqrt()
        });
        let omega: Vec<f64> = (0..n_modes)
            .map(|m| {
                let frac = if n_modes > 1 { m as f64 / (n_modes - 1) as f64 } else { 0.0 };
                2.0 * std::f64::consts::PI * 0.1 * 50f64.powf(frac)
            })
            .collect();
        let zeta: Vec<f64> = (0..n_modes).map(|_| 0.01 + 0.09 * r.random::<f64>()).collect();
        let n_stiff = n_params.div_ceil(2);
        let n_damp = n_params - n_stiff;
        let term = |values: &dyn Fn(usize) -> f64, group: usize, groups: usize| {
            let diag = Mat::<f64>::from_fn(n_modes, n_modes, |i, j| {
                if i == j && i % groups == group { values(i) } else { 0.0 }
            });
            t.transpose() * &diag * &t
        };
        let stiffness_terms = (0..n_stiff).map(|g| term(&|i| omega[i] * omega[i], g, n_stiff)).collect();
        let damping_terms =
            (0..n_damp.max(1)).map(|g| term(&|i| 2.0 * zeta[i] * omega[i], g, n_damp.max(1))).collect();
        let n_states = 2 * n_modes;
        let c = Mat::<f64>::from_fn(n_outputs, n_states, |o, s| {
            f64::from(u8::from(s == o * n_modes / n_outputs))
        });
        let mut x0 = vec![0.0; n_states];
        for v in x0.iter_mut().take(n_modes) {
            *v = r.sample::<f64, _>(StandardNormal);
        }
        // With a single parameter, damping is a fixed term (scale one) and not a parameter.
        Self { n_modes, stiffness_terms, damping_terms, c, x0, p_nominal: vec![1.0; n_params] }
    }

    /// Number of states N = 2n.
    pub fn n_states(&self) -> usize {
        2 * self.n_modes
    }

    /// Number of parameters j.
    pub fn n_params(&self) -> usize {
        self.p_nominal.len()
    }

    fn n_stiffness_params(&self) -> usize {
        self.stiffness_terms.len()
    }

    /// A(P).
    pub fn a(&self, p: &[f64]) -> Mat<f64> {
        let n = self.n_modes;
        let mut a = Mat::<f64>::zeros(2 * n, 2 * n);
        for i in 0..n {
            a[(i, n + i)] = 1.0;
        }
        let ns = self.n_stiffness_params();
        for (i, k) in self.stiffness_terms.iter().enumerate() {
            add_block(&mut a, n, 0, k, -p[i]);
        }
        for (g, d) in self.damping_terms.iter().enumerate() {
            let scale = if ns + g < self.n_params() { p[ns + g] } else { 1.0 };
            add_block(&mut a, n, n, d, -scale);
        }
        a
    }

    /// ∂A/∂P_i (constant: A is linear in P).
    pub fn da(&self, i: usize) -> Mat<f64> {
        let n = self.n_modes;
        let mut d = Mat::<f64>::zeros(2 * n, 2 * n);
        let ns = self.n_stiffness_params();
        if i < ns {
            add_block(&mut d, n, 0, &self.stiffness_terms[i], -1.0);
        } else {
            add_block(&mut d, n, n, &self.damping_terms[i - ns], -1.0);
        }
        d
    }
}

fn add_block(a: &mut Mat<f64>, row: usize, col: usize, block: &Mat<f64>, factor: f64) {
    for j in 0..block.ncols() {
        for i in 0..block.nrows() {
            a[(row + i, col + j)] += factor * block[(i, j)];
        }
    }
}

impl mem::LinearModel for ModalFamily {
    type Error = std::convert::Infallible;
    fn n_states(&self) -> usize {
        self.n_states()
    }
    fn n_params(&self) -> usize {
        self.n_params()
    }
    fn output_names(&self) -> Vec<String> {
        (0..self.c.nrows()).map(|o| format!("y{o}")).collect()
    }
    fn linearize(&self, p: &[f64]) -> Result<mem::Linearized, Self::Error> {
        Ok(mem::Linearized::new(
            self.a(p),
            (0..self.n_params()).map(|i| self.da(i)).collect(),
            self.c.clone(),
            self.x0.clone(),
        ))
    }
}

/// [`ModalFamily`] driven by a force u on its first coordinate (B = e_{n+1}, one input), from
/// the same x(0): the forced problem of the same size as the free one.
#[derive(Clone, Debug)]
pub struct ForcedFamily(pub ModalFamily);

impl mem::LinearModel for ForcedFamily {
    type Error = std::convert::Infallible;
    fn n_states(&self) -> usize {
        self.0.n_states()
    }
    fn n_params(&self) -> usize {
        self.0.n_params()
    }
    fn output_names(&self) -> Vec<String> {
        mem::LinearModel::output_names(&self.0)
    }
    fn input_names(&self) -> Vec<String> {
        vec!["u".into()]
    }
    fn linearize(&self, p: &[f64]) -> Result<mem::Linearized, Self::Error> {
        let mut lin = mem::LinearModel::linearize(&self.0, p)?;
        let n = self.0.n_modes;
        lin.b = Some(Mat::from_fn(2 * n, 1, |r, _| f64::from(u8::from(r == n))));
        Ok(lin)
    }
}

/// A record of `model` driven by a seeded random force (unit variance, zero-order hold) at
/// P = `p`, with white noise of `noise_fraction` of each output's RMS: the outputs and the
/// input column `u`.
pub fn simulate_forced(
    model: &dyn mem::ResponseModel,
    p: &[f64],
    h: f64,
    n_samples: usize,
    noise_fraction: f64,
    seed: u64,
) -> mem::Measurement {
    let mut r = rng(seed);
    let outputs = model.output_names();
    let p_out = outputs.len();
    let u: Vec<f64> = (0..n_samples).map(|_| r.sample::<f64, _>(StandardNormal)).collect();
    let names: Vec<String> = outputs.iter().cloned().chain(["u".to_string()]).collect();
    let with = |values: Mat<f64>| {
        mem::Measurement::new(names.clone(), 0.0, h, values)
            .and_then(|m| m.with_inputs(&["u"], mem::Hold::Zero))
            .expect("finite simulated data")
    };
    let zeros = with(Mat::from_fn(n_samples, p_out + 1, |k, c| if c == p_out { u[k] } else { 0.0 }));
    let clean = mem::sampled_response(model, &zeros, p).expect("the test model evaluates").outputs;
    let noisy = with_noise(&clean, noise_fraction, &mut r);
    with(Mat::from_fn(n_samples, p_out + 1, |k, c| if c == p_out { u[k] } else { noisy[(k, c)] }))
}
