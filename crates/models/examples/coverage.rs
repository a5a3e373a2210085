//! The coverage study of the fit's 95 % intervals (issue "estimates a user can trust"):
//! `cargo run --release -p models --example coverage -- [realisations]` (default 1000); the
//! ignored test `coverage_meets_the_nominal_rate` asserts it.
//!
//! Each case fits noisy records of a known truth, many times with seeded noise, and counts how
//! often each parameter's interval holds the truth. The clean records come from simulators
//! that do not share the fit's exponential path: a fixed-step fourth-order Runge–Kutta
//! integration with steps of at most 0.1 ms (error ≈ 1e-9 of the signal, negligible against
//! the noise) for the slewing plant and the near-bound building, and the independent Python
//! program of `fixtures/independent` (modal superposition checked against DOP853) for the
//! building's displacement and acceleration records. Cases:
//!
//! | case | model | free | noise |
//! | --- | --- | --- | --- |
//! | slewing, 12.8 Hz | paper model, θ, θ̇, strain | cv, kp | white, 1 % of RMS |
//! | slewing, 128 Hz decimated by 10 | the same, through the decimation filter | cv, kp | white |
//! | building, displacements | q1, q3 | k1, k2, k3, α, β | white |
//! | building, accelerations | a1, a2, a3 (C depends on P) | k1, k2, k3, α, β | white |
//! | building, α near its bound 0 | q1, q3, truth α = 0.002 | k1, k2, k3, α ≥ 0, β | white |
//! | slewing, coloured noise | as the first | cv, kp | AR(1), ρ = 0.8 |
//! | building, forced | a chirp and a random force on floor 1, a1..a3, both records in one fit | k1, k2, k3, α, β | white, outputs only (the force is known) |
//!
//! Writes a markdown table to stdout (docs/fitting.md holds the measured one).

use faer::Mat;
use mem::{Exact, Experiment, Fit, Interval, LinearModel, LinearResponse, Measurement, Parameter, Problem};
use models::{SlewingFitModel, StructureFitModel};
use plant::SlewingModel;
use rand::{Rng, SeedableRng};
use rand_distr::StandardNormal;
use test_problems::ShearBuilding;

/// y(t_k) of ẋ = Ax, y = Cx by RK4 with `sub` steps per sample.
fn rk4(lin: &mem::Linearized, h: f64, samples: usize, sub: usize) -> Mat<f64> {
    let n = lin.a.nrows();
    let mut x = lin.x0.clone();
    let step = h / sub as f64;
    let f = |x: &[f64]| -> Vec<f64> { (0..n).map(|i| (0..n).map(|j| lin.a[(i, j)] * x[j]).sum()).collect() };
    let mut y = Mat::zeros(samples, lin.c.nrows());
    for k in 0..samples {
        for o in 0..lin.c.nrows() {
            y[(k, o)] = (0..n).map(|j| lin.c[(o, j)] * x[j]).sum();
        }
        for _ in 0..sub {
            let k1 = f(&x);
            let x2: Vec<f64> = (0..n).map(|i| x[i] + 0.5 * step * k1[i]).collect();
            let k2 = f(&x2);
            let x3: Vec<f64> = (0..n).map(|i| x[i] + 0.5 * step * k2[i]).collect();
            let k3 = f(&x3);
            let x4: Vec<f64> = (0..n).map(|i| x[i] + step * k3[i]).collect();
            let k4 = f(&x4);
            for i in 0..n {
                x[i] += step / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
            }
        }
    }
    y
}

/// The clean record plus noise on its outputs (a measured input stays as it is): white (ρ = 0)
/// or AR(1), stationary, σ = 1 % of each output's RMS.
fn noisy(clean: &Measurement, rho: f64, seed: u64) -> Measurement {
    let mut rng = rand::rngs::StdRng::seed_from_u64(seed);
    let (k, p) = (clean.n_samples(), clean.n_outputs());
    let mut values = clean.values().clone();
    for o in 0..p {
        let rms = ((0..k).map(|t| values[(t, o)].powi(2)).sum::<f64>() / k as f64).sqrt();
        let sigma = 0.01 * rms;
        let mut e = sigma * rng.sample::<f64, _>(StandardNormal);
        for t in 0..k {
            if t > 0 {
                e = rho * e + (1.0 - rho * rho).sqrt() * sigma * rng.sample::<f64, _>(StandardNormal);
            }
            values[(t, o)] += e;
        }
    }
    clean.with_values(values).expect("finite")
}

