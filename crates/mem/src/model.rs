//! What a model must provide: the general response trait and the linear capability trait.

use crate::data::Inputs;
use crate::error::BoxedError;
use expm::Response;
use faer::Mat;

/// The sample grid a model is asked to respond on: t_k = start + k·interval (k < the rows of
/// the response), with the measured inputs on the same grid.
#[derive(Clone, Copy, Debug)]
pub struct Grid<'a> {
    /// Time of the first sample after the model's t = 0 (where its initial state holds).
    pub start: f64,
    /// Sample interval.
    pub interval: f64,
    /// Measured inputs u_k (one row per sample), for a forced model.
    pub inputs: Option<&'a Inputs>,
}

impl Grid<'_> {
    /// A free-decay grid from t = 0.
    pub fn free(interval: f64) -> Grid<'static> {
        Grid { start: 0.0, interval, inputs: None }
    }
}

/// Anything that can produce outputs and output sensitivities at K uniform samples:
/// the interface the [`crate::Fit`] iteration works through.
pub trait ResponseModel {
    /// Number of parameters j.
    fn n_params(&self) -> usize;
    /// Output names, in the order of the response's columns (compared with the data's).
    fn output_names(&self) -> Vec<String>;
    /// Names of the inputs that drive the model (none for a free decay).
    fn input_names(&self) -> Vec<String> {
        Vec::new()
    }
    /// Fills `out` (its size sets K) with y(t_k) and ∂y(t_k)/∂P on `grid`.
    ///
    /// # Errors
    /// The model's failure, boxed.
    fn respond(&self, p: &[f64], grid: &Grid<'_>, out: &mut Response) -> Result<(), BoxedError>;
    /// Fills only `out.outputs` (`out` has no sensitivity columns): the cost of a trial point
    /// the iteration may reject. The outputs must be those [`ResponseModel::respond`] gives,
    /// bit for bit, so that accepting a trial does not depend on which was called. The
    /// default calls `respond` and keeps the outputs; a model that can skip its sensitivities
    /// overrides it.
    ///
    /// # Errors
    /// The model's failure, boxed.
    fn respond_outputs(&self, p: &[f64], grid: &Grid<'_>, out: &mut Response) -> Result<(), BoxedError> {
        let mut full = Response::zeros(out.outputs.nrows(), out.outputs.ncols(), self.n_params());
        self.respond(p, grid, &mut full)?;
        out.outputs.copy_from(&full.outputs);
        Ok(())
    }
    /// Relative accuracy of the outputs and sensitivities (the derivative check's step and
    /// tolerance follow from it): about 1e-13 for the exponential, the tolerance of an ODE solver.
    fn accuracy(&self) -> f64 {
        1e-12
    }
    /// The largest real part of the eigenvalues of the (linearised) dynamics at P, if known:
    /// a positive value means the model is unstable.
    fn growth_rate(&self, p: &[f64]) -> Option<f64> {
        let _ = p;
        None
    }
}

/// A linear state-space model at one parameter vector P: everything the MEM needs.
#[derive(Clone, Debug)]
pub struct Linearized {
    /// A(P), N × N.
    pub a: Mat<f64>,
    /// ∂A/∂P_i, one N × N matrix per parameter.
    pub da: Vec<Mat<f64>>,
    /// C(P), p × N.
    pub c: Mat<f64>,
    /// ∂C/∂P_i if C depends on P (the paper assumes it does not, Eq. 6–7).
    pub dc: Option<Vec<Mat<f64>>>,
    /// x(0), length N.
    pub x0: Vec<f64>,
    /// ∂x(0)/∂P, N × j, if x(0) depends on P (the paper assumes it does not, Eq. 10).
    pub dx0: Option<Mat<f64>>,
    /// B(P), N × m, for a model driven by measured inputs.
    pub b: Option<Mat<f64>>,
    /// ∂B/∂P_i, one N × m matrix per parameter, if B depends on P.
    pub db: Option<Vec<Mat<f64>>>,
    /// D(P), p × m: direct feedthrough of the inputs (e.g. accelerations of a forced structure).
    pub d: Option<Mat<f64>>,
    /// ∂D/∂P_i, if D depends on P.
    pub dd: Option<Vec<Mat<f64>>>,
}

impl Linearized {
    /// A free-decay model: A, ∂A/∂P_i, C and x(0) (add the optional parts through the fields).
    pub fn new(a: Mat<f64>, da: Vec<Mat<f64>>, c: Mat<f64>, x0: Vec<f64>) -> Self {
        Self { a, da, c, dc: None, x0, dx0: None, b: None, db: None, d: None, dd: None }
    }
}

/// A parameterised family of linear models ẋ = A(P)x (+ B(P)u), y = C(P)x (+ D(P)u) from
/// x(0) (paper Eqs. 1–2).
///
/// Implement this for your own model to tune it with [`crate::Fit`] (or write the model once,
/// generic over the scalar, with [`crate::StateSpaceModel`] and let num-dual give the
/// derivatives); wrap it in [`LinearResponse`] to use it as a [`ResponseModel`].
pub trait LinearModel {
    /// The model's own error type.
    type Error: std::error::Error + Send + Sync + 'static;
    /// Number of states N.
    fn n_states(&self) -> usize;
    /// Number of parameters j.
    fn n_params(&self) -> usize;
    /// Output names (compared with the data's columns).
    fn output_names(&self) -> Vec<String>;
    /// Input names (none for a free decay).
    fn input_names(&self) -> Vec<String> {
        Vec::new()
    }
    /// A, ∂A/∂P_i, C, x(0) (and optionally ∂C/∂P_i, ∂x(0)/∂P_i, B, D and theirs) at P.
    ///
    /// # Errors
    /// Whatever makes the model impossible at P (e.g. a negative inertia).
    fn linearize(&self, p: &[f64]) -> Result<Linearized, Self::Error>;
}

/// The model's structural mistakes, found when its matrices are checked against its own
/// declaration (counts of derivatives, shapes).
#[derive(Debug, thiserror::Error)]
#[error("the model's linearization is inconsistent: {0}")]
pub struct InconsistentModel(pub String);

/// The MEM for a [`LinearModel`]: one exponential and its Fréchet derivatives per evaluation,
/// then the sensitivity propagator (paper Eq. 9 at constant h) — or, for larger
/// well-conditioned free decays, the same quantities in modal coordinates.
#[derive(Clone, Debug)]
pub struct LinearResponse<M>(pub M);

/// Checks the counts of the derivative lists against the declared number of parameters.
fn check_counts(lin: &Linearized, j: usize) -> Result<(), InconsistentModel> {
    let count = |what: &str, len: usize| {
        if len == j {
            Ok(())
        } else {
            Err(InconsistentModel(format!("linearize returned {len} {what}, but n_params() is {j}")))
        }
    };
    count("∂A/∂P", lin.da.len())?;
    if let Some(dc) = &lin.dc {
        count("∂C/∂P", dc.len())?;
    }
    if let Some(dx0) = &lin.dx0
        && dx0.ncols() != j
    {
        return Err(InconsistentModel(format!(
            "linearize returned ∂x(0)/∂P with {} columns, but n_params() is {j}",
            dx0.ncols()
        )));
    }
    if let Some(db) = &lin.db {
        count("∂B/∂P", db.len())?;
    }
    if let Some(dd) = &lin.dd {
        count("∂D/∂P", dd.len())?;
    }
    Ok(())
}

impl<M: LinearModel> LinearResponse<M> {
    /// Outputs and sensitivities of the linearization on `grid`.
    fn solve(&self, lin: &Linearized, grid: &Grid<'_>, out: &mut Response) -> Result<(), BoxedError> {
        check_counts(lin, self.0.n_params())?;
        fn refs(list: &[Mat<f64>]) -> Vec<faer::MatRef<'_, f64>> {
            list.iter().map(|d| d.as_ref()).collect()
        }
        let mut problem = expm::ResponseProblem::new(lin.a.as_ref(), lin.c.as_ref(), &lin.x0, grid.interval)
            .with_parameters(refs(&lin.da))
            .starting_at(grid.start);
        if let Some(dc) = &lin.dc {
            problem = problem.with_output_derivatives(refs(dc));
        }
        if let Some(dx0) = &lin.dx0 {
            problem = problem.with_initial_derivatives(dx0.as_ref());
        }
        match (&lin.b, grid.inputs) {
            (Some(b), Some(inputs)) => {
                problem = problem.with_inputs(expm::Forcing {
                    b: b.as_ref(),
                    db: lin.db.as_deref().map(refs).unwrap_or_default(),
                    d: lin.d.as_ref().map(|d| d.as_ref()),
                    dd: lin.dd.as_deref().map(refs),
                    u: inputs.values().as_ref(),
                    hold: inputs.hold(),
                });
            }
            (Some(_), None) => {
                return Err(
                    InconsistentModel("the model has inputs (B) but the data carry none".into()).into()
                );
            }
            (None, Some(_)) => {
                return Err(InconsistentModel("the data carry inputs but the model has no B".into()).into());
            }
            (None, None) => {}
        }
        problem.solve_into(out)?;
        Ok(())
    }
}

