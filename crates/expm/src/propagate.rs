//! The discrete-time MEM sensitivity propagator (paper Eq. 9 at a constant sample interval).

use crate::fixed::{Fixed, mat_vec_add};
use crate::frechet::Frechet;
use crate::square::Square;
use crate::{ExpmError, check};
use faer::linalg::matmul::matmul;
use faer::{Accum, Mat, MatRef, Par};

/// Φ = e^{Ah} and the stacked Ψ_i = L(Ah, h ∂A/∂P_i) ((j·N) × N), on the stack for N ≤ 16.
fn phi_psi(a: MatRef<'_, f64>, da: &[MatRef<'_, f64>], h: f64) -> Result<(Mat<f64>, Mat<f64>), ExpmError> {
    macro_rules! fixed {
        ($($n:literal)*) => {
            match a.nrows() {
                $($n => phi_psi_in::<Fixed<$n>>(a, da, h),)*
                _ => phi_psi_in::<Mat<f64>>(a, da, h),
            }
        };
    }
    fixed!(1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16)
}

/// [`phi_psi`] in the storage `M`.
fn phi_psi_in<M: Square>(
    a: MatRef<'_, f64>,
    da: &[MatRef<'_, f64>],
    h: f64,
) -> Result<(Mat<f64>, Mat<f64>), ExpmError> {
    let n = a.nrows();
    let mut ah = M::from_ref(a);
    ah.scale(h);
    let work = Frechet::new(&ah)?;
    let mut phi = Mat::zeros(n, n);
    work.exp().write_to(phi.as_mut());
    let mut psi = Mat::zeros(da.len() * n, n);
    for (i, d) in da.iter().enumerate() {
        if d.norm_max() == 0.0 {
            continue; // L(Ah, 0) = 0: e.g. a parameter that only enters x(0)
        }
        let mut dh = M::from_ref(*d);
        dh.scale(h);
        work.derivative(&dh)?.write_to(psi.as_mut().submatrix_mut(i * n, 0, n, n));
    }
    Ok((phi, psi))
}

/// Outputs and output sensitivities of a free decay at K samples.
///
/// `outputs[(k, o)]` is y_o(t_k); `sensitivities[(k·p + o, i)]` is ∂y_o(t_k)/∂P_i, so that
/// `sensitivities` is exactly the matrix S of the paper's Eq. (11)–(12) with rows ordered by
/// time, then output.
#[derive(Clone, Debug)]
pub struct Response {
    /// K × p model outputs.
    pub outputs: Mat<f64>,
    /// (K·p) × j output sensitivities.
    pub sensitivities: Mat<f64>,
}

impl Response {
    /// An empty response for `n_samples` samples of `n_outputs` outputs and `n_params` parameters.
    pub fn zeros(n_samples: usize, n_outputs: usize, n_params: usize) -> Self {
        Self {
            outputs: Mat::zeros(n_samples, n_outputs),
            sensitivities: Mat::zeros(n_samples * n_outputs, n_params),
        }
    }

    /// Number of samples K.
    pub fn n_samples(&self) -> usize {
        self.outputs.nrows()
    }
}

/// Φ = e^{Ah} and Ψ_i = L(Ah, h ∂A/∂P_i), ready to propagate free decays.
///
/// One step advances the N×(j+1) block X_k = [x_k, s_{1,k}, …, s_{j,k}]:
/// x_{k+1} = Φ x_k and s_{i,k+1} = Φ s_{i,k} + Ψ_i x_k — exact for the continuous-time system
/// at the sample instants, because [[Φ, 0], [Ψ_i, Φ]] = exp(h [[A, 0], [∂A/∂P_i, A]]) (Eq. 9).
/// Each step is one product of Φ with the block, one product of the stacked Ψ with x_k, and
/// one product of C with the block; nothing is allocated inside the loop and no history is kept.
///
/// ```
/// use faer::{mat, Mat};
/// // A damped oscillator with one parameter: the stiffness k in A = [[0, 1], [-k, -0.1]].
/// let a = mat![[0.0, 1.0], [-4.0, -0.1]];
/// let da = mat![[0.0, 0.0], [-1.0, 0.0]];
/// let c = mat![[1.0, 0.0]];
/// let prop = expm::SensitivityPropagator::new(a.as_ref(), &[da.as_ref()], c.as_ref(), 0.05).unwrap();
/// let x0 = [1.0, 0.0];
/// let response = prop.propagate(&x0, None, 200).unwrap();
/// assert_eq!(response.sensitivities.nrows(), 200);
/// ```
#[derive(Clone, Debug)]
pub struct SensitivityPropagator {
    n_states: usize,
    n_params: usize,
    n_outputs: usize,
    h: f64,
    phi: Mat<f64>,
    /// (j·N) × N: Ψ_1 on top of Ψ_2 on top of …
    psi: Mat<f64>,
    c: Mat<f64>,
    /// (j·p) × N: ∂C/∂P_1 on top of ∂C/∂P_2 … when C depends on the parameters.
    dc: Option<Mat<f64>>,
}

impl SensitivityPropagator {
    /// Builds Φ and the Ψ_i from A (N×N), the directions ∂A/∂P_i (each N×N), C (p×N) and h.
    ///
    /// # Errors
    /// Shape, finiteness and overflow errors of the arguments; [`ExpmError::InvalidInterval`]
    /// unless h is finite and positive.
    pub fn new(
        a: MatRef<'_, f64>,
        da: &[MatRef<'_, f64>],
        c: MatRef<'_, f64>,
        h: f64,
    ) -> Result<Self, ExpmError> {
        let n = check::square("a", a)?;
        if !(h.is_finite() && h > 0.0) {
            return Err(ExpmError::InvalidInterval { h });
        }
        if c.ncols() != n {
            return Err(ExpmError::ShapeMismatch {
                name: "c",
                nrows: c.nrows(),
                ncols: c.ncols(),
                expected_rows: c.nrows(),
                expected_cols: n,
            });
        }
        check::finite("c", c)?;
        for d in da {
            check::shape("da", *d, n, n)?;
            check::finite("da", *d)?;
        }
        let (phi, psi) = phi_psi(a, da, h)?;
        Ok(Self {
            n_states: n,
            n_params: da.len(),
            n_outputs: c.nrows(),
            h,
            phi,
            psi,
            c: c.to_owned(),
            dc: None,
        })
    }

    /// Adds output-matrix derivatives ∂C/∂P_i (each p × N), for models whose C depends on
    /// the parameters: then ∂y_k/∂P_i = C s_{i,k} + (∂C/∂P_i) x_k (paper Eq. 6).
    ///
    /// # Errors
    /// Shape and finiteness errors of `dc`.
    pub fn with_output_derivatives(mut self, dc: &[MatRef<'_, f64>]) -> Result<Self, ExpmError> {
        let (n, p) = (self.n_states, self.n_outputs);
        if dc.len() != self.n_params {
            return Err(ExpmError::ShapeMismatch {
                name: "dc",
                nrows: dc.len(),
                ncols: 0,
                expected_rows: self.n_params,
                expected_cols: 0,
            });
        }
        let mut stack = Mat::zeros(self.n_params * p, n);
        for (i, d) in dc.iter().enumerate() {
            check::shape("dc", *d, p, n)?;
            check::finite("dc", *d)?;
            stack.as_mut().submatrix_mut(i * p, 0, p, n).copy_from(d);
        }
        self.dc = Some(stack);
        Ok(self)
    }

    /// Number of states N.
    pub fn n_states(&self) -> usize {
        self.n_states
    }
    /// Number of parameters j.
    pub fn n_params(&self) -> usize {
        self.n_params
    }
    /// Number of outputs p.
    pub fn n_outputs(&self) -> usize {
        self.n_outputs
    }
    /// The sample interval h.
    pub fn interval(&self) -> f64 {
        self.h
    }
    /// Φ = e^{Ah}.
    pub fn phi(&self) -> MatRef<'_, f64> {
        self.phi.as_ref()
    }
    /// Ψ_i = L(Ah, h ∂A/∂P_i) = ∂Φ/∂P_i.
    pub fn psi(&self, i: usize) -> MatRef<'_, f64> {
        self.psi.as_ref().submatrix(i * self.n_states, 0, self.n_states, self.n_states)
    }

    /// Propagates from x(0) (and ∂x(0)/∂P, N×j, if it depends on the parameters) for
    /// `n_samples` samples t_k = k·h, k = 0..K−1.
    ///
    /// # Errors
    /// Shape and finiteness errors of `x0` and `dx0`.
    pub fn propagate(
        &self,
        x0: &[f64],
        dx0: Option<MatRef<'_, f64>>,
        n_samples: usize,
    ) -> Result<Response, ExpmError> {
        let mut out = Response::zeros(n_samples, self.n_outputs, self.n_params);
        self.propagate_into(x0, dx0, &mut out)?;
        Ok(out)
    }

    /// As [`Self::propagate`], writing into a caller-owned [`Response`] (its number of rows
    /// sets K), so that repeated calls allocate only the two N×(j+1) work blocks.
    ///
    /// # Errors
    /// Shape and finiteness errors of `x0`, `dx0` and `out`.
    pub fn propagate_into(
        &self,
        x0: &[f64],
        dx0: Option<MatRef<'_, f64>>,
        out: &mut Response,
    ) -> Result<(), ExpmError> {
        let (n, j, p) = (self.n_states, self.n_params, self.n_outputs);
        let x0m = MatRef::from_column_major_slice(x0, x0.len(), 1);
        check::shape("x0", x0m, n, 1)?;
        check::finite("x0", x0m)?;
        let k_samples = out.outputs.nrows();
        check::shape("outputs", out.outputs.as_ref(), k_samples, p)?;
        check::shape("sensitivities", out.sensitivities.as_ref(), k_samples * p, j)?;
        let mut s0 = Mat::<f64>::zeros(n, j);
        if let Some(d) = dx0 {
            check::shape("dx0", d, n, j)?;
            check::finite("dx0", d)?;
            s0.copy_from(d);
        }
        if k_samples == 0 {
            return Ok(());
        }
        if n <= SMALL_STATES {
            self.propagate_small(x0, s0.as_ref(), out);
        } else {
            self.propagate_chunked(x0, s0.as_ref(), out);
        }
        Ok(())
    }

    /// Tiny systems: plain loops over column-major slices, one pass per sample, compiled for
    /// the best instruction set of the machine at run time (pulp's dispatch), so that the short
    /// inner loops vectorize with AVX2/AVX-512 where available.
    fn propagate_small(&self, x0: &[f64], s0: MatRef<'_, f64>, out: &mut Response) {
        pulp::Arch::new().dispatch(SmallLoop { prop: self, x0, s0, out });
    }

    /// Dispatches to a kernel with the state dimension as a compile-time constant (fully
    /// unrolled and vectorized) when N ≤ 16 and p ≤ 8, else to the generic loop.
    #[inline(always)]
    fn small_dispatch(&self, x0: &[f64], s0: MatRef<'_, f64>, out: &mut Response) {
        macro_rules! fixed {
            ($($n:literal)*) => {
                match self.n_states {
                    $($n if self.n_outputs <= FIXED_MAX_OUTPUTS => self.fixed_loop::<$n>(x0, s0, out),)*
                    _ => self.small_loop(x0, s0, out),
                }
            };
        }
        fixed!(1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16)
    }

    /// The small loop with N fixed at compile time. Outputs are formed in groups of four
    /// (`QUAD` lanes) and written straight into `out`; the recurrence x ← Φx, sᵢ ← Φsᵢ + Ψᵢx
    /// keeps two independent accumulation chains per product (see [`mat_vec_add`]), because at
    /// this size a step is bound by the latency of its dependent multiply–adds.
    #[inline(always)]
    fn fixed_loop<const N: usize>(&self, x0: &[f64], s0: MatRef<'_, f64>, out: &mut Response) {
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
            for (s, psi_i) in sens.iter_mut().zip(&psi) {
                // Ψᵢx first: it does not wait for sᵢ, so only Φsᵢ is on the critical path.
                *s = mat_vec_add(&phi, s, mat_vec_add(psi_i, x, [0.0; N]));
            }
            *x = mat_vec_add(&phi, x, [0.0; N]);
        }
    }

    #[inline(always)]
    fn small_loop(&self, x0: &[f64], s0: MatRef<'_, f64>, out: &mut Response) {
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
            // [x, S] ← Φ·[x, S] + [0, Ψ x]
            next.iter_mut().for_each(|v| *v = 0.0);
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
    /// matrix–vector products, then Ψ·X for the whole chunk as one GEMM, then the sensitivity
    /// recursion S ← Φ S + W as products of Φ with the N×j block — split over two threads by
    /// parameter — and the outputs of the chunk as GEMMs with C. All buffers are allocated once.
    fn propagate_chunked(&self, x0: &[f64], s0: MatRef<'_, f64>, out: &mut Response) {
        let (n, j, p) = (self.n_states, self.n_params, self.n_outputs);
        let k_samples = out.outputs.nrows();
        let chunk = CHUNK.min(k_samples);
        let mut x_chunk = Mat::<f64>::zeros(n, chunk);
        let mut w = Mat::<f64>::zeros(j * n, chunk);
        let mut y_chunk = Mat::<f64>::zeros(p, chunk);
        let mut x = Mat::<f64>::zeros(n, 1);
        let mut x_next = Mat::<f64>::zeros(n, 1);
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
            // States x_start .. x_start+len−1 (x holds x_start on entry).
            for t in 0..len {
                x_chunk.col_mut(t).copy_from(x.col(0));
                matmul(x_next.as_mut(), Accum::Replace, self.phi.as_ref(), x.as_ref(), 1.0, Par::Seq);
                std::mem::swap(&mut x, &mut x_next);
            }
            let xc = x_chunk.as_ref().subcols(0, len);
            // W = [Ψ_1; …; Ψ_j]·X for the chunk, one GEMM.
            matmul(w.as_mut().subcols_mut(0, len), Accum::Replace, self.psi.as_ref(), xc, 1.0, par);
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
struct SmallLoop<'a> {
    prop: &'a SensitivityPropagator,
    x0: &'a [f64],
    s0: MatRef<'a, f64>,
    out: &'a mut Response,
}

impl pulp::WithSimd for SmallLoop<'_> {
    type Output = ();
    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _simd: S) {
        self.prop.small_dispatch(self.x0, self.s0, self.out);
    }
}

