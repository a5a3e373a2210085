//! Benches of the exponential, its Fréchet derivative, the MEM propagator and iteration.

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use faer::Mat;
use memid_benches::{SIZES, family, iteration_flops};
use std::hint::black_box;
use test_problems::ModalFamily;

/// A modal-family system matrix times h = 1/12.8 s: the shape of matrix the MEM exponentiates.
fn system_matrix(n_states: usize) -> Mat<f64> {
    let family = ModalFamily::new(n_states / 2, 2, 1, 42);
    family.a(&family.p_nominal) * faer::Scale(1.0 / 12.8)
}

fn bench_expm(c: &mut Criterion) {
    let mut group = c.benchmark_group("expm");
    for n in [8usize, 16, 64, 256, 512] {
        let a = system_matrix(n);
        if n >= 256 {
            group.sample_size(20);
        }
        group.bench_with_input(BenchmarkId::from_parameter(n), &a, |b, a| {
            b.iter(|| expm::expm(black_box(a.as_ref())).unwrap())
        });
    }
    group.finish();
}

fn bench_frechet(c: &mut Criterion) {
    let mut group = c.benchmark_group("expm_frechet");
    for n in [8usize, 16, 64, 256, 512] {
        let a = system_matrix(n);
        for j in [1usize, 5, 20] {
            group.sample_size(if n >= 256 { 10 } else { 30 });
            let es: Vec<Mat<f64>> = (0..j).map(|k| test_problems::gaussian(n, n, k as u64)).collect();
            let refs: Vec<_> = es.iter().map(|e| e.as_ref()).collect();
            group.bench_with_input(BenchmarkId::new(format!("j{j}"), n), &refs, |b, refs| {
                b.iter(|| expm::expm_frechet_many(black_box(a.as_ref()), refs).unwrap())
            });
        }
    }
    group.finish();
}

fn bench_propagator(c: &mut Criterion) {
    let mut group = c.benchmark_group("propagator");
    for size in SIZES {
        let fam = family(size);
        let a = fam.a(&fam.p_nominal);
        let das: Vec<Mat<f64>> = (0..size.params).map(|i| fam.da(i)).collect();
        let refs: Vec<_> = das.iter().map(|d| d.as_ref()).collect();
        let prop = expm::SensitivityPropagator::new(a.as_ref(), &refs, fam.c.as_ref(), 1.0 / 12.8).unwrap();
        let mut out = expm::Response::zeros(size.samples, size.outputs, size.params);
        if size.name == "large" {
            group.sample_size(10);
        }
        group.bench_function(BenchmarkId::new("propagate", size.name), |b| {
            b.iter(|| prop.propagate_into(black_box(&fam.x0), None, &mut out).unwrap())
        });
    }
    group.finish();
}

fn bench_iteration(c: &mut Criterion) {
    let mut group = c.benchmark_group("mem_iteration");
    for size in SIZES {
        let fam = family(size);
        let model = mem::LinearResponse(fam.clone());
        let truth: Vec<f64> = fam
            .p_nominal
            .iter()
            .enumerate()
            .map(|(i, v)| v * (1.0 + 0.05 * ((i % 3) as f64 - 1.0)))
            .collect();
        let data = test_problems::simulate_measurement(&model, &truth, 1.0 / 12.8, size.samples, 0.01, 1);
        let experiments =
            mem::Problem::unnamed(vec![mem::Experiment::normalized(&model, &data)], &fam.p_nominal).unwrap();
        if size.name == "large" {
            group.sample_size(10);
        }
        group.throughput(Throughput::Elements(iteration_flops(size) as u64));
        group.bench_function(size.name, |b| {
            b.iter(|| mem::gauss_newton_step(black_box(&experiments), &fam.p_nominal, 1e-10).unwrap())
        });
    }
    group.finish();
}