fn read(path: &str) -> Measurement {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../../");
    Measurement::read_csv(std::path::Path::new(&format!("{root}{path}"))).expect("fixture")
}

struct Case {
    name: &'static str,
    /// The clean records, one experiment each, fitted together.
    clean: Vec<Measurement>,
    decimate: usize,
    rho: f64,
    model: Box<dyn mem::ResponseModel + Sync>,
    parameters: Vec<Parameter>,
    truth: Vec<f64>,
}

struct Tally {
    covered: Vec<usize>,
    one_sided: Vec<usize>,
    undetermined: Vec<usize>,
    z: Vec<Vec<f64>>,
    ar1: usize,
    runs: usize,
}

fn run(case: &Case, realisations: usize) -> Tally {
    let j = case.truth.len();
    let mut t = Tally {
        covered: vec![0; j],
        one_sided: vec![0; j],
        undetermined: vec![0; j],
        z: vec![Vec::new(); j],
        ar1: 0,
        runs: 0,
    };
    for r in 0..realisations {
        let data: Vec<Measurement> = case
            .clean
            .iter()
            .enumerate()
            .map(|(e, clean)| {
                let data = noisy(clean, case.rho, 1000 + r as u64 + 1_000_000 * e as u64);
                if case.decimate > 1 { data.decimate(case.decimate).expect("decimates") } else { data }
            })
            .collect();
        let experiments = data.iter().map(|d| Experiment::normalized(case.model.as_ref(), d)).collect();
        let problem = Problem::new(experiments, case.parameters.clone()).expect("valid problem");
        let report = Fit::new().run(&problem).expect("the fit runs");
        t.runs += 1;
        if report.statistics.covariance_kind == mem::Covariance::Ar1 {
            t.ar1 += 1;
        }
        for i in 0..j {
            let interval = report.statistics.intervals[i];
            if interval.contains(case.truth[i]) {
                t.covered[i] += 1;
            }
            match interval {
                Interval::OneSided { .. } => t.one_sided[i] += 1,
                Interval::Undetermined => t.undetermined[i] += 1,
                Interval::Symmetric { .. } => {}
            }
            if let Some(se) = report.std_error(i) {
                t.z[i].push((report.parameters[i] - case.truth[i]) / se);
            }
        }
    }
    t
}

fn slewing_case(name: &'static str, rate: f64, decimate: usize, rho: f64) -> Case {
    let truth = [0.12, 7.2];
    let model = SlewingFitModel::new(SlewingModel::paper(), &["cv", "kp"]).expect("cv, kp exist");
    let lin = model.linearize(&truth).expect("the paper's model assembles");
    let h = 1.0 / rate;
    let samples = (30.0 * rate) as usize + 1;
    let names = model.output_names();
    // RK4 steps of at most 0.1 ms: global error ≈ T(ωΔt)⁴ω/120 ≈ 1e-9 of the 10.9 Hz strain mode.
    let sub = (h / 1e-4).ceil() as usize;
    let clean = Measurement::new(names, 0.0, h, rk4(&lin, h, samples, sub)).expect("finite");
    Case {
        name,
        clean: vec![clean],
        decimate,
        rho,
        parameters: model.parameters(),
        model: Box::new(model.response()),
        truth: truth.to_vec(),
    }
}

fn building_parameters(start: [f64; 5], alpha_bound: bool) -> Vec<Parameter> {
    ["k1", "k2", "k3", "alpha", "beta"]
        .iter()
        .zip(start)
        .map(|(n, v)| {
            let p = Parameter::new(*n, v);
            if alpha_bound && *n == "alpha" { p.with_bounds(0.0, f64::INFINITY) } else { p }
        })
        .collect()
}

/// One parameter's line of the coverage table.
#[derive(Clone, Debug)]
pub struct Row {
    /// The case.
    pub case: &'static str,
    /// Whether the white-noise model holds in the case.
    pub white: bool,
    /// The parameter.
    pub parameter: String,
    /// Fraction of intervals holding the truth.
    pub coverage: f64,
    /// Mean and standard deviation of (estimate − truth)/standard error.
    pub z: (f64, f64),
    /// Realisations with a one-sided or no interval, and with the AR(1) covariance chosen.
    pub one_sided: usize,
    /// Realisations whose interval was "undetermined".
    pub undetermined: usize,
    /// Realisations where the AR(1) covariance was chosen.
    pub ar1: usize,
    /// Realisations.
    pub runs: usize,
}

