//! Benches of a structure model file (issue "any structure"): the fit of the shear building
//! (2,001 samples, 5 free parameters, from the nominal file to the independent simulator's
//! record), the same fit without the finite-difference check of the derivatives, and one
//! evaluation of its expressions with their exact derivatives (A, C, x(0) and ∂/∂P over
//! num-dual), which each Gauss–Newton iteration does once; and the building with a nonlinear
//! spring at q1 simulated by the exponential integrator with its sensitivities, with and without
//! a stiffness that changes with time (the force then reads the time as well); and a linear
//! damper at q3 on the exact path against the exponential integrator's substeps; and the forced
//! building (driven on floor 1, accelerations) with a cubic spring at q1, the integrator taking
//! the measured force as a held input.

use criterion::{Criterion, criterion_group, criterion_main};
use mem::{LinearModel, ResponseModel};
use models::{FitRequest, Model, StructureFitModel};
use std::hint::black_box;
use std::path::Path;

const FREE: [&str; 5] = ["k1", "k2", "k3", "alpha", "beta"];

fn fixture(name: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../fixtures").join(name)
}

fn bench_structure(c: &mut Criterion) {
    let model = Model::load(&fixture("shear_building.ron")).unwrap();
    let data = mem::Measurement::read_csv(&fixture("shear_building_measured.csv")).unwrap();
    let mut group = c.benchmark_group("structure");
    group.sample_size(20);
    group.bench_function("fit/shear_building", |b| {
        b.iter(|| models::fit(black_box(&model), &data, &FitRequest::new(&FREE)).unwrap())
    });
    let mut unchecked = FitRequest::new(&FREE);
    unchecked.derivative_check = mem::DerivativeCheck::Skip;
    group.bench_function("fit/shear_building_unchecked", |b| {
        b.iter(|| models::fit(black_box(&model), &data, &unchecked).unwrap())
    });
    let structure = model.as_structure().unwrap().clone();
    let exact = mem::Exact(StructureFitModel::new(structure, &FREE).unwrap());
    let p: Vec<f64> = FREE.iter().map(|n| model.value(n).unwrap()).collect();
    group
        .bench_function("expressions/shear_building", |b| b.iter(|| exact.linearize(black_box(&p)).unwrap()));
    // The fixture with a spring at q1, then with its rate k₁′·t·q1 too: 2,001 samples at 200 Hz,
    // the five parameters and the spring's free.
    let text = std::fs::read_to_string(fixture("shear_building.ron")).unwrap();
    let with = |spring: &str| {
        let file =
            text.trim_end().trim_end_matches(')').to_string() + &format!("    effects: [{spring}],\n)\n");
        Model::from_ron(&file, "building.ron").unwrap()
    };
    for (name, spring, free) in [
        (
            "respond/spring",
            "CubicStiffness(coordinate: \"q1\", coefficient: 3e10, quintic: Some(5e13))",
            vec!["k1", "k2", "k3", "alpha", "beta", "cubic_q1", "quintic_q1"],
        ),
        (
            "respond/spring_with_rate",
            "CubicStiffness(coordinate: \"q1\", coefficient: 3e10, quintic: Some(5e13), rate: Some(-2e4))",
            vec!["k1", "k2", "k3", "alpha", "beta", "cubic_q1", "quintic_q1", "stiffness_rate_q1"],
        ),
    ] {
        let model = with(spring);
        let response = model.response(&free).unwrap();
        let p: Vec<f64> = free.iter().map(|n| model.value(n).unwrap()).collect();
        let mut out = expm::Response::zeros(2001, 2, free.len());
        group.bench_function(name, |b| {
            b.iter(|| response.respond(black_box(&p), &mem::Grid::free(0.005), &mut out).unwrap())
        });
    }
    // A linear damper at q3 (a drag of exponent 1 held there, the diagnosis's rival): the exact
    // path the model now takes, against the exponential integrator's substeps it took before.
    let model = with("Drag(coordinate: \"q3\", coefficient: 800.0, exponent: 1.0)");
    let free = ["k1", "k2", "k3", "alpha", "beta", "drag_q3"];
    let p: Vec<f64> = free.iter().map(|n| model.value(n).unwrap()).collect();
    let exact = model.response(&free).unwrap();
    let stepped = models::StructureExponential::new(model.as_structure().unwrap().clone(), &free).unwrap();
    let mut out = expm::Response::zeros(2001, 2, free.len());
    group.bench_function("respond/linear_damper_exact", |b| {
        b.iter(|| exact.respond(black_box(&p), &mem::Grid::free(0.005), &mut out).unwrap())
    });
    group.bench_function("respond/linear_damper_substeps", |b| {
        b.iter(|| stepped.respond(black_box(&p), &mem::Grid::free(0.005), &mut out).unwrap())
    });
    // The forced building with a cubic spring at q1, driven by the independent simulator's
    // random force (2,001 samples at 200 Hz), the five parameters and the spring's free.
    let forced = std::fs::read_to_string(fixture("shear_building_forced.ron")).unwrap();
    let file = forced.trim_end().trim_end_matches(')').to_string()
        + "    effects: [CubicStiffness(coordinate: \"q1\", coefficient: 1.03e12)],\n)\n";
    let model = Model::from_ron(&file, "forced.ron").unwrap();
    let record =
        mem::Measurement::read_csv(&fixture("independent/effects/shear_forced_cubic_q1.csv")).unwrap();
    let record = models::align(&model, &record).unwrap();
    let free = ["k1", "k2", "k3", "alpha", "beta", "cubic_q1"];
    let p: Vec<f64> = free.iter().map(|n| model.value(n).unwrap()).collect();
    let response = model.response(&free).unwrap();
    let grid = mem::Grid { start: 0.0, interval: record.interval(), inputs: record.inputs() };
    let mut out = expm::Response::zeros(2001, 3, free.len());
    group.bench_function("respond/forced_spring", |b| {
        b.iter(|| response.respond(black_box(&p), &grid, &mut out).unwrap())
    });
    group.finish();
}

criterion_group!(benches, bench_structure);
criterion_main!(benches);
