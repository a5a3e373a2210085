//! The compiled model and its assembly over any scalar.
//!
//! Every entry of the file is compiled once into a [`Coef`]; assembling evaluates the derived
//! names in order, then each matrix entry, into nalgebra matrices of the caller's scalar (f64
//! for values, a num-dual number for exact derivatives), and turns M, D, K, F into first-order
//! form with [`mem::SecondOrder`].

use crate::modal::modal_damping;
use crate::{Expr, StructureError};
use mem::nalgebra::{DMatrix, DVector};
use mem::{Scalar, SecondOrder, StateSpace};

/// The `part` of an [`StructureError::Assembly`] for a singular mass matrix.
pub(crate) const MASS: &str = "the mass matrix M";

/// Why a mass matrix without positive kinetic energy is refused ([`Compiled::positive_mass`]).
pub(crate) const NOT_POSITIVE_MASS: &str = "it is not positive definite (the kinetic energy ½ q̇ᵀ M q̇ would be ≤ 0 for \
    some motion: a mass ≤ 0, or a coupling larger than the masses it joins); check the masses";
/// The `part` of an [`StructureError::Assembly`] for modal damping that cannot be formed.
pub(crate) const MODAL: &str = "the modal damping matrix";

/// A compiled entry: a number, or an expression over all names (parameters, then derived).
#[derive(Clone, Debug)]
pub(crate) enum Coef {
    Num(f64),
    Expr(Expr),
}

impl Coef {
    fn eval<D: Scalar>(&self, values: &[D]) -> D {
        match self {
            Coef::Num(value) => D::from(*value),
            Coef::Expr(expr) => expr.eval(values),
        }
    }
}

/// What one term of an output row measures (indices of coordinates or states).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Quantity {
    Displacement(usize),
    Velocity(usize),
    Acceleration(usize),
    State(usize),
}

/// One output row.
#[derive(Clone, Debug)]
pub(crate) enum OutputRow {
    /// Σ weight × quantity.
    Terms(Vec<(Quantity, Coef)>),
    /// An explicit row of C over the states.
    Row(Vec<Coef>),
}

/// One output: its row of C and, for first-order files, its row of D.
#[derive(Clone, Debug)]
pub(crate) struct CompiledOutput {
    pub row: OutputRow,
    pub feedthrough: Option<Vec<Coef>>,
}

/// How D is built in a second-order model.
#[derive(Clone, Debug)]
pub(crate) enum CompiledDamping {
    /// n × n entries, row-major.
    Matrix(Vec<Coef>),
    /// D = αM + βK.
    Rayleigh(Coef, Coef),
    /// One damping ratio per mode, in order of frequency.
    Modal(Vec<Coef>),
}

/// The dynamics, compiled. Matrices are row-major.
#[derive(Clone, Debug)]
pub(crate) enum Dynamics {
    Second {
        n: usize,
        mass: Vec<Coef>,
        stiffness: Vec<Coef>,
        damping: CompiledDamping,
        /// F (n × m), row-major; empty without inputs.
        forces: Vec<Coef>,
        m: usize,
        q0: Vec<Coef>,
        v0: Vec<Coef>,
    },
    First {
        n: usize,
        a: Vec<Coef>,
        /// B (n × m), row-major; empty without inputs.
        b: Vec<Coef>,
        m: usize,
        x0: Vec<Coef>,
    },
}

/// The whole compiled model.
#[derive(Clone, Debug)]
pub(crate) struct Compiled {
    pub n_params: usize,
    /// `derived[i]` is an expression over the parameters and `derived[..i]`.
    pub derived: Vec<Coef>,
    pub dynamics: Dynamics,
    pub outputs: Vec<CompiledOutput>,
}

fn matrix<D: Scalar>(coefs: &[Coef], rows: usize, cols: usize, values: &[D]) -> DMatrix<D> {
    DMatrix::from_fn(rows, cols, |i, j| coefs[i * cols + j].eval(values))
}

fn vector<D: Scalar>(coefs: &[Coef], values: &[D]) -> Vec<D> {
    coefs.iter().map(|c| c.eval(values)).collect()
}

/// The first non-finite entry of a matrix, as `name[i][j] = value`.
fn non_finite<D: Scalar>(m: &DMatrix<D>, name: &str) -> Option<String> {
    (0..m.nrows()).flat_map(|i| (0..m.ncols()).map(move |j| (i, j))).find_map(|(i, j)| {
        let value = m[(i, j)].re();
        (!value.is_finite()).then(|| format!("{name}[{i}][{j}] = {value}"))
    })
}

