//! Unit tests on the tree: canonical printing, folding, power selection, limits, and a
//! round trip of random (folded) trees through `Display` and `parse`.

use super::*;
use proptest::prelude::*;

const NAMES: [&str; 3] = ["x", "y", "z"];

fn expr(text: &str) -> Expr {
    Expr::parse(text, &NAMES).unwrap_or_else(|e| panic!("`{text}`: {e}"))
}

#[test]
fn canonical_text() {
    for (text, canonical) in [
        ("x+y", "x + y"),
        ("x - (y - z)", "x - (y - z)"),
        ("(x - y) - z", "x - y - z"),
        ("x * (y / z)", "x*(y/z)"),
        ("x + -y", "x + (-y)"),
        ("x * -2", "x*(-2)"),
        ("-x*y", "-x*y"),
        ("-(x*y)", "-(x*y)"),
        ("--x", "-(-x)"),
        ("+x", "x"),
        ("-x^2", "-x^2"),
        ("(-x)^2", "(-x)^2"),
        ("x^y^z", "x^y^z"),
        ("(x^y)^z", "(x^y)^z"),
        ("x^-y", "x^-y"),
        ("x^(y+1)", "x^(y + 1)"),
        ("x^-1", "x^-1"),
        ("x^0.5", "x^0.5"),
        ("x^-2.5", "x^-2.5"),
        ("(-2)^x", "(-2)^x"),
        ("log(x) + LN_2", "ln(x) + LN_2"),
        ("2*pi*x", "6.283185307179586*x"),
        ("x*2*pi", "x*2*3.141592653589793"),
        ("1e-7*x + 2.5e20*y + 0.001*z", "1e-7*x + 2.5e20*y + 0.001*z"),
        ("sqrt( x / y )", "sqrt(x/y)"),
        ("abs(-x)", "abs(-x)"),
        ("-0", "-0"),
    ] {
        let names = ["x", "y", "z", "LN_2"];
        let e = Expr::parse(text, &names).unwrap_or_else(|e| panic!("`{text}`: {e}"));
        assert_eq!(e.to_string(), canonical, "{text}");
        assert_eq!(Expr::parse(canonical, &names), Ok(e), "{text}");
    }
}

#[test]
fn constants_fold() {
    let e = expr("2*3 + x");
    assert_eq!(e.node, Node::Bin(BinOp::Add, Box::new(Node::Num(6.0)), Box::new(Node::Var(0))));
    for (text, value) in
        [("-(2)", -2.0), ("2^-1", 0.5), ("(-2)^3", -8.0), ("sqrt(16)", 4.0), ("2^0.5", 2f64.sqrt())]
    {
        let e = expr(text);
        assert!(e.is_constant(), "{text}");
        assert_eq!(e.as_constant(), Some(value), "{text}");
        assert_eq!(e.variables(), [] as [usize; 0]);
    }
    assert_eq!(expr("x*0").as_constant(), None);
}

#[test]
fn power_kinds() {
    assert!(matches!(expr("x^3").node, Node::Powi(_, 3)));
    assert!(matches!(expr("x^-2").node, Node::Powi(_, -2)));
    assert!(matches!(expr("x^(4/2)").node, Node::Powi(_, 2)));
    assert!(matches!(expr("x^1024").node, Node::Powi(_, 1024)));
    assert!(matches!(expr("x^1025").node, Node::Powf(_, 1025.0)));
    assert!(matches!(expr("x^0.5").node, Node::Powf(_, 0.5)));
    assert!(matches!(expr("x^y").node, Node::Pow(..)));
    assert!(matches!(expr("2^y").node, Node::Pow(..)));
    assert_eq!(expr("x^3").eval(&[-2.0, 0.0, 0.0]), -8.0);
    assert!(expr("x^0.5").eval(&[-4.0f64, 0.0, 0.0]).is_nan());
    assert!(expr("x^y").eval(&[-2.0f64, 3.0, 0.0]).is_nan(), "general powers need a positive base");
}

#[test]
fn variables_sorted_unique() {
    assert_eq!(expr("z*x + x^z - 1").variables(), [0, 2]);
    assert!(!expr("y").is_constant());
}

