//! Behaviour of `Expr` through its public API: values, errors with offsets, exact derivatives,
//! and random round trips.

use approx::assert_relative_eq;
use num_dual::{Dual64, DualDVec64};
use proptest::prelude::*;
use std::f64::consts::PI;
use structure::{Expr, ExprError};

fn value(text: &str) -> f64 {
    Expr::parse(text, &[]).unwrap_or_else(|e| panic!("`{text}`: {e}")).eval::<f64>(&[])
}

#[test]
fn precedence_and_associativity() {
    for (text, expected) in [
        ("1 - 2 - 3", -4.0),
        ("2^3^2", 512.0),
        ("-2^2", -4.0),
        ("2*3 + 4/2", 8.0),
        ("(1+2)*3", 9.0),
        ("2^-1", 0.5),
        ("--3", 3.0),
        ("-+-3", 3.0),
        ("8/4/2", 1.0),
        ("2*-3", -6.0),
        ("(-2)^2", 4.0),
        ("(-2)^3", -8.0),
        ("2^-2^2", 2f64.powi(-4)),
        ("-2^-2", -0.25),
        ("1 + 2*3^2", 19.0),
        (" \t12\n", 12.0),
        ("1.5 + .5 + 5. + 2.5e6 + 1E-3", 1.5 + 0.5 + 5.0 + 2.5e6 + 1e-3),
    ] {
        assert_eq!(value(text), expected, "{text}");
    }
}

#[test]
fn functions_and_pi_match_std() {
    let x: f64 = 0.7;
    for (text, expected) in [
        ("sqrt(0.7)", x.sqrt()),
        ("exp(0.7)", x.exp()),
        ("ln(0.7)", x.ln()),
        ("log(0.7)", x.ln()),
        ("sin(0.7)", x.sin()),
        ("cos(0.7)", x.cos()),
        ("tan(0.7)", x.tan()),
        ("abs(-0.7)", x.abs()),
        ("pi", PI),
        ("sin(pi/6)", (PI / 6.0).sin()),
        ("sqrt(4)/(2*pi)", 2.0 / (2.0 * PI)),
    ] {
        assert_eq!(value(text), expected, "{text}");
    }
    let names = ["x"];
    for (text, f) in [
        ("sqrt(x)", f64::sqrt as fn(f64) -> f64),
        ("exp(x)", f64::exp),
        ("ln(x)", f64::ln),
        ("sin(x)", f64::sin),
        ("cos(x)", f64::cos),
        ("tan(x)", f64::tan),
        ("abs(x)", f64::abs),
    ] {
        let e = Expr::parse(text, &names).expect(text);
        for x in [0.3, 1.0, 2.5] {
            assert_eq!(e.eval(&[x]), f(x), "{text} at {x}");
        }
    }
    assert_eq!(Expr::parse("abs(x)", &names).map(|e| e.eval(&[-2.0])), Ok(2.0));
}

#[test]
fn variables() {
    let names = ["alpha", "beta", "m1", "k1", "k2", "unused"];
    let e = Expr::parse("alpha*m1 + beta*(k1 + k2)", &names).expect("parses");
    let vars = [0.1, 0.01, 2.0, 100.0, 50.0, 7.0];
    assert_eq!(e.eval(&vars), 0.1 * 2.0 + 0.01 * (100.0 + 50.0));
    assert_eq!(e.variables(), [0, 1, 2, 3, 4]);
    assert!(!e.is_constant());
    assert_eq!(e.names(), names);
    assert_eq!(e.to_string(), "alpha*m1 + beta*(k1 + k2)");

    let e = Expr::parse("2*zeta*omega", &["omega", "zeta"]).expect("parses");
    assert_eq!(e.eval(&[10.0, 0.02]), 0.4);
    assert_eq!(e.variables(), [0, 1]);
    // `e` is an ordinary name.
    let e = Expr::parse("e^2", &["e"]).expect("parses");
    assert_eq!(e.eval(&[3.0]), 9.0);
}

