//! Forced responses of systems too large for the fixed-size kernels: N = 20 states (the generic
//! small loop) and N = 40 with 11 outputs (the chunked propagation), where the drive
//! Γ_now u_k + Γ_next u_{k+1}, a parameter-dependent B and D, and the feedthrough's derivative
//! take paths the small systems of `forced` do not. Outputs against an independent RK4
//! integration, sensitivities against central differences.

use expm::{Forcing, Hold, Response, ResponseProblem};
use faer::Mat;

/// A fixed–free chain of unit masses, springs k and dampers c between neighbours (the first to
/// the ground), a force g·u on the first mass. P = [k, c, g]. Outputs: every other mass's
/// displacement, then the first mass's acceleration (which feeds g·u through).
struct Chain {
    masses: usize,
}

/// The chain's Laplacian with the first mass grounded.
fn laplacian(n: usize) -> Mat<f64> {
    Mat::from_fn(n, n, |i, j| {
        if i == j {
            if i + 1 < n { 2.0 } else { 1.0 }
        } else if i.abs_diff(j) == 1 {
            -1.0
        } else {
            0.0
        }
    })
}

struct Matrices {
    a: Mat<f64>,
    b: Mat<f64>,
    c: Mat<f64>,
    d: Mat<f64>,
}

impl Chain {
    fn n(&self) -> usize {
        2 * self.masses
    }

    fn displacements(&self) -> Vec<usize> {
        (0..self.masses).step_by(2).collect()
    }

    fn p(&self) -> usize {
        self.displacements().len() + 1
    }

    /// A, B, C, D with every entry `constant + k·∂/∂k + c·∂/∂c + g·∂/∂g`.
    fn value(&self, p: [f64; 3]) -> Matrices {
        let mut sum = self.constant();
        for (i, value) in p.iter().enumerate() {
            let d = self.derivative(i);
            sum.a += *value * &d.a;
            sum.b += *value * &d.b;
            sum.c += *value * &d.c;
            sum.d += *value * &d.d;
        }
        sum
    }

    /// The parts that depend on no parameter: ẋ = v, and the displacement outputs.
    fn constant(&self) -> Matrices {
        let (m, n) = (self.masses, self.n());
        let a = Mat::from_fn(n, n, |i, j| if i < m && j == m + i { 1.0 } else { 0.0 });
        let shown = self.displacements();
        let c = Mat::from_fn(self.p(), n, |o, j| if shown.get(o) == Some(&j) { 1.0 } else { 0.0 });
        Matrices { a, b: Mat::zeros(n, 1), c, d: Mat::zeros(self.p(), 1) }
    }

    /// ∂A, ∂B, ∂C, ∂D with respect to P_i (every entry is linear in k, c and g).
    fn derivative(&self, i: usize) -> Matrices {
        let (m, n) = (self.masses, self.n());
        let l = laplacian(m);
        let a = Mat::from_fn(n, n, |r, col| match (i, r >= m, col >= m) {
            (0, true, false) => -l[(r - m, col)],
            (1, true, true) => -l[(r - m, col - m)],
            _ => 0.0,
        });
        let b = Mat::from_fn(n, 1, |r, _| if i == 2 && r == m { 1.0 } else { 0.0 });
        // The last output is the first mass's acceleration: row m of A, plus g·u.
        let last = self.p() - 1;
        let c = Mat::from_fn(self.p(), n, |o, col| if o == last { a[(m, col)] } else { 0.0 });
        let d = Mat::from_fn(self.p(), 1, |o, _| if i == 2 && o == last { 1.0 } else { 0.0 });
        Matrices { a, b, c, d }
    }
}

fn input(k: usize) -> f64 {
    (0.23 * k as f64).sin() + 0.6 * (0.071 * k as f64).cos()
}

const P: [f64; 3] = [60.0, 0.4, 2.0];
const H: f64 = 0.05;
const SAMPLES: usize = 160;

