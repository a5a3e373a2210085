//! Splitting expression text into tokens. Lexing never fails: malformed pieces become tokens
//! of their own, reported by the parser when it reaches them (so the leftmost error wins).

/// What a token is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Kind {
    Number(f64),
    Name,
    Plus,
    Minus,
    Star,
    Slash,
    Caret,
    LParen,
    RParen,
    /// `**`, rejected with a hint to use `^`.
    DoubleStar,
    /// A malformed number such as `1.2.3` or `2x`.
    BadNumber,
    /// A character that starts no token.
    Invalid,
    /// The end of the text.
    End,
}

/// A token and its byte range in the text.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Token {
    pub kind: Kind,
    pub start: usize,
    pub end: usize,
}

/// The tokens of `text`, ending with one [`Kind::End`] token.
pub(super) fn tokenize(text: &str) -> Vec<Token> {
    let bytes = text.as_bytes();
    let mut tokens = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        let start = i;
        let kind = match bytes[i] {
            c if c.is_ascii_whitespace() => {
                i += 1;
                continue;
            }
            b'+' => single(&mut i, Kind::Plus),
            b'-' => single(&mut i, Kind::Minus),
            b'/' => single(&mut i, Kind::Slash),
            b'^' => single(&mut i, Kind::Caret),
            b'(' => single(&mut i, Kind::LParen),
            b')' => single(&mut i, Kind::RParen),
            b'*' if bytes.get(i + 1) == Some(&b'*') => {
                i += 2;
                Kind::DoubleStar
            }
            b'*' => single(&mut i, Kind::Star),
            b'0'..=b'9' | b'.' => {
                let (kind, end) = number(text, i);
                i = end;
                kind
            }
            c if c.is_ascii_alphabetic() || c == b'_' => {
                while i < bytes.len() && is_name_byte(bytes[i]) {
                    i += 1;
                }
                Kind::Name
            }
            _ => {
                // `i` is on a character boundary: only whole characters are ever skipped.
                let c = text[i..].chars().next().unwrap_or('\u{fffd}');
                i += c.len_utf8();
                if c.is_whitespace() {
                    continue;
                }
                Kind::Invalid
            }
        };
        tokens.push(Token { kind, start, end: i });
    }
    tokens.push(Token { kind: Kind::End, start: bytes.len(), end: bytes.len() });
    tokens
}

fn single(i: &mut usize, kind: Kind) -> Kind {
    *i += 1;
    kind
}

fn is_name_byte(c: u8) -> bool {
    c.is_ascii_alphanumeric() || c == b'_'
}

/// Lexes the number starting at `start`: digits, an optional fraction and an optional exponent,
/// with at least one digit before the exponent. A number run into letters, digits, `_` or `.`
/// (`1.2.3`, `2x`, `1e`) is malformed and swallows all of them.
fn number(text: &str, start: usize) -> (Kind, usize) {
    let bytes = text.as_bytes();
    let digits = |mut i: usize| {
        while i < bytes.len() && bytes[i].is_ascii_digit() {
            i += 1;
        }
        i
    };
    let mut i = digits(start);
    let mut count = i - start;
    if bytes.get(i) == Some(&b'.') {
        let end = digits(i + 1);
        count += end - (i + 1);
        i = end;
    }
    if count > 0 && matches!(bytes.get(i), Some(b'e' | b'E')) {
        let mut j = i + 1;
        if matches!(bytes.get(j), Some(b'+' | b'-')) {
            j += 1;
        }
        if bytes.get(j).is_some_and(u8::is_ascii_digit) {
            i = digits(j);
        }
    }
    if count == 0 || bytes.get(i).is_some_and(|&c| is_name_byte(c) || c == b'.') {
        while i < bytes.len() && (is_name_byte(bytes[i]) || bytes[i] == b'.') {
            i += 1;
        }
        return (Kind::BadNumber, i);
    }
    match text[start..i].parse() {
        Ok(value) => (Kind::Number(value), i),
        Err(_) => (Kind::BadNumber, i),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn kinds(text: &str) -> Vec<Kind> {
        tokenize(text).into_iter().map(|t| t.kind).collect()
    }

    fn spans(text: &str) -> Vec<&str> {
        tokenize(text).into_iter().map(|t| &text[t.start..t.end]).collect()
    }

    #[test]
    fn numbers() {
        for (text, value) in [
            ("12", 12.0),
            ("1.5", 1.5),
            (".5", 0.5),
            ("5.", 5.0),
            ("2.5e6", 2.5e6),
            ("1E-3", 1e-3),
            ("7e+2", 700.0),
        ] {
            assert_eq!(kinds(text), [Kind::Number(value), Kind::End], "{text}");
        }
    }

    #[test]
    fn malformed_numbers() {
        for text in ["1.2.3", "2x", "1e", "1e+", ".", "3_", "1e5.0"] {
            let tokens = tokenize(text);
            assert_eq!(tokens[0].kind, Kind::BadNumber, "{text}");
            assert_eq!(tokens[0].start, 0);
        }
        assert_eq!(spans("1.2.3 + x"), ["1.2.3", "+", "x", ""]);
        assert_eq!(spans("1e+x"), ["1e", "+", "x", ""]);
    }

    #[test]
    fn operators_names_and_offsets() {
        let text = " k_1 **2 * -(x1) ^ ÿ/\u{a0}b";
        assert_eq!(spans(text), ["k_1", "**", "2", "*", "-", "(", "x1", ")", "^", "ÿ", "/", "b", ""]);
        let tokens = tokenize(text);
        assert_eq!(tokens[0].start, 1);
        assert_eq!(tokens[1].kind, Kind::DoubleStar);
        assert_eq!(tokens[9].kind, Kind::Invalid);
        assert_eq!(tokens[10].start, tokens[9].start + 'ÿ'.len_utf8());
        assert_eq!(tokens.last().map(|t| t.start), Some(text.len()));
    }
}
