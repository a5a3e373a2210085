//! Roots against the 40-digit references of `tests/integration/reference/make_roots.py` and the limits.

use beam_modes::{Beam, characteristic, clamped_free_root, modes, pinned_free_root};
use serde::Deserialize;

#[derive(Deserialize)]
struct Reference {
    pinned_free: Vec<String>,
    clamped_free: Vec<String>,
    roots: Vec<Case>,
}

#[derive(Deserialize)]
struct Case {
    kappa: f64,
    lambda: Vec<String>,
}

fn reference() -> Reference {
    serde_json::from_str(include_str!("reference/roots.json")).unwrap()
}

/// A beam with L = EI = 1 so that κ = k.
fn unit_beam(kappa: f64) -> Beam<f64> {
    Beam { length: 1.0, flexural_rigidity: 1.0, mass_per_length: 1.0, hub_radius: 0.0, root_stiffness: kappa }
}

#[test]
fn limits_match_published_roots_to_1e_10() {
    let r = reference();
    for j in 1..=8 {
        let p: f64 = r.pinned_free[j - 1].parse().unwrap();
        let c: f64 = r.clamped_free[j - 1].parse().unwrap();
        assert!((pinned_free_root(j) - p).abs() < 1e-10 * p, "pinned-free {j}");
        assert!((clamped_free_root(j) - c).abs() < 1e-10 * c, "clamped-free {j}");
    }
    // The values printed in textbooks (Blevins, Table 8-1), to their four decimals.
    for (j, v) in [3.9266, 7.0686, 10.2102].iter().enumerate() {
        assert!((pinned_free_root(j + 1) - v).abs() < 5e-5);
    }
    for (j, v) in [1.8751, 4.6941, 7.8548, 10.9955].iter().enumerate() {
        assert!((clamped_free_root(j + 1) - v).abs() < 5e-5);
    }
}

#[test]
fn kappa_zero_is_pinned_free_with_rigid_rotation() {
    let m = modes(&unit_beam(0.0), 5).unwrap();
    assert_eq!(m[0].lambda, 0.0);
    assert_eq!(m[0].omega, 0.0);
    for j in 1..5 {
        assert!((m[j].lambda - pinned_free_root(j)).abs() < 1e-10 * m[j].lambda);
    }
}

#[test]
fn roots_match_high_precision_reference() {
    // Tolerance 1e-12 relative: the f64 characteristic function is evaluated to a few ulps and
    // its slope at the root is O(1) or larger in the normalised forms.
    for case in reference().roots {
        let m = modes(&unit_beam(case.kappa), 8).unwrap();
        for (i, s) in case.lambda.iter().enumerate() {
            let expected: f64 = s.parse().unwrap();
            let got = m[i].lambda;
            assert!(
                (got - expected).abs() <= 1e-12 * expected,
                "κ={} mode {}: {got} vs {expected}",
                case.kappa,
                i + 1
            );
        }
    }
}

#[test]
fn roots_increase_monotonically_between_the_limits() {
    let n = 6;
    let mut previous = vec![0.0; n];
    for step in 0..=120 {
        let kappa = 10f64.powf(-8.0 + step as f64 * 0.125); // 1e-8 .. 1e7
        let m = modes(&unit_beam(kappa), n).unwrap();
        for i in 0..n {
            let l = m[i].lambda;
            assert!(l > previous[i], "κ={kappa}: mode {} not increasing", i + 1);
            assert!(
                l >= pinned_free_root(i) && l <= clamped_free_root(i + 1),
                "κ={kappa}: mode {} outside its bracket",
                i + 1
            );
            previous[i] = l;
        }
    }
}

#[test]
fn no_root_is_missed_or_duplicated() {
    // A dense scan of Δ(λ)/cosh λ finds exactly as many sign changes as modes below the scan end.
    for kappa in [1e-3, 0.3, 1.0, 30.0, 1e4] {
        let n = 10;
        let m = modes(&unit_beam(kappa), n).unwrap();
        let end = clamped_free_root(n) + 0.5 * (pinned_free_root(n) - clamped_free_root(n));
        let f = |l: f64| characteristic(l, kappa) / if l < 3.0 { 0.5 * l.cosh() } else { 1.0 };
        let steps = 200_000;
        let mut count = 0;
        let mut prev = f(1e-9);
        for s in 1..=steps {
            let l = 1e-9 + end * s as f64 / steps as f64;
            let v = f(l);
            if v == 0.0 || v.signum() != prev.signum() {
                count += 1;
            }
            prev = v;
        }
        assert_eq!(count, n, "κ={kappa}: {count} sign changes for {n} modes");
        for w in m.windows(2) {
            assert!(w[1].lambda - w[0].lambda > 2.0, "roots too close (duplicate?)");
        }
    }
}

#[test]
fn small_kappa_approaches_rigid_rod_on_a_spring() {
    // λ₁⁴ → 3κ: ω₁² = k / (ρL³/3).
    for kappa in [1e-10, 1e-8, 1e-6] {
        let m = modes(&unit_beam(kappa), 2).unwrap();
        let rel = (m[0].lambda.powi(4) / (3.0 * kappa) - 1.0).abs();
        assert!(rel < 1e-5, "κ={kappa}: {rel}");
    }
}
