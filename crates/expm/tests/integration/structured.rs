//! Accuracy on nilpotent, strictly triangular and Jordan matrices against the exact references
//! of `tests/integration/reference/make_structured.py`.
//!
//! Why these matrices: for nilpotent A the norms of the powers Aᵖ vanish from p = n on, so a
//! Padé degree/scaling choice that looks only at them sees a tiny problem, while the Fréchet
//! derivative's series L(A, E) = Σₖ 1/k! Σ_{i+j=k−1} Aⁱ E Aʲ still carries non-vanishing terms
//! up to k = 2n − 1. The families: `nilpotent_super` (first superdiagonal s), `strict_triangular`
//! (random integers in [−s, s] above the diagonal), `jordan` (λI + superdiagonal s) and `issue`
//! (the reported 4×4 case, s = 1 and s = 20); two directions E per A.
//!
//! Independence of the reference: for nilpotent N the series terminate (Nⁿ = 0), so e^N and
//! L(N, E) are finite sums, evaluated by the script in exact rational arithmetic (Python
//! `fractions`, on the exact values of the float64 entries) and rounded once to float64; for
//! Jordan blocks e^{λI+N} = e^λ e^N and L(λI + N, E) = e^λ L(N, E) with e^λ at 60 digits. No
//! Padé approximant, no scaling and squaring and no floating-point arithmetic is involved before
//! the final rounding. The script cross-checks a handful of cases against the 60-digit block
//! exponential of `make_reference.py` (agreement ≤ 4e-59 relative, identical after rounding).
//!
//! Tolerance, as in `reference.rs`: the relative Frobenius error of e^A and of L(A, E) must be at
//! most 20·u·max(κ, 1), with u = 2⁻⁵³ and κ the relative condition number computed as in
//! `make_reference.py` (SciPy's `expm_cond` of A; for L, `expm_cond` of the 2n×2n block
//! [[A, cE], [0, A]] converted to a relative bound on the L block). The script also recomputes
//! both κ from the Kronecker form of the terminating series; they agree with SciPy's to 1e-5.
//! A backward-stable algorithm has error ≲ c·u·κ with a modest c; 20 leaves room for the
//! estimate's looseness. Unlike `reference.rs` there is no "no worse than SciPy" clause here:
//! the bound alone is the acceptance criterion for these cases.

use serde::Deserialize;

const U: f64 = 1.110_223_024_625_156_5e-16;

/// The families the script generates; each but `issue` (4×4 by definition) must include n = 16.
const FAMILIES: [&str; 4] = ["nilpotent_super", "strict_triangular", "jordan", "issue"];

use crate::reference::{mat, rel_err};

#[derive(Deserialize)]
struct Case {
    name: String,
    family: String,
    n: usize,
    a: Vec<Vec<f64>>,
    e: Vec<Vec<f64>>,
    exp_a: Vec<Vec<f64>>,
    frechet: Vec<Vec<f64>>,
    /// `null` in the file when SciPy's value was not finite.
    kappa_exp: Option<f64>,
    kappa_frechet: Option<f64>,
    scipy_exp_err: f64,
    scipy_frechet_err: f64,
}

#[derive(Deserialize)]
struct File {
    cases: Vec<Case>,
}

fn cases() -> Vec<Case> {
    let text = include_str!("reference/structured.json");
    serde_json::from_str::<File>(text).expect("structured reference file parses").cases
}

fn kappa(name: &str, what: &str, k: Option<f64>) -> f64 {
    k.unwrap_or_else(|| panic!("{name}: {what} is null in structured.json (not finite)"))
}

/// Per-family worst err/bound, printed after the table.
fn worst_ratios(rows: &[(String, String, f64, f64)]) -> String {
    let mut out = String::from("worst err/bound per family:\n");
    for family in FAMILIES {
        let worst = rows.iter().filter(|r| r.0 == family).max_by(|x, y| (x.2 / x.3).total_cmp(&(y.2 / y.3)));
        if let Some((_, name, err, bound)) = worst {
            out +=
                &format!("  {family:18} {:9.2e}  ({name}: err {err:.2e}, bound {bound:.2e})\n", err / bound);
        }
    }
    out
}

