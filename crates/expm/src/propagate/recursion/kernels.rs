//! The loops that advance the propagator: fixed-size kernels for N ≤ 16 (unrolled, vectorized
//! through pulp), a plain loop for N ≤ 32, and chunked GEMMs for larger systems.

use super::drive::{Drive, FixedGains};
use crate::fixed::mat_vec_add;
use crate::response::Response;
use faer::linalg::matmul::matmul;
use faer::{Accum, Mat, MatRef, Par};

/// What the loops read of the propagator: Φ, the stacked Ψ ((j·N) × N), C and the stacked ∂C,
/// borrowed, with the sizes N, j and p.
#[derive(Clone, Copy)]
pub(super) struct Parts<'a> {
    pub(super) n_states: usize,
    pub(super) n_params: usize,
    pub(super) n_outputs: usize,
    pub(super) phi: &'a Mat<f64>,
    pub(super) psi: &'a Mat<f64>,
    pub(super) c: &'a Mat<f64>,
    pub(super) dc: Option<&'a Mat<f64>>,
}

impl Parts<'_> {
    /// Dispatches to a kernel with the state dimension as a compile-time constant (fully
    /// unrolled and vectorized) when N ≤ 16 and p ≤ 8, else to the generic loop.
    #[inline(always)]
    fn small_dispatch(&self, x0: &[f64], s0: MatRef<'_, f64>, drive: Option<&Drive<'_>>, out: &mut Response) {
        macro_rules! fixed {
            ($($n:literal)*) => {
                match self.n_states {
                    $($n if self.n_outputs <= FIXED_MAX_OUTPUTS => self.fixed_loop::<$n>(x0, s0, drive, out),)*
                    _ => self.small_loop(x0, s0, drive, out),
                }
            };
        }
        fixed!(1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16)
    }

    /// The small loop with N fixed at compile time. Outputs are formed in groups of four
    /// (`QUAD` lanes) and written straight into `out`; the recurrence x ← Φx, sᵢ ← Φsᵢ + Ψᵢx
    /// keeps two independent accumulation chains per product (see [`mat_vec_add`]), because at
    /// this size a step is bound by the latency of its dependent multiply–adds. A forced
    /// model's drive Γ_now u_k + Γ_next u_{k+1} seeds the accumulators.
    #[inline(always)]
    fn fixed_loop<const N: usize>(
        &self,
        x0: &[f64],
        s0: MatRef<'_, f64>,
        drive: Option<&Drive<'_>>,
        out: &mut Response,
    ) {
        let (j, p) = (self.n_params, self.n_outputs);
        let groups = p.div_ceil(QUAD);
        let square = |m: MatRef<'_, f64>, row0: usize| -> [[f64; N]; N] {
            std::array::from_fn(|l| std::array::from_fn(|r| m[(row0 + r, l)]))
        };
        let phi = square(self.phi.as_ref(), 0);
        let psi: Vec<[[f64; N]; N]> = (0..j).map(|i| square(self.psi.as_ref(), i * N)).collect();
        // quads(m, row0)[g][l] = m[row0 + 4g .. row0 + 4g + 4, l], zero-padded past p.
        let quads = |m: MatRef<'_, f64>, row0: usize| -> Vec<[[f64; QUAD]; N]> {
            (0..groups)
                .map(|g| {
                    std::array::from_fn(|l| {
                        std::array::from_fn(|r| {
                            let row = g * QUAD + r;
                            if row < p { m[(row0 + row, l)] } else { 0.0 }
                        })
                    })
                })
                .collect()
        };
        let c = quads(self.c.as_ref(), 0);
        // dc[i][g]: the quads of ∂C/∂P_i.
        let dc: Option<Vec<Vec<[[f64; QUAD]; N]>>> =
            self.dc.as_ref().map(|d| (0..j).map(|i| quads(d.as_ref(), i * p)).collect());
        let gains = drive.map(|d| FixedGains::<N>::new(d, j));
        // block[0] = x, block[1 + i] = s_i: all j + 1 columns live in memory, so the output
        // products read them with broadcast loads (a state held in a register was unpacked
        // lane by lane into scalar code).
        let mut block: Vec<[f64; N]> = std::iter::once(std::array::from_fn(|r| x0[r]))
            .chain((0..j).map(|i| std::array::from_fn(|r| s0[(r, i)])))
            .collect();
        let k_samples = out.outputs.nrows();
        let mut columns = Columns::new(out);
        for k in 0..k_samples {
            let (x, sens) = block.split_first().expect("x is the first column");
            for (g, cg) in c.iter().enumerate() {
                let rows = g * QUAD..(g * QUAD + QUAD).min(p);
                let y = mat_vec_add(cg, x, [0.0; QUAD]);
                for o in rows.clone() {
                    columns.outputs[o][k] = y[o - g * QUAD];
                }
                for (i, s) in sens.iter().enumerate() {
                    let mut yi = mat_vec_add(cg, s, [0.0; QUAD]);
                    if let Some(dc) = &dc {
                        yi = mat_vec_add(&dc[i][g], x, yi);
                    }
                    for o in rows.clone() {
                        columns.sensitivities[i][k * p + o] = yi[o - g * QUAD];
                    }
                }
            }
            if k + 1 == k_samples {
                break;
            }
            let (x, sens) = block.split_first_mut().expect("x is the first column");
            match (&gains, drive) {
                (Some(gains), Some(drive)) => {
                    let (now, next) = drive.samples(k);
                    for (i, (s, psi_i)) in sens.iter_mut().zip(&psi).enumerate() {
                        let seed = gains.sensitivity(i, now, next);
                        *s = mat_vec_add(&phi, s, mat_vec_add(psi_i, x, seed));
                    }
                    *x = mat_vec_add(&phi, x, gains.state(now, next));
                }
                _ => {
                    for (s, psi_i) in sens.iter_mut().zip(&psi) {
                        // Ψᵢx first: it does not wait for sᵢ, so only Φsᵢ is on the critical path.
                        *s = mat_vec_add(&phi, s, mat_vec_add(psi_i, x, [0.0; N]));
                    }
                    *x = mat_vec_add(&phi, x, [0.0; N]);
                }
            }
        }
    }

    #[inline(always)]
    fn small_loop(&self, x0: &[f64], s0: MatRef<'_, f64>, drive: Option<&Drive<'_>>, out: &mut Response) {
        let (n, j, p) = (self.n_states, self.n_params, self.n_outputs);
        let cols = j + 1;
        let phi = dense(self.phi.as_ref());
        let psi = dense(self.psi.as_ref()); // (j·n) × n, column l = [Ψ_1[:, l]; …; Ψ_j[:, l]]
        let c = dense(self.c.as_ref());
        let dc = self.dc.as_ref().map(|d| dense(d.as_ref()));
        let mut block = vec![0.0; n * cols];
        let mut next = vec![0.0; n * cols];
        let mut y = vec![0.0; p * cols];
        block[..n].copy_from_slice(x0);
        for i in 0..j {
            for r in 0..n {
                block[(i + 1) * n + r] = s0[(r, i)];
            }
        }
        let k_samples = out.outputs.nrows();
        let mut outputs = vec![0.0; k_samples * p];
        let mut sensitivities = vec![0.0; k_samples * p * j];
        let mut seed = vec![0.0; n * cols];
        for k in 0..k_samples {
            // y = C·[x, S] (+ ∂C/∂P_i x)
            y.iter_mut().for_each(|v| *v = 0.0);
            for (yc, bc) in y.chunks_exact_mut(p).zip(block.chunks_exact(n)) {
                for (cl, v) in c.chunks_exact(p).zip(bc) {
                    for (yo, co) in yc.iter_mut().zip(cl) {
                        *yo += co * v;
                    }
                }
            }
            if let Some(dc) = dc.as_ref().filter(|_| j > 0) {
                for (dl, v) in dc.chunks_exact(j * p).zip(&block[..n]) {
                    for (yo, d) in y[p..].iter_mut().zip(dl) {
                        *yo += d * v;
                    }
                }
            }
            outputs[k * p..(k + 1) * p].copy_from_slice(&y[..p]);
            sensitivities[k * p * j..(k + 1) * p * j].copy_from_slice(&y[p..]);
            if k + 1 == k_samples {
                break;
            }
            // [x, S] ← Φ·[x, S] + [0, Ψ x] (+ the drive [Γu, ∂Γ u])
            match drive {
                Some(d) => d.seed(k, &mut seed, n, j),
                None => seed.iter_mut().for_each(|v| *v = 0.0),
            }
            next.copy_from_slice(&seed);
            for (target, bc) in next.chunks_exact_mut(n).zip(block.chunks_exact(n)) {
                for (fl, v) in phi.chunks_exact(n).zip(bc) {
                    for (t, f) in target.iter_mut().zip(fl) {
                        *t += f * v;
                    }
                }
            }
            if j > 0 {
                for (pl, v) in psi.chunks_exact(j * n).zip(&block[..n]) {
                    for (t, f) in next[n..].iter_mut().zip(pl) {
                        *t += f * v;
                    }
                }
            }
            std::mem::swap(&mut block, &mut next);
        }
        scatter(out, &outputs, &sensitivities, p);
    }

    /// Larger systems, in chunks of T samples: the states of the chunk by a recursion of
    /// matrix–vector products, then Ψ·X (+ ∂Γ·U) for the whole chunk as one GEMM, then the
    /// sensitivity recursion S ← Φ S + W as products of Φ with the N×j block — split over two
    /// threads by parameter — and the outputs of the chunk as GEMMs with C. All buffers are
    /// allocated once.
    pub(super) fn propagate_chunked(
        &self,
        x0: &[f64],
        s0: MatRef<'_, f64>,
        drive: Option<&Drive<'_>>,
        out: &mut Response,
    ) {
        let (n, j, p) = (self.n_states, self.n_params, self.n_outputs);
        let k_samples = out.outputs.nrows();
        let chunk = CHUNK.min(k_samples);
        let mut x_chunk = Mat::<f64>::zeros(n, chunk);
        let mut w = Mat::<f64>::zeros(j * n, chunk);
        let mut y_chunk = Mat::<f64>::zeros(p, chunk);
        let mut x = Mat::<f64>::zeros(n, 1);
        let mut x_next = Mat::<f64>::zeros(n, 1);
        // Γ_now u_k + Γ_next u_{k+1} for the chunk (N × T), and the same for ∂Γ ((j·N) × T).
        let mut g_chunk = Mat::<f64>::zeros(if drive.is_some() { n } else { 0 }, chunk);
        x.col_mut(0).copy_from(MatRef::from_column_major_slice(x0, n, 1).col(0));
        // Parameter groups, one per thread; each keeps its S block, its next block and the
        // sensitivity history of the chunk (N × (group·T)) for one output GEMM per chunk.
        let groups = if j >= 2 && n >= 64 { 2 } else { 1 };
        let bounds: Vec<(usize, usize)> =
            (0..groups).map(|g| (g * j / groups, (g + 1) * j / groups)).collect();
        let mut states: Vec<GroupState> = bounds
            .iter()
            .map(|&(a, b)| GroupState {
                first: a,
                s: s0.subcols(a, b - a).to_owned(),
                s_next: Mat::zeros(n, b - a),
                history: Mat::zeros(n, (b - a) * chunk),
                y: Mat::zeros(p, (b - a) * chunk),
            })
            .collect();
        let par = faer::get_global_parallelism();
        let mut start = 0;
        while start < k_samples {
            let len = chunk.min(k_samples - start);
            if let Some(d) = drive {
                d.chunk(
                    start,
                    len,
                    g_chunk.as_mut().subcols_mut(0, len),
                    w.as_mut().subcols_mut(0, len),
                    par,
                );
            }
            // States x_start .. x_start+len−1 (x holds x_start on entry).
            for t in 0..len {
                x_chunk.col_mut(t).copy_from(x.col(0));
                match drive {
                    Some(_) => {
                        x_next.col_mut(0).copy_from(g_chunk.col(t));
                        matmul(x_next.as_mut(), Accum::Add, self.phi.as_ref(), x.as_ref(), 1.0, Par::Seq);
                    }
                    None => {
                        matmul(x_next.as_mut(), Accum::Replace, self.phi.as_ref(), x.as_ref(), 1.0, Par::Seq)
                    }
                }
                std::mem::swap(&mut x, &mut x_next);
            }
            let xc = x_chunk.as_ref().subcols(0, len);
            // W = [Ψ_1; …; Ψ_j]·X (+ ∂Γ·U) for the chunk, one GEMM.
            let accum = if drive.is_some() { Accum::Add } else { Accum::Replace };
            matmul(w.as_mut().subcols_mut(0, len), accum, self.psi.as_ref(), xc, 1.0, par);
            matmul(y_chunk.as_mut().subcols_mut(0, len), Accum::Replace, self.c.as_ref(), xc, 1.0, par);
            for t in 0..len {
                for o in 0..p {
                    out.outputs[(start + t, o)] = y_chunk[(o, t)];
                }
            }
            let phi = self.phi.as_ref();
            let c = self.c.as_ref();
            let w_ref = w.as_ref();
            let run = |g: &mut GroupState| g.advance(phi, c, w_ref, len, n);
            match states.as_mut_slice() {
                [a, b] => {
                    rayon::join(|| run(a), || run(b));
                }
                all => all.iter_mut().for_each(run),
            }
            for g in &states {
                let width = g.s.ncols();
                for t in 0..len {
                    for i in 0..width {
                        for o in 0..p {
                            out.sensitivities[((start + t) * p + o, g.first + i)] = g.y[(o, t * width + i)];
                        }
                    }
                }
            }
            if let Some(dc) = &self.dc {
                // ∂C/∂P_i x_k for the chunk: one GEMM of the stacked ∂C with X.
                let mut extra = Mat::<f64>::zeros(j * p, len);
                matmul(extra.as_mut(), Accum::Replace, dc.as_ref(), xc, 1.0, par);
                for t in 0..len {
                    for i in 0..j {
                        for o in 0..p {
                            out.sensitivities[((start + t) * p + o, i)] += extra[(i * p + o, t)];
                        }
                    }
                }
            }
            start += len;
        }
    }
}

