//! Seeded test problems shared by memid's tests and benches, so that benches measure the same
//! models the tests check. Every generator takes an explicit seed; `StdRng` is ChaCha-based and
//! gives the same stream on every platform.

use faer::Mat;
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};
use rand_distr::StandardNormal;

/// A seeded random number generator.
pub fn rng(seed: u64) -> StdRng {
    StdRng::seed_from_u64(seed)
}

/// An n×n matrix of independent standard normal entries.
pub fn gaussian(n_rows: usize, n_cols: usize, seed: u64) -> Mat<f64> {
    let mut r = rng(seed);
    Mat::from_fn(n_rows, n_cols, |_, _| r.sample::<f64, _>(StandardNormal))
}

/// A random stable matrix: Gaussian entries scaled by 1/√n, shifted left by its Gershgorin
/// bound so that every eigenvalue has real part ≤ −0.5 (the spectrum is not computed).
pub fn random_stable(n: usize, seed: u64) -> Mat<f64> {
    let mut a = gaussian(n, n, seed) * faer::Scale(1.0 / (n as f64).sqrt());
    let shift = (0..n).map(|i| (0..n).map(|j| a[(i, j)].abs()).sum::<f64>()).fold(0.0, f64::max);
    for i in 0..n {
        a[(i, i)] -= shift + 0.5;
    }
    a
}

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

/// `clean` with white Gaussian noise of `fraction` × each column's RMS.
fn with_noise(clean: &Mat<f64>, fraction: f64, r: &mut StdRng) -> Mat<f64> {
    let (k, p) = (clean.nrows(), clean.ncols());
    let mut values = clean.clone();
    for o in 0..p {
        let rms = ((0..k).map(|t| clean[(t, o)].powi(2)).sum::<f64>() / k as f64).sqrt();
        for t in 0..k {
            values[(t, o)] += fraction * rms * r.sample::<f64, _>(StandardNormal);
        }
    }
    values
}

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

/// The three-storey shear building of `fixtures/shear_building.ron`, written once for any
/// scalar (`mem::StateSpaceModel`): masses m_i (fixed at 1000 kg unless `free_masses`),
/// storey stiffnesses k1..k3, Rayleigh damping D = αM + βK, q(0) = [0.01, 0.02, 0.03] m at rest.
/// P = [k1, k2, k3, α, β], or [m1, m2, m3, k1, k2, k3, α, β] with free masses.
#[derive(Clone, Debug)]
pub struct ShearBuilding {
    /// What each output measures.
    pub outputs: Vec<mem::Quantity>,
    /// Whether the masses are parameters.
    pub free_masses: bool,
}

impl ShearBuilding {
    /// Nominal values of k1, k2, k3, α, β.
    pub const NOMINAL: [f64; 5] = [2.5e6, 2.25e6, 1.875e6, 0.375, 1.25e-3];

    /// Displacements of floors 1 and 3 (the fixture's outputs), masses fixed.
    pub fn displacements() -> Self {
        Self {
            outputs: vec![mem::Quantity::Displacement(0), mem::Quantity::Displacement(2)],
            free_masses: false,
        }
    }

    /// Accelerations of the three floors, masses fixed.
    pub fn accelerations() -> Self {
        Self { outputs: (0..3).map(mem::Quantity::Acceleration).collect(), free_masses: false }
    }
}

impl mem::StateSpaceModel for ShearBuilding {
    fn parameter_names(&self) -> Vec<String> {
        let core = ["k1", "k2", "k3", "alpha", "beta"];
        let masses = if self.free_masses { vec!["m1", "m2", "m3"] } else { Vec::new() };
        masses.into_iter().chain(core).map(String::from).collect()
    }
    fn output_names(&self) -> Vec<String> {
        self.outputs
            .iter()
            .map(|q| match q {
                mem::Quantity::Displacement(i) => format!("q{}", i + 1),
                mem::Quantity::Velocity(i) => format!("v{}", i + 1),
                mem::Quantity::Acceleration(i) => format!("a{}", i + 1),
            })
            .collect()
    }
    fn state_space<D: mem::Scalar>(&self, p: &[D]) -> Result<mem::StateSpace<D>, mem::BoxedError> {
        use mem::nalgebra::DMatrix;
        let (masses, rest) =
            if self.free_masses { ([p[0], p[1], p[2]], &p[3..]) } else { ([D::from(1000.0); 3], p) };
        let (k1, k2, k3, alpha, beta, z) = (rest[0], rest[1], rest[2], rest[3], rest[4], D::from(0.0));
        let m = DMatrix::from_diagonal(&mem::nalgebra::DVector::from_row_slice(&masses));
        let k = DMatrix::from_row_slice(3, 3, &[k1 + k2, -k2, z, -k2, k2 + k3, -k3, z, -k3, k3]);
        let d = &m * alpha + &k * beta;
        let q0 = [0.01, 0.02, 0.03].map(D::from);
        Ok(mem::SecondOrder::new(m, d, k).state_space(&self.outputs, &q0, &[z; 3])?)
    }
}

