//! Measures, in one run, what docs/performance.md reports beside the SciPy peer:
//! this machine's GEMM rate (faer, 1024³), each size's flop count and GEMM-bound lower bound,
//! memid's MEM iteration (median), a whole paper-size fit, and the speed-ups of the two cores.
//! Prints JSON. `cargo run --release -p memid-benches --example sizes`

use faer::{Accum, Mat, Par};
use memid_benches::{SIZES, Size, family, iteration_flops};
use std::time::Instant;

fn median_seconds(reps: usize, mut f: impl FnMut()) -> f64 {
    f();
    let mut times: Vec<f64> = (0..reps)
        .map(|_| {
            let t = Instant::now();
            f();
            t.elapsed().as_secs_f64()
        })
        .collect();
    times.sort_by(f64::total_cmp);
    times[reps / 2]
}

fn gemm_rate() -> f64 {
    let n = 1024;
    let a = test_problems::gaussian(n, n, 1);
    let b = test_problems::gaussian(n, n, 2);
    let mut c = Mat::<f64>::zeros(n, n);
    let t = median_seconds(7, || {
        faer::linalg::matmul::matmul(
            c.as_mut(),
            Accum::Replace,
            a.as_ref(),
            b.as_ref(),
            1.0,
            faer::get_global_parallelism(),
        )
    });
    2.0 * (n as f64).powi(3) / t
}

fn iteration_time(size: Size, experiments_count: usize) -> f64 {
    let fam = family(size);
    let model = mem::LinearResponse(fam.clone());
    let truth: Vec<f64> =
        fam.p_nominal.iter().enumerate().map(|(i, v)| v * (1.0 + 0.05 * ((i % 3) as f64 - 1.0))).collect();
    let data: Vec<mem::Measurement> = (0..experiments_count)
        .map(|e| {
            test_problems::simulate_measurement(&model, &truth, 1.0 / 12.8, size.samples, 0.01, 1 + e as u64)
        })
        .collect();
    let experiments = mem::Problem::unnamed(
        data.iter().map(|d| mem::Experiment::normalized(&model, d)).collect(),
        &fam.p_nominal,
    )
    .unwrap();
    let reps = match size.name {
        "paper" => 2001,
        "medium" => 101,
        _ => 5,
    };
    median_seconds(reps, || {
        std::hint::black_box(mem::gauss_newton_step(&experiments, &fam.p_nominal, 1e-10).unwrap());
    })
}

fn paper_fit_time() -> f64 {
    let size = SIZES[0];
    let fam = family(size);
    let model = mem::LinearResponse(fam.clone());
    let data = test_problems::simulate_measurement(&model, &fam.p_nominal, 1.0 / 12.8, size.samples, 0.01, 1);
    let start: Vec<f64> = fam.p_nominal.iter().map(|v| v * 1.3).collect();
    let experiments =
        mem::Problem::unnamed(vec![mem::Experiment::normalized(&model, &data)], &start).unwrap();
    median_seconds(201, || {
        std::hint::black_box(mem::Fit::new().run(&experiments).unwrap());
    })
}

/// Propagation against the modal form for growing N (j = 5, p = 4, K = 2000).
fn crossover() -> Vec<serde_json::Value> {
    [8usize, 12, 16, 24, 32, 48, 64, 128, 200]
        .iter()
        .map(|&n| {
            let fam = test_problems::ModalFamily::new(n / 2, 5, 4, 2026);
            let a = fam.a(&fam.p_nominal);
            let das: Vec<Mat<f64>> = (0..5).map(|i| fam.da(i)).collect();
            let refs: Vec<_> = das.iter().map(|d| d.as_ref()).collect();
            let mut out = expm::Response::zeros(2000, 4, 5);
            let mut run = |strategy| {
                let mut method = expm::Method::Propagation;
                let t = median_seconds(if n <= 64 { 31 } else { 7 }, || {
                    method = expm::free_decay(a.as_ref(), &refs, fam.c.as_ref(), None, &fam.x0, None, 1.0 / 12.8, &mut out, strategy).unwrap();
                });
                (t, method)
            };
            let (propagation, _) = run(expm::Strategy::Propagation);
            let (modal, method) = run(expm::Strategy::Modal);
            serde_json::json!({"n_states": n, "propagation_s": propagation, "modal_s": modal, "modal_taken": method == expm::Method::Modal})
        })
        .collect()
}

fn main() {
    let rate = gemm_rate();
    let mut sizes = Vec::new();
    for size in SIZES {
        let flops = iteration_flops(size);
        let t = iteration_time(size, 1);
        sizes.push(serde_json::json!({
            "size": size.name, "n_states": 2 * size.modes, "n_params": size.params,
            "n_outputs": size.outputs, "n_samples": size.samples,
            "flops": flops, "lower_bound_s": flops / rate, "memid_s": t,
        }));
    }
    // Two cores: the large iteration with faer and the propagation threads limited to one.
    let large = SIZES[2];
    let two = iteration_time(large, 1);
    let one_pool = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
    faer::set_global_parallelism(Par::Seq);
    let one = one_pool.install(|| iteration_time(large, 1));
    faer::set_global_parallelism(Par::rayon(0));
    // Two experiments at the medium size, evaluated in parallel or not.
    let medium = SIZES[1];
    let exp_two = iteration_time(medium, 2);
    let exp_one = one_pool.install(|| iteration_time(medium, 2));
    let doc = serde_json::json!({
        "gemm_flops_per_s": rate,
        "sizes": sizes,
        "paper_fit_s": paper_fit_time(),
        "crossover": crossover(),
        "parallel": {
            "large_iteration_one_thread_s": one, "large_iteration_two_threads_s": two,
            "medium_two_experiments_one_thread_s": exp_one, "medium_two_experiments_two_threads_s": exp_two,
        },
    });
    println!("{}", serde_json::to_string_pretty(&doc).unwrap());
}
