//! Exact derivatives: `state_space::<Dual64>` seeded on each parameter against central
//! differences of `state_space::<f64>`, for the fixtures, for a file that uses modal damping,
//! derived names, combinations and parameter-valued initial states, and for a first-order file.

use crate::common::{check_derivatives, fixture};
use approx::assert_relative_eq;
use mem::nalgebra::DMatrix;
use num_dual::Dual64;
use structure::StructureModel;

/// A building with a coupled (non-diagonal) mass matrix, modal damping, derived stiffnesses,
/// combined outputs, a force input with an expression and an initial state made of parameters.
const MODAL: &str = r#"
// Modal damping, derived names, combinations, parameter-valued initial state.
(
    name: "Modal test building",
    parameters: {
        "m": (value: 1000, unit: "kg", free: true, bounds: (1, 1e6)),
        "mc": (value: 50, unit: "kg", free: true),
        "k": (value: 2e6, unit: "N/m", free: true, bounds: (0, 1e10), typical: 1e6),
        "ratio": (value: 0.8, free: true),
        "z1": (value: 0.02, free: true, bounds: (0, 1)),
        "z2": (value: 0.03, free: true),
        "z3": (value: 0.05, free: true),
        "q10": (value: 0.01, unit: "m", free: true),
    },
    derived: [("k2", "ratio*k"), ("k3", "ratio*k2"), ("m3", "m/2")],
    structure: SecondOrder(
        coordinates: ["q1", "q2", "q3"],
        mass: [["m", "mc", 0], ["mc", "m", 0], [0, 0, "m3"]],
        stiffness: [["k + k2", "-k2", 0], ["-k2", "k2 + k3", "-k3"], [0, "-k3", "k3"]],
        damping: Modal(["z1", "z2", "z3"]),
        inputs: [(name: "u", unit: "N", force: [0, 0, "m3/m"])],
    ),
    hold: FirstOrder,
    outputs: [
        (column: "drift", measures: Combination([(Displacement("q2"), 1), (Displacement("q1"), -1)])),
        (column: "mix", measures: Combination([(Acceleration("q3"), "m3/m"), (Velocity("q1"), 2)])),
        (column: "a2", measures: Acceleration("q2")),
    ],
    initial: (displacement: ["q10", "2*q10", 0], velocity: [0, "10*q10", 0]),
)
"#;

/// A two-state oscillator written in first-order form.
const FIRST_ORDER: &str = r#"
(
    name: "Two-state oscillator",
    parameters: {
        "k": (value: 40, unit: "1/s^2", free: true),
        "c": (value: 0.8, unit: "1/s", free: true),
        "g": (value: 0.5, free: true),
        "b2": (value: 2, free: true),
        "d": (value: 0.1, free: true),
        "x10": (value: 1, free: true),
    },
    structure: FirstOrder(
        states: ["x1", "x2"],
        a: [[0, 1], ["-k", "-c"]],
        b: [[0], ["b2"]],
        inputs: [(name: "u", unit: "V")],
    ),
    outputs: [
        (column: "y1", measures: State("x1")),
        (column: "y2", measures: Row([1, "g"]), feedthrough: ["d"]),
        (column: "y3", measures: Combination([(State("x2"), "g"), (State("x1"), -1)])),
    ],
    initial: (state: ["x10", "-x10*c"]),
)
"#;

#[test]
fn fixtures_have_exact_derivatives() {
    for name in ["shear_building.ron", "shear_building_acc.ron", "shear_building_forced.ron"] {
        let model = fixture(name);
        let nonzero = check_derivatives(&model, &model.values(), 1e-7);
        assert!(nonzero >= 8, "{name}: every parameter moves A");
        check_derivatives(&model, &[1100.0, 950.0, 1020.0, 2.6e6, 2.2e6, 1.9e6, 0.4, 1.1e-3], 1e-7);
    }
}

#[test]
fn modal_damping_derived_names_and_combinations_have_exact_derivatives() {
    let model = StructureModel::from_ron(MODAL, "modal.ron").unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(model.hold(), mem::Hold::FirstOrder);
    assert_eq!(model.typical("k"), Some(1e6));
    let nonzero = check_derivatives(&model, &model.values(), 1e-7);
    // A and C (accelerations) on the 7 parameters other than q10, x(0) on q10, B and D on m.
    assert_eq!(nonzero, 17);
    check_derivatives(&model, &[1200.0, -30.0, 3e6, 0.7, 0.01, 0.1, 0.2, -0.02], 1e-7);
}