#[test]
fn non_finite_constants() {
    for (text, part, offset) in
        [("1/0", "1/0", 0), ("x + (0/0)", "0/0", 5), ("ln(-1)*x", "ln(-1)", 0), ("1e999", "1e999", 0)]
    {
        match Expr::parse(text, &NAMES) {
            Err(ExprError::NonFiniteConstant { text: found, offset: at, .. }) => {
                assert_eq!((found.as_str(), at), (part, offset), "{text}")
            }
            other => panic!("`{text}`: {other:?}"),
        }
    }
}

#[test]
fn depth_limits() {
    let nested = |n: usize| format!("{}x{}", "(".repeat(n), ")".repeat(n));
    assert!(Expr::parse(&nested(50), &NAMES).is_ok());
    assert!(matches!(Expr::parse(&nested(10_000), &NAMES), Err(ExprError::TooDeep { .. })));
    let negations = format!("{}x", "-".repeat(10_000));
    assert!(matches!(Expr::parse(&negations, &NAMES), Err(ExprError::TooDeep { .. })));
    let chain = vec!["x"; 10_000].join(" + ");
    assert!(matches!(Expr::parse(&chain, &NAMES), Err(ExprError::TooDeep { .. })));
    let powers = vec!["x"; 10_000].join("^");
    assert!(matches!(Expr::parse(&powers, &NAMES), Err(ExprError::TooDeep { .. })));
    // A tree at the limit prints as text that parses back to it, however its print nests.
    for text in [
        format!("{}x", "-".repeat(MAX_DEPTH - 1)),
        format!("{}x{}", "x - -(".repeat(MAX_DEPTH / 2 - 1), ")".repeat(MAX_DEPTH / 2 - 1)),
        format!("{}x{}", "y^-(".repeat(MAX_DEPTH / 2 - 1), ")".repeat(MAX_DEPTH / 2 - 1)),
    ] {
        let e = Expr::parse(&text, &NAMES).unwrap_or_else(|err| panic!("{text}: {err}"));
        let printed = e.to_string();
        assert_eq!(Expr::parse(&printed, &NAMES).as_ref(), Ok(&e), "{text} printed as {printed}");
    }
    // Constant chains fold as they go, so their length is not limited.
    let sum = vec!["1"; 10_000].join(" + ");
    assert_eq!(Expr::parse(&sum, &NAMES).map(|e| e.as_constant()), Ok(Some(10_000.0)));
}

#[test]
fn eval_checked_names_the_first_non_finite_part() {
    let e = expr("x + ln(y - z)/2");
    assert_eq!(e.eval_checked(&[1.0, 3.0, 2.0]), Ok(1.0));
    let error = e.eval_checked(&[1.0, 2.0, 3.0]).unwrap_err();
    assert_eq!(error.part, "ln(y - z)");
    assert!(error.value.is_nan());
    assert_eq!(
        error.to_string(),
        "`x + ln(y - z)/2` evaluates to NaN; the first non-finite part is `ln(y - z)`"
    );
    let error = expr("x/y").eval_checked(&[1.0, 0.0, 0.0]).unwrap_err();
    assert_eq!(error.to_string(), "`x/y` evaluates to inf");
    let error = expr("x*y").eval_checked(&[f64::NAN, 1.0, 0.0]).unwrap_err();
    assert_eq!(error.part, "x");
    // Only the result counts: a finite value passes even if a part overflowed.
    assert_eq!(expr("1/exp(x)").eval_checked(&[1000.0, 0.0, 0.0]), Ok(0.0));
}

#[test]
#[should_panic(expected = "takes 3 parameter values, got 2")]
fn eval_checks_the_number_of_values() {
    expr("x").eval(&[1.0, 2.0]);
}

