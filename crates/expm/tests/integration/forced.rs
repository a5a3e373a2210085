//! Forced responses (Van Loan's augmented exponential): outputs against an independent
//! fixed-step RK4 integration with the input held as the hold says, and the sensitivities
//! against central differences of the whole response.

use expm::{Forcing, Hold, Response, ResponseProblem};
use faer::{Mat, mat};

/// Two masses, one input force on the first; P = [k1, k2, c]; outputs x1 and the acceleration
/// of mass 2 (which has no feedthrough) plus a direct-feedthrough output.
fn system(p: &[f64]) -> (Mat<f64>, Mat<f64>, Mat<f64>, Mat<f64>) {
    let (k1, k2, c) = (p[0], p[1], p[2]);
    let (m1, m2) = (1.0, 0.5);
    let a = mat![
        [0.0, 0.0, 1.0, 0.0],
        [0.0, 0.0, 0.0, 1.0],
        [-(k1 + k2) / m1, k2 / m1, -c / m1, 0.0],
        [k2 / m2, -k2 / m2, 0.0, -c / m2],
    ];
    let b = mat![[0.0], [0.0], [1.0 / m1], [0.0]];
    let cm = mat![[1.0, 0.0, 0.0, 0.0], [-(k1 + k2) / m1, k2 / m1, -c / m1, 0.0]];
    let d = mat![[0.0], [1.0 / m1]];
    (a, b, cm, d)
}

fn input(k: usize) -> f64 {
    (0.37 * k as f64).sin() + 0.5 * (0.11 * k as f64).cos()
}

fn respond(p: &[f64], hold: Hold, h: f64, n: usize, with_parameters: bool) -> Response {
    let (a, b, c, d) = system(p);
    let u = Mat::from_fn(n, 1, |k, _| input(k));
    let x0 = [0.01, 0.0, 0.0, 0.0];
    // ∂A, ∂B, ∂C, ∂D by hand for this small system (checked below against differences).
    let (m1, m2) = (1.0, 0.5);
    let da = [
        mat![[0.0, 0.0, 0.0, 0.0], [0.0, 0.0, 0.0, 0.0], [-1.0 / m1, 0.0, 0.0, 0.0], [0.0, 0.0, 0.0, 0.0]],
        mat![
            [0.0, 0.0, 0.0, 0.0],
            [0.0, 0.0, 0.0, 0.0],
            [-1.0 / m1, 1.0 / m1, 0.0, 0.0],
            [1.0 / m2, -1.0 / m2, 0.0, 0.0]
        ],
        mat![
            [0.0, 0.0, 0.0, 0.0],
            [0.0, 0.0, 0.0, 0.0],
            [0.0, 0.0, -1.0 / m1, 0.0],
            [0.0, 0.0, 0.0, -1.0 / m2]
        ],
    ];
    let dc = [
        mat![[0.0, 0.0, 0.0, 0.0], [-1.0 / m1, 0.0, 0.0, 0.0]],
        mat![[0.0, 0.0, 0.0, 0.0], [-1.0 / m1, 1.0 / m1, 0.0, 0.0]],
        mat![[0.0, 0.0, 0.0, 0.0], [0.0, 0.0, -1.0 / m1, 0.0]],
    ];
    let j = if with_parameters { 3 } else { 0 };
    let mut out = Response::zeros(n, 2, j);
    let mut problem = ResponseProblem::new(a.as_ref(), c.as_ref(), &x0, h).with_inputs(Forcing {
        b: b.as_ref(),
        db: Vec::new(),
        d: Some(d.as_ref()),
        dd: None,
        u: u.as_ref(),
        hold,
    });
    if with_parameters {
        problem = problem
            .with_parameters(da.iter().map(|m| m.as_ref()).collect())
            .with_output_derivatives(dc.iter().map(|m| m.as_ref()).collect());
    }
    problem.solve_into(&mut out).unwrap();
    out
}

/// RK4 with 200 substeps per sample, the input held (zero order) or interpolated (first order).
fn rk4(p: &[f64], hold: Hold, h: f64, n: usize) -> Mat<f64> {
    let (a, b, c, d) = system(p);
    rk4_linear([&a, &b, &c, &d], &[0.01, 0.0, 0.0, 0.0], input, hold, h, n, 200)
}

