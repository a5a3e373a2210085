//! A model file's expression (`"k1 + k2"`, `"sqrt(k/m)"`, …): parsing must answer Ok or a located
//! error, never panic; an expression that parses must print as text that parses to the same
//! tree and values, and evaluate alike in f64 and checked.
//!
//! The dual number's real part is not compared: num-dual rounds powers differently in the last
//! bits (`a^3` as a product, `x^n` through x^(n−1)), and a cancellation (`1 - 0.7^1e-7`) turns
//! that into any relative difference. Its first runs found one real fault that way (a negative
//! base's constant power, now `expr::eval::constant_pow`, with its own test).
#![no_main]

use libfuzzer_sys::fuzz_target;
use structure::Expr;

const NAMES: [&str; 3] = ["a", "b", "c"];
const VALUES: [f64; 3] = [1.3, -0.7, 2.5];

fn same(x: f64, y: f64) -> bool {
    x == y || (x.is_nan() && y.is_nan())
}

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else { return };
    let Ok(expr) = Expr::parse(text, &NAMES) else { return };
    let value = expr.eval(&VALUES);
    match expr.eval_checked(&VALUES) {
        Ok(checked) => assert!(same(value, checked), "{text}: {value} but checked {checked}"),
        Err(e) => assert!(!value.is_finite(), "{text}: {value} reported as {e}"),
    }
    let printed = expr.to_string();
    let again = Expr::parse(&printed, &NAMES)
        .unwrap_or_else(|e| panic!("{text:?} printed as {printed:?}, which does not parse: {e}"));
    assert!(again == expr, "{text:?} printed as {printed:?} parses to another tree");
    let value_again = again.eval(&VALUES);
    assert!(same(value, value_again), "{text:?} = {value}, printed as {printed:?} = {value_again}");
});
