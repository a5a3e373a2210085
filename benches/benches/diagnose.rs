//! Benches of `diagnose` (issue "diagnose generalises"): the lattice tests on one sensor's
//! readings (exact, blurred, then the model-based sawtooth, which is what a noise-after
//! quantizer needs), and a whole diagnosis of the shear building whose q3 sensor rounds with
//! the noise after the rounding (`fixtures/independent/effects/quant_after_q3.csv`, 2,001
//! samples, 5 free parameters, every candidate of the structure catalog).

use criterion::{Criterion, criterion_group, criterion_main};
use discrepancy::{DiagnoseOptions, diagnose, quantization};
use models::Model;
use std::hint::black_box;
use std::path::Path;

fn fixture(name: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../fixtures").join(name)
}

fn column(data: &mem::Measurement, o: usize) -> Vec<f64> {
    (0..data.n_samples()).map(|k| data.values()[(k, o)]).collect()
}

fn bench_diagnose(c: &mut Criterion) {
    let data = mem::Measurement::read_csv(&fixture("independent/effects/quant_after_q3.csv")).unwrap();
    let clean =
        mem::Measurement::read_csv(&fixture("independent/clean/shear_building_measured.csv")).unwrap();
    // q3 is the second column of both records.
    let (readings, response) = (column(&data, 1), column(&clean, 1));
    assert!(quantization::detect(&readings, &response, 8.0).is_some(), "the bench's lattice must be found");
    let mut group = c.benchmark_group("diagnose");
    group.sample_size(10);
    group.bench_function("quantization/detect_q3", |b| {
        b.iter(|| quantization::detect(black_box(&readings), &response, 8.0))
    });
    let model = Model::load(&fixture("shear_building.ron")).unwrap();
    let options = DiagnoseOptions::new(&["k1", "k2", "k3", "alpha", "beta"]);
    group.bench_function("diagnose/shear_building_quant_after_q3", |b| {
        b.iter(|| diagnose(black_box(&model), &data, &options).unwrap())
    });
    group.finish();
}

criterion_group!(benches, bench_diagnose);
criterion_main!(benches);