/// The small-system loop as a pulp operation (compiled per instruction set).
pub(super) struct SmallLoop<'a> {
    pub(super) prop: Parts<'a>,
    pub(super) x0: &'a [f64],
    pub(super) s0: MatRef<'a, f64>,
    pub(super) drive: Option<&'a Drive<'a>>,
    pub(super) out: &'a mut Response,
}

impl pulp::WithSimd for SmallLoop<'_> {
    type Output = ();
    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _simd: S) {
        self.prop.small_dispatch(self.x0, self.s0, self.drive, self.out);
    }
}

/// Output lanes per group in the fixed-size kernels.
const QUAD: usize = 4;
/// Up to this many outputs the fixed-size kernels are used.
const FIXED_MAX_OUTPUTS: usize = 8;

/// Samples per chunk of the large-system path.
const CHUNK: usize = 128;
/// Up to this many states the plain-loop path is used.
pub(super) const SMALL_STATES: usize = 32;

/// The sensitivity block of one group of parameters.
struct GroupState {
    first: usize,
    s: Mat<f64>,
    s_next: Mat<f64>,
    history: Mat<f64>,
    y: Mat<f64>,
}

impl GroupState {
    /// Records S_t and advances S_{t+1} = Φ S_t + W_t for the chunk, then Y = C·history.
    fn advance(
        &mut self,
        phi: MatRef<'_, f64>,
        c: MatRef<'_, f64>,
        w: MatRef<'_, f64>,
        len: usize,
        n: usize,
    ) {
        let width = self.s.ncols();
        for t in 0..len {
            self.history.as_mut().subcols_mut(t * width, width).copy_from(&self.s);
            matmul(self.s_next.as_mut(), Accum::Replace, phi, self.s.as_ref(), 1.0, Par::Seq);
            for i in 0..width {
                let wi = w.col(t).subrows((self.first + i) * n, n);
                let mut col = self.s_next.as_mut().col_mut(i);
                for r in 0..n {
                    col[r] += wi[r];
                }
            }
            std::mem::swap(&mut self.s, &mut self.s_next);
        }
        matmul(
            self.y.as_mut().subcols_mut(0, len * width),
            Accum::Replace,
            c,
            self.history.as_ref().subcols(0, len * width),
            1.0,
            Par::Seq,
        );
    }
}

