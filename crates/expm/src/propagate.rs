//! The discrete-time MEM sensitivity propagator (paper Eq. 9 at a constant sample interval).

use crate::frechet::ExpmFrechet;
use crate::{ExpmError, check};
use faer::linalg::matmul::matmul;
use faer::{Accum, Mat, MatMut, MatRef, Par};

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
        let ah = a.to_owned() * faer::Scale(h);
        let work = ExpmFrechet::new(ah.as_ref())?;
        let mut psi = Mat::zeros(da.len() * n, n);
        for (i, d) in da.iter().enumerate() {
            if d.norm_max() == 0.0 {
                continue; // L(Ah, 0) = 0: e.g. a parameter that only enters x(0)
            }
            let dh = d.to_owned() * faer::Scale(h);
            let l = work.derivative(dh.as_ref())?;
            psi.as_mut().submatrix_mut(i * n, 0, n, n).copy_from(&l);
        }
        Ok(Self {
            n_states: n,
            n_params: da.len(),
            n_outputs: c.nrows(),
            h,
            phi: work.exp().to_owned(),
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
        let mut block = Mat::<f64>::zeros(n, j + 1);
        let mut next = Mat::<f64>::zeros(n, j + 1);
        let mut psi_x = Mat::<f64>::zeros(j * n, 1);
        let mut y = Mat::<f64>::zeros(p, j + 1);
        let mut dc_x = Mat::<f64>::zeros(if self.dc.is_some() { j * p } else { 0 }, 1);
        block.col_mut(0).copy_from(x0m.col(0));
        if let Some(d) = dx0 {
            check::shape("dx0", d, n, j)?;
            check::finite("dx0", d)?;
            block.as_mut().submatrix_mut(0, 1, n, j).copy_from(d);
        }
        let par = if n >= 192 { faer::get_global_parallelism() } else { Par::Seq };
        for k in 0..k_samples {
            matmul(y.as_mut(), Accum::Replace, self.c.as_ref(), block.as_ref(), 1.0, Par::Seq);
            if let Some(dc) = &self.dc {
                let x = block.as_ref().col(0).as_mat();
                matmul(dc_x.as_mut(), Accum::Replace, dc.as_ref(), x, 1.0, Par::Seq);
                for i in 0..j {
                    for o in 0..p {
                        y[(o, i + 1)] += dc_x[(i * p + o, 0)];
                    }
                }
            }
            store(y.as_ref(), k, out.outputs.as_mut(), out.sensitivities.as_mut());
            if k + 1 == k_samples {
                break;
            }
            matmul(next.as_mut(), Accum::Replace, self.phi.as_ref(), block.as_ref(), 1.0, par);
            if j > 0 {
                matmul(
                    psi_x.as_mut(),
                    Accum::Replace,
                    self.psi.as_ref(),
                    block.as_ref().col(0).as_mat(),
                    1.0,
                    par,
                );
                for i in 0..j {
                    let mut col = next.as_mut().col_mut(i + 1);
                    for r in 0..n {
                        col[r] += psi_x[(i * n + r, 0)];
                    }
                }
            }
            std::mem::swap(&mut block, &mut next);
        }
        Ok(())
    }
}

/// Copies y = C X_k (p × (j+1)) into row k of the outputs and rows k·p.. of S.
#[inline]
fn store(y: MatRef<'_, f64>, k: usize, mut outputs: MatMut<'_, f64>, mut sens: MatMut<'_, f64>) {
    let p = y.nrows();
    for o in 0..p {
        outputs[(k, o)] = y[(o, 0)];
        for i in 1..y.ncols() {
            sens[(k * p + o, i - 1)] = y[(o, i)];
        }
    }
}