/// y_k of ẋ = A x + B u, y = C x + D u from x0 (one input), by fixed-step RK4 with `sub` steps
/// per sample and u between samples as `hold` says: the independent reference of the forced
/// tests.
pub(super) fn rk4_linear(
    [a, b, c, d]: [&Mat<f64>; 4],
    x0: &[f64],
    input: impl Fn(usize) -> f64,
    hold: Hold,
    h: f64,
    samples: usize,
    sub: usize,
) -> Mat<f64> {
    let n = x0.len();
    let f = |x: &[f64], u: f64| -> Vec<f64> {
        (0..n).map(|i| (0..n).map(|j| a[(i, j)] * x[j]).sum::<f64>() + b[(i, 0)] * u).collect()
    };
    let step =
        |x: &[f64], s: f64, d: &[f64]| -> Vec<f64> { x.iter().zip(d).map(|(a, b)| a + s * b).collect() };
    let mut x = x0.to_vec();
    let mut y = Mat::zeros(samples, c.nrows());
    let dt = h / sub as f64;
    for k in 0..samples {
        for o in 0..c.nrows() {
            y[(k, o)] = (0..n).map(|j| c[(o, j)] * x[j]).sum::<f64>() + d[(o, 0)] * input(k);
        }
        let u_at = |s: f64| match hold {
            Hold::Zero => input(k),
            Hold::FirstOrder => input(k) + s / h * (input(k + 1) - input(k)),
        };
        for i in 0..sub {
            let s = i as f64 * dt;
            let k1 = f(&x, u_at(s));
            let k2 = f(&step(&x, 0.5 * dt, &k1), u_at(s + 0.5 * dt));
            let k3 = f(&step(&x, 0.5 * dt, &k2), u_at(s + 0.5 * dt));
            let k4 = f(&step(&x, dt, &k3), u_at(s + dt));
            for r in 0..n {
                x[r] += dt / 6.0 * (k1[r] + 2.0 * k2[r] + 2.0 * k3[r] + k4[r]);
            }
        }
    }
    y
}

const P: [f64; 3] = [40.0, 15.0, 0.3];

#[test]
fn zero_and_first_order_holds_match_an_independent_integration() {
    for hold in [Hold::Zero, Hold::FirstOrder] {
        let (h, n) = (0.05, 300);
        let exact = respond(&P, hold, h, n, false);
        let reference = rk4(&P, hold, h, n);
        for o in 0..2 {
            let scale = (0..n).map(|k| reference[(k, o)].abs()).fold(0.0, f64::max);
            for k in 0..n {
                let err = (exact.outputs[(k, o)] - reference[(k, o)]).abs();
                assert!(err < 1e-9 * scale, "{hold:?} output {o} sample {k}: {err:e} of {scale:e}");
            }
        }
    }
    // The two holds differ (the test can tell them apart).
    let (zoh, foh) =
        (respond(&P, Hold::Zero, 0.05, 100, false), respond(&P, Hold::FirstOrder, 0.05, 100, false));
    assert!((&zoh.outputs - &foh.outputs).norm_max() > 1e-4);
}

#[test]
fn forced_sensitivities_match_central_differences_to_1e_7() {
    for hold in [Hold::Zero, Hold::FirstOrder] {
        let (h, n) = (0.05, 300);
        let base = respond(&P, hold, h, n, true);
        for i in 0..3 {
            let step = 1e-5 * P[i];
            let shifted = |sign: f64| {
                let mut q = P;
                q[i] += sign * step;
                respond(&q, hold, h, n, false).outputs
            };
            let (plus, minus) = (shifted(1.0), shifted(-1.0));
            let (mut diff, mut norm) = (0.0f64, 0.0f64);
            for k in 0..n {
                for o in 0..2 {
                    let fd = (plus[(k, o)] - minus[(k, o)]) / (2.0 * step);
                    let s = base.sensitivities[(k * 2 + o, i)];
                    diff = diff.max((fd - s).abs());
                    norm = norm.max(s.abs());
                }
            }
            assert!(diff < 1e-7 * norm, "{hold:?} parameter {i}: {:e}", diff / norm);
        }
    }
}
