//! Writing current parameter values back into the model file's own text.

use crate::scan::{AtomKind, Node, Path, Tree};

/// The text with the `value:` of each parameter whose value differs from the file's rewritten,
/// everything else (comments, layout, expressions) untouched; `None` if a value is not a plain
/// number in the text.
pub(crate) fn patch_values(text: &str, tree: &Tree, file_values: &[f64], values: &[f64]) -> Option<String> {
    let root = Path::default().field("parameters");
    let mut edits = Vec::new();
    for (i, (old, new)) in file_values.iter().zip(values).enumerate() {
        if old.to_bits() == new.to_bits() {
            continue;
        }
        match tree.find(&root.index(i).field("value")).1 {
            Some(Node::Atom { start, end, kind: AtomKind::Other }) => {
                edits.push((*start, *end, format!("{new:?}")))
            }
            _ => return None,
        }
    }
    edits.sort_by_key(|edit| edit.0);
    let mut out = String::with_capacity(text.len() + 16 * edits.len());
    let mut at = 0;
    for (start, end, number) in edits {
        if start < at || end > text.len() {
            return None;
        }
        out.push_str(&text[at..start]);
        out.push_str(&number);
        at = end;
    }
    out.push_str(&text[at..]);
    Some(out)
}