#[test]
fn modal_damping_gives_the_declared_ratios_at_the_generalised_frequencies() {
    let model = StructureModel::from_ron(MODAL, "modal.ron").unwrap();
    let so = model.second_order::<f64>(&model.values()).unwrap().unwrap();
    // Independent: nalgebra's Cholesky and symmetric eigen-solver for K φ = ω² M φ.
    let l = so.m.clone().cholesky().unwrap().l();
    let l_inv = l.clone().try_inverse().unwrap();
    let s = &l_inv * &so.k * l_inv.transpose();
    let eigen = mem::nalgebra::SymmetricEigen::new((&s + s.transpose()) * 0.5);
    let mut omega2: Vec<f64> = eigen.eigenvalues.iter().copied().collect();
    omega2.sort_by(f64::total_cmp);
    let modes = model.modes().unwrap();
    for (i, (mode, zeta)) in modes.iter().zip([0.02, 0.03, 0.05]).enumerate() {
        assert_relative_eq!(
            2.0 * std::f64::consts::PI * mode.frequency_hz,
            omega2[i].sqrt(),
            max_relative = 1e-10
        );
        assert_relative_eq!(mode.damping_ratio, zeta, max_relative = 1e-10);
    }
    // Φᵀ D Φ = diag(2ζω) with the mass-normalised modes Φ = L⁻ᵀ V.
    let mut order: Vec<usize> = (0..3).collect();
    order.sort_by(|&a, &b| eigen.eigenvalues[a].total_cmp(&eigen.eigenvalues[b]));
    let phi = l_inv.transpose() * &eigen.eigenvectors;
    let modal = phi.transpose() * &so.d * &phi;
    for (rank, &i) in order.iter().enumerate() {
        let expected = 2.0 * [0.02, 0.03, 0.05][rank] * eigen.eigenvalues[i].sqrt();
        assert_relative_eq!(modal[(i, i)], expected, max_relative = 1e-10);
        for j in 0..3 {
            if j != i {
                assert!(modal[(i, j)].abs() <= 1e-10 * expected);
            }
        }
    }
}

#[test]
fn modal_damping_is_exact_for_diagonal_and_dual_vector_seeds() {
    // A diagonal M and K (Jacobi starts converged) still gives exact derivatives of D, and a
    // DualSVec64 seeded on all parameters at once agrees with Dual64 seeded one at a time.
    let text = MODAL
        .replace(
            r#"[["m", "mc", 0], ["mc", "m", 0], [0, 0, "m3"]]"#,
            r#"[["m", 0, 0], [0, "m + mc", 0], [0, 0, "m3"]]"#,
        )
        .replace(
            r#"[["k + k2", "-k2", 0], ["-k2", "k2 + k3", "-k3"], [0, "-k3", "k3"]]"#,
            r#"[["k", 0, 0], [0, "k2", 0], [0, 0, "3*k3"]]"#,
        );
    let model = StructureModel::from_ron(&text, "diagonal.ron").unwrap_or_else(|e| panic!("{e}"));
    check_derivatives(&model, &model.values(), 1e-7);
    let p = model.values();
    let n = p.len();
    assert_eq!(n, 8);
    let all: Vec<num_dual::DualSVec64<8>> = (0..n)
        .map(|i| {
            let seed = mem::nalgebra::SVector::<f64, 8>::from_fn(|j, _| f64::from(u8::from(i == j)));
            num_dual::DualSVec64::new(p[i], num_dual::Derivative::some(seed))
        })
        .collect();
    let together = model.second_order(&all).unwrap().unwrap().d;
    for i in 0..n {
        let seeded: Vec<Dual64> = (0..n).map(|l| Dual64::new(p[l], if l == i { 1.0 } else { 0.0 })).collect();
        let single = model.second_order(&seeded).unwrap().unwrap().d;
        for (a, b) in together.iter().zip(single.iter()) {
            let da = a.eps.0.as_ref().map_or(0.0, |v| v[i]);
            assert_relative_eq!(da, b.eps, max_relative = 1e-12, epsilon = 1e-12);
        }
    }
}

