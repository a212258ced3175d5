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
