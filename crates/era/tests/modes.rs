//! ERA recovers the modes of a simulated free decay (closed-form frequencies and damping).

use faer::Mat;
use test_problems::ModalFamily;

/// Two uncoupled damped oscillators, summed into two outputs: exact modes known.
fn two_mode_decay(noise: f64) -> (Mat<f64>, f64) {
    let h = 1.0 / 12.8;
    let modes = [(0.15, 0.10), (1.6, 0.03)];
    let k = 400;
    let mut r = test_problems::rng(3);
    let data = Mat::from_fn(k, 2, |step, o| {
        let t = step as f64 * h;
        let y: f64 = modes
            .iter()
            .enumerate()
            .map(|(m, (f, z))| {
                let w = 2.0 * std::f64::consts::PI * f;
                let wd = w * (1.0f64 - z * z).sqrt();
                let amp = if o == m { 1.0 } else { 0.3 };
                amp * (-z * w * t).exp() * (wd * t).cos()
            })
            .sum();
        y + noise * rand::Rng::sample::<f64, _>(&mut r, rand_distr::StandardNormal)
    });
    (data, h)
}

#[test]
fn recovers_frequencies_and_damping_noise_free() {
    let (data, h) = two_mode_decay(0.0);
    let result = era::identify(data.as_ref(), h, 4).unwrap();
    let physical: Vec<_> = result.modes.iter().filter(|m| m.physical).collect();
    assert_eq!(physical.len(), 2, "{:?}", result.modes);
    for (m, (f, z)) in physical.iter().zip([(0.15, 0.10), (1.6, 0.03)]) {
        assert!((m.frequency_hz / f - 1.0).abs() < 1e-8, "{} vs {f}", m.frequency_hz);
        assert!((m.damping_ratio / z - 1.0).abs() < 1e-7, "{} vs {z}", m.damping_ratio);
        assert!(m.consistency > 0.999);
    }
}

#[test]
fn noise_modes_are_flagged_and_physical_ones_kept() {
    let (data, h) = two_mode_decay(0.01);
    let result = era::identify(data.as_ref(), h, 12).unwrap();
    let physical: Vec<_> = result.modes.iter().filter(|m| m.physical).collect();
    // Both true modes are found within 2 % (noise) and labelled physical.
    for f in [0.15, 1.6] {
        assert!(
            physical.iter().any(|m| (m.frequency_hz / f - 1.0).abs() < 0.02),
            "{f} Hz missing: {:?}",
            result.modes
        );
    }
    // Most of the 6 extra (noise) modes are flagged.
    let spurious = result.modes.iter().filter(|m| !m.physical).count();
    assert!(spurious >= 3, "{:?}", result.modes);
}

#[test]
fn matches_a_modal_family_system() {
    // A coupled 3-mode system: ERA's frequencies equal the eigenvalues of A.
    let fam = ModalFamily::new(3, 2, 3, 9);
    let a = fam.a(&fam.p_nominal);
    let h = 1.0 / 12.8;
    let prop = expm::SensitivityPropagator::new(a.as_ref(), &[], fam.c.as_ref(), h).unwrap();
    let response = prop.propagate(&fam.x0, None, 300).unwrap();
    let result = era::identify(response.outputs.as_ref(), h, 6).unwrap();
    let eig = a.eigen().unwrap();
    for k in 0..6 {
        let s = eig.S()[k];
        if s.im <= 0.0 {
            continue;
        }
        let f = (s.re * s.re + s.im * s.im).sqrt() / (2.0 * std::f64::consts::PI);
        assert!(result.modes.iter().any(|m| (m.frequency_hz / f - 1.0).abs() < 1e-6), "{f} Hz not found");
    }
}

#[test]
fn too_short_records_are_errors() {
    let data = Mat::<f64>::zeros(5, 1);
    assert!(era::identify(data.as_ref(), 0.1, 4).is_err());
    assert!(era::identify(data.as_ref(), 0.1, 0).is_err());
}

/// The magnitude of the data does not matter: scaled by 1e-300 or 1e300 the same modes come out
/// (the RMS normalisation once squared 1e-300 to zero and gave NaN consistencies).
#[test]
fn tiny_and_huge_data_give_the_same_modes() {
    let (data, h) = two_mode_decay(0.0);
    let reference = era::identify(data.as_ref(), h, 4).unwrap();
    for factor in [1e-300, 1e300] {
        let scaled = Mat::from_fn(data.nrows(), data.ncols(), |k, o| data[(k, o)] * factor);
        let result = era::identify(scaled.as_ref(), h, 4).unwrap();
        assert_eq!(result.modes.len(), reference.modes.len());
        for (a, b) in result.modes.iter().zip(&reference.modes) {
            assert!(a.consistency.is_finite() && a.damping_ratio.is_finite(), "{factor}: {a:?}");
            assert!((a.frequency_hz / b.frequency_hz - 1.0).abs() < 1e-8, "{factor}: {a:?} vs {b:?}");
        }
    }
}
