//! Benches of `diagnose` (issue "diagnose generalises"): the lattice tests on one sensor's
//! readings (exact, blurred, then the model-based sawtooth, which is what a noise-after
//! quantizer needs), and a whole diagnosis of the shear building whose q3 sensor rounds with
//! the noise after the rounding (`fixtures/independent/effects/quant_after_q3.csv`, 2,001
//! samples, 5 free parameters, every candidate of the structure catalog). For backlash, the
//! slewing catalog's dearest candidate: one exponential-integrator response with sensitivities of
//! the rig with a geared dead band (12.8 Hz, 30 s, C_v, K_p and the band free) beside the same
//! rig with a Coulomb friction (and each response's outputs alone, what a fit's trial point costs
//! before it is accepted), and a whole diagnosis of the independent backlash record
//! (`fixtures/independent/effects/slewing_backlash.csv`, decimated to 12.8 Hz) and of the record
//! with a heavily damped mode the search follows from its seeds (`slewing_damped_mode.csv`), and
//! of a current clamp in coloured noise, whose saturation trials are refitted from the catalog's
//! limiter and from a clamp (`slewing_clamp_coloured.csv`). On a forced record: the peak picking
//! on the frequency response from the measured force (`discrepancy::frf::resonances`, 2,001
//! samples, two outputs) and a whole diagnosis of the building shaken on the roof with a driven
//! appendage (`fixtures/independent/forced/appendage_q3.csv`), and of one whose q3 sensor reads
//! 1 % low (`scale_q3_small.csv`), which the diagnosis assesses twice, with the masses and
//! without them. A named spring's form test, with its rival law in time (eight more
//! parameters refitted from the reference): the building whose storey-1 spring hardens
//! (`cubic_q1.csv`, the spring named) and whose storey-2 spring loses stiffness early and
//! settles (`settling_q2.csv`, the spring set aside for the law). An appendage at every
//! coordinate for every mode seed: the building with a 35 kg appendage on floor 1 released so
//! that it rings (`appendage_ringing_q1.csv`, named at q1), and two released relaxed above the
//! building's modes, found from the start above them (`appendage_q3.csv`, 25 kg at 19 Hz on the
//! roof; `structure_stiff_appendage_q1.csv`, the structure study's 50 kg at 17 Hz on floor 1),
//! and one the masses take up unless the body is chosen among floors by its fit, which the
//! diagnosis assesses with the masses and without them (`structure_body_or_masses_q1.csv`).
//! A gauge scale tied with the other
//! gauge's while the masses are free, weighed again without them (`study_scale_q1_noisy_force.csv`,
//! named at q1).

use criterion::{Criterion, criterion_group, criterion_main};
use discrepancy::{DiagnoseOptions, diagnose, quantization};
use mem::ResponseModel;
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
    for case in [
        "cubic_q1",
        "settling_q2",
        "appendage_ringing_q1",
        "appendage_q3",
        "structure_stiff_appendage_q1",
        "structure_body_or_masses_q1",
    ] {
        let data = mem::Measurement::read_csv(&fixture(&format!("independent/effects/{case}.csv"))).unwrap();
        group.bench_function(format!("diagnose/shear_building_{case}"), |b| {
            b.iter(|| diagnose(black_box(&model), &data, &options).unwrap())
        });
    }
    group.finish();
}

