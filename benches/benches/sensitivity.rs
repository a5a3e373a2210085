//! Benches of the exponential, its Fréchet derivative and the MEM propagator.

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use faer::Mat;
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
            if n >= 256 && j == 20 {
                group.sample_size(10);
            }
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
    // The paper's size: N = 8 states, j = 2 parameters, p = 3 outputs, K = 400 samples.
    let family = ModalFamily::new(4, 2, 3, 7);
    let a = family.a(&family.p_nominal);
    let das: Vec<Mat<f64>> = (0..2).map(|i| family.da(i)).collect();
    let refs: Vec<_> = das.iter().map(|d| d.as_ref()).collect();
    let h = 1.0 / 12.8;
    c.bench_function("propagator/paper/build", |b| {
        b.iter(|| {
            expm::SensitivityPropagator::new(black_box(a.as_ref()), &refs, family.c.as_ref(), h).unwrap()
        })
    });
    let prop = expm::SensitivityPropagator::new(a.as_ref(), &refs, family.c.as_ref(), h).unwrap();
    let mut out = expm::Response::zeros(400, 3, 2);
    c.bench_function("propagator/paper/propagate", |b| {
        b.iter(|| prop.propagate_into(black_box(&family.x0), None, &mut out).unwrap())
    });
}

criterion_group!(benches, bench_expm, bench_frechet, bench_propagator);
criterion_main!(benches);
