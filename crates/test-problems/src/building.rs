//! The three-storey shear building of `fixtures/shear_building.ron`, twice: once generic over the
//! scalar ([`ShearBuilding`]) and once with hand-derived sensitivities ([`HandDerivedBuilding`]).

use faer::Mat;

/// The three-storey shear building of `fixtures/shear_building.ron`, written once for any
/// scalar (`mem::StateSpaceModel`): masses m_i (fixed at 1000 kg unless `free_masses`),
/// storey stiffnesses k1..k3, Rayleigh damping D = αM + βK, q(0) = [0.01, 0.02, 0.03] m at rest.
/// P = [k1, k2, k3, α, β], or [m1, m2, m3, k1, k2, k3, α, β] with free masses.
#[derive(Clone, Debug)]
pub struct ShearBuilding {
    /// What each output measures.
    pub outputs: Vec<mem::Quantity>,
    /// Whether the masses are parameters.
    pub free_masses: bool,
}

impl ShearBuilding {
    /// Nominal values of k1, k2, k3, α, β.
    pub const NOMINAL: [f64; 5] = [2.5e6, 2.25e6, 1.875e6, 0.375, 1.25e-3];

    /// Displacements of floors 1 and 3 (the fixture's outputs), masses fixed.
    pub fn displacements() -> Self {
        Self {
            outputs: vec![mem::Quantity::Displacement(0), mem::Quantity::Displacement(2)],
            free_masses: false,
        }
    }

    /// Accelerations of the three floors, masses fixed.
    pub fn accelerations() -> Self {
        Self { outputs: (0..3).map(mem::Quantity::Acceleration).collect(), free_masses: false }
    }
}

impl mem::StateSpaceModel for ShearBuilding {
    fn parameter_names(&self) -> Vec<String> {
        let core = ["k1", "k2", "k3", "alpha", "beta"];
        let masses = if self.free_masses { vec!["m1", "m2", "m3"] } else { Vec::new() };
        masses.into_iter().chain(core).map(String::from).collect()
    }
    fn output_names(&self) -> Vec<String> {
        self.outputs
            .iter()
            .map(|q| match q {
                mem::Quantity::Displacement(i) => format!("q{}", i + 1),
                mem::Quantity::Velocity(i) => format!("v{}", i + 1),
                mem::Quantity::Acceleration(i) => format!("a{}", i + 1),
            })
            .collect()
    }
    fn state_space<D: mem::Scalar>(&self, p: &[D]) -> Result<mem::StateSpace<D>, mem::BoxedError> {
        use mem::nalgebra::DMatrix;
        let (masses, rest) =
            if self.free_masses { ([p[0], p[1], p[2]], &p[3..]) } else { ([D::from(1000.0); 3], p) };
        let (k1, k2, k3, alpha, beta, z) = (rest[0], rest[1], rest[2], rest[3], rest[4], D::from(0.0));
        let m = DMatrix::from_diagonal(&mem::nalgebra::DVector::from_row_slice(&masses));
        let k = DMatrix::from_row_slice(3, 3, &[k1 + k2, -k2, z, -k2, k2 + k3, -k3, z, -k3, k3]);
        let d = &m * alpha + &k * beta;
        let q0 = [0.01, 0.02, 0.03].map(D::from);
        Ok(mem::SecondOrder::new(m, d, k).state_space(&self.outputs, &q0, &[z; 3])?)
    }
}

/// The same building with its derivatives written by hand (P = [k1, k2, k3, α, β], outputs
/// q1 and q3), optionally with a sign error in ∂A/∂k1 — the mistake the derivative check must catch.
#[derive(Clone, Debug)]
pub struct HandDerivedBuilding {
    /// Flip the sign of ∂A/∂k1.
    pub sign_error: bool,
}

impl mem::LinearModel for HandDerivedBuilding {
    type Error = std::convert::Infallible;
    fn n_states(&self) -> usize {
        6
    }
    fn n_params(&self) -> usize {
        5
    }
    fn output_names(&self) -> Vec<String> {
        vec!["q1".into(), "q3".into()]
    }
    fn linearize(&self, p: &[f64]) -> Result<mem::Linearized, Self::Error> {
        let m = 1000.0;
        let (k1, k2, k3, alpha, beta) = (p[0], p[1], p[2], p[3], p[4]);
        let k = |a: f64, b: f64, c: f64| faer::mat![[a + b, -b, 0.0], [-b, b + c, -c], [0.0, -c, c]];
        let stiffness = k(k1, k2, k3);
        let first_order = |kk: &Mat<f64>, dd: &Mat<f64>, identity: bool| {
            let mut a = Mat::<f64>::zeros(6, 6);
            for i in 0..3 {
                if identity {
                    a[(i, 3 + i)] = 1.0;
                }
                for j in 0..3 {
                    a[(3 + i, j)] = -kk[(i, j)] / m;
                    a[(3 + i, 3 + j)] = -dd[(i, j)] / m;
                }
            }
            a
        };
        let damping = Mat::<f64>::identity(3, 3) * faer::Scale(alpha * m) + &stiffness * faer::Scale(beta);
        let a = first_order(&stiffness, &damping, true);
        let dk = [k(1.0, 0.0, 0.0), k(0.0, 1.0, 0.0), k(0.0, 0.0, 1.0)];
        let mut da: Vec<Mat<f64>> =
            dk.iter().map(|d| first_order(d, &(d * faer::Scale(beta)), false)).collect();
        if self.sign_error {
            da[0] = &da[0] * faer::Scale(-1.0);
        }
        da.push(first_order(&Mat::zeros(3, 3), &(Mat::<f64>::identity(3, 3) * faer::Scale(m)), false));
        da.push(first_order(&Mat::zeros(3, 3), &stiffness, false));
        let mut c = Mat::<f64>::zeros(2, 6);
        c[(0, 0)] = 1.0;
        c[(1, 2)] = 1.0;
        Ok(mem::Linearized::new(a, da, c, vec![0.01, 0.02, 0.03, 0.0, 0.0, 0.0]))
    }
}
