//! Sampled responses and their sensitivities: the problem description, the discretisation
//! ([`discretise`]), the recursion ([`recursion`]) and the modal path (`crate::modal`).
//!
//! A [`ResponseProblem`] says everything about one sampled response — A, C, x(0), h, the
//! parameter directions ∂A/∂P_i (and ∂C/∂P_i, ∂x(0)/∂P_i), measured inputs with B, D and
//! their derivatives, the time of the first sample — and is validated as a whole before any
//! exponential is formed (in the manner of diffsol's `OdeSolverProblem`).

mod discretise;
mod recursion;

pub use discretise::{StepGains, step_gains};
pub use recursion::SensitivityPropagator;

pub use crate::response::Response;
use crate::{ExpmError, check};
use faer::{Mat, MatRef};

/// How a sampled input is held between samples.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Hold {
    /// u(t) = u_k on [t_k, t_{k+1}) (zero-order hold, the default).
    #[default]
    Zero,
    /// u(t) linear between u_k and u_{k+1} (first-order hold).
    FirstOrder,
}

/// How a free decay's outputs and sensitivities are computed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Strategy {
    /// Modal form when A is large enough for it to pay and well-conditioned, else propagation.
    Auto,
    /// Always the propagator (Φ, Ψ_i and the recursion).
    Propagation,
    /// The modal form if it is safe, else the propagator.
    Modal,
}

/// Which method computed a response.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Method {
    /// The sensitivity propagator.
    Propagation,
    /// Modal coordinates (Daleckii–Krein and a geometric sum).
    Modal,
}

/// From this many states on, `Strategy::Auto` tries the modal form for a free decay (the
/// measured crossover, docs/performance.md: up to 16 states the fixed-size propagation is faster).
pub const MODAL_MIN_STATES: usize = 17;

/// The input side of a forced response: ẋ = Ax + Bu, y = Cx + Du, u sampled.
#[derive(Clone, Debug)]
pub struct Forcing<'a> {
    /// B (N × m).
    pub b: MatRef<'a, f64>,
    /// ∂B/∂P_i, one N × m matrix per parameter (empty: B does not depend on P).
    pub db: Vec<MatRef<'a, f64>>,
    /// D (p × m), if the outputs feed the input through.
    pub d: Option<MatRef<'a, f64>>,
    /// ∂D/∂P_i, one p × m matrix per parameter, if D depends on P.
    pub dd: Option<Vec<MatRef<'a, f64>>>,
    /// u_k in row k (K × m, K the samples of the response).
    pub u: MatRef<'a, f64>,
    /// How u is held between samples.
    pub hold: Hold,
}

/// One sampled response: ẋ = A x (+ B u), y = C x (+ D u) from x(0) at t = 0, sampled at
/// t_k = t₀ + k·h, with the sensitivities to j parameters. Build with [`ResponseProblem::new`]
/// and the `with_*` methods; [`ResponseProblem::solve_into`] validates and computes.
///
/// ```
/// use faer::mat;
/// use expm::{ResponseProblem, Response};
/// let a = mat![[0.0, 1.0], [-4.0, -0.1]];
/// let da = mat![[0.0, 0.0], [-1.0, 0.0]];
/// let c = mat![[1.0, 0.0]];
/// let x0 = [1.0, 0.0];
/// let mut out = Response::zeros(100, 1, 1);
/// ResponseProblem::new(a.as_ref(), c.as_ref(), &x0, 0.05)
///     .with_parameters(vec![da.as_ref()])
///     .starting_at(0.5) // the first sample is at t = 0.5 s
///     .solve_into(&mut out)
///     .unwrap();
/// ```
#[derive(Clone, Debug)]
pub struct ResponseProblem<'a> {
    a: MatRef<'a, f64>,
    c: MatRef<'a, f64>,
    x0: &'a [f64],
    h: f64,
    da: Vec<MatRef<'a, f64>>,
    dc: Option<Vec<MatRef<'a, f64>>>,
    dx0: Option<MatRef<'a, f64>>,
    forcing: Option<Forcing<'a>>,
    start: f64,
    strategy: Strategy,
}

