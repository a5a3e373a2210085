//! Where things are in the RON text: a lenient reader that keeps byte positions.
//!
//! serde tells what a file says but not where; this module reads the same text into a small tree
//! of values with their positions (comments skipped, string literals decoded with a map from
//! decoded to raw bytes), so that a validation error can name the line and column of the
//! offending value — inside a string literal, the very character an expression error points
//! at. It never fails: malformed text gives a partial tree (the file has already been read by
//! RON when errors are located; [`crate::is_structure_file`] reads any text).

mod lex;

use lex::{Tok, Token, is_ident_char, tokenize};
use std::fmt;

/// Deeper groups than this are skipped rather than read (keeps the recursion bounded).
const MAX_NESTING: usize = 128;

/// A value in the text.
#[derive(Clone, Debug)]
pub(crate) enum Node {
    /// A number, identifier or literal.
    Atom { start: usize, end: usize, kind: AtomKind },
    /// `(…)`, `[…]`, `{…}`, possibly named (`Rayleigh(…)`, `Some(…)`).
    Group { start: usize, name: Option<String>, items: Vec<Item> },
}

/// What an atom is.
#[derive(Clone, Debug)]
pub(crate) enum AtomKind {
    /// A string literal.
    Str(StringLiteral),
    /// An identifier (a key, or a unit variant such as `Zero`).
    Ident(String),
    /// A number or anything else.
    Other,
}

/// A string literal: its decoded text and, for each decoded byte (and the end), the raw byte
/// offset in the file.
#[derive(Clone, Debug)]
pub(crate) struct StringLiteral {
    pub text: String,
    pub raw: Vec<usize>,
}

/// One element of a group: a value, or a `key: value` pair (struct field or map entry).
#[derive(Clone, Debug)]
pub(crate) struct Item {
    pub key: Option<String>,
    pub key_start: usize,
    pub value: Node,
}

impl Node {
    /// Byte offset where the value starts.
    pub fn start(&self) -> usize {
        match self {
            Node::Atom { start, .. } | Node::Group { start, .. } => *start,
        }
    }

    fn items(&self) -> &[Item] {
        match self {
            Node::Group { items, .. } => items,
            Node::Atom { .. } => &[],
        }
    }

    /// The content of `Some(x)`, or the node itself.
    fn unwrap_some(&self) -> &Node {
        match self {
            Node::Group { name: Some(name), items, .. }
                if name == "Some" && items.len() == 1 && items[0].key.is_none() =>
            {
                &items[0].value
            }
            _ => self,
        }
    }

    /// The value of field (or map key) `name`.
    pub fn field(&self, name: &str) -> Option<&Node> {
        self.unwrap_some()
            .items()
            .iter()
            .find(|item| item.key.as_deref() == Some(name))
            .map(|item| &item.value)
    }
}

/// One step of a path into the file.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Step {
    /// A struct field.
    Field(&'static str),
    /// The i-th element of a list or tuple.
    Index(usize),
    /// The value of the i-th entry of a map, shown by its key.
    Entry(usize, String),
    /// The key of the i-th entry of a map (ends a path).
    Key(usize, String),
    /// The content of a one-element enum variant such as `Matrix([…])` or `Displacement("q1")`.
    Inner,
}

/// A path into the file, e.g. `structure.stiffness[0][1]`.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct Path(pub Vec<Step>);

impl Path {
    fn with(&self, step: Step) -> Path {
        let mut steps = self.0.clone();
        steps.push(step);
        Path(steps)
    }
    pub fn field(&self, name: &'static str) -> Path {
        self.with(Step::Field(name))
    }
    pub fn index(&self, i: usize) -> Path {
        self.with(Step::Index(i))
    }
    pub fn entry(&self, i: usize, name: &str) -> Path {
        self.with(Step::Entry(i, name.to_string()))
    }
    pub fn key(&self, i: usize, name: &str) -> Path {
        self.with(Step::Key(i, name.to_string()))
    }
    pub fn inner(&self) -> Path {
        self.with(Step::Inner)
    }
}

impl fmt::Display for Path {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let mut first = true;
        for step in &self.0 {
            match step {
                Step::Field(name) => write!(f, "{}{name}", if first { "" } else { "." })?,
                Step::Entry(_, name) | Step::Key(_, name) => {
                    write!(f, "{}{name}", if first { "" } else { "." })?
                }
                Step::Index(i) => write!(f, "[{i}]")?,
                Step::Inner => continue,
            }
            first = false;
        }
        Ok(())
    }
}

/// The text's values with their positions.
#[derive(Clone, Debug)]
pub(crate) struct Tree {
    pub root: Option<Node>,
}

impl Tree {
    /// Reads `text` leniently.
    pub fn parse(text: &str) -> Tree {
        let tokens = tokenize(text);
        let mut reader = Reader { tokens, at: 0 };
        reader.skip_attributes();
        Tree { root: reader.value(0) }
    }

    /// Follows `path` as far as it goes: the byte offset of the last value (or key) reached,
    /// and the value itself if the whole path was found.
    pub fn find(&self, path: &Path) -> (usize, Option<&Node>) {
        let Some(mut node) = self.root.as_ref() else { return (0, None) };
        for step in &path.0 {
            let here = node.unwrap_some();
            let next = match step {
                Step::Field(name) => here.field(name),
                Step::Index(i) | Step::Entry(i, _) => here.items().get(*i).map(|item| &item.value),
                Step::Key(i, _) => match here.items().get(*i) {
                    Some(item) => return (item.key_start, None),
                    None => None,
                },
                Step::Inner => match here.items() {
                    [item] => Some(&item.value),
                    _ => None,
                },
            };
            match next {
                Some(next) => node = next,
                None => return (here.start(), None),
            }
        }
        (node.start(), Some(node))
    }
}