/// Runs every case with `realisations` noise seeds.
pub fn study(realisations: usize) -> Vec<Row> {
    let building_truth = vec![2.62e6, 2.16e6, 1.96e6, 0.42, 1.18e-3];
    let nominal = ShearBuilding::NOMINAL;
    let near_bound_truth = [2.62e6, 2.16e6, 1.96e6, 0.002, 1.18e-3];
    let near_bound_clean = {
        let model = Exact(ShearBuilding::displacements());
        let lin = model.linearize(&near_bound_truth).expect("assembles");
        Measurement::new(model.output_names(), 0.0, 0.005, rk4(&lin, 0.005, 2001, 50)).expect("finite")
    };
    let forced = {
        let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../../");
        let file = structure::StructureModel::load(std::path::Path::new(&format!(
            "{root}fixtures/shear_building_forced.ron"
        )))
        .expect("the fixture loads");
        StructureFitModel::new(file, &["k1", "k2", "k3", "alpha", "beta"]).expect("its parameters")
    };
    let cases = vec![
        slewing_case("slewing θ, θ̇, strain at 12.8 Hz; cv, kp", 12.8, 1, 0.0),
        slewing_case("slewing at 128 Hz decimated by 10; cv, kp", 128.0, 10, 0.0),
        Case {
            name: "building, displacements q1, q3; k1..k3, α, β",
            clean: vec![read("fixtures/independent/clean/shear_building_measured.csv")],
            decimate: 1,
            rho: 0.0,
            model: Box::new(LinearResponse(Exact(ShearBuilding::displacements()))),
            parameters: building_parameters(nominal, false),
            truth: building_truth.clone(),
        },
        Case {
            name: "building, accelerations a1..a3; k1..k3, α, β",
            clean: vec![read("fixtures/independent/clean/shear_building_acc_measured.csv")],
            decimate: 1,
            rho: 0.0,
            model: Box::new(LinearResponse(Exact(ShearBuilding::accelerations()))),
            parameters: building_parameters(nominal, false),
            truth: building_truth.clone(),
        },
        Case {
            name: "building, α = 0.002 near its bound α ≥ 0",
            clean: vec![near_bound_clean],
            decimate: 1,
            rho: 0.0,
            model: Box::new(LinearResponse(Exact(ShearBuilding::displacements()))),
            parameters: building_parameters(nominal, true),
            truth: near_bound_truth.to_vec(),
        },
        slewing_case("slewing at 12.8 Hz, AR(1) noise ρ = 0.8", 12.8, 1, 0.8),
        Case {
            name: "building, forced: chirp and random force on floor 1, fitted together",
            clean: ["chirp", "random"]
                .iter()
                .map(|r| {
                    read(&format!("fixtures/independent/clean/shear_building_forced_{r}.csv"))
                        .with_inputs(&["u"], mem::Hold::Zero)
                        .expect("the record has u")
                })
                .collect(),
            decimate: 1,
            rho: 0.0,
            model: Box::new(forced.clone().response()),
            parameters: forced.parameters(),
            truth: building_truth.clone(),
        },
    ];
    let mut rows = Vec::new();
    for case in &cases {
        let t = run(case, realisations);
        for (i, p) in case.parameters.iter().enumerate() {
            let z = &t.z[i];
            let mean = z.iter().sum::<f64>() / z.len().max(1) as f64;
            let sd = (z.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (z.len().max(2) - 1) as f64).sqrt();
            rows.push(Row {
                case: case.name,
                white: case.rho == 0.0,
                parameter: p.name.clone(),
                coverage: t.covered[i] as f64 / t.runs as f64,
                z: (mean, sd),
                one_sided: t.one_sided[i],
                undetermined: t.undetermined[i],
                ar1: t.ar1,
                runs: t.runs,
            });
        }
    }
    rows
}

#[allow(dead_code)]
fn main() {
    let realisations: usize = std::env::args().nth(1).and_then(|a| a.parse().ok()).unwrap_or(1000);
    println!(
        "{realisations} realisations per case; 1 % noise of each output's RMS; nominal 95 % intervals.\n"
    );
    println!(
        "| case | parameter | coverage | mean z | sd z | one-sided | undetermined | AR(1) covariance chosen |"
    );
    println!("| --- | --- | --- | --- | --- | --- | --- | --- |");
    let mut last = "";
    for r in study(realisations) {
        println!(
            "| {} | {} | {:.1} % | {:+.2} | {:.2} | {} | {} | {}/{} |",
            if r.case != last { r.case } else { "" },
            r.parameter,
            100.0 * r.coverage,
            r.z.0,
            r.z.1,
            r.one_sided,
            r.undetermined,
            r.ar1,
            r.runs
        );
        last = r.case;
    }
}
