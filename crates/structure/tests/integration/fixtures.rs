//! The three shear-building fixtures: what they declare, what they assemble to (against the
//! hand-written building of `test-problems`), their modes (against the independent values of
//! `fixtures/independent/README.md`), and `to_ron` round trips.

use crate::common::{fixture, fixture_text};
use approx::assert_relative_eq;
use mem::StateSpaceModel;
use mem::nalgebra::DMatrix;
use structure::{StructureModel, is_structure_file};
use test_problems::ShearBuilding;

const FIXTURES: [&str; 3] = ["shear_building.ron", "shear_building_acc.ron", "shear_building_forced.ron"];
const NAMES: [&str; 8] = ["m1", "m2", "m3", "k1", "k2", "k3", "alpha", "beta"];
const NOMINAL: [f64; 8] = [1000.0, 1000.0, 1000.0, 2.5e6, 2.25e6, 1.875e6, 0.375, 1.25e-3];

#[test]
fn fixtures_declare_parameters_in_file_order_with_free_list_bounds_and_units() {
    for name in FIXTURES {
        let model = fixture(name);
        assert_eq!(model.parameter_names(), NAMES, "{name}");
        assert_eq!(model.values(), NOMINAL, "{name}");
        assert_eq!(model.free(), ["k1", "k2", "k3", "alpha", "beta"], "{name}");
        for k in ["k1", "k2", "k3"] {
            assert_eq!(model.bounds(k), Some((0.0, 1e10)), "{name} {k}");
            assert_eq!(model.unit(k), Some("N/m"));
        }
        assert_eq!(model.bounds("alpha"), Some((0.0, 100.0)));
        assert_eq!(model.bounds("beta"), Some((0.0, 1.0)));
        assert_eq!(model.bounds("m1"), None);
        assert_eq!(model.unit("m1"), Some("kg"));
        assert_eq!(model.unit("alpha"), Some("1/s"));
        assert_eq!(model.unit("beta"), Some("s"));
        assert_eq!(model.typical("k1"), None);
        assert_eq!(model.description("alpha"), Some("Rayleigh mass coefficient"));
        assert_eq!(model.unit("nope"), None);
        assert_eq!(model.coordinates(), ["q1", "q2", "q3"]);
        assert!(model.is_second_order());
        assert_eq!(model.n_states(), 6);
        assert_eq!(model.coordinate_index("q3"), Some(2));
        assert_eq!(model.coordinate_index("q4"), None);
        assert_eq!(model.hold(), mem::Hold::Zero);
    }
    let free = fixture("shear_building.ron");
    assert_eq!(free.name(), "Three-storey shear building");
    assert_eq!(free.output_names(), ["q1", "q3"]);
    assert_eq!(free.output_unit("q3"), Some("m"));
    assert!(free.input_names().is_empty());
    assert_eq!(fixture("shear_building_acc.ron").output_names(), ["a1", "a2", "a3"]);
    let forced = fixture("shear_building_forced.ron");
    assert_eq!(forced.output_names(), ["a1", "a2", "a3"]);
    assert_eq!(forced.input_names(), ["u"]);
    assert_eq!(forced.input_unit("u"), Some("N"));
    assert_eq!(forced.output_unit("a2"), Some("m/s^2"));
}

fn assert_matrix_eq(a: &DMatrix<f64>, b: &DMatrix<f64>, what: &str) {
    assert_eq!(a.shape(), b.shape(), "{what}");
    for (x, y) in a.iter().zip(b.iter()) {
        assert_relative_eq!(*x, *y, max_relative = 1e-14, epsilon = 1e-300);
    }
}

#[test]
fn fixtures_assemble_like_the_hand_written_building() {
    let cases = [
        ("shear_building.ron", ShearBuilding { free_masses: true, ..ShearBuilding::displacements() }),
        ("shear_building_acc.ron", ShearBuilding { free_masses: true, ..ShearBuilding::accelerations() }),
    ];
    let p = [1100.0, 950.0, 1020.0, 2.6e6, 2.2e6, 1.9e6, 0.4, 1.1e-3];
    for (name, reference) in cases {
        let model = fixture(name);
        let ours = model.state_space::<f64>(&p).unwrap();
        let theirs = reference.state_space::<f64>(&p).unwrap();
        assert_matrix_eq(&ours.a, &theirs.a, name);
        assert_matrix_eq(&ours.c, &theirs.c, name);
        assert_eq!(ours.x0.as_slice(), theirs.x0.as_slice());
        assert!(ours.b.is_none() && ours.d.is_none());
    }
    // The forced building: the same A and C as the accelerometer record, B = [0; M⁻¹e₁] and the
    // accelerations' feedthrough D = M⁻¹e₁ (a1 = u/m1 + …), at rest.
    let forced = fixture("shear_building_forced.ron").state_space::<f64>(&p).unwrap();
    let acc = fixture("shear_building_acc.ron").state_space::<f64>(&p).unwrap();
    assert_matrix_eq(&forced.a, &acc.a, "forced A");
    assert_matrix_eq(&forced.c, &acc.c, "forced C");
    assert!(forced.x0.iter().all(|v| *v == 0.0));
    let b = forced.b.unwrap();
    let d = forced.d.unwrap();
    assert_eq!(b.shape(), (6, 1));
    assert_eq!(d.shape(), (3, 1));
    assert_eq!(b.column(0).as_slice(), [0.0, 0.0, 0.0, 1.0 / 1100.0, 0.0, 0.0]);
    assert_eq!(d.column(0).as_slice(), [1.0 / 1100.0, 0.0, 0.0]);
    let second = fixture("shear_building_forced.ron").second_order::<f64>(&p).unwrap().unwrap();
    assert_eq!(second.f.unwrap().column(0).as_slice(), [1.0, 0.0, 0.0]);
    assert_relative_eq!(second.d[(0, 1)], 1.1e-3 * -2.2e6, max_relative = 1e-15);
    assert_relative_eq!(second.d[(0, 0)], 0.4 * 1100.0 + 1.1e-3 * 4.8e6, max_relative = 1e-15);
}

