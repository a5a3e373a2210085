//! The modal path against the propagator, and its fallback.

use expm::{Method, Response, Strategy, free_decay};
use faer::Mat;
use test_problems::ModalFamily;

fn both(fam: &ModalFamily, p: &[f64], k: usize, with_extras: bool) -> (Response, Response, Method) {
    let n = fam.n_states();
    let j = fam.n_params();
    let outputs = fam.c.nrows();
    let a = fam.a(p);
    let das: Vec<Mat<f64>> = (0..j).map(|i| fam.da(i)).collect();
    let refs: Vec<_> = das.iter().map(|d| d.as_ref()).collect();
    let dcs: Vec<Mat<f64>> =
        (0..j).map(|i| Mat::from_fn(outputs, n, |o, s| if s == n / 2 + o + i { 0.3 } else { 0.0 })).collect();
    let dc_refs: Vec<_> = dcs.iter().map(|d| d.as_ref()).collect();
    let dx0 = Mat::<f64>::from_fn(n, j, |r, i| if r == i { 0.5 } else { 0.0 });
    let (dc, dx0) = if with_extras { (Some(dc_refs.as_slice()), Some(dx0.as_ref())) } else { (None, None) };
    let mut modal = Response::zeros(k, outputs, j);
    let mut prop = Response::zeros(k, outputs, j);
    let method = free_decay(
        a.as_ref(),
        &refs,
        fam.c.as_ref(),
        dc,
        &fam.x0,
        dx0,
        1.0 / 12.8,
        &mut modal,
        Strategy::Modal,
    )
    .unwrap();
    free_decay(
        a.as_ref(),
        &refs,
        fam.c.as_ref(),
        dc,
        &fam.x0,
        dx0,
        1.0 / 12.8,
        &mut prop,
        Strategy::Propagation,
    )
    .unwrap();
    (modal, prop, method)
}

/// Relative agreement required: the modal path's accepted error bound is ~1e-8 (amplification
/// ≤ 1e8 times the unit roundoff, times the modest growth of the powers over K samples).
const TOL: f64 = 1e-8;

#[test]
fn modal_path_matches_propagation() {
    for (modes, j, p, k, seed) in [(4, 2, 3, 400, 1), (20, 5, 4, 1500, 2), (40, 6, 5, 700, 3)] {
        let fam = ModalFamily::new(modes, j, p, seed);
        let params: Vec<f64> = (0..j).map(|i| 1.0 + 0.03 * i as f64).collect();
        for extras in [false, true] {
            let (modal, prop, method) = both(&fam, &params, k, extras);
            assert_eq!(method, Method::Modal, "N = {} should take the modal path", 2 * modes);
            let scale_y = prop.outputs.norm_max();
            assert!(
                (&modal.outputs - &prop.outputs).norm_max() <= TOL * scale_y,
                "outputs, N = {}",
                2 * modes
            );
            for i in 0..j {
                let scale = prop.sensitivities.col(i).norm_max();
                let diff = (0..k * p)
                    .map(|r| (modal.sensitivities[(r, i)] - prop.sensitivities[(r, i)]).abs())
                    .fold(0.0, f64::max);
                assert!(
                    diff <= TOL * scale,
                    "sensitivity {i}, N = {}, extras {extras}: {diff:e} of {scale:e}",
                    2 * modes
                );
            }
        }
    }
}

#[test]
fn repeated_or_defective_spectra_fall_back_to_propagation() {
    // A Jordan block (not diagonalisable) and two identical uncoupled oscillators (repeated
    // eigenvalues): the modal method must refuse and the propagator answer.
    let jordan = faer::mat![[-0.5, 1.0], [0.0, -0.5]];
    let twins = faer::mat![
        [0.0, 0.0, 1.0, 0.0],
        [0.0, 0.0, 0.0, 1.0],
        [-4.0, 0.0, -0.1, 0.0],
        [0.0, -4.0, 0.0, -0.1],
    ];
    for a in [jordan, twins] {
        let n = a.nrows();
        let da = Mat::<f64>::identity(n, n) * faer::Scale(-0.1);
        let c = Mat::<f64>::from_fn(1, n, |_, s| if s == 0 { 1.0 } else { 0.0 });
        let x0: Vec<f64> = (0..n).map(|i| 1.0 / (1.0 + i as f64)).collect();
        let mut out = Response::zeros(50, 1, 1);
        let method = free_decay(
            a.as_ref(),
            &[da.as_ref()],
            c.as_ref(),
            None,
            &x0,
            None,
            0.1,
            &mut out,
            Strategy::Modal,
        )
        .unwrap();
        assert_eq!(method, Method::Propagation);
        let reference = expm::SensitivityPropagator::new(a.as_ref(), &[da.as_ref()], c.as_ref(), 0.1)
            .unwrap()
            .propagate(&x0, None, 50)
            .unwrap();
        assert_eq!((&out.outputs - &reference.outputs).norm_max(), 0.0);
    }
}
