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

/// Templates and instances (issue 13) print back in canonical layout: the
/// body indented one level, comments kept once, arguments `name = value`.
/// (The link is off the plane of symmetry: a mirrored part on it is E0117.)
#[test]
fn templates_and_instances_format_canonically_and_keep_comments() {
    let messy = "ground chassis {\n    marker o at (0, 100, 0) mm\n}\ntemplate arm( k = 100  N/mm ,len) {\n// the link\npart link {\nmarker o at (0,100,0) mm\n}\n    bushing mount {   // to the chassis\n        i chassis.o\n  j link.o\n        k (k, k, k)\n        kt (1000, 1000, 1000) N*mm/deg\n    }\n}\ninstance left = arm( len = 3 mm )\ninstance right=mirror   arm(k = 200 N/mm, len = 3 mm)\n";
    let canonical = "ground chassis {\n    marker o at (0, 100, 0) mm\n}\n\ntemplate arm(k = 100 N/mm, len) {\n    // the link\n    part link {\n        marker o at (0, 100, 0) mm\n    }\n\n    bushing mount { // to the chassis\n        i chassis.o\n        j link.o\n        k (k, k, k)\n        kt (1000, 1000, 1000) N*mm/deg\n    }\n}\n\ninstance left = arm(len = 3 mm)\ninstance right = mirror arm(k = 200 N/mm, len = 3 mm)\n";
    let once = fmt(messy);
    assert_eq!(once, canonical);
    assert_eq!(fmt(&once), once);
    assert_eq!(model(messy), model(&once));
}