impl Compiled {
    /// The values of all names: the parameters, then each derived name in order.
    pub fn values<D: Scalar>(&self, p: &[D]) -> Result<Vec<D>, StructureError> {
        if p.len() != self.n_params {
            return Err(StructureError::ParameterCount { expected: self.n_params, got: p.len() });
        }
        let mut values = Vec::with_capacity(self.n_params + self.derived.len());
        values.extend_from_slice(p);
        for coef in &self.derived {
            let value = coef.eval(&values);
            values.push(value);
        }
        Ok(values)
    }

    /// Whether M at the parameters `p` gives positive kinetic energy ½ q̇ᵀ M q̇ for every motion
    /// (its symmetric part positive definite); `Ok(true)` for a first-order model. A negative
    /// mass, or a coupling larger than the masses it joins, fails; a singular M fails too.
    pub fn positive_mass(&self, p: &[f64]) -> Result<bool, StructureError> {
        let Some(model) = self.second_order_at(&self.values(p)?)? else { return Ok(true) };
        Ok(((&model.m + model.m.transpose()) * 0.5).cholesky().is_some())
    }

    /// M, D, K, F at the given values of all names (`None` for a first-order model).
    pub fn second_order_at<D: Scalar>(&self, values: &[D]) -> Result<Option<SecondOrder<D>>, StructureError> {
        let Dynamics::Second { n, mass, stiffness, damping, forces, m, .. } = &self.dynamics else {
            return Ok(None);
        };
        let n = *n;
        let mass = matrix(mass, n, n, values);
        let stiffness = matrix(stiffness, n, n, values);
        let damping = match damping {
            CompiledDamping::Matrix(entries) => matrix(entries, n, n, values),
            CompiledDamping::Rayleigh(alpha, beta) => {
                &mass * alpha.eval(values) + &stiffness * beta.eval(values)
            }
            CompiledDamping::Modal(ratios) => {
                modal_damping(&mass, &stiffness, &vector(ratios, values)).map_err(|failure| {
                    StructureError::Assembly { part: MODAL.into(), reason: failure.to_string() }
                })?
            }
        };
        let mut model = SecondOrder::new(mass, damping, stiffness);
        if *m > 0 {
            model = model.with_forces(matrix(forces, n, *m, values));
        }
        Ok(Some(model))
    }

    /// A, C, x(0), B, D at the parameter values `p`.
    pub fn state_space<D: Scalar>(&self, p: &[D]) -> Result<StateSpace<D>, StructureError> {
        self.state_space_damped(p, &[])
    }

    /// [`state_space`](Self::state_space) with linear dampers c_j added to D at coordinates j
    /// (`(j, c_j)`, a second-order model's; ignored for a first-order one).
    pub fn state_space_damped<D: Scalar>(
        &self,
        p: &[D],
        dampers: &[(usize, D)],
    ) -> Result<StateSpace<D>, StructureError> {
        let values = self.values(p)?;
        let (a, b, x0, n_coordinates) = match &self.dynamics {
            Dynamics::Second { n, q0, v0, .. } => {
                let mut model = self.second_order_at(&values)?.ok_or_else(|| StructureError::Assembly {
                    part: "the second-order model".into(),
                    reason: "internal inconsistency; please report it".into(),
                })?;
                for &(j, c) in dampers {
                    model.d[(j, j)] += c;
                }
                for (part, m) in [("M", &model.m), ("D", &model.d), ("K", &model.k)] {
                    if let Some(entry) = non_finite(m, part) {
                        return Err(StructureError::Assembly {
                            part: format!("the matrix {part}"),
                            reason: format!("{entry} is not finite"),
                        });
                    }
                }
                let space =
                    model.state_space(&[], &vector(q0, &values), &vector(v0, &values)).map_err(|_| {
                        StructureError::Assembly {
                            part: MASS.into(),
                            reason: "it is singular, so M q̈ = … cannot be solved for q̈; check the masses"
                                .into(),
                        }
                    })?;
                (space.a, space.b, space.x0, Some(*n))
            }
            Dynamics::First { n, a, b, m, x0 } => {
                let a = matrix(a, *n, *n, &values);
                let b = (*m > 0).then(|| matrix(b, *n, *m, &values));
                (a, b, DVector::from_vec(vector(x0, &values)), None)
            }
        };
        let c = self.output_matrix(&a, &values, n_coordinates);
        let d = b.as_ref().map(|b| self.feedthrough_matrix(b, &values, n_coordinates));
        let space = StateSpace { a, c, x0, b, d };
        check_finite(&space)?;
        Ok(space)
    }

