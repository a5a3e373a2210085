//! ∂A/∂P and ∂C/∂P (num-dual through the whole chain) against central finite differences.

use plant::{ParamId, SlewingModel};

fn fixture() -> SlewingModel {
    SlewingModel::paper()
}

#[test]
fn exact_derivatives_match_central_differences_for_every_parameter() {
    let model = fixture();
    let ids = ParamId::all(model.n_modes());
    let lin = model.linearization(&ids).unwrap();
    for (k, &id) in ids.iter().enumerate() {
        let value = model.get(id);
        // Relative step 1e-6: truncation O(h²) ≈ 1e-12, rounding O(u/h) ≈ 1e-10 relative.
        let h = 1e-6 * value.abs().max(1e-3);
        let eval = |v: f64| {
            let mut m = model.clone();
            m.set(id, v).unwrap();
            m.state_space().unwrap()
        };
        let (plus, minus) = (eval(value + h), eval(value - h));
        let scale_a = lin.a.norm_max();
        for i in 0..lin.a.nrows() {
            for j in 0..lin.a.ncols() {
                let fd = (plus.a[(i, j)] - minus.a[(i, j)]) / (2.0 * h);
                let exact = lin.da[k][(i, j)];
                assert!(
                    (exact - fd).abs()
                        <= 1e-6 * (fd.abs().max(exact.abs()) + scale_a / value.abs().max(1e-3) * 1e-4),
                    "∂A[{i},{j}]/∂{}: exact {exact} fd {fd}",
                    id.name()
                );
            }
        }
        for i in 0..lin.c.nrows() {
            for j in 0..lin.c.ncols() {
                let fd = (plus.c[(i, j)] - minus.c[(i, j)]) / (2.0 * h);
                let exact = lin.dc[k][(i, j)];
                assert!(
                    (exact - fd).abs() <= 1e-6 * fd.abs().max(exact.abs()).max(1e-6),
                    "∂C[{i},{j}]/∂{}",
                    id.name()
                );
            }
        }
    }
}

#[test]
fn position_gain_changes_the_mode_shapes() {
    // ∂A/∂K_p has non-zero entries in the modal stiffness block (ω_i² depends on K_p through
    // the root spring), not only in the servo entries.
    let model = fixture();
    let lin = model.linearization(&[ParamId::PositionGain]).unwrap();
    let n = model.n_modes() + 1;
    assert!(lin.da[0][(n + 1, 1)].abs() > 1e-3, "∂(−M⁻¹K)[1,1]/∂K_p = {}", lin.da[0][(n + 1, 1)]);
    assert!(lin.dc[0].norm_max() > 0.0, "the strain row depends on K_p through φ″(0)");
}
