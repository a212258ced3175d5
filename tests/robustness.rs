//! Random and mutated sources never make the parser, checker or formatter
//! panic; whatever parses formats idempotently and keeps its comments.

use axle::check::check_str;
use axle::span::FileId;
use proptest::prelude::*;

const SEEDS: &[&str] = &[
    include_str!("../examples/mcpherson.axle"),
    include_str!("../examples/four_bar.axle"),
    include_str!("../examples/tour.axle"),
    include_str!("../stdlib/mcpherson_loads.axle"),
];

const TOKENS: &[&str] = &[
    "part",
    "ground",
    "marker",
    "landmark",
    "joint",
    "bushing",
    "spring",
    "stop",
    "wheel",
    "loads",
    "table",
    "sweep",
    "param",
    "unknown",
    "import",
    "default",
    "model",
    "at",
    "euler",
    "z",
    "x",
    "i",
    "j",
    "k",
    "kt",
    "k_x",
    "law",
    "by",
    "->",
    "{",
    "}",
    "(",
    ")",
    "[",
    "]",
    ",",
    ".",
    "=",
    "-",
    "+",
    "*",
    "/",
    "^",
    "_",
    "\n",
    " ",
    "//c\n",
    "0",
    "1.5",
    "-2e3",
    "1e400",
    "mm",
    "N/mm",
    "N*mm/deg",
    "deg",
    "sqrt(",
    "chassis.B",
    "spherical",
    "compression",
    "fz",
    "left.fz",
    "a.b.fx",
    "\u{e9}",
    "\t",
    "0.",
    // Large powers and magnitudes (dimension exponents once overflowed).
    "mm^99",
    "^-128",
    "100",
    "1e308",
    "\u{feff}",
    "\r\n",
];

fn token_soup() -> impl Strategy<Value = String> {
    prop::collection::vec(prop::sample::select(TOKENS), 0..60).prop_map(|t| t.join(" "))
}

#[derive(Debug, Clone)]
enum Mutation {
    Delete(usize, usize),
    Insert(usize, &'static str),
    DuplicateLine(usize),
    Truncate(usize),
}

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        (any::<usize>(), 0usize..40).prop_map(|(a, n)| Mutation::Delete(a, n)),
        (any::<usize>(), prop::sample::select(TOKENS)).prop_map(|(a, t)| Mutation::Insert(a, t)),
        any::<usize>().prop_map(Mutation::DuplicateLine),
        any::<usize>().prop_map(Mutation::Truncate),
    ]
}

fn floor_char(s: &str, i: usize) -> usize {
    let mut i = i % (s.len() + 1);
    while !s.is_char_boundary(i) {
        i -= 1;
    }
    i
}

fn apply(src: &str, muts: &[Mutation]) -> String {
    let mut s = src.to_string();
    for m in muts {
        match m {
            Mutation::Delete(a, n) => {
                let a = floor_char(&s, *a);
                let b = floor_char(&s, (a + n).min(s.len()));
                if b > a {
                    s.replace_range(a..b, "");
                }
            }
            Mutation::Insert(a, t) => {
                let a = floor_char(&s, *a);
                s.insert_str(a, t);
            }
            Mutation::DuplicateLine(l) => {
                let lines: Vec<&str> = s.lines().collect();
                if !lines.is_empty() {
                    let k = l % lines.len();
                    let mut out: Vec<&str> = lines.clone();
                    out.insert(k, lines[k]);
                    s = out.join("\n");
                }
            }
            Mutation::Truncate(a) => {
                let a = floor_char(&s, *a);
                s.truncate(a);
            }
        }
    }
    s
}

/// Checking never panics, and formatting what parses is idempotent, parses
/// again, and keeps every comment.
fn exercise(src: &str) {
    let (_, checked) = check_str("fuzz.axle", src);
    assert!(checked.model.is_some() || checked.problems.has_errors());
    if let Ok(once) = axle::fmt::format_source(FileId(0), src) {
        let twice = axle::fmt::format_source(FileId(0), &once).expect("formatted text parses");
        assert_eq!(once, twice, "formatting is not idempotent for:\n{src}");
        let before: Vec<String> = axle::syntax::trivia::comments(src)
            .into_iter()
            .map(|c| c.text)
            .collect();
        let after: Vec<String> = axle::syntax::trivia::comments(&once)
            .into_iter()
            .map(|c| c.text)
            .collect();
        assert_eq!(before, after, "comments lost for:\n{src}");
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 300, .. ProptestConfig::default() })]

    #[test]
    fn token_soup_never_panics(src in token_soup()) {
        exercise(&src);
    }

    #[test]
    fn mutated_examples_never_panic(seed in 0..SEEDS.len(), muts in prop::collection::vec(mutation(), 1..5)) {
        exercise(&apply(SEEDS[seed], &muts));
    }
}

