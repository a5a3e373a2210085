//! The discrete-time MEM sensitivity recursion (paper Eq. 9 at a constant sample interval),
//! free or driven by a sampled input.

use super::Response;
use super::discretise::{Discrete, InputGains, InputMatrices, discretise};
use crate::fixed::mat_vec_add;
use crate::{ExpmError, Hold, check};
use faer::linalg::matmul::matmul;
use faer::{Accum, Mat, MatRef, Par};

/// The input side of a forced propagator: gains of the discretisation and the feedthrough.
#[derive(Clone, Debug)]
struct InputPart {
    gains: InputGains,
    /// D (p × m).
    d: Option<Mat<f64>>,
    /// ∂D/∂P_i stacked ((j·p) × m).
    dd: Option<Mat<f64>>,
}

/// Φ = e^{Ah} and Ψ_i = L(Ah, h ∂A/∂P_i) (and, for a forced model, the input gains Γ and ∂Γ/∂P_i),
/// ready to propagate.
///
/// One step advances the N×(j+1) block X_k = [x_k, s_{1,k}, …, s_{j,k}]:
/// x_{k+1} = Φ x_k (+ Γu_k) and s_{i,k+1} = Φ s_{i,k} + Ψ_i x_k (+ ∂Γ/∂P_i u_k) — exact for the
/// continuous-time system at the sample instants, because [[Φ, 0], [Ψ_i, Φ]] =
/// exp(h [[A, 0], [∂A/∂P_i, A]]) (Eq. 9). Each step is one product of Φ with the block, one
/// product of the stacked Ψ with x_k, and one product of C with the block; nothing is allocated
/// inside the loop and no history is kept.
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
    input: Option<InputPart>,
}