#[test]
fn first_order_file_assembles_and_differentiates() {
    let model = StructureModel::from_ron(FIRST_ORDER, "oscillator.ron").unwrap_or_else(|e| panic!("{e}"));
    assert!(!model.is_second_order());
    assert_eq!(model.n_states(), 2);
    assert_eq!(model.coordinates(), ["x1", "x2"]);
    assert_eq!(model.coordinate_index("x2"), Some(1));
    assert_eq!(model.input_names(), ["u"]);
    assert_eq!(model.output_names(), ["y1", "y2", "y3"]);
    assert!(model.second_order::<f64>(&model.values()).unwrap().is_none());
    let s = model.state_space::<f64>(&model.values()).unwrap();
    assert_eq!(s.a, DMatrix::from_row_slice(2, 2, &[0.0, 1.0, -40.0, -0.8]));
    assert_eq!(s.b, Some(DMatrix::from_row_slice(2, 1, &[0.0, 2.0])));
    assert_eq!(s.c, DMatrix::from_row_slice(3, 2, &[1.0, 0.0, 1.0, 0.5, -1.0, 0.5]));
    assert_eq!(s.d, Some(DMatrix::from_row_slice(3, 1, &[0.0, 0.1, 0.0])));
    assert_eq!(s.x0.as_slice(), [1.0, -0.8]);
    check_derivatives(&model, &model.values(), 1e-7);
    let modes = model.modes().unwrap();
    assert_eq!(modes.len(), 1);
    assert_relative_eq!(
        modes[0].frequency_hz,
        40f64.sqrt() / (2.0 * std::f64::consts::PI),
        max_relative = 1e-12
    );
    assert_relative_eq!(modes[0].damping_ratio, 0.8 / (2.0 * 40f64.sqrt()), max_relative = 1e-12);
    assert!(modes[0].shape.is_none());
    // An overdamped first-order model has two real eigenvalues: one mode each.
    let mut over = model.clone();
    over.set("c", 20.0).unwrap();
    let modes = over.modes().unwrap();
    assert_eq!(modes.len(), 2);
    assert!(modes.iter().all(|m| m.eigenvalue.1 == 0.0 && m.damping_ratio == 1.0));
}

#[test]
fn mem_exact_derivatives_match() {
    // What the fit uses: mem's Exact adapter over the same model.
    use mem::LinearModel;
    let model = StructureModel::from_ron(MODAL, "modal.ron").unwrap();
    let lin = mem::Exact(model.clone()).linearize(&model.values()).unwrap();
    assert_eq!(lin.da.len(), 8);
    assert!(lin.dx0.is_some() && lin.dc.is_some() && lin.db.is_some() && lin.dd.is_some());
}

#[test]
fn modal_damping_is_exact_when_a_coupling_vanishes_at_the_point() {
    // K is diagonal at kc = 0 but ∂K/∂kc is not: the Jacobi rotations must still turn the
    // derivative's off-diagonal part away (the rotation angle is 0 with a nonzero derivative).
    let text = r#"(
        name: "two coordinates, vanishing coupling",
        parameters: {
            "m": (value: 2), "k1": (value: 300), "k2": (value: 500), "kc": (value: 0),
            "z1": (value: 0.05), "z2": (value: 0.1),
        },
        structure: SecondOrder(
            coordinates: ["a", "b"],
            mass: [["m", 0], [0, "m"]],
            stiffness: [["k1", "kc"], ["kc", "k2"]],
            damping: Modal(["z1", "z2"]),
        ),
        outputs: [(column: "a", measures: Displacement("a"))],
        initial: (displacement: [1, 0]),
    )"#;
    let model = StructureModel::from_ron(text, "coupling.ron").unwrap_or_else(|e| panic!("{e}"));
    check_derivatives(&model, &model.values(), 1e-7);
    // By hand: with M = mI, D = m Σ c_i v_i v_iᵀ (c_i = 2ζ_iω_i, v_i the orthonormal eigenvectors
    // of K); to first order in kc, v₁ = (1, −δ), v₂ = (δ, 1) with δ = kc/(k2 − k1) and the ω_i do
    // not move, so ∂D_ab/∂kc = m (c₂ − c₁)/(k2 − k1).
    let seeded: Vec<Dual64> = model
        .values()
        .iter()
        .enumerate()
        .map(|(i, v)| Dual64::new(*v, if i == 3 { 1.0 } else { 0.0 }))
        .collect();
    let d = model.second_order(&seeded).unwrap().unwrap().d;
    let (w1, w2) = ((300.0f64 / 2.0).sqrt(), (500.0f64 / 2.0).sqrt());
    let expected = 2.0 * (2.0 * 0.1 * w2 - 2.0 * 0.05 * w1) / (500.0 - 300.0);
    assert_relative_eq!(d[(0, 1)].eps, expected, max_relative = 1e-10);
    assert_relative_eq!(d[(1, 0)].eps, expected, max_relative = 1e-10);
}