/// 1-based line and column (in characters, as RON counts them) of a byte offset.
pub(crate) fn line_column(text: &str, offset: usize) -> (usize, usize) {
    let mut offset = offset.min(text.len());
    while !text.is_char_boundary(offset) {
        offset -= 1;
    }
    let before = &text[..offset];
    let line = before.matches('\n').count() + 1;
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    (line, before[line_start..].chars().count() + 1)
}

struct Reader {
    tokens: Vec<Token>,
    at: usize,
}

impl Reader {
    fn peek(&self) -> Option<&Tok> {
        self.tokens.get(self.at).map(|t| &t.tok)
    }

    /// Skips `#![enable(…)]` attributes before the value.
    fn skip_attributes(&mut self) {
        while matches!(self.peek(), Some(Tok::Hash)) {
            self.at += 1;
            if matches!(self.peek(), Some(Tok::Other)) {
                self.at += 1; // `!`
            }
            if matches!(self.peek(), Some(Tok::Open(_))) {
                self.skip_group();
            }
        }
    }

    /// Skips a group from its opening token to its closing one (or the end).
    fn skip_group(&mut self) {
        let mut depth = 0usize;
        while let Some(tok) = self.peek() {
            match tok {
                Tok::Open(_) => depth += 1,
                Tok::Close => depth = depth.saturating_sub(1),
                _ => {}
            }
            self.at += 1;
            if depth == 0 {
                break;
            }
        }
    }

    fn value(&mut self, depth: usize) -> Option<Node> {
        let token = self.tokens.get(self.at)?.clone();
        match token.tok {
            Tok::Ident(name) => {
                self.at += 1;
                if matches!(self.peek(), Some(Tok::Open('('))) {
                    Some(self.group(token.start, Some(name), depth))
                } else {
                    Some(Node::Atom { start: token.start, end: token.end, kind: AtomKind::Ident(name) })
                }
            }
            Tok::Open(_) => Some(self.group(token.start, None, depth)),
            Tok::Str(literal) => {
                self.at += 1;
                Some(Node::Atom { start: token.start, end: token.end, kind: AtomKind::Str(literal) })
            }
            _ => {
                self.at += 1;
                Some(Node::Atom { start: token.start, end: token.end, kind: AtomKind::Other })
            }
        }
    }

    /// Reads a group whose opening token is next.
    fn group(&mut self, start: usize, name: Option<String>, depth: usize) -> Node {
        if depth >= MAX_NESTING {
            self.skip_group();
            return Node::Group { start, name, items: Vec::new() };
        }
        self.at += 1;
        let mut items = Vec::new();
        while let Some(tok) = self.peek() {
            match tok {
                Tok::Close => {
                    self.at += 1;
                    break;
                }
                Tok::Comma => self.at += 1,
                _ => {
                    let key_start = self.tokens[self.at].start;
                    let Some(first) = self.value(depth + 1) else { break };
                    if matches!(self.peek(), Some(Tok::Colon)) {
                        self.at += 1;
                        let key = match &first {
                            Node::Atom { kind: AtomKind::Str(literal), .. } => Some(literal.text.clone()),
                            Node::Atom { kind: AtomKind::Ident(name), .. } => Some(name.clone()),
                            _ => None,
                        };
                        let Some(value) = self.value(depth + 1) else { break };
                        items.push(Item { key, key_start, value });
                    } else {
                        items.push(Item { key: None, key_start, value: first });
                    }
                }
            }
        }
        Node::Group { start, name, items }
    }
}

/// Whether the RON value in `text` is a group with a field named `field` at its top level.
pub(crate) fn has_top_level_field(text: &str, field: &str) -> bool {
    match Tree::parse(text).root {
        Some(root @ Node::Group { .. }) => root.field(field).is_some(),
        _ => false,
    }
}

/// The byte offset of a 1-based line and column (in characters), clamped to the text.
pub(crate) fn offset_of(text: &str, line: usize, column: usize) -> usize {
    let line_start =
        if line <= 1 { 0 } else { text.match_indices('\n').nth(line - 2).map_or(text.len(), |(i, _)| i + 1) };
    text[line_start..]
        .char_indices()
        .nth(column.saturating_sub(1))
        .map_or(text.len(), |(i, _)| line_start + i)
}

/// The start of the last whole identifier `ident` that ends at or before `offset`, if any.
pub(crate) fn ident_before(text: &str, offset: usize, ident: &str) -> Option<usize> {
    let mut end = offset.min(text.len());
    while !text.is_char_boundary(end) {
        end -= 1;
    }
    let mut search = &text[..end];
    while let Some(at) = search.rfind(ident) {
        let before_ok = !text[..at].ends_with(is_ident_char);
        let after_ok = !text[at + ident.len()..].starts_with(is_ident_char);
        if before_ok && after_ok {
            return Some(at);
        }
        search = &text[..at];
    }
    None
}

#[cfg(test)]
mod tests;
