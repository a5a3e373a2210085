//! Recursive-descent parser with constant folding.

use super::lexer::{Kind, Token, tokenize};
use super::{BinOp, ExprError, Func, MAX_DEPTH, MAX_POWI, Node};

/// How deeply the parser may recurse (a guard for the stack): the tree is held to [`MAX_DEPTH`]
/// levels, and its text may nest deeper than its tree — `-(-(-x))` is three levels of tree and
/// six of text. The canonical print of a tree [`MAX_DEPTH`] deep nests at most three times as
/// deep (a negative right operand is parenthesised), so it parses back (found with `fuzz/`:
/// 65 negations printed as `-(-(…))` did not).
const MAX_NESTING: usize = 4 * MAX_DEPTH;

/// Parses `text` with parameters `names` into a folded tree.
pub(super) fn parse(text: &str, names: &[&str]) -> Result<Node, ExprError> {
    check_names(names)?;
    let mut parser = Parser { text, tokens: tokenize(text), pos: 0, last_end: 0, depth: 0, names };
    if parser.tokens[0].kind == Kind::End {
        return Err(ExprError::Empty);
    }
    let part = parser.expr()?;
    let token = parser.peek()?;
    match token.kind {
        Kind::End => Ok(part.node),
        Kind::RParen => Err(ExprError::UnmatchedParen { offset: token.start }),
        _ => Err(parser.unexpected(token, "an operator or the end of the expression")),
    }
}

fn check_names(names: &[&str]) -> Result<(), ExprError> {
    for (i, &name) in names.iter().enumerate() {
        let mut bytes = name.bytes();
        let valid = bytes.next().is_some_and(|c| c.is_ascii_alphabetic() || c == b'_')
            && bytes.all(|c| c.is_ascii_alphanumeric() || c == b'_');
        if !valid {
            return Err(ExprError::InvalidName { name: name.to_string() });
        }
        if name == "pi" || Func::from_name(name).is_some() {
            return Err(ExprError::ReservedName { name: name.to_string() });
        }
        if names[..i].contains(&name) {
            return Err(ExprError::DuplicateName { name: name.to_string() });
        }
    }
    Ok(())
}

/// A parsed subexpression: its (folded) tree, where its text starts, and its tree depth.
struct Part {
    node: Node,
    start: usize,
    depth: usize,
}

struct Parser<'a> {
    text: &'a str,
    tokens: Vec<Token>,
    pos: usize,
    /// End of the last consumed token: the end of the subexpression just parsed.
    last_end: usize,
    /// Current nesting of `unary` calls, which every recursion passes through.
    depth: usize,
    names: &'a [&'a str],
}

