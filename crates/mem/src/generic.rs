//! Models written once, generic over the scalar: exact derivatives by num-dual.
//!
//! A [`StateSpaceModel`] gives A(P), C(P), x(0)(P) (and B, D for inputs) for any scalar type
//! D — f64 for values, `num_dual::Dual64` for derivatives. [`Exact`] evaluates it once in f64
//! and once per parameter in dual numbers seeded with ε = 1 on that parameter, so that
//! ∂A/∂P_i, ∂C/∂P_i, ∂x(0)/∂P_i, ∂B/∂P_i and ∂D/∂P_i come from the very code that defines the
//! model: nothing is differentiated by hand. [`SecondOrder`] turns M q̈ + D q̇ + K q = F u into
//! first-order form for any scalar (A = [[0, I], [−M⁻¹K, −M⁻¹D]] by one LU of M, no inverse),
//! with displacement, velocity and acceleration outputs.

use crate::error::BoxedError;
use crate::model::{InconsistentModel, LinearModel, Linearized};
use faer::Mat;
use nalgebra::{DMatrix, DVector, RealField};
use num_dual::{Dual64, DualNum};

/// The scalar a generic model is written over (f64, or a num-dual number carrying derivatives).
pub trait Scalar: DualNum<Primitive = f64> + RealField + Copy {}
impl<T: DualNum<Primitive = f64> + RealField + Copy> Scalar for T {}

/// The matrices of a linear model at one P, in scalar type D.
#[derive(Clone, Debug)]
pub struct StateSpace<D: Scalar> {
    /// A (N × N).
    pub a: DMatrix<D>,
    /// C (p × N).
    pub c: DMatrix<D>,
    /// x(0) (N).
    pub x0: DVector<D>,
    /// B (N × m), for a model with inputs.
    pub b: Option<DMatrix<D>>,
    /// D (p × m), the direct feedthrough of the inputs.
    pub d: Option<DMatrix<D>>,
}

/// A linear model written once for any scalar: `state_space::<f64>` gives its values,
/// `state_space::<Dual64>` its exact derivatives (see [`Exact`]).
pub trait StateSpaceModel {
    /// The parameters' names, in the order of P.
    fn parameter_names(&self) -> Vec<String>;
    /// The outputs' names (CSV column names).
    fn output_names(&self) -> Vec<String>;
    /// The inputs' names (none for a free decay).
    fn input_names(&self) -> Vec<String> {
        Vec::new()
    }
    /// A, C, x(0) (and B, D) at P.
    ///
    /// # Errors
    /// Whatever makes the model impossible at P.
    fn state_space<D: Scalar>(&self, p: &[D]) -> Result<StateSpace<D>, BoxedError>;
}

/// A [`StateSpaceModel`] as a [`LinearModel`] with exact derivatives (one evaluation in f64 and
/// one in dual numbers per parameter); wrap it in [`crate::LinearResponse`] to fit it.
#[derive(Clone, Debug)]
pub struct Exact<M>(pub M);

fn to_faer<D: Scalar>(m: &DMatrix<D>, part: impl Fn(&D) -> f64) -> Mat<f64> {
    Mat::from_fn(m.nrows(), m.ncols(), |i, j| part(&m[(i, j)]))
}

fn shape_of<D: Scalar>(m: &DMatrix<D>) -> (usize, usize) {
    (m.nrows(), m.ncols())
}

