//! The canonical text form: parentheses only where the tree needs them (and around a negative
//! right operand of `+ - * /`), spaces around `+` and `-` only, numbers in their shortest
//! round-trip form. It parses back to an equal tree.

use super::{BinOp, Node};
use std::fmt::{self, Display, Formatter};

/// A node with the names of its variables, for printing.
pub(super) struct Show<'a> {
    pub node: &'a Node,
    pub names: &'a [String],
}

impl Display for Show<'_> {
    fn fmt(&self, f: &mut Formatter<'_>) -> fmt::Result {
        write_node(f, self.node, self.names)
    }
}

// Binding strength, loosest first.
const SUM: u8 = 1;
const PRODUCT: u8 = 2;
const NEGATION: u8 = 3;
const POWER: u8 = 4;
const ATOM: u8 = 5;

fn strength(node: &Node) -> u8 {
    match node {
        Node::Bin(BinOp::Add | BinOp::Sub, ..) => SUM,
        Node::Bin(BinOp::Mul | BinOp::Div, ..) => PRODUCT,
        Node::Neg(_) => NEGATION,
        Node::Num(value) if value.is_sign_negative() => NEGATION,
        Node::Powi(..) | Node::Powf(..) | Node::Pow(..) => POWER,
        Node::Num(_) | Node::Var(_) | Node::Call(..) => ATOM,
    }
}

fn write_node(f: &mut Formatter<'_>, node: &Node, names: &[String]) -> fmt::Result {
    match node {
        Node::Num(value) => write_number(f, *value),
        Node::Var(i) => f.write_str(&names[*i]),
        Node::Neg(a) => {
            f.write_str("-")?;
            write_operand(f, a, names, strength(a) < POWER)
        }
        Node::Bin(op, a, b) => {
            let (own, symbol) = match op {
                BinOp::Add => (SUM, " + "),
                BinOp::Sub => (SUM, " - "),
                BinOp::Mul => (PRODUCT, "*"),
                BinOp::Div => (PRODUCT, "/"),
            };
            write_operand(f, a, names, strength(a) < own)?;
            f.write_str(symbol)?;
            let right = strength(b);
            write_operand(f, b, names, right <= own || right == NEGATION)
        }
        Node::Powi(a, n) => {
            write_operand(f, a, names, strength(a) < ATOM)?;
            write!(f, "^{n}")
        }
        Node::Powf(a, n) => {
            write_operand(f, a, names, strength(a) < ATOM)?;
            f.write_str("^")?;
            write_number(f, *n)
        }
        Node::Pow(a, b) => {
            write_operand(f, a, names, strength(a) < ATOM)?;
            f.write_str("^")?;
            write_operand(f, b, names, strength(b) < NEGATION)
        }
        Node::Call(func, a) => {
            write!(f, "{}(", func.name())?;
            write_node(f, a, names)?;
            f.write_str(")")
        }
    }
}

fn write_operand(f: &mut Formatter<'_>, node: &Node, names: &[String], parenthesise: bool) -> fmt::Result {
    if parenthesise {
        f.write_str("(")?;
        write_node(f, node, names)?;
        f.write_str(")")
    } else {
        write_node(f, node, names)
    }
}

/// Shortest round-trip form; exponent notation for very small or large magnitudes.
fn write_number(f: &mut Formatter<'_>, value: f64) -> fmt::Result {
    let magnitude = value.abs();
    if magnitude == 0.0 || (1e-4..1e16).contains(&magnitude) {
        write!(f, "{value}")
    } else {
        write!(f, "{value:e}")
    }
}
