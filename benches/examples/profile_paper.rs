//! Times the pieces of one paper-size MEM iteration (development aid).
use faer::linalg::solvers::Solve;
use memid_benches::{SIZES, family};
use std::time::Instant;

fn time<F: FnMut()>(name: &str, reps: usize, mut f: F) {
    f();
    let t = Instant::now();
    for _ in 0..reps {
        f();
    }
    println!("{name:<28} {:>10.2} µs", t.elapsed().as_secs_f64() * 1e6 / reps as f64);
}

fn main() {
    let size = SIZES[0];
    let fam = family(size);
    let a = fam.a(&fam.p_nominal);
    let das: Vec<faer::Mat<f64>> = (0..size.params).map(|i| fam.da(i)).collect();
    let refs: Vec<_> = das.iter().map(|d| d.as_ref()).collect();
    let h = 1.0 / 12.8;
    if std::env::args().any(|a| a == "--step-only") {
        // For `perf record`: nothing but the whole iteration.
        let model = mem::LinearResponse(fam.clone());
        let data = test_problems::simulate_measurement(&model, &fam.p_nominal, h, size.samples, 0.01, 1);
        let experiments =
            mem::Problem::unnamed(vec![mem::Experiment::normalized(&model, &data)], &fam.p_nominal).unwrap();
        time("gauss_newton_step", 100000, || {
            std::hint::black_box(mem::gauss_newton_step(&experiments, &fam.p_nominal, 1e-10).unwrap());
        });
        use mem::LinearModel;
        time("  linearize", 100000, || {
            std::hint::black_box(fam.linearize(&fam.p_nominal).unwrap());
        });
        let lin = fam.linearize(&fam.p_nominal).unwrap();
        let das: Vec<_> = lin.da.iter().map(|d| d.as_ref()).collect();
        time("  free_decay (new response)", 100000, || {
            let mut out = expm::Response::zeros(size.samples, size.outputs, size.params);
            expm::free_decay(
                lin.a.as_ref(),
                &das,
                lin.c.as_ref(),
                None,
                &lin.x0,
                None,
                h,
                &mut out,
                expm::Strategy::Auto,
            )
            .unwrap();
            std::hint::black_box(&out);
        });
        return;
    }
    if std::env::args().any(|a| a == "--fit-only") {
        let memid_benches::PaperFit { adapter, model, data, p0 } = memid_benches::paper_fit();
        let experiments = mem::Problem::unnamed(vec![mem::Experiment::new(&model, &data)], &p0).unwrap();
        let report = mem::Fit::new().run(&experiments).unwrap();
        println!("{} iterations, {:?}", report.iterations, report.termination);
        time("paper fit", 2000, || {
            std::hint::black_box(mem::Fit::new().run(&experiments).unwrap());
        });
        time("linearize", 20000, || {
            use mem::LinearModel;
            std::hint::black_box(adapter.linearize(&p0).unwrap());
        });
        return;
    }
    if std::env::args().any(|a| a == "--build-only") {
        time("propagator build", 200000, || {
            std::hint::black_box(
                expm::SensitivityPropagator::new(a.as_ref(), &refs, fam.c.as_ref(), h).unwrap(),
            );
        });
        return;
    }
    let ah = a.clone() * faer::Scale(h);
    let work = expm::ExpmFrechet::new(ah.as_ref()).unwrap();
    println!("Padé degree {}, squarings {}", work.degree(), work.squarings());
    let mut prod = faer::Mat::<f64>::zeros(8, 8);
    time("faer matmul 8x8", 200000, || {
        faer::linalg::matmul::matmul(
            prod.as_mut(),
            faer::Accum::Replace,
            ah.as_ref(),
            ah.as_ref(),
            1.0,
            faer::Par::Seq,
        );
        std::hint::black_box(&prod);
    });
    time("faer lu 8x8 + solve", 200000, || {
        std::hint::black_box(ah.partial_piv_lu().solve(&ah));
    });
    time("propagator build", 20000, || {
        std::hint::black_box(expm::SensitivityPropagator::new(a.as_ref(), &refs, fam.c.as_ref(), h).unwrap());
    });
    let prop = expm::SensitivityPropagator::new(a.as_ref(), &refs, fam.c.as_ref(), h).unwrap();
    let mut out = expm::Response::zeros(size.samples, size.outputs, size.params);
    time("propagate", 20000, || prop.propagate_into(&fam.x0, None, &mut out).unwrap());
    let s = faer::Mat::<f64>::from_fn(1200, 2, |i, j| ((i * 7 + j * 3) as f64).sin());
    time("thin svd 1200x2", 20000, || {
        std::hint::black_box(s.thin_svd().unwrap());
    });
    let model = mem::LinearResponse(fam.clone());
    let data = test_problems::simulate_measurement(&model, &fam.p_nominal, h, size.samples, 0.01, 1);
    let experiments =
        mem::Problem::unnamed(vec![mem::Experiment::normalized(&model, &data)], &fam.p_nominal).unwrap();
    qr_probe();
    time("gauss_newton_step", 20000, || {
        std::hint::black_box(mem::gauss_newton_step(&experiments, &fam.p_nominal, 1e-10).unwrap());
    });
}

fn qr_probe() {
    let s = faer::Mat::<f64>::from_fn(1200, 2, |i, j| ((i * 7 + j * 3) as f64).sin());
    time("qr 1200x2", 20000, || {
        std::hint::black_box(s.qr());
    });
    let r = s.qr().R().to_owned();
    time("svd of R 2x2", 20000, || {
        std::hint::black_box(r.thin_svd().unwrap());
    });
    let q = s.qr();
    time("qr + thin Q", 20000, || {
        std::hint::black_box(q.compute_thin_Q());
    });
}