fn x0(n: usize) -> Vec<f64> {
    (0..n).map(|i| if i < n / 2 { 0.002 * (i as f64 + 1.0) } else { 0.0 }).collect()
}

fn respond(chain: &Chain, p: [f64; 3], hold: Hold, with_parameters: bool) -> Response {
    let v = chain.value(p);
    let derivatives: Vec<Matrices> = (0..3).map(|i| chain.derivative(i)).collect();
    let u = Mat::from_fn(SAMPLES, 1, |k, _| input(k));
    let x0 = x0(chain.n());
    let j = if with_parameters { 3 } else { 0 };
    let mut out = Response::zeros(SAMPLES, chain.p(), j);
    let forcing = Forcing {
        b: v.b.as_ref(),
        db: if with_parameters { derivatives.iter().map(|m| m.b.as_ref()).collect() } else { Vec::new() },
        d: Some(v.d.as_ref()),
        dd: with_parameters.then(|| derivatives.iter().map(|m| m.d.as_ref()).collect()),
        u: u.as_ref(),
        hold,
    };
    let mut problem = ResponseProblem::new(v.a.as_ref(), v.c.as_ref(), &x0, H).with_inputs(forcing);
    if with_parameters {
        problem = problem
            .with_parameters(derivatives.iter().map(|m| m.a.as_ref()).collect())
            .with_output_derivatives(derivatives.iter().map(|m| m.c.as_ref()).collect());
    }
    problem.solve_into(&mut out).unwrap();
    out
}

/// RK4 with 100 substeps per sample (ω_max·dt ≈ 8e-3), the input held or interpolated.
fn rk4(chain: &Chain, hold: Hold) -> Mat<f64> {
    let v = chain.value(P);
    super::forced::rk4_linear([&v.a, &v.b, &v.c, &v.d], &x0(chain.n()), input, hold, H, SAMPLES, 100)
}

const CHAINS: [Chain; 2] = [Chain { masses: 10 }, Chain { masses: 20 }];

#[test]
fn large_forced_responses_match_an_independent_integration() {
    for chain in &CHAINS {
        assert!(chain.n() > 16, "beyond the fixed-size kernels");
        for hold in [Hold::Zero, Hold::FirstOrder] {
            let exact = respond(chain, P, hold, false);
            let reference = rk4(chain, hold);
            for o in 0..chain.p() {
                let scale = (0..SAMPLES).map(|k| reference[(k, o)].abs()).fold(0.0, f64::max);
                for k in 0..SAMPLES {
                    let err = (exact.outputs[(k, o)] - reference[(k, o)]).abs();
                    assert!(
                        err < 1e-9 * scale,
                        "N {} {hold:?} output {o} sample {k}: {err:e} of {scale:e}",
                        chain.n()
                    );
                }
            }
        }
    }
}

#[test]
fn large_forced_sensitivities_match_central_differences() {
    for chain in &CHAINS {
        for hold in [Hold::Zero, Hold::FirstOrder] {
            let base = respond(chain, P, hold, true);
            let p = chain.p();
            for i in 0..3 {
                let step = 1e-5 * P[i];
                let shifted = |sign: f64| {
                    let mut q = P;
                    q[i] += sign * step;
                    respond(chain, q, hold, false).outputs
                };
                let (plus, minus) = (shifted(1.0), shifted(-1.0));
                let (mut diff, mut norm) = (0.0f64, 0.0f64);
                for k in 0..SAMPLES {
                    for o in 0..p {
                        let fd = (plus[(k, o)] - minus[(k, o)]) / (2.0 * step);
                        let s = base.sensitivities[(k * p + o, i)];
                        diff = diff.max((fd - s).abs());
                        norm = norm.max(s.abs());
                    }
                }
                assert!(
                    norm > 0.0 && diff < 1e-7 * norm,
                    "N {} {hold:?} parameter {i}: {:e}",
                    chain.n(),
                    diff / norm
                );
            }
        }
    }
}