#[test]
fn errors_with_offsets() {
    let names = ["k1", "k2", "k3"];
    let parse = |text: &str| Expr::parse(text, &names).expect_err(text);

    let error = parse("k1 + k4");
    assert_eq!(
        error,
        ExprError::UnknownName {
            name: "k4".into(),
            offset: 5,
            known: vec!["k1".into(), "k2".into(), "k3".into()]
        }
    );
    assert_eq!(error.offset(), Some(5));
    assert_eq!(error.to_string(), "unknown parameter `k4`; known parameters: k1, k2, k3");
    assert_eq!(
        Expr::parse("x", &[]).expect_err("x").to_string(),
        "unknown parameter `x`; this expression has no parameters"
    );

    let error = parse("2*sqr(k1)");
    assert_eq!(error, ExprError::UnknownFunction { name: "sqr".into(), offset: 2 });
    assert!(error.to_string().starts_with("unknown function `sqr`; the functions are sqrt"));
    assert!(matches!(parse("k1(k2)"), ExprError::UnknownFunction { offset: 0, .. }));

    let error = parse("2*(k1 + k2");
    assert_eq!(error, ExprError::UnclosedParen { offset: 2 });
    assert_eq!(error.to_string(), "`(` is never closed; add a matching `)`");
    assert_eq!(parse("sqrt(k1"), ExprError::UnclosedParen { offset: 4 });
    assert_eq!(
        parse("(k1 k2)"),
        ExprError::Unexpected { found: "k2".into(), offset: 4, expected: "an operator or `)`" }
    );

    let error = parse("k1 k2");
    assert_eq!(
        error,
        ExprError::Unexpected {
            found: "k2".into(),
            offset: 3,
            expected: "an operator or the end of the expression"
        }
    );
    assert_eq!(error.to_string(), "unexpected `k2`; expected an operator or the end of the expression");
    assert_eq!(parse("k1)"), ExprError::UnmatchedParen { offset: 2 });
    assert_eq!(
        parse("k1 + "),
        ExprError::UnexpectedEnd { offset: 5, expected: "a number, a parameter, a function call or `(`" }
    );
    assert_eq!(
        parse("k1 + )"),
        ExprError::Unexpected {
            found: ")".into(),
            offset: 5,
            expected: "a number, a parameter, a function call or `(`"
        }
    );
    assert_eq!(
        parse("k1 & k2"),
        ExprError::Unexpected {
            found: "&".into(),
            offset: 3,
            expected: "an operator or the end of the expression"
        }
    );
    assert_eq!(
        parse("sqrt + 1"),
        ExprError::Unexpected { found: "+".into(), offset: 5, expected: "`(` after the function name" }
    );

    for text in ["", "   ", "\n\t"] {
        assert_eq!(parse(text), ExprError::Empty);
    }
    assert_eq!(ExprError::Empty.offset(), None);

    let error = parse("1.2.3");
    assert_eq!(error, ExprError::BadNumber { text: "1.2.3".into(), offset: 0 });
    assert!(error.to_string().starts_with("malformed number `1.2.3`"));
    assert_eq!(parse("k1 + 2k2"), ExprError::BadNumber { text: "2k2".into(), offset: 5 });

    let error = parse("k1**2");
    assert_eq!(error, ExprError::DoubleStar { offset: 2 });
    assert_eq!(error.to_string(), "`**` is not an operator; write powers with `^`, e.g. `x^2`");

    // The leftmost problem is reported.
    assert!(matches!(parse("k4 + 1.2.3"), ExprError::UnknownName { offset: 0, .. }));
    assert!(matches!(parse("1.2.3 + k4"), ExprError::BadNumber { offset: 0, .. }));

    let error = Expr::parse("2*pi*k", &["k", "pi"]).expect_err("pi is reserved");
    assert_eq!(error, ExprError::ReservedName { name: "pi".into() });
    assert!(error.to_string().contains("`pi` is reserved"));
    assert_eq!(error.offset(), None);
    // Checked even when the text does not use the name.
    assert!(matches!(Expr::parse("k", &["k", "sqrt"]), Err(ExprError::ReservedName { .. })));
    assert!(matches!(Expr::parse("k", &["k", "k"]), Err(ExprError::DuplicateName { .. })));
    assert!(matches!(Expr::parse("k", &["k", "2k"]), Err(ExprError::InvalidName { .. })));
}

/// Expressions over the parameters `a`, `b`, `c`, with values where they are all smooth.
const SMOOTH: [&str; 14] = [
    "a + b",
    "-b",
    "a*c + b*(a + c)",
    "2*a*b",
    "sqrt(a/b)/(2*pi)",
    "a^3 - b^-2",
    "a^2.5 + c^(1/3)",
    "a^b",
    "2^a*c",
    "exp(-a*b)*sin(c)",
    "ln(a) + log(b*c)",
    "cos(a*b)/tan(c)",
    "abs(a - b)*c",
    "(a - b)^2/(1 + c^2)^-1.5",
];
const NAMES: [&str; 3] = ["a", "b", "c"];
const POINT: [f64; 3] = [1.3, 0.7, 0.4];

