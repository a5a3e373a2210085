//! A model file's expression (`"k1 + k2"`, `"sqrt(k/m)"`, …): parsing must answer Ok or a located
//! error, never panic; an expression that parses must print as text that parses to the same
//! values, and evaluate alike in f64, checked, and (but for rounding) as a dual number's real part.
#![no_main]

use libfuzzer_sys::fuzz_target;
use num_dual::Dual64;
use structure::Expr;

const NAMES: [&str; 3] = ["a", "b", "c"];
const VALUES: [f64; 3] = [1.3, -0.7, 2.5];

fn same(x: f64, y: f64) -> bool {
    x == y || (x.is_nan() && y.is_nan())
}

/// Equal but for rounding: num-dual's powers and functions may round the real part differently
/// in the last bits (`a^3` as a product, not `powi`; `a^(a^22)` through exp and ln).
fn close(x: f64, y: f64) -> bool {
    same(x, y) || (x - y).abs() <= 1e-10 * x.abs().max(y.abs())
}

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else { return };
    let Ok(expr) = Expr::parse(text, &NAMES) else { return };
    let value = expr.eval(&VALUES);
    match expr.eval_checked(&VALUES) {
        Ok(checked) => assert!(same(value, checked), "{text}: {value} but checked {checked}"),
        Err(e) => assert!(!value.is_finite(), "{text}: {value} reported as {e}"),
    }
    let dual = expr.eval(&VALUES.map(Dual64::from_re).map(|d| d.derivative()));
    // Through an infinite part the two may differ (`ln(0)^-1` is -0 in f64, NaN in num-dual). A
    // model checks the values it assembles and reports a non-finite one, so only finite values
    // must agree.
    if value.is_finite() && dual.re.is_finite() {
        assert!(close(value, dual.re), "{text}: {value} but the dual's real part {}", dual.re);
    }
    let printed = expr.to_string();
    let again = Expr::parse(&printed, &NAMES)
        .unwrap_or_else(|e| panic!("{text:?} printed as {printed:?}, which does not parse: {e}"));
    let value_again = again.eval(&VALUES);
    assert!(same(value, value_again), "{text:?} = {value}, printed as {printed:?} = {value_again}");
});
