//! A sampled input and the gains it drives the recursion through (Γ_now u_k + Γ_next u_{k+1},
//! and their parameter derivatives), for the general loops and as stack columns for the
//! fixed-size kernels.

use crate::propagate::discretise::InputGains;
use crate::response::Response;
use faer::linalg::matmul::matmul;
use faer::{Accum, Mat, MatRef, Par};

/// The input side of a forced propagator: gains of the discretisation and the feedthrough.
#[derive(Clone, Debug)]
pub(super) struct InputPart {
    pub(super) gains: InputGains,
    /// D (p × m).
    pub(super) d: Option<Mat<f64>>,
    /// ∂D/∂P_i stacked ((j·p) × m).
    pub(super) dd: Option<Mat<f64>>,
}

/// A sampled input and the gains it drives the recursion through.
pub(super) struct Drive<'a> {
    /// K × m.
    pub(super) u: MatRef<'a, f64>,
    pub(super) input: &'a InputPart,
}

impl Drive<'_> {
    /// (u_k, u_{k+1}) as row indices; u_{k+1} is zero past the end (never needed: the last
    /// sample's update is not taken).
    pub(super) fn samples(&self, k: usize) -> (usize, Option<usize>) {
        (k, (k + 1 < self.u.nrows()).then_some(k + 1))
    }

    /// seed = [Γ_now u_k + Γ_next u_{k+1}; ∂Γ_now u_k + ∂Γ_next u_{k+1}] (N·(j+1), column blocks).
    pub(super) fn seed(&self, k: usize, seed: &mut [f64], n: usize, j: usize) {
        let gains = &self.input.gains;
        let (now, next) = self.samples(k);
        seed.iter_mut().for_each(|v| *v = 0.0);
        for c in 0..self.u.ncols() {
            let u_now = self.u[(now, c)];
            let u_next = next.map_or(0.0, |r| self.u[(r, c)]);
            for r in 0..n {
                seed[r] +=
                    gains.now[(r, c)] * u_now + gains.next.as_ref().map_or(0.0, |g| g[(r, c)] * u_next);
            }
            for r in 0..j * n {
                seed[n + r] +=
                    gains.d_now[(r, c)] * u_now + gains.d_next.as_ref().map_or(0.0, |g| g[(r, c)] * u_next);
            }
        }
    }

    /// The drive of samples start..start+len: G (N × len) and W += ∂Γ·U ((j·N) × len).
    pub(super) fn chunk(
        &self,
        start: usize,
        len: usize,
        mut g: faer::MatMut<'_, f64>,
        mut w: faer::MatMut<'_, f64>,
        par: Par,
    ) {
        let gains = &self.input.gains;
        let m = self.u.ncols();
        let k = self.u.nrows();
        let now = self.u.subrows(start, len).transpose();
        matmul(g.as_mut(), Accum::Replace, gains.now.as_ref(), now, 1.0, par);
        matmul(w.as_mut(), Accum::Replace, gains.d_now.as_ref(), now, 1.0, par);
        if let (Some(next), Some(d_next)) = (&gains.next, &gains.d_next) {
            let shifted =
                Mat::<f64>::from_fn(
                    m,
                    len,
                    |c, t| if start + t + 1 < k { self.u[(start + t + 1, c)] } else { 0.0 },
                );
            matmul(g.as_mut(), Accum::Add, next.as_ref(), shifted.as_ref(), 1.0, par);
            matmul(w.as_mut(), Accum::Add, d_next.as_ref(), shifted.as_ref(), 1.0, par);
        }
    }

    /// y_k += D u_k and ∂y_k/∂P_i += ∂D/∂P_i u_k.
    pub(super) fn feedthrough(&self, out: &mut Response, p: usize, j: usize) {
        let m = self.u.ncols();
        if let Some(d) = &self.input.d {
            matmul(out.outputs.as_mut(), Accum::Add, self.u, d.as_ref().transpose(), 1.0, Par::Seq);
        }
        if let Some(dd) = &self.input.dd {
            for k in 0..self.u.nrows() {
                for i in 0..j {
                    for o in 0..p {
                        let v: f64 = (0..m).map(|c| dd[(i * p + o, c)] * self.u[(k, c)]).sum();
                        out.sensitivities[(k * p + o, i)] += v;
                    }
                }
            }
        }
    }
}

/// The input gains as stack columns for the fixed-size kernel.
pub(super) struct FixedGains<const N: usize> {
    /// (column of Γ_now, column of Γ_next) per input.
    state: Vec<([f64; N], [f64; N])>,
    /// The same for ∂Γ/∂P_i, per parameter.
    sensitivity: Vec<Vec<([f64; N], [f64; N])>>,
    u: Vec<f64>,
    m: usize,
}

impl<const N: usize> FixedGains<N> {
    pub(super) fn new(drive: &Drive<'_>, j: usize) -> Self {
        let g = &drive.input.gains;
        let m = drive.u.ncols();
        let column = |mat: &Mat<f64>, row0: usize, c: usize| -> [f64; N] {
            std::array::from_fn(|r| mat[(row0 + r, c)])
        };
        let pair = |now: &Mat<f64>, next: &Option<Mat<f64>>, row0: usize, c: usize| {
            (column(now, row0, c), next.as_ref().map_or([0.0; N], |nx| column(nx, row0, c)))
        };
        Self {
            state: (0..m).map(|c| pair(&g.now, &g.next, 0, c)).collect(),
            sensitivity: (0..j)
                .map(|i| (0..m).map(|c| pair(&g.d_now, &g.d_next, i * N, c)).collect())
                .collect(),
            u: (0..drive.u.nrows())
                .flat_map(|k| (0..m).map(move |c| (k, c)))
                .map(|(k, c)| drive.u[(k, c)])
                .collect(),
            m,
        }
    }

    #[inline(always)]
    fn combine(&self, columns: &[([f64; N], [f64; N])], now: usize, next: Option<usize>) -> [f64; N] {
        let mut acc = [0.0; N];
        for (c, (a, b)) in columns.iter().enumerate() {
            let u_now = self.u[now * self.m + c];
            let u_next = next.map_or(0.0, |k| self.u[k * self.m + c]);
            for r in 0..N {
                acc[r] = a[r].mul_add(u_now, b[r].mul_add(u_next, acc[r]));
            }
        }
        acc
    }

    #[inline(always)]
    pub(super) fn state(&self, now: usize, next: Option<usize>) -> [f64; N] {
        self.combine(&self.state, now, next)
    }

    #[inline(always)]
    pub(super) fn sensitivity(&self, i: usize, now: usize, next: Option<usize>) -> [f64; N] {
        self.combine(&self.sensitivity[i], now, next)
    }
}