impl<M: StateSpaceModel> LinearModel for Exact<M> {
    type Error = ExactError;
    fn n_states(&self) -> usize {
        self.0.state_space::<f64>(&vec![0.0; self.n_params()]).map_or(0, |s| s.a.nrows())
    }
    fn n_params(&self) -> usize {
        self.0.parameter_names().len()
    }
    fn output_names(&self) -> Vec<String> {
        self.0.output_names()
    }
    fn input_names(&self) -> Vec<String> {
        self.0.input_names()
    }
    fn linearize(&self, p: &[f64]) -> Result<Linearized, ExactError> {
        let values = self.0.state_space::<f64>(p).map_err(ExactError::Model)?;
        check_shapes(&values, self.0.output_names().len(), self.0.input_names().len())?;
        let n = values.a.nrows();
        let j = p.len();
        let mut lin = Linearized::new(
            to_faer(&values.a, |v| *v),
            Vec::with_capacity(j),
            to_faer(&values.c, |v| *v),
            values.x0.iter().copied().collect(),
        );
        lin.b = values.b.as_ref().map(|b| to_faer(b, |v| *v));
        lin.d = values.d.as_ref().map(|d| to_faer(d, |v| *v));
        let mut dc = Vec::with_capacity(j);
        let mut db = Vec::with_capacity(j);
        let mut dd = Vec::with_capacity(j);
        let mut dx0 = Mat::<f64>::zeros(n, j);
        for i in 0..j {
            let seeded: Vec<Dual64> =
                p.iter().enumerate().map(|(l, v)| Dual64::new(*v, if l == i { 1.0 } else { 0.0 })).collect();
            let dual = self.0.state_space::<Dual64>(&seeded).map_err(ExactError::Model)?;
            let eps = |d: &Dual64| d.eps;
            if shape_of(&dual.a) != shape_of(&values.a) || shape_of(&dual.c) != shape_of(&values.c) {
                return Err(ExactError::Inconsistent(InconsistentModel(
                    "state_space returns matrices of other shapes for dual numbers than for f64".into(),
                )));
            }
            lin.da.push(to_faer(&dual.a, eps));
            dc.push(to_faer(&dual.c, eps));
            for r in 0..n {
                dx0[(r, i)] = dual.x0[r].eps;
            }
            if let Some(b) = &dual.b {
                db.push(to_faer(b, eps));
            }
            if let Some(d) = &dual.d {
                dd.push(to_faer(d, eps));
            }
        }
        let any = |list: &Vec<Mat<f64>>| list.iter().any(|m| m.norm_max() > 0.0);
        lin.dc = any(&dc).then_some(dc);
        lin.dx0 = (dx0.norm_max() > 0.0).then_some(dx0);
        lin.db = (lin.b.is_some() && any(&db)).then_some(db);
        lin.dd = (lin.d.is_some() && any(&dd)).then_some(dd);
        Ok(lin)
    }
}

fn check_shapes<D: Scalar>(s: &StateSpace<D>, p: usize, m: usize) -> Result<(), ExactError> {
    let n = s.a.nrows();
    let bad = |what: String| Err(ExactError::Inconsistent(InconsistentModel(what)));
    if s.a.ncols() != n || n == 0 {
        return bad(format!("A is {}×{}; it must be square and not empty", s.a.nrows(), s.a.ncols()));
    }
    if shape_of(&s.c) != (p, n) {
        return bad(format!(
            "C is {}×{}, but there are {p} outputs and {n} states",
            s.c.nrows(),
            s.c.ncols()
        ));
    }
    if s.x0.len() != n {
        return bad(format!("x(0) has {} entries for {n} states", s.x0.len()));
    }
    match (&s.b, m) {
        (None, 0) => {}
        (Some(b), m) if m > 0 && shape_of(b) == (n, m) => {}
        (b, m) => {
            return bad(format!(
                "B is {} but the model declares {m} inputs",
                b.as_ref().map_or("absent".to_string(), |b| format!("{}×{}", b.nrows(), b.ncols()))
            ));
        }
    }
    if let Some(d) = &s.d
        && shape_of(d) != (p, m)
    {
        return bad(format!("D is {}×{}, but there are {p} outputs and {m} inputs", d.nrows(), d.ncols()));
    }
    Ok(())
}

/// Failures of an [`Exact`] model.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ExactError {
    /// The model's own error.
    #[error(transparent)]
    Model(BoxedError),
    /// Matrices of the wrong shapes.
    #[error(transparent)]
    Inconsistent(#[from] InconsistentModel),
}

/// What an output of a second-order model measures at one coordinate.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Quantity {
    /// q_i.
    Displacement(usize),
    /// q̇_i.
    Velocity(usize),
    /// q̈_i = [M⁻¹(F u − D q̇ − K q)]_i: depends on the parameters through M⁻¹, and on the
    /// input directly.
    Acceleration(usize),
}

