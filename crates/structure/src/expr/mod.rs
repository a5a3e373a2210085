//! Expressions of named parameters: parsed once, evaluated over any num-dual scalar.
//!
//! [`Expr::parse`] turns text such as `sqrt(k/m)/(2*pi)` into a small tree in which every
//! parameter is an index into the list of names it was parsed with and every constant subtree
//! is already folded into one number. [`Expr::eval`] then evaluates the tree for `f64` or any
//! dual number over `f64`, which gives exact derivatives with respect to the parameters.
//!
//! Powers are evaluated as follows:
//!
//! * a constant integer exponent (|n| ≤ 1024) uses `powi`: exact derivatives and correct signs
//!   for negative bases, `(-2)^3 = -8`;
//! * any other constant exponent uses `powf` (a negative base gives NaN);
//! * an exponent that depends on parameters uses `exp(b*ln(a))`, so the base must be positive
//!   (otherwise the value is NaN, for `f64` and for dual numbers alike).
//!
//! The grammar is described in the [crate documentation](crate).

mod display;
mod eval;
mod lexer;
mod parser;

use num_dual::DualNum;
use std::fmt;
use std::sync::Arc;

/// The largest integer exponent evaluated with `powi`; larger ones use `powf`.
const MAX_POWI: f64 = 1024.0;

/// How deeply an expression's tree may nest (unary operators, operator chains, calls); its text
/// may nest parentheses more deeply, up to four times this.
pub const MAX_DEPTH: usize = 100;

/// A parsed expression of named parameters.
///
/// Two expressions are equal when they have the same tree and the same parameter names.
/// [`Display`](fmt::Display) prints a canonical form that parses back (with the same names) to
/// an equal expression.
#[derive(Clone, Debug, PartialEq)]
pub struct Expr {
    node: Node,
    names: Arc<[String]>,
}

/// A node of the expression tree. Invariant: every subtree without variables is a `Num`.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Node {
    Num(f64),
    Var(usize),
    Neg(Box<Node>),
    Bin(BinOp, Box<Node>, Box<Node>),
    /// Constant integer exponent.
    Powi(Box<Node>, i32),
    /// Constant non-integer exponent.
    Powf(Box<Node>, f64),
    /// Exponent that depends on variables: `exp(b*ln(a))`.
    Pow(Box<Node>, Box<Node>),
    Call(Func, Box<Node>),
}

/// A binary arithmetic operator.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum BinOp {
    Add,
    Sub,
    Mul,
    Div,
}

/// A built-in function of one argument.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Func {
    Sqrt,
    Exp,
    Ln,
    Sin,
    Cos,
    Tan,
    Abs,
}

impl Func {
    pub(crate) fn from_name(name: &str) -> Option<Func> {
        Some(match name {
            "sqrt" => Func::Sqrt,
            "exp" => Func::Exp,
            "ln" | "log" => Func::Ln,
            "sin" => Func::Sin,
            "cos" => Func::Cos,
            "tan" => Func::Tan,
            "abs" => Func::Abs,
            _ => return None,
        })
    }

    /// The canonical name, used when printing.
    pub(crate) fn name(self) -> &'static str {
        match self {
            Func::Sqrt => "sqrt",
            Func::Exp => "exp",
            Func::Ln => "ln",
            Func::Sin => "sin",
            Func::Cos => "cos",
            Func::Tan => "tan",
            Func::Abs => "abs",
        }
    }
}

impl Expr {
    /// Parses `text`, in which the parameters `names` may appear; a parameter becomes its index
    /// in `names`, the index of its value in the slice given to [`eval`](Self::eval).
    ///
    /// The names must be distinct identifiers other than `pi` and the function names; this is
    /// checked even when the text does not use them.
    ///
    /// ```
    /// use structure::Expr;
    ///
    /// let f = Expr::parse("sqrt(k/m)/(2*pi)", &["k", "m"])?;
    /// let hz = f.eval(&[4.0 * std::f64::consts::PI.powi(2), 1.0]);
    /// assert!((hz - 1.0).abs() < 1e-15);
    /// assert_eq!(f.to_string(), "sqrt(k/m)/6.283185307179586");
    /// # Ok::<(), structure::ExprError>(())
    /// ```
    pub fn parse(text: &str, names: &[&str]) -> Result<Expr, ExprError> {
        let node = parser::parse(text, names)?;
        Ok(Expr { node, names: names.iter().map(|name| name.to_string()).collect() })
    }