/// Output lanes per group in the fixed-size kernels.
const QUAD: usize = 4;
/// Up to this many outputs the fixed-size kernels are used.
const FIXED_MAX_OUTPUTS: usize = 8;

/// Samples per chunk of the large-system path.
const CHUNK: usize = 128;
/// Up to this many states the plain-loop path is used.
const SMALL_STATES: usize = 32;

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

/// How [`free_decay`] computes outputs and sensitivities.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Strategy {
    /// Modal form when A is large enough for it to pay and well-conditioned, else propagation.
    Auto,
    /// Always the propagator (Φ, Ψ_i and the recursion).
    Propagation,
    /// The modal form if it is safe, else the propagator.
    Modal,
}

/// Which method [`free_decay`] used.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Method {
    /// The sensitivity propagator.
    Propagation,
    /// Modal coordinates (Daleckii–Krein and a geometric sum).
    Modal,
}

/// From this many states on, `Strategy::Auto` tries the modal form (the measured crossover,
/// docs/performance.md: up to 16 states the fixed-size propagation is faster).
pub const MODAL_MIN_STATES: usize = 17;

/// Outputs and output sensitivities of ẋ = Ax, y = Cx from x(0) at t_k = k·h (the size of
/// `out` sets K): the MEM's Eq. 9 by the propagator, or — for larger, diagonalisable and
/// well-conditioned A — in modal coordinates at a fraction of the cost (module `modal`).
///
/// # Errors
/// Shape, finiteness and overflow errors of the arguments.
#[allow(clippy::too_many_arguments)]
pub fn free_decay(
    a: MatRef<'_, f64>,
    da: &[MatRef<'_, f64>],
    c: MatRef<'_, f64>,
    dc: Option<&[MatRef<'_, f64>]>,
    x0: &[f64],
    dx0: Option<MatRef<'_, f64>>,
    h: f64,
    out: &mut Response,
    strategy: Strategy,
) -> Result<Method, ExpmError> {
    let n = check::square("a", a)?;
    let try_modal = match strategy {
        Strategy::Auto => n >= MODAL_MIN_STATES,
        Strategy::Modal => true,
        Strategy::Propagation => false,
    };
    if try_modal {
        // Validate exactly as the propagator would, so both paths reject the same input.
        if !(h.is_finite() && h > 0.0) {
            return Err(ExpmError::InvalidInterval { h });
        }
        check::finite("a", a)?;
        check::shape("c", c, c.nrows(), n)?;
        check::finite("c", c)?;
        for d in da {
            check::shape("da", *d, n, n)?;
            check::finite("da", *d)?;
        }
        let x0m = MatRef::from_column_major_slice(x0, x0.len(), 1);
        check::shape("x0", x0m, n, 1)?;
        check::finite("x0", x0m)?;
        if let Some(dc) = dc {
            for d in dc {
                check::shape("dc", *d, c.nrows(), n)?;
                check::finite("dc", *d)?;
            }
        }
        if let Some(d) = dx0 {
            check::shape("dx0", d, n, da.len())?;
            check::finite("dx0", d)?;
        }
        check::shape("outputs", out.outputs.as_ref(), out.outputs.nrows(), c.nrows())?;
        check::shape("sensitivities", out.sensitivities.as_ref(), out.outputs.nrows() * c.nrows(), da.len())?;
        if crate::modal::modal_response(a, da, c, dc, x0, dx0, h, out)? {
            return Ok(Method::Modal);
        }
    }
    let mut prop = SensitivityPropagator::new(a, da, c, h)?;
    if let Some(dc) = dc {
        prop = prop.with_output_derivatives(dc)?;
    }
    prop.propagate_into(x0, dx0, out)?;
    Ok(Method::Propagation)
}