impl Parser<'_> {
    /// The next token; malformed numbers and `**` are reported here, wherever they stand.
    fn peek(&self) -> Result<Token, ExprError> {
        let token = self.tokens[self.pos];
        match token.kind {
            Kind::BadNumber => {
                Err(ExprError::BadNumber { text: self.slice(token).to_string(), offset: token.start })
            }
            Kind::DoubleStar => Err(ExprError::DoubleStar { offset: token.start }),
            _ => Ok(token),
        }
    }

    fn advance(&mut self) {
        self.last_end = self.tokens[self.pos].end;
        self.pos += 1;
    }

    fn slice(&self, token: Token) -> &str {
        &self.text[token.start..token.end]
    }

    fn unexpected(&self, token: Token, expected: &'static str) -> ExprError {
        if token.kind == Kind::End {
            ExprError::UnexpectedEnd { offset: token.start, expected }
        } else {
            ExprError::Unexpected { found: self.slice(token).to_string(), offset: token.start, expected }
        }
    }

    /// `expr := term (('+' | '-') term)*`
    fn expr(&mut self) -> Result<Part, ExprError> {
        let mut lhs = self.term()?;
        loop {
            let op = match self.peek()?.kind {
                Kind::Plus => BinOp::Add,
                Kind::Minus => BinOp::Sub,
                _ => return Ok(lhs),
            };
            self.advance();
            let rhs = self.term()?;
            lhs = self.binary(op, lhs, rhs)?;
        }
    }

    /// `term := unary (('*' | '/') unary)*`
    fn term(&mut self) -> Result<Part, ExprError> {
        let mut lhs = self.unary()?;
        loop {
            let op = match self.peek()?.kind {
                Kind::Star => BinOp::Mul,
                Kind::Slash => BinOp::Div,
                _ => return Ok(lhs),
            };
            self.advance();
            let rhs = self.unary()?;
            lhs = self.binary(op, lhs, rhs)?;
        }
    }

    /// `unary := ('-' | '+') unary | power`
    fn unary(&mut self) -> Result<Part, ExprError> {
        let token = self.peek()?;
        self.depth += 1;
        if self.depth > MAX_NESTING {
            return Err(ExprError::TooDeep { offset: token.start });
        }
        let part = match token.kind {
            Kind::Minus => {
                self.advance();
                let operand = self.unary()?;
                self.make(Node::Neg(Box::new(operand.node)), token.start, operand.depth + 1)?
            }
            Kind::Plus => {
                self.advance();
                Part { start: token.start, ..self.unary()? }
            }
            _ => self.power()?,
        };
        self.depth -= 1;
        Ok(part)
    }

    /// `power := primary ('^' unary)?`
    fn power(&mut self) -> Result<Part, ExprError> {
        let base = self.primary()?;
        if self.peek()?.kind != Kind::Caret {
            return Ok(base);
        }
        self.advance();
        let exponent = self.unary()?;
        let depth = base.depth.max(exponent.depth) + 1;
        let a = Box::new(base.node);
        let node = match exponent.node {
            Node::Num(n) if n.fract() == 0.0 && n.abs() <= MAX_POWI => Node::Powi(a, n as i32),
            Node::Num(n) => Node::Powf(a, n),
            b => Node::Pow(a, Box::new(b)),
        };
        self.make(node, base.start, depth)
    }

    /// `primary := number | name | name '(' expr ')' | '(' expr ')'`
    fn primary(&mut self) -> Result<Part, ExprError> {
        let token = self.peek()?;
        match token.kind {
            Kind::Number(value) => {
                self.advance();
                self.make(Node::Num(value), token.start, 1)
            }
            Kind::Name => {
                self.advance();
                let name = self.slice(token);
                let next = self.peek()?;
                if next.kind == Kind::LParen {
                    let func = Func::from_name(name).ok_or_else(|| ExprError::UnknownFunction {
                        name: name.to_string(),
                        offset: token.start,
                    })?;
                    self.advance();
                    let argument = self.expr()?;
                    self.close(next)?;
                    self.make(Node::Call(func, Box::new(argument.node)), token.start, argument.depth + 1)
                } else if let Some(index) = self.names.iter().position(|&known| known == name) {
                    Ok(Part { node: Node::Var(index), start: token.start, depth: 1 })
                } else if name == "pi" {
                    Ok(Part { node: Node::Num(std::f64::consts::PI), start: token.start, depth: 1 })
                } else if Func::from_name(name).is_some() {
                    Err(self.unexpected(next, "`(` after the function name"))
                } else {
                    Err(ExprError::UnknownName {
                        name: name.to_string(),
                        offset: token.start,
                        known: self.names.iter().map(|known| known.to_string()).collect(),
                    })
                }
            }
            Kind::LParen => {
                self.advance();
                let inner = self.expr()?;
                self.close(token)?;
                Ok(Part { start: token.start, ..inner })
            }
            _ => Err(self.unexpected(token, "a number, a parameter, a function call or `(`")),
        }
    }

    /// Consumes the `)` matching `open`.
    fn close(&mut self, open: Token) -> Result<(), ExprError> {
        let token = self.peek()?;
        match token.kind {
            Kind::RParen => {
                self.advance();
                Ok(())
            }
            Kind::End => Err(ExprError::UnclosedParen { offset: open.start }),
            _ => Err(self.unexpected(token, "an operator or `)`")),
        }
    }

    fn binary(&self, op: BinOp, lhs: Part, rhs: Part) -> Result<Part, ExprError> {
        let depth = lhs.depth.max(rhs.depth) + 1;
        self.make(Node::Bin(op, Box::new(lhs.node), Box::new(rhs.node)), lhs.start, depth)
    }

    /// Checks the depth and folds a node whose operands are all numbers (children are folded
    /// already, so these are exactly the subtrees without variables).
    fn make(&self, node: Node, start: usize, depth: usize) -> Result<Part, ExprError> {
        if depth > MAX_DEPTH {
            return Err(ExprError::TooDeep { offset: start });
        }
        let constant = match &node {
            Node::Num(_) => true,
            Node::Var(_) => false,
            Node::Neg(a) | Node::Powi(a, _) | Node::Powf(a, _) | Node::Call(_, a) => is_num(a),
            Node::Bin(_, a, b) | Node::Pow(a, b) => is_num(a) && is_num(b),
        };
        if !constant {
            return Ok(Part { node, start, depth });
        }
        let value: f64 = node.eval(&[]);
        if !value.is_finite() {
            let text = self.text[start..self.last_end].to_string();
            return Err(ExprError::NonFiniteConstant { text, offset: start, value });
        }
        Ok(Part { node: Node::Num(value), start, depth: 1 })
    }
}

fn is_num(node: &Node) -> bool {
    matches!(node, Node::Num(_))
}