    /// The parameter names the expression was parsed with.
    pub fn names(&self) -> &[String] {
        &self.names
    }

    /// Evaluates the expression with `vars[i]` as the value of parameter `names[i]`.
    ///
    /// Works for `f64` and for every num-dual number over `f64` (`Dual64`, `DualDVec64`, …), so
    /// seeding the parameters with derivative directions gives exact derivatives. Non-finite
    /// results (division by zero, `ln` of a negative number, …) are returned as they are; see
    /// [`eval_checked`](Self::eval_checked).
    ///
    /// ```
    /// use num_dual::Dual64;
    /// use structure::Expr;
    ///
    /// let e = Expr::parse("k1^3/k2", &["k1", "k2"])?;
    /// let d = e.eval(&[Dual64::from_re(2.0).derivative(), Dual64::from_re(4.0)]);
    /// assert_eq!((d.re, d.eps), (2.0, 3.0)); // ∂/∂k1 = 3 k1²/k2
    /// # Ok::<(), structure::ExprError>(())
    /// ```
    ///
    /// # Panics
    ///
    /// If `vars.len()` differs from the number of names.
    pub fn eval<D: DualNum<Primitive = f64>>(&self, vars: &[D]) -> D {
        self.check_len(vars.len());
        self.node.eval(vars)
    }

    /// Evaluates in `f64` and reports a non-finite result, naming the expression and its first
    /// non-finite part (innermost, leftmost).
    ///
    /// # Panics
    ///
    /// If `vars.len()` differs from the number of names.
    pub fn eval_checked(&self, vars: &[f64]) -> Result<f64, EvalError> {
        self.check_len(vars.len());
        let value = self.node.eval(vars);
        if value.is_finite() {
            return Ok(value);
        }
        let part = self.node.first_non_finite(vars).unwrap_or(&self.node);
        Err(EvalError {
            expression: self.to_string(),
            value,
            part: display::Show { node: part, names: &self.names }.to_string(),
        })
    }

    /// The indices of the parameters the expression depends on, sorted and without repeats.
    pub fn variables(&self) -> Vec<usize> {
        let mut out = Vec::new();
        self.node.collect_variables(&mut out);
        out.sort_unstable();
        out.dedup();
        out
    }

    /// Whether the expression depends on no parameter.
    pub fn is_constant(&self) -> bool {
        matches!(self.node, Node::Num(_))
    }

    /// The value of a constant expression, `None` if it depends on parameters.
    pub fn as_constant(&self) -> Option<f64> {
        match self.node {
            Node::Num(value) => Some(value),
            _ => None,
        }
    }

    fn check_len(&self, len: usize) {
        assert_eq!(
            len,
            self.names.len(),
            "expression `{self}` takes {} parameter values, got {len}",
            self.names.len()
        );
    }
}

impl fmt::Display for Expr {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        display::Show { node: &self.node, names: &self.names }.fmt(f)
    }
}

impl Node {
    fn collect_variables(&self, out: &mut Vec<usize>) {
        match self {
            Node::Num(_) => {}
            Node::Var(i) => out.push(*i),
            Node::Neg(a) | Node::Powi(a, _) | Node::Powf(a, _) | Node::Call(_, a) => a.collect_variables(out),
            Node::Bin(_, a, b) | Node::Pow(a, b) => {
                a.collect_variables(out);
                b.collect_variables(out);
            }
        }
    }
}