#[test]
fn formatter_normalises_layout_and_keeps_comments() {
    let messy = "// head\nmodel  m   // trailing\n\n\n\nground g{\n  marker o at (0,0,0) mm // o\n\n  // inside\n   marker p at (1 ,2,3)mm\n}\npart p {\n marker o at (0, 0, 0) mm\n}\nbushing b {\n i g.o\n j p.o\n k (1, 2,\n    // odd\n    3) N/mm\n kt (1,1,1) N*mm/deg\n}\n";
    let out = axle::fmt::format_source(FileId(0), messy).expect("parses");
    let expected = "// head\nmodel m // trailing\n\nground g {\n    marker o at (0, 0, 0) mm // o\n\n    // inside\n    marker p at (1, 2, 3) mm\n}\n\npart p {\n    marker o at (0, 0, 0) mm\n}\n\nbushing b {\n    i g.o\n    j p.o\n    k (1, 2,\n    // odd\n    3) N/mm\n    kt (1, 1, 1) N*mm/deg\n}\n";
    assert_eq!(out, expected);
    exercise(messy);
}

/// Extreme numbers and unit powers (found by hand: `mm^100*mm^100` overflowed
/// the dimension exponents) give diagnostics, never a panic.
#[test]
fn extreme_powers_and_numbers_never_panic() {
    for value in [
        "(0, 0, 0) mm^100*mm^100",
        "(0, 0, 0) mm^999",
        "(0, 0, 0) mm^-128/mm^127",
        "(((1 mm^9)^9)^9, 0, 0) mm",
        "((1 mm^-9)^9 / (1 mm^9)^9, 0, 0) mm",
        "(1e308 * 1e308, 0, 0) mm",
        "(1e999, 0, 0) mm",
        "(sqrt((1 mm^9)^9), 0, 0) mm",
    ] {
        let src = format!("ground g {{\n    marker o at {value}\n}}\n");
        let (_, checked) = check_str("extreme.axle", &src);
        assert!(checked.problems.has_errors(), "{value} was accepted");
        exercise(&src);
    }
}

/// The primary label's 1-based line of a diagnostic of `check_str`.
fn first_line(src: &str, d: &axle::diagnostic::Diagnostic) -> usize {
    let l = d
        .labels
        .iter()
        .find(|l| l.primary)
        .expect("a primary label");
    src[..l.span.start as usize].matches('\n').count() + 1
}

/// Expressions deep enough to overflow any recursion (on the 2 MB stack of a
/// test thread) are E0005 on their line, never an abort.
#[test]
fn deep_and_long_expressions_are_a_located_diagnostic_not_a_stack_overflow() {
    let nested = format!("{}1{}", "(".repeat(1600), ")".repeat(1600));
    let sum = vec!["1"; 20_000].join(" + ");
    let minus = format!("{}1", "-".repeat(100_000));
    let product = vec!["2"; 20_000].join(" * ");
    for value in [nested, sum, minus, product] {
        let src = format!("ground g {{\n    marker o at ({value}, 0, 0) mm\n}}\n");
        let (_, checked) = check_str("deep.axle", &src);
        let d = &checked.problems.list[0];
        assert_eq!(d.code, "E0005", "{}", d.message);
        assert_eq!(first_line(&src, d), 2);
        assert!(axle::fmt::format_source(FileId(0), &src).is_err());
    }
}

/// 10 000 parts held by nothing: one E0411 each, and no dense mobility
/// analysis of a model that is wrong already (its 60 000 x 60 000 matrix
/// would need 28.8 GB: the allocation aborted the process).
#[test]
fn ten_thousand_unconnected_parts_get_one_error_each_and_no_dense_analysis() {
    let mut src = String::from("ground g {\n    marker o at (0, 0, 0) mm\n}\n");
    for k in 0..10_000 {
        src += &format!("part p{k} {{\n    marker o at ({k}, 0, 0) mm\n}}\n");
    }
    let (_, checked) = check_str("many.axle", &src);
    let codes: Vec<&str> = checked.problems.list.iter().map(|d| d.code).collect();
    assert_eq!(codes.len(), 10_000);
    assert!(codes.iter().all(|c| *c == "E0411"));
    let last = checked.problems.list.last().expect("errors");
    assert_eq!(first_line(&src, last), 4 + 3 * 9_999);
}
