//! Bad input gives typed errors naming the property.

use beam_modes::{Beam, BeamError, modes};

fn good() -> Beam<f64> {
    Beam { length: 1.0, flexural_rigidity: 1.0, mass_per_length: 1.0, hub_radius: 0.1, root_stiffness: 1.0 }
}

#[test]
fn non_positive_properties_are_rejected() {
    for (name, value) in [
        ("length", 0.0),
        ("length", -1.0),
        ("flexural_rigidity", 0.0),
        ("mass_per_length", -2.0),
        ("mass_per_length", f64::NAN),
    ] {
        let mut b = good();
        match name {
            "length" => b.length = value,
            "flexural_rigidity" => b.flexural_rigidity = value,
            _ => b.mass_per_length = value,
        }
        match modes(&b, 3) {
            Err(BeamError::InvalidProperty { name: got, .. }) => assert_eq!(got, name),
            other => panic!("{name}={value}: {other:?}"),
        }
    }
    let mut b = good();
    b.root_stiffness = -1.0;
    assert!(matches!(modes(&b, 3), Err(BeamError::InvalidProperty { name: "root_stiffness", .. })));
    b = good();
    b.hub_radius = f64::INFINITY;
    assert!(matches!(modes(&b, 3), Err(BeamError::InvalidProperty { name: "hub_radius", .. })));
}

#[test]
fn zero_modes_is_an_error() {
    assert_eq!(modes(&good(), 0).unwrap_err(), BeamError::NoModes);
}