#[test]
fn dual64_derivatives_match_central_differences() {
    for text in SMOOTH {
        let e = Expr::parse(text, &NAMES).expect(text);
        for i in 0..NAMES.len() {
            let seeded: Vec<Dual64> = POINT
                .iter()
                .enumerate()
                .map(|(j, &x)| if j == i { Dual64::from_re(x).derivative() } else { Dual64::from_re(x) })
                .collect();
            let exact = e.eval(&seeded);
            // num-dual divides by multiplying with the reciprocal: equal to rounding.
            assert_relative_eq!(exact.re, e.eval(&POINT), max_relative = 1e-15);
            let h = 1e-5;
            let shifted = |step: f64| {
                let mut x = POINT;
                x[i] += step;
                e.eval(&x)
            };
            let central = (shifted(h) - shifted(-h)) / (2.0 * h);
            assert_relative_eq!(exact.eps, central, max_relative = 1e-7, epsilon = 1e-8);
        }
    }
}

#[test]
fn dual_dvec64_gradient_matches_dual64_passes() {
    let n = NAMES.len();
    for text in SMOOTH {
        let e = Expr::parse(text, &NAMES).expect(text);
        let seeded: Vec<DualDVec64> =
            POINT.iter().enumerate().map(|(i, &x)| DualDVec64::from_re(x).derivative(n, i)).collect();
        let all = e.eval(&seeded);
        assert_relative_eq!(all.re, e.eval(&POINT), max_relative = 1e-15);
        let gradient = all.eps.0.expect("every expression here has variables");
        for i in 0..n {
            let seeded: Vec<Dual64> = POINT
                .iter()
                .enumerate()
                .map(|(j, &x)| if j == i { Dual64::from_re(x).derivative() } else { Dual64::from_re(x) })
                .collect();
            assert_relative_eq!(gradient[i], e.eval(&seeded).eps, max_relative = 1e-13, epsilon = 1e-15);
        }
    }
    // A constant has no derivative part at all.
    let constant = Expr::parse("2*pi", &NAMES).expect("parses");
    assert!(
        constant
            .eval(&[DualDVec64::from_re(1.0), DualDVec64::from_re(1.0), DualDVec64::from_re(1.0)])
            .eps
            .0
            .is_none()
    );
}

#[test]
fn negative_bases_with_integer_exponents_have_exact_derivatives() {
    let e = Expr::parse("x^3 + x^-1", &["x"]).expect("parses");
    let d = e.eval(&[Dual64::from_re(-2.0).derivative()]);
    assert_eq!(d.re, -8.0 - 0.5);
    assert_eq!(d.eps, 3.0 * 4.0 - 1.0 / 4.0);
}

/// A random expression: its text, fully parenthesised, and a reference evaluator.
#[derive(Clone, Debug)]
enum Tree {
    Num(f64),
    Var(usize),
    Neg(Box<Tree>),
    Bin(char, Box<Tree>, Box<Tree>),
    Pow(Box<Tree>, Box<Tree>),
    Call(&'static str, Box<Tree>),
}

impl Tree {
    fn text(&self) -> String {
        match self {
            Tree::Num(v) => format!("{v}"),
            Tree::Var(i) => NAMES[*i].to_string(),
            Tree::Neg(a) => format!("-({})", a.text()),
            Tree::Bin(op, a, b) => format!("({}) {op} ({})", a.text(), b.text()),
            Tree::Pow(a, b) => format!("({})^({})", a.text(), b.text()),
            Tree::Call(f, a) => format!("{f}({})", a.text()),
        }
    }

    fn has_variables(&self) -> bool {
        match self {
            Tree::Num(_) => false,
            Tree::Var(_) => true,
            Tree::Neg(a) | Tree::Call(_, a) => a.has_variables(),
            Tree::Bin(_, a, b) | Tree::Pow(a, b) => a.has_variables() || b.has_variables(),
        }
    }