fn bench_backlash(c: &mut Criterion) {
    let paper = std::fs::read_to_string(fixture("slewing.ron")).unwrap();
    let with = |effect: &str| {
        let text = paper.replace("    free:", &format!("    effects: [{effect}],\n    free:"));
        plant::SlewingModel::from_ron(&text, "bench.ron").unwrap()
    };
    let mut group = c.benchmark_group("diagnose");
    group.sample_size(10);
    for (name, effect, strength) in [
        (
            "backlash",
            "Backlash(dead_band: 0.008, gear_frequency_hz: 10.0, tachometer_on_motor: false)",
            "backlash",
        ),
        ("coulomb", "CoulombFriction(torque: 0.01, smoothing_velocity: 0.003)", "coulomb_torque"),
    ] {
        let model = with(effect);
        let free = ["cv", "kp", strength];
        let p: Vec<f64> = free.iter().map(|n| model.get(model.parameter(n).unwrap())).collect();
        let response = models::ExponentialResponse::new(model, &free).unwrap();
        let mut out = expm::Response::zeros(385, 3, free.len());
        group.bench_function(format!("respond_12.8Hz/{name}"), |b| {
            b.iter(|| response.simulate(black_box(&p), 0.0, 1.0 / 12.8, &mut out).unwrap())
        });
        // The outputs alone: what a trial point of the fit costs before it is accepted.
        let mut alone = expm::Response::zeros(385, 3, 0);
        group.bench_function(format!("respond_outputs_12.8Hz/{name}"), |b| {
            b.iter(|| response.simulate(black_box(&p), 0.0, 1.0 / 12.8, &mut alone).unwrap())
        });
    }
    // A hub spring without its cubic part (the rival `hub_stiffness`): the exact path the
    // model now takes, against the exponential integrator's substeps it took before.
    let servo = plant::assemble::servo_stiffness(with("").constants());
    let spring = with(&format!("CubicStiffness(coefficient: 0.0, linear: Some({:e}))", 0.05 * servo));
    let free = ["cv", "kp", "hub_stiffness"];
    let p: Vec<f64> = free.iter().map(|n| spring.get(spring.parameter(n).unwrap())).collect();
    let grid = mem::Grid::free(1.0 / 12.8);
    let exact = Model::Slewing(spring.clone())
        .response_with(&free, models::Integrator::Exponential { max_step: 1.0 / 640.0 })
        .unwrap();
    let stepped = models::ExponentialResponse::new(spring, &free).unwrap().with_max_step(1.0 / 640.0);
    let mut out = expm::Response::zeros(385, 3, free.len());
    group.bench_function("respond_12.8Hz/hub_spring_exact", |b| {
        b.iter(|| exact.respond(black_box(&p), &grid, &mut out).unwrap())
    });
    group.bench_function("respond_12.8Hz/hub_spring_substeps", |b| {
        b.iter(|| stepped.respond(black_box(&p), &grid, &mut out).unwrap())
    });
    let model = Model::load(&fixture("slewing.ron")).unwrap();
    let mut options = DiagnoseOptions::new(&["cv", "kp"]);
    options.decimate = Some(10);
    // The dearest effect, a heavily damped mode the search follows from its seeds, and a clamp
    // (a named saturation, with its knee test).
    for record in ["slewing_backlash", "slewing_damped_mode", "slewing_clamp_coloured"] {
        let data =
            mem::Measurement::read_csv(&fixture(&format!("independent/effects/{record}.csv"))).unwrap();
        group.bench_function(format!("diagnose/{record}_12.8Hz"), |b| {
            b.iter(|| diagnose(black_box(&model), &data, &options).unwrap())
        });
    }
    // A strain scale the beam's mass per length takes up: nothing is named, and the scale is
    // refitted in ρ's place (`scale_in_place`).
    let text = std::fs::read_to_string(fixture("slewing.ron"))
        .unwrap()
        .replace("hub_angle: 0.5,", "hub_angle: 0.7006818341003855,");
    let scaled = Model::from_ron(&text, "slewing.ron").unwrap();
    let data = mem::Measurement::read_csv(&fixture("independent/effects/slewing_scale_in_place_of_rho.csv"))
        .unwrap();
    group.bench_function("diagnose/slewing_scale_in_place_of_rho_12.8Hz", |b| {
        b.iter(|| diagnose(black_box(&scaled), &data, &options).unwrap())
    });
    group.finish();
}

