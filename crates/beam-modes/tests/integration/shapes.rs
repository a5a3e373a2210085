//! Orthonormality, Rayleigh quotients and the closed forms against quadrature.

use beam_modes::quadrature::integrate;
use beam_modes::{Beam, modes};

fn beam(kappa: f64) -> Beam<f64> {
    // Steel-strip-like numbers; k chosen to give the requested κ = kL/EI.
    let (length, ei) = (1.19, 0.407);
    Beam {
        length,
        flexural_rigidity: ei,
        mass_per_length: 0.475,
        hub_radius: 0.06,
        root_stiffness: kappa * ei / length,
    }
}

/// Quadrature: 40 panels × 20 Gauss points resolve 10 modes (at most ~5 wavelengths) to
/// far below 1e-12; the tolerance 1e-10 is the issue's.
const PANELS: usize = 40;
const POINTS: usize = 20;

#[test]
fn ten_modes_are_mass_orthonormal() {
    for kappa in [0.1, 1.0, 10.0, 1e3] {
        let b = beam(kappa);
        let m = modes(&b, 10).unwrap();
        for i in 0..10 {
            for j in 0..=i {
                let v = integrate(
                    |x: f64| b.mass_per_length * m[i].shape(x)[0] * m[j].shape(x)[0],
                    0.0,
                    b.length,
                    PANELS,
                    POINTS,
                );
                let expected = if i == j { 1.0 } else { 0.0 };
                assert!((v - expected).abs() < 1e-10, "κ={kappa} ({i},{j}): {v}");
            }
        }
    }
}

#[test]
fn rayleigh_quotient_equals_omega_squared() {
    for kappa in [0.1, 1.0, 10.0, 1e3] {
        let b = beam(kappa);
        for mode in modes(&b, 10).unwrap() {
            let strain = integrate(
                |x: f64| b.flexural_rigidity * mode.shape(x)[2].powi(2),
                0.0,
                b.length,
                PANELS,
                POINTS,
            );
            let spring = b.root_stiffness * mode.root_slope.powi(2);
            let w2 = mode.omega * mode.omega;
            assert!(
                ((strain + spring) - w2).abs() < 1e-10 * w2,
                "κ={kappa} λ={}: {} vs {w2}",
                mode.lambda,
                strain + spring
            );
        }
    }
}

#[test]
fn boundary_conditions_hold() {
    for kappa in [1e-4, 0.644, 50.0, 1e6] {
        let b = beam(kappa);
        for mode in modes(&b, 8).unwrap() {
            let root = mode.shape(0.0);
            let tip = mode.shape(b.length);
            let scale = root[1].abs().max(tip[0].abs()).max(1.0);
            let beta = mode.lambda / b.length;
            assert!(root[0].abs() < 1e-12 * scale, "φ(0) = {}", root[0]);
            let moment = b.flexural_rigidity * root[2] - b.root_stiffness * root[1];
            assert!(
                moment.abs()
                    < 1e-10 * b.flexural_rigidity * beta * beta * scale + 1e-10 * b.root_stiffness * scale
            );
            assert!(tip[2].abs() < 1e-10 * beta * beta * scale, "φ″(L) = {}", tip[2]);
            assert!(tip[3].abs() < 1e-10 * beta.powi(3) * scale, "φ‴(L) = {}", tip[3]);
        }
    }
}

#[test]
fn closed_form_quantities_match_quadrature() {
    for kappa in [0.0, 1e-3, 0.644, 10.0, 1e3] {
        let b = beam(kappa);
        for mode in modes(&b, 10).unwrap() {
            let participation = integrate(
                |x: f64| b.mass_per_length * (b.hub_radius + x) * mode.shape(x)[0],
                0.0,
                b.length,
                PANELS,
                POINTS,
            );
            let scale = participation.abs().max(1e-3);
            assert!(
                (participation - mode.participation).abs() < 1e-10 * scale,
                "κ={kappa} λ={}: I {participation} vs {}",
                mode.lambda,
                mode.participation
            );
            assert_eq!(mode.shape(0.0)[1], mode.root_slope);
            assert_eq!(mode.shape(0.0)[2], mode.root_curvature);
            assert_eq!(mode.shape(b.length)[0], mode.tip_deflection);
        }
    }
}

#[test]
fn high_modes_are_evaluated_without_cancellation() {
    // Mode 30 (λ ≈ 93): cosh λ ≈ 1e40, a naive form would lose every digit. The normalised
    // shape must stay bounded by twice its asymptotic amplitude 1/√(ρL)·√2 and φ(L) must approach
    // ±2/√(ρL): ρLφ(L)²/4 = 1 − ρkφ′(0)²/(4EIβ⁴), and the spring term is O(κ/λ²).
    let b = beam(1.0);
    let m = modes(&b, 30).unwrap();
    let amplitude = (1.0 / (b.mass_per_length * b.length)).sqrt();
    for x in (0..=100).map(|k| b.length * k as f64 / 100.0) {
        assert!(m[29].shape(x)[0].abs() <= 2.0 * amplitude * 1.0001);
    }
    let ratio = m[29].tip_deflection.abs() / amplitude;
    let kappa = b.root_stiffness * b.length / b.flexural_rigidity;
    assert!((ratio - 2.0).abs() < kappa / m[29].lambda.powi(2), "tip/amplitude = {ratio}");
    let norm = integrate(|x: f64| b.mass_per_length * m[29].shape(x)[0].powi(2), 0.0, b.length, 200, 20);
    assert!((norm - 1.0).abs() < 1e-10);
}