    /// The documented semantics, written independently of the crate.
    fn eval(&self, x: &[f64]) -> f64 {
        match self {
            Tree::Num(v) => *v,
            Tree::Var(i) => x[*i],
            Tree::Neg(a) => -a.eval(x),
            Tree::Bin(op, a, b) => {
                let (a, b) = (a.eval(x), b.eval(x));
                match op {
                    '+' => a + b,
                    '-' => a - b,
                    '*' => a * b,
                    _ => a / b,
                }
            }
            Tree::Pow(a, b) => {
                let base = a.eval(x);
                let exponent = b.eval(x);
                if b.has_variables() {
                    (exponent * base.ln()).exp()
                } else if exponent.fract() == 0.0 && exponent.abs() <= 1024.0 {
                    base.powi(exponent as i32)
                } else {
                    base.powf(exponent)
                }
            }
            Tree::Call(f, a) => {
                let a = a.eval(x);
                match *f {
                    "sqrt" => a.sqrt(),
                    "exp" => a.exp(),
                    "ln" | "log" => a.ln(),
                    "sin" => a.sin(),
                    "cos" => a.cos(),
                    "tan" => a.tan(),
                    _ => a.abs(),
                }
            }
        }
    }
}

fn tree() -> impl Strategy<Value = Tree> {
    let leaf = prop_oneof![
        1 => (0u8..10).prop_map(|n| Tree::Num(f64::from(n))),
        1 => (0.01..100.0f64).prop_map(Tree::Num),
        3 => (0usize..3).prop_map(Tree::Var),
    ];
    leaf.prop_recursive(5, 32, 2, |inner| {
        let boxed = inner.prop_map(Box::new);
        prop_oneof![
            boxed.clone().prop_map(Tree::Neg),
            (prop::sample::select(vec!['+', '-', '*', '/']), boxed.clone(), boxed.clone())
                .prop_map(|(op, a, b)| Tree::Bin(op, a, b)),
            (boxed.clone(), (-3i8..4).prop_map(|n| Box::new(Tree::Num(f64::from(n)))))
                .prop_map(|(a, b)| Tree::Pow(a, b)),
            (boxed.clone(), boxed.clone()).prop_map(|(a, b)| Tree::Pow(a, b)),
            (prop::sample::select(vec!["sqrt", "exp", "ln", "log", "sin", "cos", "tan", "abs"]), boxed)
                .prop_map(|(f, a)| Tree::Call(f, a)),
        ]
    })
}

fn close(a: f64, b: f64) -> bool {
    if a.is_finite() && b.is_finite() {
        (a - b).abs() <= 1e-12 * a.abs().max(b.abs()) || a == b
    } else {
        a.is_nan() == b.is_nan() && (a.is_nan() || a == b)
    }
}

proptest! {
    #[test]
    fn random_trees_print_parse_and_evaluate_alike(tree in tree(), x in prop::array::uniform3(0.1..10.0f64)) {
        let text = tree.text();
        let e = match Expr::parse(&text, &NAMES) {
            Ok(e) => e,
            // A constant part such as `1/0` or `ln(-2)`: rejected by design.
            Err(ExprError::NonFiniteConstant { .. }) => return Ok(()),
            Err(error) => panic!("`{text}`: {error}"),
        };
        let reference = tree.eval(&x);
        prop_assert!(close(e.eval(&x), reference), "`{}` at {:?}: {} vs {}", text, x, e.eval(&x), reference);
        let canonical = e.to_string();
        let again = Expr::parse(&canonical, &NAMES);
        prop_assert_eq!(again.as_ref(), Ok(&e), "`{}` printed as `{}`", text, canonical);
        prop_assert!(close(again.map_or(f64::NAN, |a| a.eval(&x)), reference));
    }

    #[test]
    fn random_text_never_panics(text in "[a-c0-9_+*/^(). eE,-]{0,40}") {
        check_result(&text)?;
    }

    #[test]
    fn arbitrary_unicode_never_panics(text in any::<String>()) {
        check_result(&text)?;
    }

    #[test]
    fn near_misses_never_panic(
        base in prop::sample::select(SMOOTH.to_vec()),
        at in any::<prop::sample::Index>(),
        insert in "[-+*/^()., a-z0-9]{0,3}",
    ) {
        let mut text = base.to_string();
        let at = at.index(text.len() + 1);
        text.insert_str(at, &insert);
        check_result(&text)?;
    }
}

/// Parsing returns; an error's offset lies in the text; a success prints as something that
/// parses back to it.
fn check_result(text: &str) -> Result<(), TestCaseError> {
    match Expr::parse(text, &NAMES) {
        Ok(e) => prop_assert_eq!(Expr::parse(&e.to_string(), &NAMES), Ok(e)),
        Err(error) => {
            if let Some(offset) = error.offset() {
                prop_assert!(offset <= text.len() && text.is_char_boundary(offset), "{:?}", error);
            }
            prop_assert!(!error.to_string().is_empty());
        }
    }
    Ok(())
}
