//! Criterion benches of memid (`cargo bench -p memid-benches --bench sensitivity`), and the
//! problem sizes they share with the tests.

use test_problems::ModalFamily;

/// One MEM-iteration problem size: N = 2·modes states, j parameters, p outputs, k samples.
#[derive(Clone, Copy, Debug)]
pub struct Size {
    /// Criterion id.
    pub name: &'static str,
    /// Number of modes n (N = 2n).
    pub modes: usize,
    /// Parameters j.
    pub params: usize,
    /// Outputs p.
    pub outputs: usize,
    /// Samples k.
    pub samples: usize,
}

/// The three sizes: paper (N = 8, j = 2, p = 3, k = 400), medium (40, 5, 4, 2000),
/// large (200, 20, 10, 10 000).
pub const SIZES: [Size; 3] = [
    Size { name: "paper", modes: 4, params: 2, outputs: 3, samples: 400 },
    Size { name: "medium", modes: 20, params: 5, outputs: 4, samples: 2000 },
    Size { name: "large", modes: 100, params: 20, outputs: 10, samples: 10_000 },
];

/// The seeded modal test family at a size, and its nominal parameters.
pub fn family(size: Size) -> ModalFamily {
    ModalFamily::new(size.modes, size.params, size.outputs, 2026)
}

/// The `fit/paper` problem: C_v and K_p of the paper's slewing plant (potentiometer only) from
/// the fixture's initial values, against 385 samples at 12.8 Hz simulated at C_v = 0.15,
/// K_p = 6.8 with 1 % noise (seed 5).
pub struct PaperFit {
    /// The plant with its free parameters.
    pub adapter: models::SlewingFitModel,
    /// The MEM model.
    pub model: mem::LinearResponse<models::SlewingFitModel>,
    /// The simulated measurement.
    pub data: mem::Measurement,
    /// The starting values.
    pub p0: Vec<f64>,
}

/// Builds [`PaperFit`].
pub fn paper_fit() -> PaperFit {
    let text = plant::PAPER_MODEL_RON
        .replace("outputs: [Potentiometer, Tachometer, StrainGauge]", "outputs: [Potentiometer]");
    let position = plant::SlewingModel::from_ron(&text, "position").expect("the embedded model parses");
    let adapter = models::SlewingFitModel::new(position, &["cv", "kp"]).expect("cv and kp exist");
    let p0 = adapter.values();
    let model = adapter.clone().response();
    let data = test_problems::simulate_measurement(&model, &[0.15, 6.8], 1.0 / 12.8, 385, 0.01, 5);
    PaperFit { adapter, model, data, p0 }
}

/// Flops of one straightforward MEM iteration at a size, counting a multiply-add as 2:
/// the exponential and j Fréchet derivatives (≈ (6 + s) N³ for e^A plus ≈ (13 + 2s) N³ per
/// direction with s ≈ 3 squarings at h = 1/12.8 s for these spectra), the propagation
/// (k steps of Φ·[x, S] and Ψ·x: 2 (2j + 1) N² flops each, plus the outputs 2 p N (j + 1)),
/// and the thin SVD of the (k·p) × j sensitivity matrix (≈ 4 k p j² flops).
pub fn iteration_flops(size: Size) -> f64 {
    let n = 2.0 * size.modes as f64;
    let (j, p, k) = (size.params as f64, size.outputs as f64, size.samples as f64);
    let s = 3.0;
    let exponential = 2.0 * ((6.0 + s) + j * (13.0 + 2.0 * s)) * n.powi(3);
    let propagation = k * (2.0 * (2.0 * j + 1.0) * n * n + 2.0 * p * n * (j + 1.0));
    let svd = 4.0 * k * p * j * j;
    exponential + propagation + svd
}