/// The same building with its derivatives written by hand (P = [k1, k2, k3, α, β], outputs
/// q1 and q3), optionally with a sign error in ∂A/∂k1 — the mistake the derivative check must catch.
#[derive(Clone, Debug)]
pub struct HandDerivedBuilding {
    /// Flip the sign of ∂A/∂k1.
    pub sign_error: bool,
}

impl mem::LinearModel for HandDerivedBuilding {
    type Error = std::convert::Infallible;
    fn n_states(&self) -> usize {
        6
    }
    fn n_params(&self) -> usize {
        5
    }
    fn output_names(&self) -> Vec<String> {
        vec!["q1".into(), "q3".into()]
    }
    fn linearize(&self, p: &[f64]) -> Result<mem::Linearized, Self::Error> {
        let m = 1000.0;
        let (k1, k2, k3, alpha, beta) = (p[0], p[1], p[2], p[3], p[4]);
        let k = |a: f64, b: f64, c: f64| faer::mat![[a + b, -b, 0.0], [-b, b + c, -c], [0.0, -c, c]];
        let stiffness = k(k1, k2, k3);
        let first_order = |kk: &Mat<f64>, dd: &Mat<f64>, identity: bool| {
            let mut a = Mat::<f64>::zeros(6, 6);
            for i in 0..3 {
                if identity {
                    a[(i, 3 + i)] = 1.0;
                }
                for j in 0..3 {
                    a[(3 + i, j)] = -kk[(i, j)] / m;
                    a[(3 + i, 3 + j)] = -dd[(i, j)] / m;
                }
            }
            a
        };
        let damping = Mat::<f64>::identity(3, 3) * faer::Scale(alpha * m) + &stiffness * faer::Scale(beta);
        let a = first_order(&stiffness, &damping, true);
        let dk = [k(1.0, 0.0, 0.0), k(0.0, 1.0, 0.0), k(0.0, 0.0, 1.0)];
        let mut da: Vec<Mat<f64>> =
            dk.iter().map(|d| first_order(d, &(d * faer::Scale(beta)), false)).collect();
        if self.sign_error {
            da[0] = &da[0] * faer::Scale(-1.0);
        }
        da.push(first_order(&Mat::zeros(3, 3), &(Mat::<f64>::identity(3, 3) * faer::Scale(m)), false));
        da.push(first_order(&Mat::zeros(3, 3), &stiffness, false));
        let mut c = Mat::<f64>::zeros(2, 6);
        c[(0, 0)] = 1.0;
        c[(1, 2)] = 1.0;
        Ok(mem::Linearized::new(a, da, c, vec![0.01, 0.02, 0.03, 0.0, 0.0, 0.0]))
    }
}

/// Adds seeded white Gaussian noise of `fraction` × each output's RMS to a record.
pub fn add_noise(data: &mem::Measurement, fraction: f64, seed: u64) -> mem::Measurement {
    let values = with_noise(data.values(), fraction, &mut rng(seed));
    mem::Measurement::new(data.names().to_vec(), data.start(), data.interval(), values).expect("finite data")
}

/// Named, unbounded parameters starting at `p0`.
pub fn parameters(names: &[&str], p0: &[f64]) -> Vec<mem::Parameter> {
    names.iter().zip(p0).map(|(n, v)| mem::Parameter::new(*n, *v)).collect()
}

/// A scratch directory for one test, `<temp>/<prefix>-<pid>-<test>`, emptied when made and
/// removed when dropped — unless the test is failing (panicking), so that its files stay to be
/// looked at.
pub struct Scratch(std::path::PathBuf);

impl Scratch {
    /// Makes (or empties) the directory.
    pub fn new(prefix: &str, test: &str) -> Self {
        let dir = std::env::temp_dir().join(format!("{prefix}-{}-{test}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("the temporary directory is writable");
        Self(dir)
    }
}

impl std::ops::Deref for Scratch {
    type Target = std::path::Path;
    fn deref(&self) -> &std::path::Path {
        &self.0
    }
}

impl AsRef<std::path::Path> for Scratch {
    fn as_ref(&self) -> &std::path::Path {
        &self.0
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        if !std::thread::panicking() {
            let _ = std::fs::remove_dir_all(&self.0);
        }
    }
}