impl<'a> ResponseProblem<'a> {
    /// A free decay of ẋ = Ax, y = Cx from x(0) = `x0`, sampled every `h` from t = 0.
    pub fn new(a: MatRef<'a, f64>, c: MatRef<'a, f64>, x0: &'a [f64], h: f64) -> Self {
        Self {
            a,
            c,
            x0,
            h,
            da: Vec::new(),
            dc: None,
            dx0: None,
            forcing: None,
            start: 0.0,
            strategy: Strategy::Auto,
        }
    }
    /// The parameter directions ∂A/∂P_i (j of them; each N × N).
    pub fn with_parameters(mut self, da: Vec<MatRef<'a, f64>>) -> Self {
        self.da = da;
        self
    }
    /// ∂C/∂P_i (j of them; each p × N), when C depends on P.
    pub fn with_output_derivatives(mut self, dc: Vec<MatRef<'a, f64>>) -> Self {
        self.dc = Some(dc);
        self
    }
    /// ∂x(0)/∂P (N × j), when x(0) depends on P.
    pub fn with_initial_derivatives(mut self, dx0: MatRef<'a, f64>) -> Self {
        self.dx0 = Some(dx0);
        self
    }
    /// Measured inputs (the model is forced; the input is zero before the first sample).
    pub fn with_inputs(mut self, forcing: Forcing<'a>) -> Self {
        self.forcing = Some(forcing);
        self
    }
    /// The time of the first sample, t₀ ≥ 0 (x(0) holds at t = 0).
    pub fn starting_at(mut self, t0: f64) -> Self {
        self.start = t0;
        self
    }
    /// How a free decay is computed.
    pub fn with_strategy(mut self, strategy: Strategy) -> Self {
        self.strategy = strategy;
        self
    }

