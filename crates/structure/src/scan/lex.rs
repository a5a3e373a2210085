//! The tokens of RON text, with their byte spans: comments and whitespace skipped, string
//! literals decoded with a map from decoded to raw bytes.

use super::StringLiteral;

/// A token.
#[derive(Clone, Debug)]
pub(super) enum Tok {
    Open(char),
    Close,
    Comma,
    Colon,
    Hash,
    Ident(String),
    Str(StringLiteral),
    Other,
}

/// A token and its byte span.
#[derive(Clone, Debug)]
pub(super) struct Token {
    pub tok: Tok,
    pub start: usize,
    pub end: usize,
}

fn is_ident_start(c: char) -> bool {
    c.is_alphabetic() || c == '_'
}

pub(super) fn is_ident_char(c: char) -> bool {
    c.is_alphanumeric() || c == '_'
}

/// The tokens of `text`; never fails (an unterminated literal or comment runs to the end).
pub(super) fn tokenize(text: &str) -> Vec<Token> {
    let mut tokens = Vec::new();
    let mut i = 0;
    while i < text.len() {
        let c = text[i..].chars().next().unwrap_or(' ');
        let start = i;
        let rest = &text[i..];
        if c.is_whitespace() {
            i += c.len_utf8();
            continue;
        }
        if rest.starts_with("//") {
            i += rest.find('\n').unwrap_or(rest.len());
            continue;
        }
        if rest.starts_with("/*") {
            i = skip_block_comment(text, i);
            continue;
        }
        if let Some((end, literal)) = matches!(c, 'r' | 'b').then(|| raw_or_byte_string(text, i)).flatten() {
            tokens.push(Token { tok: Tok::Str(literal), start, end });
            i = end;
            continue;
        }
        let tok = match c {
            '(' | '[' | '{' => {
                i += 1;
                Tok::Open(c)
            }
            ')' | ']' | '}' => {
                i += 1;
                Tok::Close
            }
            ',' => {
                i += 1;
                Tok::Comma
            }
            ':' => {
                i += 1;
                Tok::Colon
            }
            '#' => {
                i += 1;
                Tok::Hash
            }
            '"' => {
                let (end, literal) = quoted_string(text, i + 1);
                i = end;
                Tok::Str(literal)
            }
            '\'' => {
                i = char_literal_end(text, i);
                Tok::Other
            }
            c if is_ident_start(c) => {
                // `r#name` is a raw identifier only when a name follows; a bare `r#` is `r`, then `#`.
                let raw_ident = rest
                    .strip_prefix("r#")
                    .and_then(|after| after.chars().next())
                    .is_some_and(is_ident_start);
                let from = if raw_ident { i + 2 } else { i };
                // At least the identifier's first character, which is one (is_ident_start ⊂ is_ident_char).
                let len = text[from..].find(|c: char| !is_ident_char(c)).unwrap_or(text.len() - from);
                i = from + len;
                Tok::Ident(text[from..i].to_string())
            }
            '0'..='9' | '.' | '+' | '-' => {
                i = number_end(text, i);
                Tok::Other
            }
            _ => {
                i += c.len_utf8();
                Tok::Other
            }
        };
        tokens.push(Token { tok, start, end: i });
    }
    tokens
}

/// End of a (nested) block comment starting at `i`.
fn skip_block_comment(text: &str, mut i: usize) -> usize {
    let mut depth = 0usize;
    while i < text.len() {
        let rest = &text[i..];
        if rest.starts_with("/*") {
            depth += 1;
            i += 2;
        } else if rest.starts_with("*/") {
            depth -= 1;
            i += 2;
            if depth == 0 {
                return i;
            }
        } else {
            i += rest.chars().next().map_or(1, char::len_utf8);
        }
    }
    text.len()
}

