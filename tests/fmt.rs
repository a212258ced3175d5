//! `axle fmt` keeps every comment exactly once, is a fixed point, treats a
//! lone CR as the parser does, and never changes the model it formats.

use axle::check::check_str;
use axle::span::FileId;

fn fmt(src: &str) -> String {
    axle::fmt::format_source(FileId(0), src).expect("formats")
}

fn comments(src: &str) -> Vec<String> {
    axle::syntax::trivia::comments(src)
        .into_iter()
        .map(|c| c.text)
        .collect()
}

/// The checked model as the canonical printer writes it (no spans).
fn model(src: &str) -> String {
    let (_, c) = check_str("m.axle", src);
    axle::fmt::print_model(&c.model.expect("checks"))
}

const COLUMNS: &str = "ground g {\n    marker o at (0, 0, 0) mm\n}\n\nloads set table (g.o.fx N,   // first\n                 g.o.fz N) {  // second\n    a  1  2  // row\n    b  3  4\n}\n";

#[test]
fn a_comment_inside_a_multi_line_column_list_is_kept_once() {
    let once = fmt(COLUMNS);
    assert_eq!(
        comments(&once),
        ["// first", "// second", "// row"],
        "{once}"
    );
    let twice = fmt(&once);
    assert_eq!(twice, once);
    assert_eq!(fmt(&twice), once);
    assert_eq!(model(&once), model(COLUMNS));
}

#[test]
fn a_cr_only_file_formats_to_the_same_model() {
    let text = std::fs::read_to_string("examples/four_bar.axle").expect("example");
    let cr = text.replace('\n', "\r");
    // The parser reads a lone CR as a line end: the file is valid as it is.
    assert_eq!(model(&cr), model(&text));
    let out = fmt(&cr);
    assert!(!out.contains('\r'));
    assert_eq!(out, fmt(&text));
    assert_eq!(model(&out), model(&text));
    assert_eq!(comments(&out), comments(&text));
}

#[test]
fn every_example_is_a_fixed_point_and_keeps_its_model() {
    for entry in std::fs::read_dir("examples").expect("examples") {
        let path = entry.expect("entry").path();
        let text = std::fs::read_to_string(&path).expect("read");
        let messy = text.replace("    ", "\t  ").replace(", ", " ,");
        let out = fmt(&messy);
        assert_eq!(fmt(&out), out, "{}", path.display());
        assert_eq!(model(&out), model(&text), "{}", path.display());
        assert_eq!(comments(&out), comments(&messy), "{}", path.display());
    }
}