/// A forced iteration against a free-decay one of the same size: the same modal family, driven
/// by a random force under a zero-order hold (issue 16: ≤ 1.5× the free iteration).
fn bench_forced_iteration(c: &mut Criterion) {
    let mut group = c.benchmark_group("forced_vs_free");
    for size in &SIZES[..2] {
        let fam = family(*size);
        let free = mem::LinearResponse(fam.clone());
        let forced = mem::LinearResponse(test_problems::ForcedFamily(fam.clone()));
        let truth: Vec<f64> = fam.p_nominal.iter().map(|v| v * 1.03).collect();
        let free_data = test_problems::simulate_measurement(&free, &truth, 1.0 / 12.8, size.samples, 0.01, 1);
        let forced_data = test_problems::simulate_forced(&forced, &truth, 1.0 / 12.8, size.samples, 0.01, 1);
        let free_problem =
            mem::Problem::unnamed(vec![mem::Experiment::normalized(&free, &free_data)], &fam.p_nominal)
                .unwrap();
        let forced_problem =
            mem::Problem::unnamed(vec![mem::Experiment::normalized(&forced, &forced_data)], &fam.p_nominal)
                .unwrap();
        group.bench_function(BenchmarkId::new("free", size.name), |b| {
            b.iter(|| mem::gauss_newton_step(black_box(&free_problem), &fam.p_nominal, 1e-10).unwrap())
        });
        group.bench_function(BenchmarkId::new("forced", size.name), |b| {
            b.iter(|| mem::gauss_newton_step(black_box(&forced_problem), &fam.p_nominal, 1e-10).unwrap())
        });
    }
    group.finish();
}

/// A Gauss–Newton step whose residuals and sensitivities are whitened (generalised least
/// squares) against the same step unwhitened: AR(1), and a predictor of order 20 (a resonant
/// autocovariance, γ_l = 0.95^l cos(0.3 l)), as the diagnosis's force-noise likelihood uses.
fn bench_whitened_iteration(c: &mut Criterion) {
    let mut group = c.benchmark_group("whitened_iteration");
    let gamma: Vec<f64> = (0..=20).map(|l| 0.95_f64.powi(l) * (0.3 * l as f64).cos()).collect();
    let predictor = mem::NoisePredictor::of_autocovariance(&gamma).expect("positive definite");
    for size in &SIZES[..2] {
        let fam = family(*size);
        let model = mem::LinearResponse(fam.clone());
        let truth: Vec<f64> = fam.p_nominal.iter().map(|v| v * 1.03).collect();
        let data = test_problems::simulate_measurement(&model, &truth, 1.0 / 12.8, size.samples, 0.01, 1);
        let outputs = data.n_outputs();
        let plain = || mem::Experiment::normalized(&model, &data);
        let problems = [
            ("white", plain()),
            ("ar1", plain().with_noise_correlation(vec![0.9; outputs])),
            ("order_20", plain().with_noise_predictors(vec![predictor.clone(); outputs])),
        ]
        .map(|(name, e)| (name, mem::Problem::unnamed(vec![e], &fam.p_nominal).unwrap()));
        for (name, problem) in &problems {
            group.bench_function(BenchmarkId::new(*name, size.name), |b| {
                b.iter(|| mem::gauss_newton_step(black_box(problem), &fam.p_nominal, 1e-10).unwrap())
            });
        }
    }
    group.finish();
}

fn bench_paper_fit(c: &mut Criterion) {
    let problem = memid_benches::paper_fit();
    let experiments =
        mem::Problem::unnamed(vec![mem::Experiment::new(&problem.model, &problem.data)], &problem.p0)
            .unwrap();
    c.bench_function("fit/paper", |b| b.iter(|| mem::Fit::new().run(black_box(&experiments)).unwrap()));
}

criterion_group!(
    benches,
    bench_expm,
    bench_frechet,
    bench_propagator,
    bench_iteration,
    bench_forced_iteration,
    bench_whitened_iteration,
    bench_paper_fit
);
criterion_main!(benches);
