//! The discrete-time MEM sensitivity recursion (paper Eq. 9 at a constant sample interval),
//! free or driven by a sampled input: the propagator and its entry points here, the loops
//! that advance it in [`kernels`], the sampled input's drive in [`drive`].

mod drive;
mod kernels;

use super::discretise::{Discrete, InputMatrices, discretise};
use crate::response::Response;
use crate::{ExpmError, Hold, check};
use drive::{Drive, InputPart};
use faer::{Mat, MatRef};
use kernels::{Parts, SMALL_STATES, SmallLoop};

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

    /// What the loops read: Φ, the stacked Ψ, C and ∂C, and the sizes.
    fn parts(&self) -> Parts<'_> {
        Parts {
            n_states: self.n_states,
            n_params: self.n_params,
            n_outputs: self.n_outputs,
            phi: &self.phi,
            psi: &self.psi,
            c: &self.c,
            dc: self.dc.as_ref(),
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
                prop: self.parts(),
                x0,
                s0: s0.as_ref(),
                drive: drive.as_ref(),
                out,
            });
        } else {
            self.parts().propagate_chunked(x0, s0.as_ref(), drive.as_ref(), out);
        }
        if let Some(drive) = &drive {
            drive.feedthrough(out, p, j);
        }
        if !(out.outputs.as_ref().is_all_finite() && out.sensitivities.as_ref().is_all_finite()) {
            return Err(ExpmError::NonFiniteResult { what: "the propagated response" });
        }
        Ok(())
    }
}