fn bench_forced(c: &mut Criterion) {
    let model = Model::load(&fixture("shear_building_forced_q.ron")).unwrap();
    let raw = mem::Measurement::read_csv(&fixture("independent/forced/appendage_q3.csv")).unwrap();
    let data = models::align(&model, &raw).unwrap();
    let series = faer::Mat::from_fn(data.n_samples(), data.n_outputs(), |t, o| data.values()[(t, o)]);
    assert!(!discrepancy::frf::resonances(&data, &series).unwrap().is_empty(), "the building's peaks");
    let mut group = c.benchmark_group("diagnose");
    group.sample_size(10);
    group.bench_function("frf/resonances_forced_2001", |b| {
        b.iter(|| discrepancy::frf::resonances(black_box(&data), &series))
    });
    // The same scan read under per-output noise predictors of 80 lags (a resonant noise of the
    // force's kind: AR(2) poles at 3.5 Hz, 0.5 % damping, above a white floor), as a forced
    // record with noise on its force is scanned (`frf::resonances_under`).
    let w = 2.0 * std::f64::consts::PI * 3.5 * data.interval();
    let ar2 = test_problems::Ar2::resonance(1.0 - 0.005 * 0.11, w);
    let mut gamma = ar2.autocovariance(80, 1e-4);
    gamma[0] += 1.0;
    let predictor = mem::NoisePredictor::of_autocovariance(&gamma).expect("positive definite");
    let noise = vec![Some(predictor); data.n_outputs()];
    let under = [discrepancy::frf::Scanned { series: &series, noise: Some(&noise) }];
    assert!(discrepancy::frf::resonances_under(&data, &under).is_some());
    group.bench_function("frf/resonances_under_noise_forced_2001", |b| {
        b.iter(|| discrepancy::frf::resonances_under(black_box(&data), &under))
    });
    // The force's noise read from a residual (once per diagnosis and once per candidate that
    // acts through the dynamics); its cost does not depend on the values, so the record stands
    // for both the simulation and the residual.
    assert!(discrepancy::frf::input_noise(&data, &series, &series).is_some());
    group.bench_function("frf/input_noise_forced_2001", |b| {
        b.iter(|| discrepancy::frf::input_noise(black_box(&data), &series, &series))
    });
    // The fitted model's exact response to white noise on its force (the discrete Lyapunov
    // equation by doubling, then 500 lags: a Welch segment of the 2,001-sample record), once per
    // fit whose force's noise is read (`frf::NoiseResponse`).
    let structure = model.as_structure().expect("a structure");
    let space = structure.state_space::<f64>(&structure.values()).unwrap();
    let weights = vec![1.0; data.n_outputs()];
    assert!(
        discrepancy::frf::NoiseResponse::new(&space, mem::Hold::Zero, data.interval(), &weights, 500)
            .is_some()
    );
    group.bench_function("frf/noise_response_forced_500_lags", |b| {
        b.iter(|| {
            discrepancy::frf::NoiseResponse::new(
                black_box(&space),
                mem::Hold::Zero,
                data.interval(),
                &weights,
                500,
            )
        })
    });
    // The scan of trial appendages reacting through the building (`frf::AppendageScan`), once
    // per diagnosis of a forced structure: three coordinates, a 1 % grid over the band the force
    // excites, each trial's exact mass sensitivity whitened by the 80-lag predictors above.
    let free: Vec<String> = ["k1", "k2", "k3", "alpha", "beta"].map(String::from).to_vec();
    let names: Vec<&str> = free.iter().map(String::as_str).collect();
    let reference = models::fit(&model, &data, &models::FitRequest::new(&names)).unwrap();
    let residual = reference.first().residual();
    let whitening: Vec<mem::NoisePredictor> = noise.iter().flatten().cloned().collect();
    let scan = discrepancy::frf::AppendageScan {
        model: reference.fitted.as_structure().expect("a structure"),
        free: &free,
        data: &reference.first().data,
        residual: &residual,
        noise: &whitening,
        margin: 10.0,
    };
    assert_eq!(scan.run().first().map(|b| b.coordinate.as_str()), Some("q3"), "the roof's appendage");
    group.bench_function("frf/appendage_scan_forced_2001", |b| b.iter(|| black_box(&scan).run()));
    let options = DiagnoseOptions::new(&["k1", "k2", "k3", "alpha", "beta"]);
    group.bench_function("diagnose/shear_building_forced_appendage_q3", |b| {
        b.iter(|| diagnose(black_box(&model), &raw, &options).unwrap())
    });
    // A scale error the masses take up: assessed against the reference with them, nothing is
    // chosen, and everything is assessed again without them (module `secondary`): the dearest
    // kind of forced diagnosis.
    let small = mem::Measurement::read_csv(&fixture("independent/forced/scale_q3_small.csv")).unwrap();
    assert_eq!(diagnose(&model, &small, &options).unwrap().effect(), "sensor_scale");
    group.bench_function("diagnose/shear_building_forced_scale_q3_small", |b| {
        b.iter(|| diagnose(black_box(&model), &small, &options).unwrap())
    });
    // The structure a noise spectrum implies (the force noise's floor, once per output of a
    // forced diagnosis): a resonance above a white floor on the 512 bins of a 1024-sample segment.
    let levels: Vec<f64> = (0..512)
        .map(|b| {
            let x = (b as f64 - 51.2) / 3.0;
            1.0 + 20.0 / (1.0 + x * x)
        })
        .collect();
    assert!(discrepancy::diagnose::evidence::structure_of_spectrum(&levels, 0.5, 2001) > 0.0);
    group.bench_function("evidence/structure_of_spectrum_512", |b| {
        b.iter(|| discrepancy::diagnose::evidence::structure_of_spectrum(black_box(&levels), 0.5, 2001))
    });
    // A record whose force carries 2 % noise: the noise's predictors, the force-noise screen and
    // the named drag's rivals (the dampers at every coordinate) all run.
    let noisy = mem::Measurement::read_csv(&fixture("independent/forced/offset_q3_noisy_force.csv")).unwrap();
    assert!(!diagnose(&model, &noisy, &options).unwrap().noise.predictors.iter().all(Option::is_none));
    group.bench_function("diagnose/shear_building_forced_offset_q3_noisy_force", |b| {
        b.iter(|| diagnose(black_box(&model), &noisy, &options).unwrap())
    });
    // A gauge's scale the masses take up, tied with the other gauge's: the tied scale is
    // refitted against the reference without the masses too, and that reference assessed again
    // (module `secondary`, `tied`); the q1 scale is named there.
    let ratio =
        mem::Measurement::read_csv(&fixture("independent/forced/study_scale_q1_noisy_force.csv")).unwrap();
    assert_eq!(
        diagnose(&model, &ratio, &options).unwrap().named().map(|c| c.label.as_str()),
        Some("sensor_scale(q1)")
    );
    group.bench_function("diagnose/shear_building_forced_scale_q1_tied_noisy_force", |b| {
        b.iter(|| diagnose(black_box(&model), &ratio, &options).unwrap())
    });
    group.finish();
}

criterion_group!(benches, bench_diagnose, bench_backlash, bench_forced);
criterion_main!(benches);