/// Why a text is not a valid expression.
///
/// Offsets are byte offsets into the expression text, for the caller to turn into a line and
/// column of its file.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum ExprError {
    /// The text holds no expression.
    #[error("empty expression; write a number, a parameter or a formula such as `k1 + k2`")]
    Empty,
    /// A name that is neither a parameter nor `pi`.
    #[error("unknown parameter `{name}`; {}", known_names(.known))]
    UnknownName {
        /// The name as written.
        name: String,
        /// Byte offset of the name.
        offset: usize,
        /// The parameter names the expression may use.
        known: Vec<String>,
    },
    /// A call of a function that does not exist.
    #[error(
        "unknown function `{name}`; the functions are sqrt, exp, ln, log, sin, cos, tan and abs \
         (write a product with `*`)"
    )]
    UnknownFunction {
        /// The name as written.
        name: String,
        /// Byte offset of the name.
        offset: usize,
    },
    /// A token that cannot stand where it is.
    #[error("unexpected `{found}`; expected {expected}")]
    Unexpected {
        /// The token as written.
        found: String,
        /// Byte offset of the token.
        offset: usize,
        /// What could stand there.
        expected: &'static str,
    },
    /// The text ends where more is needed.
    #[error("the expression ends too early; expected {expected}")]
    UnexpectedEnd {
        /// Byte offset of the end (the length of the text).
        offset: usize,
        /// What is missing.
        expected: &'static str,
    },
    /// A `(` without its `)`.
    #[error("`(` is never closed; add a matching `)`")]
    UnclosedParen {
        /// Byte offset of the `(`.
        offset: usize,
    },
    /// A `)` without its `(`.
    #[error("`)` has no matching `(`; remove it or add a `(`")]
    UnmatchedParen {
        /// Byte offset of the `)`.
        offset: usize,
    },
    /// A malformed number such as `1.2.3`, `1e` or `2x`.
    #[error("malformed number `{text}`; write numbers like 12, 1.5, .5 or 2.5e6, and products with `*`")]
    BadNumber {
        /// The number as written.
        text: String,
        /// Byte offset of the number.
        offset: usize,
    },
    /// `**` used as the power operator.
    #[error("`**` is not an operator; write powers with `^`, e.g. `x^2`")]
    DoubleStar {
        /// Byte offset of the `**`.
        offset: usize,
    },
    /// A constant part of the expression is infinite or NaN, such as `1/0` or `1e999`.
    #[error("the constant `{text}` evaluates to {value}, which is not a finite number")]
    NonFiniteConstant {
        /// The constant part as written.
        text: String,
        /// Byte offset of the constant part.
        offset: usize,
        /// Its value.
        value: f64,
    },
    /// The expression nests more than [`MAX_DEPTH`] levels.
    #[error("the expression nests more than {MAX_DEPTH} levels deep; split it into simpler parts")]
    TooDeep {
        /// Byte offset of the token where the limit was exceeded.
        offset: usize,
    },
    /// A parameter is named `pi` or like a function.
    #[error("parameter name `{name}` is reserved for a built-in constant or function; rename the parameter")]
    ReservedName {
        /// The parameter name.
        name: String,
    },
    /// A parameter name that is not an identifier, so it could never be written.
    #[error(
        "parameter name `{name}` is not a valid name; names start with a letter or `_`, followed \
         by letters, digits or `_`"
    )]
    InvalidName {
        /// The parameter name.
        name: String,
    },
    /// A parameter name given twice.
    #[error("parameter name `{name}` is given twice; parameter names must be distinct")]
    DuplicateName {
        /// The parameter name.
        name: String,
    },
}

fn known_names(known: &[String]) -> String {
    if known.is_empty() {
        "this expression has no parameters".to_string()
    } else {
        format!("known parameters: {}", known.join(", "))
    }
}

impl ExprError {
    /// Byte offset in the expression text of the offending token, if the error has one.
    pub fn offset(&self) -> Option<usize> {
        match self {
            ExprError::UnknownName { offset, .. }
            | ExprError::UnknownFunction { offset, .. }
            | ExprError::Unexpected { offset, .. }
            | ExprError::UnexpectedEnd { offset, .. }
            | ExprError::UnclosedParen { offset }
            | ExprError::UnmatchedParen { offset }
            | ExprError::BadNumber { offset, .. }
            | ExprError::DoubleStar { offset }
            | ExprError::NonFiniteConstant { offset, .. }
            | ExprError::TooDeep { offset } => Some(*offset),
            ExprError::Empty
            | ExprError::ReservedName { .. }
            | ExprError::InvalidName { .. }
            | ExprError::DuplicateName { .. } => None,
        }
    }
}

/// A non-finite value from [`Expr::eval_checked`].
#[derive(Clone, Debug, PartialEq)]
pub struct EvalError {
    /// The expression, in its canonical text form.
    pub expression: String,
    /// Its value (infinite or NaN).
    pub value: f64,
    /// The innermost, leftmost non-finite part of the expression (perhaps the whole of it, or a
    /// parameter whose value is not finite).
    pub part: String,
}

impl fmt::Display for EvalError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "`{}` evaluates to {}", self.expression, self.value)?;
        if self.part != self.expression {
            write!(f, "; the first non-finite part is `{}`", self.part)?;
        }
        Ok(())
    }
}

impl std::error::Error for EvalError {}

#[cfg(test)]
mod tests;
