//! Helpers shared by the structure model tests.
#![allow(dead_code)]

use mem::nalgebra::DMatrix;
use num_dual::Dual64;
use std::path::PathBuf;
use structure::StructureModel;

/// The path of a file in the repository's `fixtures/`.
pub fn fixture_path(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../fixtures").join(name)
}

/// The text of a fixture.
pub fn fixture_text(name: &str) -> String {
    std::fs::read_to_string(fixture_path(name)).unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// A fixture, loaded.
pub fn fixture(name: &str) -> StructureModel {
    StructureModel::load(&fixture_path(name)).unwrap_or_else(|e| panic!("{e}"))
}

/// 1-based line and column (in characters) of `within` inside the first occurrence of
/// `needle` in `text`.
pub fn position(text: &str, needle: &str, within: &str) -> (usize, usize) {
    let start = text.find(needle).unwrap_or_else(|| panic!("`{needle}` not in the text"));
    let offset = start + needle.find(within).unwrap_or_else(|| panic!("`{within}` not in `{needle}`"));
    let before = &text[..offset];
    let line = before.matches('\n').count() + 1;
    let column = before[before.rfind('\n').map_or(0, |i| i + 1)..].chars().count() + 1;
    (line, column)
}

fn columns(m: &DMatrix<f64>) -> Vec<f64> {
    m.iter().copied().collect()
}

/// All matrices of the state space at `p`, flattened: A, C, x(0), B, D (absent ones empty).
fn parts<D: mem::Scalar>(
    model: &StructureModel,
    p: &[D],
    part: impl Fn(&D) -> f64,
) -> Vec<(&'static str, Vec<f64>)> {
    let s = model.state_space(p).unwrap_or_else(|e| panic!("{e}"));
    let flat = |m: &DMatrix<D>| columns(&m.map(|v| part(&v)));
    let x0 = DMatrix::from_column_slice(s.x0.len(), 1, s.x0.as_slice());
    vec![
        ("A", flat(&s.a)),
        ("C", flat(&s.c)),
        ("x0", flat(&x0)),
        ("B", s.b.as_ref().map(flat).unwrap_or_default()),
        ("D", s.d.as_ref().map(flat).unwrap_or_default()),
    ]
}

/// Checks ∂(A, C, x(0), B, D)/∂P_i from `state_space::<Dual64>` seeded on parameter i against
/// central differences of `state_space::<f64>`, for every parameter, to `tolerance` relative to
/// the largest entry of each derivative. Returns how many (parameter, matrix) pairs had a
/// nonzero derivative.
pub fn check_derivatives(model: &StructureModel, p: &[f64], tolerance: f64) -> usize {
    let mut nonzero = 0;
    for i in 0..p.len() {
        let seeded: Vec<Dual64> =
            p.iter().enumerate().map(|(l, v)| Dual64::new(*v, if l == i { 1.0 } else { 0.0 })).collect();
        let exact = parts(model, &seeded, |d| d.eps);
        let values = parts(model, &seeded, |d| d.re);
        let reference = parts(model, p, |v| *v);
        let h = 1e-6 * p[i].abs().max(1e-3);
        let shifted = |sign: f64| {
            let mut q = p.to_vec();
            q[i] += sign * h;
            parts(model, &q, |v| *v)
        };
        let (plus, minus) = (shifted(1.0), shifted(-1.0));
        for k in 0..exact.len() {
            let name = exact[k].0;
            let size = reference[k].1.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            for (a, b) in values[k].1.iter().zip(&reference[k].1) {
                assert!(
                    (a - b).abs() <= 1e-14 * size,
                    "{name}: the dual's real part {a} differs from the f64 value {b}"
                );
            }
            let fd: Vec<f64> = plus[k].1.iter().zip(&minus[k].1).map(|(a, b)| (a - b) / (2.0 * h)).collect();
            let scale = exact[k].1.iter().chain(&fd).fold(0.0f64, |m, v| m.max(v.abs()));
            let error = exact[k].1.iter().zip(&fd).fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
            assert!(
                error <= tolerance * scale,
                "∂{name}/∂{}: exact {:?} vs central differences {:?} (error {error:e}, scale {scale:e})",
                model.parameter_names()[i],
                exact[k].1,
                fd
            );
            if scale > 0.0 {
                nonzero += 1;
            }
        }
    }
    nonzero
}