fn validate_core(
    a: MatRef<'_, f64>,
    da: &[MatRef<'_, f64>],
    c: MatRef<'_, f64>,
    h: f64,
) -> Result<usize, ExpmError> {
    let n = check::square("a", a)?;
    check::finite("a", a)?;
    if !(h.is_finite() && h > 0.0) {
        return Err(ExpmError::InvalidInterval { h });
    }
    check::shape("c", c, c.nrows(), n)?;
    check::finite("c", c)?;
    for d in da {
        check::shape("da", *d, n, n)?;
        check::finite("da", *d)?;
    }
    Ok(n)
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
        let n = validate_core(a, da, c, h)?;
        let discrete = discretise(a, da, None, h)?;
        Ok(Self::from_discrete(n, da.len(), c, h, discrete))
    }

    /// A propagator for ẋ = Ax + Bu with u sampled and held by `hold`: Φ, Γ and their
    /// derivatives from one exponential of the augmented generator (Van Loan). `b` is N×m and
    /// `db` one N×m matrix per parameter (the same count as `da`).
    ///
    /// # Errors
    /// As [`Self::new`], and shape and finiteness errors of `b` and `db`.
    pub fn forced(
        a: MatRef<'_, f64>,
        da: &[MatRef<'_, f64>],
        b: MatRef<'_, f64>,
        db: &[MatRef<'_, f64>],
        c: MatRef<'_, f64>,
        h: f64,
        hold: Hold,
    ) -> Result<Self, ExpmError> {
        let n = validate_core(a, da, c, h)?;
        check::shape("b", b, n, b.ncols())?;
        check::finite("b", b)?;
        if db.len() != da.len() {
            return Err(ExpmError::ShapeMismatch {
                name: "db",
                nrows: db.len(),
                ncols: 0,
                expected_rows: da.len(),
                expected_cols: 0,
            });
        }
        for d in db {
            check::shape("db", *d, n, b.ncols())?;
            check::finite("db", *d)?;
        }
        let mut discrete = discretise(a, da, Some(InputMatrices { b, db, hold }), h)?;
        let gains = discrete.gains.take().expect("inputs were given");
        let mut prop = Self::from_discrete(n, da.len(), c, h, discrete);
        prop.input = Some(InputPart { gains, d: None, dd: None });
        Ok(prop)
    }

    fn from_discrete(n: usize, j: usize, c: MatRef<'_, f64>, h: f64, discrete: Discrete) -> Self {
        Self {
            n_states: n,
            n_params: j,
            n_outputs: c.nrows(),
            h,
            phi: discrete.phi,
            psi: discrete.psi,
            c: c.to_owned(),
            dc: None,
            input: None,
        }
    }

    /// Adds output-matrix derivatives ∂C/∂P_i (each p × N), for models whose C depends on
    /// the parameters: then ∂y_k/∂P_i = C s_{i,k} + (∂C/∂P_i) x_k (paper Eq. 6).
    ///
    /// # Errors
    /// Shape and finiteness errors of `dc`.
    pub fn with_output_derivatives(mut self, dc: &[MatRef<'_, f64>]) -> Result<Self, ExpmError> {
        self.dc = Some(self.stack("dc", dc, self.n_states)?);
        Ok(self)
    }

    /// Adds the direct feedthrough y = Cx + Du (D p × m) and its derivatives ∂D/∂P_i (none: D
    /// does not depend on P) to a forced propagator.
    ///
    /// # Errors
    /// Shape and finiteness errors; [`ExpmError::ShapeMismatch`] on a free-decay propagator.
    pub fn with_feedthrough(
        mut self,
        d: MatRef<'_, f64>,
        dd: Option<&[MatRef<'_, f64>]>,
    ) -> Result<Self, ExpmError> {
        let m = self.n_inputs();
        check::shape("d", d, self.n_outputs, m)?;
        check::finite("d", d)?;
        let dd = dd.map(|dd| self.stack("dd", dd, m)).transpose()?;
        let Some(input) = self.input.as_mut() else {
            return Err(ExpmError::ShapeMismatch {
                name: "d",
                nrows: d.nrows(),
                ncols: d.ncols(),
                expected_rows: self.n_outputs,
                expected_cols: 0,
            });
        };
        input.d = Some(d.to_owned());
        input.dd = dd;
        Ok(self)
    }

    /// The j matrices (each p × `cols`) stacked, after checking their count, shapes and values.
    fn stack(
        &self,
        name: &'static str,
        list: &[MatRef<'_, f64>],
        cols: usize,
    ) -> Result<Mat<f64>, ExpmError> {
        let p = self.n_outputs;
        if list.len() != self.n_params {
            return Err(ExpmError::ShapeMismatch {
                name,
                nrows: list.len(),
                ncols: 0,
                expected_rows: self.n_params,
                expected_cols: 0,
            });
        }
        let mut stack = Mat::zeros(self.n_params * p, cols);
        for (i, d) in list.iter().enumerate() {
            check::shape(name, *d, p, cols)?;
            check::finite(name, *d)?;
            stack.as_mut().submatrix_mut(i * p, 0, p, cols).copy_from(d);
        }
        Ok(stack)
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
    /// Number of inputs m (0 for a free-decay propagator).
    pub fn n_inputs(&self) -> usize {
        self.input.as_ref().map_or(0, |i| i.gains.now.ncols())
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
    /// Shape and finiteness errors of `x0` and `dx0`; a forced propagator needs
    /// [`Self::propagate_forced_into`].
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
        if self.input.is_some() {
            return Err(ExpmError::ShapeMismatch {
                name: "u",
                nrows: 0,
                ncols: 0,
                expected_rows: out.outputs.nrows(),
                expected_cols: self.n_inputs(),
            });
        }
        self.run(x0, dx0, None, out)
    }

    /// Propagates a forced response: `u` holds u_k in row k (K × m, K the rows of `out`).
    ///
    /// # Errors
    /// As [`Self::propagate_into`], and shape and finiteness errors of `u`.
    pub fn propagate_forced_into(
        &self,
        x0: &[f64],
        dx0: Option<MatRef<'_, f64>>,
        u: MatRef<'_, f64>,
        out: &mut Response,
    ) -> Result<(), ExpmError> {
        check::shape("u", u, out.outputs.nrows(), self.n_inputs())?;
        check::finite("u", u)?;
        match &self.input {
            Some(input) => self.run(x0, dx0, Some(Drive { u, input }), out),
            None => self.run(x0, dx0, None, out),
        }
    }

    fn run(
        &self,
        x0: &[f64],
        dx0: Option<MatRef<'_, f64>>,
        drive: Option<Drive<'_>>,
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
            pulp::Arch::new().dispatch(SmallLoop {
                prop: self,
                x0,
                s0: s0.as_ref(),
                drive: drive.as_ref(),
                out,
            });
        } else {
            self.propagate_chunked(x0, s0.as_ref(), drive.as_ref(), out);
        }
        if let Some(drive) = &drive {
            drive.feedthrough(out, p, j);
        }
        if !(out.outputs.as_ref().is_all_finite() && out.sensitivities.as_ref().is_all_finite()) {
            return Err(ExpmError::NonFiniteResult { what: "the propagated response" });
        }
        Ok(())
    }

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
    fn propagate_chunked(
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

/// A sampled input and the gains it drives the recursion through.
struct Drive<'a> {
    /// K × m.
    u: MatRef<'a, f64>,
    input: &'a InputPart,
}

impl Drive<'_> {
    /// (u_k, u_{k+1}) as row indices; u_{k+1} is zero past the end (never needed: the last
    /// sample's update is not taken).
    fn samples(&self, k: usize) -> (usize, Option<usize>) {
        (k, (k + 1 < self.u.nrows()).then_some(k + 1))
    }

    /// seed = [Γ_now u_k + Γ_next u_{k+1}; ∂Γ_now u_k + ∂Γ_next u_{k+1}] (N·(j+1), column blocks).
    fn seed(&self, k: usize, seed: &mut [f64], n: usize, j: usize) {
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
    fn chunk(
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
    fn feedthrough(&self, out: &mut Response, p: usize, j: usize) {
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
struct FixedGains<const N: usize> {
    /// (column of Γ_now, column of Γ_next) per input.
    state: Vec<([f64; N], [f64; N])>,
    /// The same for ∂Γ/∂P_i, per parameter.
    sensitivity: Vec<Vec<([f64; N], [f64; N])>>,
    u: Vec<f64>,
    m: usize,
}

impl<const N: usize> FixedGains<N> {
    fn new(drive: &Drive<'_>, j: usize) -> Self {
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
    fn state(&self, now: usize, next: Option<usize>) -> [f64; N] {
        self.combine(&self.state, now, next)
    }

    #[inline(always)]
    fn sensitivity(&self, i: usize, now: usize, next: Option<usize>) -> [f64; N] {
        self.combine(&self.sensitivity[i], now, next)
    }
}

/// The small-system loop as a pulp operation (compiled per instruction set).
struct SmallLoop<'a> {
    prop: &'a SensitivityPropagator,
    x0: &'a [f64],
    s0: MatRef<'a, f64>,
    drive: Option<&'a Drive<'a>>,
    out: &'a mut Response,
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