#[test]
fn modes_match_the_independent_values() {
    // fixtures/independent/README.md, nominal: undamped f_n from K φ = ω² M φ and ζ.
    let f_n = [3.4139699088, 9.0887311061, 13.3431801825];
    let zeta = [0.0221476404, 0.0389747209, 0.0546350108];
    let f_d = [3.4131324993, 9.0818254601, 13.3232507067];
    for name in FIXTURES {
        let modes = fixture(name).modes().unwrap();
        assert_eq!(modes.len(), 3, "{name}");
        for (i, mode) in modes.iter().enumerate() {
            // Rayleigh damping is proportional: |λ| is the undamped ω_n exactly.
            assert_relative_eq!(mode.frequency_hz, f_n[i], max_relative = 1e-8);
            assert_relative_eq!(mode.damping_ratio, zeta[i], max_relative = 1e-8);
            assert_relative_eq!(
                mode.eigenvalue.1 / (2.0 * std::f64::consts::PI),
                f_d[i],
                max_relative = 1e-8
            );
            let shape = mode.shape.as_ref().unwrap();
            assert_eq!(shape.len(), 3);
            assert!(shape.iter().all(|v| v.abs() <= 1.0 + 1e-12) && shape.contains(&1.0), "{shape:?}");
        }
        // The first mode of a shear building moves all floors the same way, the top most.
        assert!(modes[0].shape.as_ref().unwrap().iter().all(|v| *v > 0.0));
    }
}

#[test]
fn mode_shapes_are_the_generalised_eigenvectors() {
    let model = fixture("shear_building.ron");
    let so = model.second_order::<f64>(&model.values()).unwrap().unwrap();
    for mode in model.modes().unwrap() {
        let omega2 = (2.0 * std::f64::consts::PI * mode.frequency_hz).powi(2);
        let phi = mem::nalgebra::DVector::from_vec(mode.shape.unwrap());
        let residual = &so.k * &phi - &so.m * &phi * omega2;
        assert!(residual.amax() <= 1e-8 * (&so.k * &phi).amax(), "{residual}");
    }
}

#[test]
fn to_ron_round_trips_values_and_matrices() {
    for name in FIXTURES {
        let mut model = fixture(name);
        // Unchanged: the very text.
        assert_eq!(model.to_ron(), fixture_text(name));
        let new = [("k1", 2.62e6), ("k3", 1.96e6), ("alpha", 0.42), ("beta", 1.18e-3), ("m2", 1000.5)];
        for (p, v) in new {
            model.set(p, v).unwrap();
        }
        let text = model.to_ron();
        assert!(text.contains("storey 1 stiffness") && text.contains("// "), "comments and fields kept");
        let back = StructureModel::from_ron(&text, name).unwrap_or_else(|e| panic!("{e}\n{text}"));
        assert_eq!(back.values(), model.values());
        assert_eq!(back.parameter_names(), model.parameter_names());
        assert_eq!(back.free(), model.free());
        assert_eq!(back.output_names(), model.output_names());
        assert_eq!(back.input_names(), model.input_names());
        for p in [model.values(), NOMINAL.to_vec()] {
            let (a, b) = (model.state_space::<f64>(&p).unwrap(), back.state_space::<f64>(&p).unwrap());
            assert_eq!((a.a, a.c, a.x0, a.b, a.d), (b.a, b.c, b.x0, b.b, b.d));
        }
    }
}

#[test]
fn is_structure_file_tells_the_two_kinds_apart() {
    for name in FIXTURES {
        assert!(is_structure_file(&fixture_text(name)), "{name}");
    }
    assert!(!is_structure_file(&fixture_text("slewing.ron")));
    assert!(!is_structure_file(&fixture_text("truth.ron")));
    // Only a top-level field counts: not a comment, a string or a nested field.
    assert!(!is_structure_file("// structure: here\n(name: \"structure: x\", beam: (structure: 1))"));
    assert!(!is_structure_file("/* (structure: 1) */ (name: \"x\")"));
    assert!(is_structure_file("#![enable(implicit_some)]\nModel(name: \"x\", structure: FirstOrder())"));
    assert!(!is_structure_file(""));
    assert!(!is_structure_file("structure: 1"));
    assert!(!is_structure_file(&"[".repeat(100_000)));
}

#[test]
fn the_model_is_a_mem_state_space_model() {
    let model = fixture("shear_building_forced.ron");
    let exact = mem::Exact(model.clone());
    use mem::LinearModel;
    assert_eq!(exact.n_params(), 8);
    // (mem's `Exact::n_states` evaluates the model at P = 0, where this model's masses vanish.)
    assert_eq!(LinearModel::input_names(&exact), ["u"]);
    let lin = exact.linearize(&model.values()).unwrap();
    assert_eq!(lin.da.len(), 8);
    assert!(lin.db.is_some() && lin.dd.is_some(), "B and D depend on the masses");
}