#[test]
fn structured_file_covers_every_family_with_n_16() {
    let cases = cases();
    for family in FAMILIES {
        let in_family: Vec<&Case> = cases.iter().filter(|c| c.family == family).collect();
        assert!(!in_family.is_empty(), "no {family} cases");
        if family != "issue" {
            assert!(in_family.iter().any(|c| c.n == 16), "{family}: no case with n = 16");
        }
    }
    for wanted in ["issue_n4_s1_int", "issue_n4_s1_normal", "issue_n4_s20_int", "issue_n4_s20_normal"] {
        assert!(cases.iter().any(|c| c.name == wanted), "missing case {wanted}");
    }
    for c in &cases {
        assert!(FAMILIES.contains(&c.family.as_str()), "{}: unknown family {}", c.name, c.family);
        for (what, m) in [("a", &c.a), ("e", &c.e), ("exp_a", &c.exp_a), ("frechet", &c.frechet)] {
            assert!(
                m.len() == c.n && m.iter().all(|r| r.len() == c.n),
                "{}: {what} is not {}×{}",
                c.name,
                c.n,
                c.n
            );
        }
        kappa(&c.name, "kappa_exp", c.kappa_exp);
        kappa(&c.name, "kappa_frechet", c.kappa_frechet);
    }
}

#[test]
fn expm_matches_exact_structured_reference() {
    let mut report = format!("{:36} {:>9} {:>9} {:>9}\n", "case", "err", "bound", "scipy");
    let mut rows = Vec::new();
    let mut failures = Vec::new();
    for case in cases() {
        let a = mat(&case.a);
        let x = expm::expm(a.as_ref()).unwrap_or_else(|e| panic!("{}: expm failed: {e}", case.name));
        let err = rel_err(&x, &mat(&case.exp_a));
        let bound = 20.0 * U * kappa(&case.name, "kappa_exp", case.kappa_exp).max(1.0);
        report += &format!("{:36} {err:9.2e} {bound:9.2e} {:9.2e}\n", case.name, case.scipy_exp_err);
        if err.is_nan() || err > bound {
            failures.push(format!(
                "{}: expm error {err:e} > 20uκ = {bound:e} (ratio {:.2e})",
                case.name,
                err / bound
            ));
        }
        rows.push((case.family, case.name, err, bound));
    }
    println!("{report}\n{}", worst_ratios(&rows));
    assert!(failures.is_empty(), "{} case(s) fail:\n{}", failures.len(), failures.join("\n"));
}

#[test]
fn frechet_matches_exact_structured_reference() {
    let mut report = format!("{:36} {:>9} {:>9} {:>9}\n", "case", "err", "bound", "scipy");
    let mut rows = Vec::new();
    let mut failures = Vec::new();
    for case in cases() {
        let a = mat(&case.a);
        let e = mat(&case.e);
        let (x, l) = expm::expm_frechet(a.as_ref(), e.as_ref())
            .unwrap_or_else(|err| panic!("{}: expm_frechet failed: {err}", case.name));
        let exp_err = rel_err(&x, &mat(&case.exp_a));
        let exp_bound = 20.0 * U * kappa(&case.name, "kappa_exp", case.kappa_exp).max(1.0);
        let err = rel_err(&l, &mat(&case.frechet));
        let bound = 20.0 * U * kappa(&case.name, "kappa_frechet", case.kappa_frechet).max(1.0);
        report += &format!("{:36} {err:9.2e} {bound:9.2e} {:9.2e}\n", case.name, case.scipy_frechet_err);
        if exp_err.is_nan() || exp_err > exp_bound {
            failures.push(format!("{}: e^A from expm_frechet {exp_err:e} > 20uκ = {exp_bound:e}", case.name));
        }
        if err.is_nan() || err > bound {
            failures.push(format!(
                "{}: L error {err:e} > 20uκ = {bound:e} (ratio {:.2e})",
                case.name,
                err / bound
            ));
        }
        rows.push((case.family, case.name, err, bound));
    }
    println!("{report}\n{}", worst_ratios(&rows));
    assert!(failures.is_empty(), "{} case(s) fail:\n{}", failures.len(), failures.join("\n"));
}
