//! The MEM propagator against exponentials at each sample and finite differences.

use faer::Mat;
use test_problems::ModalFamily;

fn family() -> (ModalFamily, f64) {
    (ModalFamily::new(4, 3, 2, 11), 1.0 / 12.8)
}

#[test]
fn outputs_equal_exponential_at_each_sample() {
    let (fam, h) = family();
    let p = vec![1.1, 0.9, 1.3];
    let a = fam.a(&p);
    let das: Vec<Mat<f64>> = (0..3).map(|i| fam.da(i)).collect();
    let refs: Vec<_> = das.iter().map(|d| d.as_ref()).collect();
    let prop = expm::SensitivityPropagator::new(a.as_ref(), &refs, fam.c.as_ref(), h).unwrap();
    let k = 60;
    let response = prop.propagate(&fam.x0, None, k).unwrap();
    let x0 = Mat::<f64>::from_fn(fam.n_states(), 1, |i, _| fam.x0[i]);
    for step in [0usize, 1, 7, 30, 59] {
        let at = a.clone() * faer::Scale(h * step as f64);
        let y = &fam.c * expm::expm(at.as_ref()).unwrap() * &x0;
        for o in 0..2 {
            let got = response.outputs[(step, o)];
            // Error grows linearly with the number of steps (one rounding per product).
            assert!(
                (got - y[(o, 0)]).abs() <= 1e-13 * (1.0 + step as f64),
                "k={step} o={o}: {got} vs {}",
                y[(o, 0)]
            );
        }
    }
}

#[test]
fn sensitivities_equal_central_differences() {
    let (fam, h) = family();
    let p = vec![1.1, 0.9, 1.3];
    let das: Vec<Mat<f64>> = (0..3).map(|i| fam.da(i)).collect();
    let refs: Vec<_> = das.iter().map(|d| d.as_ref()).collect();
    let k = 80;
    let run = |p: &[f64]| {
        expm::SensitivityPropagator::new(fam.a(p).as_ref(), &refs, fam.c.as_ref(), h)
            .unwrap()
            .propagate(&fam.x0, None, k)
            .unwrap()
    };
    let base = run(&p);
    let scale = base.outputs.norm_max();
    for i in 0..3 {
        // Central difference with step 1e-5: truncation O(δ²)·|y'''| ≈ 1e-10 relative,
        // rounding O(u/δ) ≈ 1e-11; the tolerance 1e-7 of the output scale leaves a margin.
        let delta = 1e-5;
        let mut plus = p.clone();
        plus[i] += delta;
        let mut minus = p.clone();
        minus[i] -= delta;
        let (yp, ym) = (run(&plus), run(&minus));
        let mut worst = 0.0f64;
        for step in 0..k {
            for o in 0..2 {
                let fd = (yp.outputs[(step, o)] - ym.outputs[(step, o)]) / (2.0 * delta);
                worst = worst.max((fd - base.sensitivities[(step * 2 + o, i)]).abs());
            }
        }
        assert!(worst <= 1e-7 * scale, "parameter {i}: worst mismatch {worst:e}");
    }
}

#[test]
fn initial_state_sensitivity_is_propagated() {
    // ∂x(0)/∂P = I_N selects columns: the sensitivity is then C Φ^k e_i, i.e. the free response
    // from the unit initial state e_i — checked against a second propagation.
    let (fam, h) = family();
    let n = fam.n_states();
    let a = fam.a(&[1.0, 1.0, 1.0]);
    let prop = expm::SensitivityPropagator::new(a.as_ref(), &[], fam.c.as_ref(), h).unwrap();
    let eye = Mat::<f64>::identity(n, n);
    let zeros = vec![0.0; n];
    let with_dx0 = expm::SensitivityPropagator::new(
        a.as_ref(),
        &vec![Mat::<f64>::zeros(n, n).as_ref(); n],
        fam.c.as_ref(),
        h,
    )
    .unwrap()
    .propagate(&zeros, Some(eye.as_ref()), 20)
    .unwrap();
    for i in 0..n {
        let mut unit = vec![0.0; n];
        unit[i] = 1.0;
        let free = prop.propagate(&unit, None, 20).unwrap();
        for step in 0..20 {
            for o in 0..2 {
                assert!((with_dx0.sensitivities[(step * 2 + o, i)] - free.outputs[(step, o)]).abs() < 1e-14);
            }
        }
    }
}

