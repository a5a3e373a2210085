//! Evaluation over num-dual scalars.

use super::{BinOp, Func, Node};
use num_dual::DualNum;

impl Node {
    /// The value with `vars[i]` for variable `i`. Used for constant folding too (with no
    /// variables), so folded constants are exactly what evaluation would compute.
    pub(super) fn eval<D: DualNum<Primitive = f64>>(&self, vars: &[D]) -> D {
        match self {
            Node::Num(value) => D::from(*value),
            Node::Var(i) => vars[*i].clone(),
            Node::Neg(a) => -a.eval(vars),
            Node::Bin(op, a, b) => op.apply(a.eval(vars), b.eval(vars)),
            Node::Powi(a, n) => a.eval(vars).powi(*n),
            Node::Powf(a, n) => constant_pow(a.eval(vars), *n),
            Node::Pow(a, b) => general_pow(a.eval(vars), b.eval(vars)),
            Node::Call(func, a) => func.apply(a.eval(vars)),
        }
    }

    /// The innermost, leftmost subtree whose `f64` value is not finite, if any.
    pub(super) fn first_non_finite(&self, vars: &[f64]) -> Option<&Node> {
        let children: [Option<&Node>; 2] = match self {
            Node::Num(_) | Node::Var(_) => [None, None],
            Node::Neg(a) | Node::Powi(a, _) | Node::Powf(a, _) | Node::Call(_, a) => [Some(a), None],
            Node::Bin(_, a, b) | Node::Pow(a, b) => [Some(a), Some(b)],
        };
        children.into_iter().flatten().find_map(|child| child.first_non_finite(vars)).or_else(|| {
            let value: f64 = self.eval(vars);
            (!value.is_finite()).then_some(self)
        })
    }
}

impl BinOp {
    fn apply<D: DualNum<Primitive = f64>>(self, a: D, b: D) -> D {
        match self {
            BinOp::Add => a + b,
            BinOp::Sub => a - b,
            BinOp::Mul => a * b,
            BinOp::Div => a / b,
        }
    }
}

impl Func {
    fn apply<D: DualNum<Primitive = f64>>(self, a: D) -> D {
        match self {
            Func::Sqrt => a.sqrt(),
            Func::Exp => a.exp(),
            Func::Ln => a.ln(),
            Func::Sin => a.sin(),
            Func::Cos => a.cos(),
            Func::Tan => a.tan(),
            Func::Abs => a.abs(),
        }
    }
}

/// `a^n` for a constant exponent too large for `powi` or not an integer, alike for `f64` and dual
/// numbers. num-dual's `powf` raises the real part to n − 1 (or n − 3) and multiplies back, so
/// for a negative base it gave a number where `f64` gives NaN (`x^1e-200`, where n − 1 rounds to −1), or the
/// wrong sign (an even n beyond 2⁵³, where n − 1 rounds to n); found with `fuzz/expression`. A
/// negative base is raised as ±|a|^n for an integer n and is NaN otherwise, as in `f64`.
fn constant_pow<D: DualNum<Primitive = f64>>(a: D, n: f64) -> D {
    if a.re() >= 0.0 || a.re().is_nan() {
        return a.powf(n);
    }
    if n.fract() != 0.0 {
        return D::from(f64::NAN);
    }
    let magnitude = (-a).powf(n);
    if (n / 2.0).fract() == 0.0 { magnitude } else { -magnitude }
}

/// `a^b = exp(b*ln(a))` for an exponent that depends on variables: the same formula for `f64`
/// and dual numbers (num-dual's `powd` is `powf` for `f64`), so a negative base gives NaN for all.
fn general_pow<D: DualNum<Primitive = f64>>(a: D, b: D) -> D {
    (a.ln() * b).exp()
}