    /// Checks every shape and value before anything is computed.
    ///
    /// # Errors
    /// [`ExpmError::Empty`] for a 0×0 A, shape and finiteness errors naming the argument,
    /// [`ExpmError::InvalidInterval`] for h or t₀.
    pub fn validate(&self, n_samples: usize) -> Result<(), ExpmError> {
        let n = check::square("a", self.a)?;
        if n == 0 {
            return Err(ExpmError::Empty { name: "a" });
        }
        check::finite("a", self.a)?;
        if !(self.h.is_finite() && self.h > 0.0) {
            return Err(ExpmError::InvalidInterval { h: self.h });
        }
        if !(self.start.is_finite() && self.start >= 0.0) {
            return Err(ExpmError::InvalidStart { t0: self.start });
        }
        let p = self.c.nrows();
        check::shape("c", self.c, p, n)?;
        check::finite("c", self.c)?;
        let x0 = MatRef::from_column_major_slice(self.x0, self.x0.len(), 1);
        check::shape("x0", x0, n, 1)?;
        check::finite("x0", x0)?;
        let j = self.da.len();
        let each = |name: &'static str, list: &[MatRef<'_, f64>], rows: usize, cols: usize| {
            check::count(name, list.len(), j)?;
            list.iter()
                .try_for_each(|d| check::shape(name, *d, rows, cols).and_then(|()| check::finite(name, *d)))
        };
        each("da", &self.da, n, n)?;
        if let Some(dc) = &self.dc {
            each("dc", dc, p, n)?;
        }
        if let Some(d) = self.dx0 {
            check::shape("dx0", d, n, j)?;
            check::finite("dx0", d)?;
        }
        if let Some(f) = &self.forcing {
            let m = f.b.ncols();
            check::shape("b", f.b, n, m)?;
            check::finite("b", f.b)?;
            if !f.db.is_empty() {
                each("db", &f.db, n, m)?;
            }
            if let Some(d) = f.d {
                check::shape("d", d, p, m)?;
                check::finite("d", d)?;
            }
            if let Some(dd) = &f.dd {
                each("dd", dd, p, m)?;
            }
            check::shape("u", f.u, n_samples, m)?;
            check::finite("u", f.u)?;
        }
        Ok(())
    }

    /// Validates and computes the outputs and sensitivities into `out` (its size sets K).
    ///
    /// # Errors
    /// As [`Self::validate`]; overflow of the exponential; [`ExpmError::NonFiniteResult`] if
    /// the response does not fit in `f64`.
    pub fn solve_into(&self, out: &mut Response) -> Result<Method, ExpmError> {
        let k = out.outputs.nrows();
        self.validate(k)?;
        let (n, j, p) = (self.a.nrows(), self.da.len(), self.c.nrows());
        check::shape("outputs", out.outputs.as_ref(), k, p)?;
        check::shape("sensitivities", out.sensitivities.as_ref(), k * p, j)?;
        // Advance x(0), ∂x(0)/∂P to the first sample (the input is zero before it).
        let advanced = if self.start > 0.0 {
            let s0 = self.dx0.map_or_else(|| Mat::zeros(n, j), |d| d.to_owned());
            Some(discretise::advance(self.a, &self.da, self.x0, s0.as_ref(), self.start)?)
        } else {
            None
        };
        let (x0, dx0): (&[f64], Option<MatRef<'_, f64>>) = match &advanced {
            Some((x, s)) => (x, Some(s.as_ref())),
            None => (self.x0, self.dx0),
        };
        let Some(forcing) = &self.forcing else {
            let try_modal = match self.strategy {
                Strategy::Auto => n >= MODAL_MIN_STATES,
                Strategy::Modal => true,
                Strategy::Propagation => false,
            };
            if try_modal
                && crate::modal::modal_response(
                    self.a,
                    &self.da,
                    self.c,
                    self.dc.as_deref(),
                    x0,
                    dx0,
                    self.h,
                    out,
                )?
            {
                return Ok(Method::Modal);
            }
            let mut prop = SensitivityPropagator::new(self.a, &self.da, self.c, self.h)?;
            if let Some(dc) = &self.dc {
                prop = prop.with_output_derivatives(dc)?;
            }
            prop.propagate_into(x0, dx0, out)?;
            return Ok(Method::Propagation);
        };
        let zeros: Vec<Mat<f64>>;
        let db: Vec<MatRef<'_, f64>> = if forcing.db.is_empty() {
            zeros = (0..j).map(|_| Mat::zeros(n, forcing.b.ncols())).collect();
            zeros.iter().map(|z| z.as_ref()).collect()
        } else {
            forcing.db.clone()
        };
        let mut prop =
            SensitivityPropagator::forced(self.a, &self.da, forcing.b, &db, self.c, self.h, forcing.hold)?;
        if let Some(dc) = &self.dc {
            prop = prop.with_output_derivatives(dc)?;
        }
        if let Some(d) = forcing.d {
            prop = prop.with_feedthrough(d, forcing.dd.as_deref())?;
        }
        prop.propagate_forced_into(x0, dx0, forcing.u, out)?;
        Ok(Method::Propagation)
    }
}

/// Outputs and output sensitivities of ẋ = Ax, y = Cx from x(0) at t_k = k·h (the size of
/// `out` sets K): the MEM's Eq. 9 by the propagator, or — for larger, diagonalisable and
/// well-conditioned A — in modal coordinates at a fraction of the cost (module `modal`).
/// A shorthand for [`ResponseProblem`].
///
/// # Errors
/// As [`ResponseProblem::solve_into`].
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
    let mut problem = ResponseProblem::new(a, c, x0, h).with_parameters(da.to_vec()).with_strategy(strategy);
    if let Some(dc) = dc {
        problem = problem.with_output_derivatives(dc.to_vec());
    }
    if let Some(dx0) = dx0 {
        problem = problem.with_initial_derivatives(dx0);
    }
    problem.solve_into(out)
}