#[test]
fn output_matrix_derivatives_enter_the_sensitivities() {
    // C(P) = C₀ + P₂·C₁ with A depending on P₁ only: ∂y/∂P₂ = C₁ x_k exactly.
    let (fam, h) = family();
    let n = fam.n_states();
    let c1 = Mat::<f64>::from_fn(2, n, |o, s| if s == n / 2 + o { 1.0 } else { 0.0 });
    let run = |p: &[f64]| {
        let c = &fam.c + &c1 * faer::Scale(p[1]);
        expm::SensitivityPropagator::new(
            fam.a(&[p[0], 1.0, 1.0]).as_ref(),
            &[fam.da(0).as_ref(), Mat::<f64>::zeros(n, n).as_ref()],
            c.as_ref(),
            h,
        )
        .unwrap()
        .with_output_derivatives(&[Mat::<f64>::zeros(2, n).as_ref(), c1.as_ref()])
        .unwrap()
        .propagate(&fam.x0, None, 50)
        .unwrap()
    };
    let p = [1.05, 0.3];
    let base = run(&p);
    for i in 0..2 {
        let delta = 1e-6;
        let (mut plus, mut minus) = (p, p);
        plus[i] += delta;
        minus[i] -= delta;
        let (yp, ym) = (run(&plus), run(&minus));
        for k in 0..50 {
            for o in 0..2 {
                let fd = (yp.outputs[(k, o)] - ym.outputs[(k, o)]) / (2.0 * delta);
                assert!(
                    (fd - base.sensitivities[(k * 2 + o, i)]).abs() < 1e-7 * base.outputs.norm_max().max(1.0)
                );
            }
        }
    }
}

/// The generic small loop (16 < N ≤ 32) and the chunked path (N > 32): 300 samples cross two
/// chunk boundaries, 3 parameters use both parameter groups, and ∂C/∂P is exercised.
#[test]
fn chunked_path_matches_exponentials_and_differences() {
    check_family(40);
}

#[test]
fn generic_small_path_matches_exponentials_and_differences() {
    check_family(12);
}

fn check_family(modes: usize) {
    let fam = ModalFamily::new(modes, 3, 4, 21);
    let n = fam.n_states();
    let h = 1.0 / 12.8;
    let k = 300;
    let c1 = Mat::<f64>::from_fn(4, n, |o, s| if s == n / 2 + 3 * o { 0.5 } else { 0.0 });
    let run = |p: &[f64]| {
        let c = &fam.c + &c1 * faer::Scale(p[2]);
        let das: Vec<Mat<f64>> = (0..3).map(|i| fam.da(i)).collect();
        let refs: Vec<_> = das.iter().map(|d| d.as_ref()).collect();
        let zero = Mat::<f64>::zeros(4, n);
        expm::SensitivityPropagator::new(fam.a(p).as_ref(), &refs, c.as_ref(), h)
            .unwrap()
            .with_output_derivatives(&[zero.as_ref(), zero.as_ref(), c1.as_ref()])
            .unwrap()
            .propagate(&fam.x0, None, k)
            .unwrap()
    };
    let p = [1.02, 0.97, 1.05];
    let base = run(&p);
    let x0 = Mat::<f64>::from_fn(n, 1, |i, _| fam.x0[i]);
    let c = &fam.c + &c1 * faer::Scale(p[2]);
    for step in [0usize, 127, 128, 129, 299] {
        let y = &c * expm::expm((fam.a(&p) * faer::Scale(h * step as f64)).as_ref()).unwrap() * &x0;
        for o in 0..4 {
            assert!(
                (base.outputs[(step, o)] - y[(o, 0)]).abs() < 1e-12 * (1.0 + step as f64),
                "k={step} o={o}"
            );
        }
    }
    let scale = base.outputs.norm_max();
    for i in 0..3 {
        let delta = 1e-6;
        let (mut plus, mut minus) = (p, p);
        plus[i] += delta;
        minus[i] -= delta;
        let (yp, ym) = (run(&plus), run(&minus));
        let mut worst = 0.0f64;
        for step in 0..k {
            for o in 0..4 {
                let fd = (yp.outputs[(step, o)] - ym.outputs[(step, o)]) / (2.0 * delta);
                worst = worst.max((fd - base.sensitivities[(step * 4 + o, i)]).abs());
            }
        }
        assert!(worst < 1e-6 * scale, "parameter {i}: {worst:e}");
    }
}
