//! Tests of the RON position reader.

use super::*;

fn literal(text: &str, path: &Path) -> StringLiteral {
    match Tree::parse(text).find(path).1 {
        Some(Node::Atom { kind: AtomKind::Str(literal), .. }) => literal.clone(),
        other => panic!("{other:?}"),
    }
}

#[test]
fn string_literals_map_decoded_bytes_to_raw_offsets() {
    let text = r###"(a: "x\ty\u{e9}z\"", b: r##"q"#"##, c: b"k")"###;
    let a = literal(text, &Path::default().field("a"));
    assert_eq!(a.text, "x\ty\u{e9}z\"");
    let raw = |decoded: usize| a.raw[decoded];
    assert_eq!(&text[raw(0)..raw(0) + 1], "x");
    assert_eq!(&text[raw(1)..raw(1) + 2], "\\t");
    assert_eq!(&text[raw(2)..raw(2) + 1], "y");
    assert_eq!(raw(3), raw(4), "both bytes of é come from one escape");
    assert_eq!(&text[raw(5)..raw(5) + 1], "z");
    assert_eq!(&text[raw(a.text.len())..], "\", b: r##\"q\"#\"##, c: b\"k\")");
    let b = literal(text, &Path::default().field("b"));
    assert_eq!(b.text, "q\"#");
    assert_eq!(&text[b.raw[0]..b.raw[0] + 1], "q");
    assert_eq!(literal(text, &Path::default().field("c")).text, "k");
}

#[test]
fn comments_chars_and_attributes_are_skipped() {
    let text = "#![enable(implicit_some)]\n/* a /* nested ( */ \" */ Name( // x: (\n x: ['(', '\\''], y: [1, -2.5e-3, +inf] )";
    let tree = Tree::parse(text);
    let (y, node) = tree.find(&Path::default().field("y").index(1));
    assert_eq!(&text[y..y + 7], "-2.5e-3");
    assert!(matches!(node, Some(Node::Atom { end, .. }) if &text[y..*end] == "-2.5e-3"));
    assert!(tree.find(&Path::default().field("x").index(1)).1.is_some());
    assert!(tree.find(&Path::default().field("x").index(2)).1.is_none());
}

#[test]
fn paths_follow_some_and_variants_and_stop_where_the_text_ends() {
    let text = r#"(d: Matrix([[1, 2], [3, "k"]]), o: Some([4]), m: {"k1": (v: 1), "k1": (v: 2)})"#;
    let tree = Tree::parse(text);
    let root = Path::default();
    let (at, _) = tree.find(&root.field("d").inner().index(1).index(1));
    assert_eq!(&text[at..at + 3], "\"k\"");
    let (at, _) = tree.find(&root.field("o").index(0));
    assert_eq!(&text[at..at + 1], "4");
    let (at, _) = tree.find(&root.field("m").entry(1, "k1").field("v"));
    assert_eq!(&text[at..at + 1], "2");
    let (at, node) = tree.find(&root.field("m").key(1, "k1"));
    assert!(node.is_none());
    assert_eq!(&text[at..at + 5], "\"k1\":");
    // A path that goes too far stops at the last value found.
    let (at, node) = tree.find(&root.field("d").inner().index(7));
    assert!(node.is_none());
    assert_eq!(&text[at..at + 2], "[[");
    assert_eq!(root.field("d").inner().index(1).index(0).to_string(), "d[1][0]");
    assert_eq!(root.field("m").entry(0, "k1").field("v").to_string(), "m.k1.v");
}

#[test]
fn line_column_and_offset_of_are_inverse() {
    let text = "ab\nçé\"x\n\nlast";
    for (offset, _) in text.char_indices() {
        let (line, column) = line_column(text, offset);
        assert_eq!(offset_of(text, line, column), offset);
    }
    assert_eq!(line_column(text, text.find('x').unwrap()), (2, 4));
    assert_eq!(offset_of(text, 99, 1), text.len());
    assert_eq!(ident_before(text, text.len(), "last"), text.find("last"));
    assert_eq!(ident_before("mass masses", 11, "mass"), Some(0));
}

#[test]
fn malformed_text_never_panics() {
    for text in
        ["", "(", ")", "\"", "r#\"", "/*", "'", "(a: [1, (b: \"", "#!", "(:::)", "(a:)", "é(", "((((]]]]"]
    {
        let tree = Tree::parse(text);
        let _ = tree.find(&Path::default().field("a").index(0).inner());
        let _ = has_top_level_field(text, "a");
    }
}

/// Found by `fuzz/` (model_file, the 4 bytes "\r\0r#"): a bare `r#` at the end of the text, or
/// before a character that starts no name, read one byte past the text or into a character.
#[test]
fn a_bare_raw_identifier_prefix_is_read_without_panic() {
    for text in ["\r\0r#", "r#", "(a: r#é)", "(a: r#)", "(r#: 1)", "r#\u{e9}", "(x: r#abc)"] {
        let _ = Tree::parse(text);
        let tokens = tokenize(text);
        assert!(tokens.iter().all(|t| t.end <= text.len() && text.is_char_boundary(t.end)), "{text:?}");
    }
    let tree = Tree::parse("(x: r#abc, y: 2)");
    assert!(matches!(tree.find(&Path::default().field("y")).1, Some(Node::Atom { .. })));
}