/// The columns of a [`Response`] as mutable slices, for writing one sample at a time.
struct Columns<'a> {
    outputs: Vec<&'a mut [f64]>,
    sensitivities: Vec<&'a mut [f64]>,
}

impl<'a> Columns<'a> {
    fn new(out: &'a mut Response) -> Self {
        let slices = |m: &'a mut Mat<f64>| -> Vec<&'a mut [f64]> {
            m.as_mut()
                .col_iter_mut()
                .map(|c| c.try_as_col_major_mut().expect("an owned Mat is column-major").as_slice_mut())
                .collect()
        };
        Self { outputs: slices(&mut out.outputs), sensitivities: slices(&mut out.sensitivities) }
    }
}

/// Copies sample-major buffers into the column-major result: `outputs[k·stride + o]` is y_o(t_k)
/// and `sensitivities[(k·j + i)·stride + o]` is ∂y_o(t_k)/∂P_i (`stride` ≥ p pads the rows).
fn scatter(out: &mut Response, outputs: &[f64], sensitivities: &[f64], stride: usize) {
    let (k_samples, p, j) = (out.outputs.nrows(), out.outputs.ncols(), out.sensitivities.ncols());
    for o in 0..p {
        for k in 0..k_samples {
            out.outputs[(k, o)] = outputs[k * stride + o];
        }
    }
    for i in 0..j {
        for k in 0..k_samples {
            for o in 0..p {
                out.sensitivities[(k * p + o, i)] = sensitivities[(k * j + i) * stride + o];
            }
        }
    }
}

/// A column-major copy of a matrix as a flat vector.
fn dense(m: MatRef<'_, f64>) -> Vec<f64> {
    let mut v = Vec::with_capacity(m.nrows() * m.ncols());
    for j in 0..m.ncols() {
        for i in 0..m.nrows() {
            v.push(m[(i, j)]);
        }
    }
    v
}