impl<M: LinearModel> ResponseModel for LinearResponse<M> {
    fn n_params(&self) -> usize {
        self.0.n_params()
    }
    fn output_names(&self) -> Vec<String> {
        self.0.output_names()
    }
    fn input_names(&self) -> Vec<String> {
        self.0.input_names()
    }
    fn respond(&self, p: &[f64], grid: &Grid<'_>, out: &mut Response) -> Result<(), BoxedError> {
        let lin = self.0.linearize(p)?;
        self.solve(&lin, grid, out)
    }
    fn accuracy(&self) -> f64 {
        1e-13
    }
    fn growth_rate(&self, p: &[f64]) -> Option<f64> {
        let lin = self.0.linearize(p).ok()?;
        growth_rate(&lin.a)
    }
}

/// The largest real part of the eigenvalues of A (None if they cannot be computed).
pub fn growth_rate(a: &Mat<f64>) -> Option<f64> {
    if a.nrows() == 0 || !a.as_ref().is_all_finite() {
        return None;
    }
    let eigenvalues = a.eigenvalues().ok()?;
    eigenvalues.iter().map(|l| l.re).reduce(f64::max)
}

/// The residual of an interval reading: the distance of the model's output from
/// [y − half_width, y + half_width], signed, for the plain residual `r` = y − ŷ (0 inside;
/// `r` itself for an exact reading, half_width = 0). See [`crate::Experiment::with_quantization`].
pub fn interval_residual(r: f64, half_width: f64) -> f64 {
    r - r.clamp(-half_width, half_width)
}
