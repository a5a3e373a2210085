//! Model descriptions of any linear structure.
//!
//! A model file writes the entries of its matrices as expressions of named parameters, for
//! example `k1 + k2`, `-k2`, `alpha*m1 + beta*(k1 + k2)`, `2*zeta*omega` or `sqrt(k/m)/(2*pi)`.
//! Each expression is parsed once into an [`Expr`] and then evaluated as often as needed over
//! any num-dual scalar (`f64`, `Dual64`, `DualDVec64`, …), so exact derivatives with respect to
//! the parameters come out of the same code.
//!
//! # The expression language
//!
//! ```text
//! expr    := term (('+' | '-') term)*
//! term    := unary (('*' | '/') unary)*
//! unary   := ('-' | '+') unary | power
//! power   := primary ('^' unary)?          right-associative: 2^3^2 = 2^9, -x^2 = -(x^2), 2^-1 = 0.5
//! primary := number | name | name '(' expr ')' | '(' expr ')'
//! number  := 12 | 1.5 | .5 | 5. | 2.5e6 | 1E-3
//! name    := [A-Za-z_][A-Za-z0-9_]*
//! ```
//!
//! Whitespace may separate any two tokens. The functions are `sqrt`, `exp`, `ln` (alias `log`),
//! `sin`, `cos`, `tan` and `abs`; the only constant is `pi` (`e` is an ordinary name). Any other
//! name must be one of the parameters the expression is parsed with; the function names and
//! `pi` cannot be parameter names. Powers are written `^` (`**` is rejected).
//!
//! ```
//! use structure::Expr;
//!
//! let e = Expr::parse("alpha*m1 + beta*(k1 + k2)", &["alpha", "beta", "m1", "k1", "k2"])?;
//! assert_eq!(e.eval(&[0.1, 0.01, 2.0, 100.0, 50.0]), 0.1 * 2.0 + 0.01 * 150.0);
//! # Ok::<(), structure::ExprError>(())
//! ```

pub mod expr;

pub use expr::{EvalError, Expr, ExprError};