/// Random trees over x, y, z with numbers of any sign and size.
fn tree() -> impl Strategy<Value = Node> {
    let number = prop_oneof![
        (-20i32..20).prop_map(f64::from),
        -1e3..1e3f64,
        prop::sample::select(vec![0.5, -0.25, 1e-7, -3e-9, 2.5e20, 6.02e23, 1e15, 1e16, -0.0, 1e-4, 9.99e-5]),
    ];
    let leaf = prop_oneof![1 => number.prop_map(Node::Num), 2 => (0usize..3).prop_map(Node::Var)];
    leaf.prop_recursive(6, 48, 2, |inner| {
        let boxed = inner.clone().prop_map(Box::new);
        prop_oneof![
            boxed.clone().prop_map(Node::Neg),
            (
                prop::sample::select(vec![BinOp::Add, BinOp::Sub, BinOp::Mul, BinOp::Div]),
                boxed.clone(),
                boxed.clone()
            )
                .prop_map(|(op, a, b)| Node::Bin(op, a, b)),
            (boxed.clone(), -4i32..5).prop_map(|(a, n)| Node::Powi(a, n)),
            (boxed.clone(), prop::sample::select(vec![0.5, -1.5, 1.0 / 3.0, 2.25e-5]))
                .prop_map(|(a, n)| Node::Powf(a, n)),
            (boxed.clone(), boxed.clone()).prop_map(|(a, b)| Node::Pow(a, b)),
            (
                prop::sample::select(vec![
                    Func::Sqrt,
                    Func::Exp,
                    Func::Ln,
                    Func::Sin,
                    Func::Cos,
                    Func::Tan,
                    Func::Abs
                ]),
                boxed
            )
                .prop_map(|(func, a)| Node::Call(func, a)),
        ]
    })
}

/// Folds constant subtrees as the parser does; `None` if a constant is not finite.
fn fold(node: Node) -> Option<Node> {
    let node = match node {
        Node::Num(_) | Node::Var(_) => node,
        Node::Neg(a) => Node::Neg(Box::new(fold(*a)?)),
        Node::Bin(op, a, b) => Node::Bin(op, Box::new(fold(*a)?), Box::new(fold(*b)?)),
        Node::Powi(a, n) => Node::Powi(Box::new(fold(*a)?), n),
        Node::Powf(a, n) => Node::Powf(Box::new(fold(*a)?), n),
        Node::Pow(a, b) => match fold(*b)? {
            Node::Num(n) if n.fract() == 0.0 && n.abs() <= MAX_POWI => {
                Node::Powi(Box::new(fold(*a)?), n as i32)
            }
            Node::Num(n) => Node::Powf(Box::new(fold(*a)?), n),
            b => Node::Pow(Box::new(fold(*a)?), Box::new(b)),
        },
        Node::Call(func, a) => Node::Call(func, Box::new(fold(*a)?)),
    };
    let mut variables = Vec::new();
    node.collect_variables(&mut variables);
    if !variables.is_empty() {
        return Some(node);
    }
    let value: f64 = node.eval(&[]);
    value.is_finite().then_some(Node::Num(value))
}

proptest! {
    #[test]
    fn random_trees_print_and_parse_back(node in tree()) {
        let Some(node) = fold(node) else { return Ok(()) };
        let names: Arc<[String]> = NAMES.iter().map(|name| name.to_string()).collect();
        let e = Expr { node, names };
        let text = e.to_string();
        prop_assert_eq!(Expr::parse(&text, &NAMES), Ok(e), "{}", text);
    }
}

/// A constant power beyond `powi` or not an integer, of a negative base: the dual number's real
/// part is f64's value and its derivative n·a^(n−1) (found with `fuzz/expression`: num-dual's
/// `powf` gave a finite value where f64 gives NaN, and the wrong sign for huge even powers).
#[test]
fn constant_powers_of_a_negative_base_agree_with_f64() {
    use num_dual::Dual64;
    let seeded = |x: f64| [Dual64::from_re(x).derivative(), Dual64::from_re(0.0), Dual64::from_re(0.0)];
    for (text, n) in [("x^2001", 2001.0), ("x^2000", 2000.0), ("x^-1025", -1025.0)] {
        let e = expr(text);
        let (value, dual) = (e.eval(&[-1.01, 0.0, 0.0]), e.eval(&seeded(-1.01)));
        let exact = (-1.01f64).powi(n as i32);
        assert!((value - exact).abs() <= 1e-12 * exact.abs(), "{text}: {value} against {exact}");
        assert_eq!(dual.re, value, "{text}");
        let slope = n * (-1.01f64).powi(n as i32 - 1);
        assert!((dual.eps - slope).abs() <= 1e-12 * slope.abs(), "{text}: {} against {slope}", dual.eps);
    }
    let e = expr("x^1e-200");
    assert!(e.eval(&[-0.7f64, 0.0, 0.0]).is_nan());
    assert!(e.eval(&seeded(-0.7)).re.is_nan());
    let huge = expr("x^-777777777777777778");
    assert_eq!(huge.eval(&seeded(-0.7)).re, huge.eval(&[-0.7f64, 0.0, 0.0]));
}