/// M q̈ + D q̇ + K q = F u, for any scalar.
#[derive(Clone, Debug)]
pub struct SecondOrder<D: Scalar> {
    /// Mass matrix M (n × n).
    pub m: DMatrix<D>,
    /// Damping matrix D.
    pub d: DMatrix<D>,
    /// Stiffness matrix K.
    pub k: DMatrix<D>,
    /// Input matrix F (n × m), if the structure is forced.
    pub f: Option<DMatrix<D>>,
}

/// The mass matrix cannot be factored.
#[derive(Debug, thiserror::Error)]
#[error("the mass matrix is singular (or not square): M q̈ cannot be solved for q̈")]
pub struct SingularMass;

impl<D: Scalar> SecondOrder<D> {
    /// M q̈ + D q̇ + K q = 0.
    pub fn new(m: DMatrix<D>, d: DMatrix<D>, k: DMatrix<D>) -> Self {
        Self { m, d, k, f: None }
    }

    /// Adds the input matrix F (n × m).
    pub fn with_forces(mut self, f: DMatrix<D>) -> Self {
        self.f = Some(f);
        self
    }

    /// The number of coordinates n.
    pub fn n_coordinates(&self) -> usize {
        self.m.nrows()
    }

    /// [−M⁻¹K, −M⁻¹D] (n × 2n) and M⁻¹F (n × m): the lower half of A and of B.
    fn solved(&self) -> Result<(DMatrix<D>, Option<DMatrix<D>>), SingularMass> {
        let n = self.n_coordinates();
        if self.m.ncols() != n || shape_of(&self.k) != (n, n) || shape_of(&self.d) != (n, n) {
            return Err(SingularMass);
        }
        let lu = self.m.clone().lu();
        let mut kd = DMatrix::from_element(n, 2 * n, D::zero());
        kd.view_mut((0, 0), (n, n)).copy_from(&self.k);
        kd.view_mut((0, n), (n, n)).copy_from(&self.d);
        let lower = -lu.solve(&kd).ok_or(SingularMass)?;
        let forces = match &self.f {
            Some(f) => Some(lu.solve(f).ok_or(SingularMass)?),
            None => None,
        };
        if lower.iter().any(|v| !num_dual::DualStruct::re(v).is_finite()) {
            return Err(SingularMass);
        }
        Ok((lower, forces))
    }

    /// The first-order model for x = [q; q̇] with the given outputs and initial displacement
    /// and velocity.
    ///
    /// # Errors
    /// [`SingularMass`] if M cannot be factored.
    pub fn state_space(
        &self,
        outputs: &[Quantity],
        q0: &[D],
        v0: &[D],
    ) -> Result<StateSpace<D>, SingularMass> {
        let n = self.n_coordinates();
        let (lower, forces) = self.solved()?;
        let mut a = DMatrix::from_element(2 * n, 2 * n, D::zero());
        for i in 0..n {
            a[(i, n + i)] = D::one();
        }
        a.view_mut((n, 0), (n, 2 * n)).copy_from(&lower);
        let m_inputs = forces.as_ref().map_or(0, |f| f.ncols());
        let b = forces.as_ref().map(|f| {
            let mut b = DMatrix::from_element(2 * n, m_inputs, D::zero());
            b.view_mut((n, 0), (n, m_inputs)).copy_from(f);
            b
        });
        let p = outputs.len();
        let mut c = DMatrix::from_element(p, 2 * n, D::zero());
        let mut d = forces.as_ref().map(|_| DMatrix::from_element(p, m_inputs, D::zero()));
        for (row, q) in outputs.iter().enumerate() {
            match *q {
                Quantity::Displacement(i) => c[(row, i)] = D::one(),
                Quantity::Velocity(i) => c[(row, n + i)] = D::one(),
                Quantity::Acceleration(i) => {
                    for col in 0..2 * n {
                        c[(row, col)] = lower[(i, col)];
                    }
                    if let (Some(d), Some(f)) = (d.as_mut(), forces.as_ref()) {
                        for col in 0..m_inputs {
                            d[(row, col)] = f[(i, col)];
                        }
                    }
                }
            }
        }
        let x0 = DVector::from_iterator(2 * n, q0.iter().chain(v0).copied());
        Ok(StateSpace { a, c, x0, b, d })
    }
}
