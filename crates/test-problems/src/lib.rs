//! Seeded test problems shared by memid's tests and benches, so that benches measure the same
//! models the tests check. Every generator takes an explicit seed; `StdRng` is ChaCha-based and
//! gives the same stream on every platform.

mod ar2;
mod building;
mod modal;
mod oscillators;

pub use ar2::Ar2;
pub use building::{HandDerivedBuilding, ShearBuilding};
pub use modal::{ForcedFamily, ModalFamily, simulate_forced};
pub use oscillators::{ProductOscillator, SpringChain, simulate_measurement};

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
