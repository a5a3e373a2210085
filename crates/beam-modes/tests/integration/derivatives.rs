//! Exact (num-dual) derivatives against central finite differences.

use beam_modes::{Beam, Mode, modes};
use num_dual::Dual64;

const BASE: [f64; 5] = [1.19, 0.407, 0.475, 0.06, 0.22]; // L, EI, ρ, a, k
const NAMES: [&str; 5] = ["length", "flexural_rigidity", "mass_per_length", "hub_radius", "root_stiffness"];

fn beam_with<D: Copy>(values: [D; 5]) -> Beam<D> {
    Beam {
        length: values[0],
        flexural_rigidity: values[1],
        mass_per_length: values[2],
        hub_radius: values[3],
        root_stiffness: values[4],
    }
}

fn quantities<D: num_dual::DualNum<Primitive = f64> + Copy>(m: &Mode<D>) -> [D; 5] {
    [m.lambda, m.omega, m.participation, m.root_slope, m.root_curvature]
}

#[test]
fn dual_derivatives_match_central_differences() {
    for kappa_scale in [0.01, 1.0, 100.0] {
        let mut base = BASE;
        base[4] *= kappa_scale;
        for p in 0..5 {
            let dual =
                beam_with(std::array::from_fn(|i| Dual64::new(base[i], if i == p { 1.0 } else { 0.0 })));
            let exact = modes(&dual, 4).unwrap();
            // Step 1e-6 relative: truncation ~1e-12, rounding ~1e-10 relative.
            let h = 1e-6 * base[p];
            let shifted = |sign: f64| {
                let mut v = base;
                v[p] += sign * h;
                modes(&beam_with(v), 4).unwrap()
            };
            let (plus, minus) = (shifted(1.0), shifted(-1.0));
            for mode in 0..4 {
                let (e, qp, qm) =
                    (quantities(&exact[mode]), quantities(&plus[mode]), quantities(&minus[mode]));
                for q in 0..5 {
                    let fd = (qp[q] - qm[q]) / (2.0 * h);
                    let scale = (e[q].re.abs() / base[p]).max(fd.abs()).max(1e-12);
                    assert!(
                        (e[q].eps - fd).abs() <= 1e-6 * scale,
                        "∂(quantity {q} of mode {})/∂{}, κ scale {kappa_scale}: exact {} fd {fd}",
                        mode + 1,
                        NAMES[p],
                        e[q].eps
                    );
                }
            }
        }
    }
}