/// End of a number (with sign, exponent, suffix or `inf`/`NaN`) starting at `i`.
fn number_end(text: &str, i: usize) -> usize {
    let bytes = text.as_bytes();
    let mut j = i;
    if matches!(bytes.get(j), Some(b'+' | b'-')) {
        j += 1;
    }
    let mut previous = 0u8;
    while let Some(&b) = bytes.get(j) {
        let exponent_sign = matches!(b, b'+' | b'-') && matches!(previous, b'e' | b'E');
        if b.is_ascii_alphanumeric() || b == b'_' || b == b'.' || exponent_sign {
            previous = b;
            j += 1;
        } else {
            break;
        }
    }
    j.max(i + 1)
}

/// End of a char literal `'x'` (with escapes) starting at `i`.
fn char_literal_end(text: &str, i: usize) -> usize {
    let mut chars = text[i + 1..].char_indices();
    while let Some((k, c)) = chars.next() {
        match c {
            '\\' => {
                chars.next();
            }
            '\'' => return i + 1 + k + 1,
            '\n' => return i + 1 + k,
            _ => {}
        }
    }
    text.len()
}

/// A raw string `r"…"`, `r#"…"#`, or a byte string `b"…"`, `br"…"` starting at `i`.
fn raw_or_byte_string(text: &str, i: usize) -> Option<(usize, StringLiteral)> {
    let rest = &text[i..];
    let after_b = if rest.starts_with('b') { 1 } else { 0 };
    if rest[after_b..].starts_with('"') {
        return (after_b == 1).then(|| quoted_string(text, i + 2));
    }
    if !rest[after_b..].starts_with('r') {
        return None;
    }
    let hashes = rest[after_b + 1..].bytes().take_while(|&b| b == b'#').count();
    let quote = i + after_b + 1 + hashes;
    if text.as_bytes().get(quote) != Some(&b'"') {
        return None;
    }
    let content = quote + 1;
    let closing = format!("\"{}", "#".repeat(hashes));
    let end = text[content..].find(&closing).map_or(text.len(), |k| content + k);
    let literal = StringLiteral { text: text[content..end].to_string(), raw: (content..=end).collect() };
    Some(((end + closing.len()).min(text.len()), literal))
}

/// A quoted string whose content starts at `content`: decodes escapes and maps each decoded
/// byte to its raw offset.
fn quoted_string(text: &str, content: usize) -> (usize, StringLiteral) {
    let mut decoded = String::new();
    let mut raw = Vec::new();
    let mut chars = text[content..].char_indices().peekable();
    while let Some((k, c)) = chars.next() {
        let at = content + k;
        let value = match c {
            '"' => {
                raw.push(at);
                return (at + 1, StringLiteral { text: decoded, raw });
            }
            '\\' => match chars.next() {
                Some((_, 'n')) => '\n',
                Some((_, 't')) => '\t',
                Some((_, 'r')) => '\r',
                Some((_, '0')) => '\0',
                Some((_, 'b')) => '\u{8}',
                Some((_, 'f')) => '\u{c}',
                Some((_, 'u')) => {
                    let mut hex = String::new();
                    if chars.peek().map(|(_, c)| *c) == Some('{') {
                        chars.next();
                        for (_, c) in chars.by_ref() {
                            if c == '}' {
                                break;
                            }
                            hex.push(c);
                        }
                    } else {
                        for _ in 0..4 {
                            if let Some((_, c)) = chars.next() {
                                hex.push(c);
                            }
                        }
                    }
                    u32::from_str_radix(&hex, 16).ok().and_then(char::from_u32).unwrap_or('\u{fffd}')
                }
                Some((_, 'x')) => {
                    let hex: String = (0..2).filter_map(|_| chars.next().map(|(_, c)| c)).collect();
                    u8::from_str_radix(&hex, 16).map_or('\u{fffd}', char::from)
                }
                Some((_, other)) => other,
                None => break,
            },
            c => c,
        };
        let mut buffer = [0u8; 4];
        let encoded = value.encode_utf8(&mut buffer);
        raw.extend(std::iter::repeat_n(at, encoded.len()));
        decoded.push_str(encoded);
    }
    raw.push(text.len());
    (text.len(), StringLiteral { text: decoded, raw })
}