    /// The force columns G = [0; −M⁻¹e_j] of unit forces at the coordinates `columns`, and
    /// the acceleration outputs' share H of them (second order only).
    pub fn force_columns<D: Scalar>(
        &self,
        values: &[D],
        columns: &[usize],
    ) -> Result<(DMatrix<D>, DMatrix<D>), StructureError> {
        let Some(model) = self.second_order_at(values)? else {
            return Err(StructureError::Assembly {
                part: "the force columns".into(),
                reason: "forces at coordinates need a second-order model".into(),
            });
        };
        let n = model.m.nrows();
        let mut f = DMatrix::from_element(n, columns.len(), D::zero());
        for (k, &j) in columns.iter().enumerate() {
            f[(j, k)] = D::from(-1.0);
        }
        let zeros = vec![D::zero(); n];
        let space = model.with_forces(f).state_space(&[], &zeros, &zeros).map_err(|_| {
            StructureError::Assembly { part: MASS.into(), reason: "it is singular; check the masses".into() }
        })?;
        let g = space.b.expect("a model with forces has B");
        let h = self.acceleration_share(&g, values, n);
        Ok((g, h))
    }

    /// C: each output's row (second order: accelerations are rows of the lower half of A).
    fn output_matrix<D: Scalar>(
        &self,
        a: &DMatrix<D>,
        values: &[D],
        n_coordinates: Option<usize>,
    ) -> DMatrix<D> {
        let n_states = a.nrows();
        let half = n_coordinates.unwrap_or(0);
        let mut c = DMatrix::from_element(self.outputs.len(), n_states, D::zero());
        for (row, output) in self.outputs.iter().enumerate() {
            match &output.row {
                OutputRow::Row(entries) => {
                    for (col, entry) in entries.iter().enumerate() {
                        c[(row, col)] = entry.eval(values);
                    }
                }
                OutputRow::Terms(terms) => {
                    for (quantity, weight) in terms {
                        let w = weight.eval(values);
                        match *quantity {
                            Quantity::Displacement(i) | Quantity::State(i) => c[(row, i)] += w,
                            Quantity::Velocity(i) => c[(row, half + i)] += w,
                            Quantity::Acceleration(i) => {
                                for col in 0..n_states {
                                    c[(row, col)] += w * a[(half + i, col)];
                                }
                            }
                        }
                    }
                }
            }
        }
        c
    }

    /// D: the accelerations' feedthrough (second order) or the declared feedthrough rows.
    fn feedthrough_matrix<D: Scalar>(
        &self,
        b: &DMatrix<D>,
        values: &[D],
        n_coordinates: Option<usize>,
    ) -> DMatrix<D> {
        let mut d = self.acceleration_share(b, values, n_coordinates.unwrap_or(0));
        for (row, output) in self.outputs.iter().enumerate() {
            if let Some(entries) = &output.feedthrough {
                for (col, entry) in entries.iter().enumerate() {
                    d[(row, col)] = entry.eval(values);
                }
            }
        }
        d
    }
}

impl Compiled {
    /// The acceleration outputs' share of the columns `b` of the state equation: Σ w·b[n + i].
    pub(crate) fn acceleration_share<D: Scalar>(
        &self,
        b: &DMatrix<D>,
        values: &[D],
        half: usize,
    ) -> DMatrix<D> {
        let m = b.ncols();
        let mut d = DMatrix::from_element(self.outputs.len(), m, D::zero());
        for (row, output) in self.outputs.iter().enumerate() {
            if let OutputRow::Terms(terms) = &output.row {
                for (quantity, weight) in terms {
                    if let Quantity::Acceleration(i) = *quantity {
                        let w = weight.eval(values);
                        for col in 0..m {
                            d[(row, col)] += w * b[(half + i, col)];
                        }
                    }
                }
            }
        }
        d
    }
}

fn check_finite<D: Scalar>(space: &StateSpace<D>) -> Result<(), StructureError> {
    let x0 = DMatrix::from_column_slice(space.x0.len(), 1, space.x0.as_slice());
    let parts = [
        ("A", Some(&space.a)),
        ("C", Some(&space.c)),
        ("x(0)", Some(&x0)),
        ("B", space.b.as_ref()),
        ("D", space.d.as_ref()),
    ];
    for (name, matrix) in parts {
        if let Some(entry) = matrix.and_then(|m| non_finite(m, name)) {
            return Err(StructureError::Assembly {
                part: format!("the matrix {name}"),
                reason: format!("{entry} is not finite; check the expressions and the parameter values"),
            });
        }
    }
    Ok(())
}
