//! A seeded mutation test of the examples: lines and tokens deleted,
//! duplicated and swapped, special numbers, garbage and non-UTF-8 bytes,
//! truncation, deep nesting and huge sweeps. Each mutant is read as the
//! command line reads a file, checked, and (when it checks) solved, in
//! process. Asserted: no panic (a panic fails the test), every diagnostic
//! has a location, and time and memory are bounded by construction: the
//! checked model is no larger than its source allows and the solve runs at
//! most `CASES` cases of each set (each Newton solve is iteration-capped).

use axle::check::check_str;
use axle::model::LoadSetId;
use proptest::prelude::*;
use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};
use std::sync::atomic::{AtomicUsize, Ordering::Relaxed};

/// What the mutants came to: not UTF-8, rejected by the checker, solved.
static NOT_UTF8: AtomicUsize = AtomicUsize::new(0);
static REJECTED: AtomicUsize = AtomicUsize::new(0);
static SOLVED: AtomicUsize = AtomicUsize::new(0);

const EXAMPLES: &[&str] = &[
    include_str!("../examples/mcpherson.axle"),
    include_str!("../examples/four_bar.axle"),
    include_str!("../examples/slider_crank.axle"),
    include_str!("../examples/single_bushing.axle"),
    include_str!("../examples/tour.axle"),
];

/// Cases solved per load set of a mutant that checks.
const CASES: usize = 2;

const SPECIAL: &[&str] = &[
    "NaN",
    "inf",
    "-inf",
    "1e400",
    "-1e400",
    "1e-400",
    "1e-300",
    "1e200",
    "-0",
    "0",
    "1e308",
    "0.0000001",
    "99999999999999999999",
    "--1",
    "(1",
    "1)",
    "1e",
    ".",
    "",
];

const GARBAGE: &[&[u8]] = &[
    b"\xff",
    b"\xc3\x28",
    b"\x00",
    b"\xe2\x82",
    b"\r",
    b"\t\t",
    b"{",
    b"}",
    b"//",
    "\u{202e}".as_bytes(),
    "é".as_bytes(),
];

#[derive(Debug, Clone)]
enum Mutation {
    DeleteLine(usize),
    DuplicateLine(usize),
    SwapLines(usize, usize),
    DeleteToken(usize),
    DuplicateToken(usize),
    SwapTokens(usize, usize),
    SpecialNumber(usize, usize),
    Garbage(usize, usize),
    Truncate(usize),
    DeepNesting(usize, usize),
    HugeSweep(usize),
}

fn mutation() -> impl Strategy<Value = Mutation> {
    let i = any::<usize>;
    prop_oneof![
        i().prop_map(Mutation::DeleteLine),
        i().prop_map(Mutation::DuplicateLine),
        (i(), i()).prop_map(|(a, b)| Mutation::SwapLines(a, b)),
        i().prop_map(Mutation::DeleteToken),
        i().prop_map(Mutation::DuplicateToken),
        (i(), i()).prop_map(|(a, b)| Mutation::SwapTokens(a, b)),
        (i(), i()).prop_map(|(a, b)| Mutation::SpecialNumber(a, b)),
        (i(), i()).prop_map(|(a, b)| Mutation::Garbage(a, b)),
        i().prop_map(Mutation::Truncate),
        (i(), 1usize..3000).prop_map(|(a, n)| Mutation::DeepNesting(a, n)),
        i().prop_map(Mutation::HugeSweep),
    ]
}

/// Byte ranges of the whitespace-separated tokens.
fn tokens(s: &[u8]) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut start = None;
    for (k, b) in s.iter().enumerate() {
        match (b.is_ascii_whitespace(), start) {
            (false, None) => start = Some(k),
            (true, Some(a)) => {
                out.push((a, k));
                start = None;
            }
            _ => {}
        }
    }
    if let Some(a) = start {
        out.push((a, s.len()));
    }
    out
}

fn lines(s: &[u8]) -> Vec<Vec<u8>> {
    s.split(|b| *b == b'\n').map(<[u8]>::to_vec).collect()
}

fn apply(src: &[u8], m: &Mutation) -> Vec<u8> {
    let mut s = src.to_vec();
    let ls = lines(&s);
    let ts = tokens(&s);
    let splice = |s: &mut Vec<u8>, (a, b): (usize, usize), with: &[u8]| {
        s.splice(a..b, with.iter().copied());
    };
    match *m {
        Mutation::DeleteLine(k) | Mutation::DuplicateLine(k) | Mutation::SwapLines(k, _)
            if ls.is_empty() =>
        {
            let _ = k;
        }
        Mutation::DeleteLine(k) => {
            let mut l = ls.clone();
            l.remove(k % ls.len());
            s = l.join(&b'\n');
        }
        Mutation::DuplicateLine(k) => {
            let mut l = ls.clone();
            l.insert(k % ls.len(), ls[k % ls.len()].clone());
            s = l.join(&b'\n');
        }
        Mutation::SwapLines(a, b) => {
            let mut l = ls.clone();
            l.swap(a % ls.len(), b % ls.len());
            s = l.join(&b'\n');
        }
        Mutation::DeleteToken(k) if !ts.is_empty() => splice(&mut s, ts[k % ts.len()], b""),
        Mutation::DuplicateToken(k) if !ts.is_empty() => {
            let (a, b) = ts[k % ts.len()];
            let mut t = src[a..b].to_vec();
            t.push(b' ');
            splice(&mut s, (a, a), &t);
        }
        Mutation::SwapTokens(x, y) if !ts.is_empty() => {
            let (p, q) = (ts[x % ts.len()], ts[y % ts.len()]);
            let (first, second) = if p.0 <= q.0 { (p, q) } else { (q, p) };
            if first != second && first.1 <= second.0 {
                let (t1, t2) = (
                    src[first.0..first.1].to_vec(),
                    src[second.0..second.1].to_vec(),
                );
                splice(&mut s, second, &t1);
                splice(&mut s, first, &t2);
            }
        }
        Mutation::SpecialNumber(k, n) if !ts.is_empty() => {
            // Numbers are what the special values replace.
            let nums: Vec<_> = ts
                .iter()
                .filter(|(a, _)| src[*a].is_ascii_digit() || src[*a] == b'-')
                .collect();
            if !nums.is_empty() {
                splice(
                    &mut s,
                    *nums[k % nums.len()],
                    SPECIAL[n % SPECIAL.len()].as_bytes(),
                );
            }
        }
        Mutation::Garbage(at, g) => {
            let at = at % (s.len() + 1);
            splice(&mut s, (at, at), GARBAGE[g % GARBAGE.len()]);
        }
        Mutation::Truncate(at) => s.truncate(at % (s.len() + 1)),
        Mutation::DeepNesting(k, n) if !ts.is_empty() => {
            let t = ts[k % ts.len()];
            let v = src[t.0..t.1].to_vec();
            let mut deep = b"(".repeat(n);
            deep.extend(&v);
            deep.extend(b")".repeat(n));
            splice(&mut s, t, &deep);
        }
        Mutation::HugeSweep(k) => {
            let extra: &[u8] = match k % 3 {
                0 => b"\nloads huge sweep {\n    chassis.o.fz 0 N -> 1 N by 1e-300 N\n}\n",
                1 => b"\nloads huge sweep {\n    upright.wc.fz 0 N -> 1e6 N by 1e-3 N\n}\n",
                _ => b"\nloads huge sweep {\n    left.fz 0 N -> 9e6 N by 1 N\n}\n",
            };
            s.extend_from_slice(extra);
        }
        _ => {}
    }
    s
}

/// Reads the bytes as the command line reads a file, checks and solves.
fn exercise(bytes: &[u8], scratch: &std::path::Path) {
    std::fs::write(scratch, bytes).expect("scratch file");
    let text = match axle::cli::read::read_text(scratch) {
        Ok(t) => t,
        Err(e) => {
            let mut sources = axle::source::SourceMap::new();
            let d = e.to_diagnostic(&mut sources, scratch);
            assert_eq!(d.code, "E0002", "{}", d.message);
            assert!(!d.labels.is_empty(), "{}", d.message);
            let l = &d.labels[0];
            let (line, col) = sources.line_col(l.span.file, l.span.start as usize);
            assert!(line >= 1 && col >= 1);
            NOT_UTF8.fetch_add(1, Relaxed);
            return;
        }
    };
    let (_, checked) = check_str("mutant.axle", &text);
    for d in &checked.problems.list {
        assert!(
            d.labels.iter().any(|l| l.primary),
            "{} {} has no location in:\n{text}",
            d.code,
            d.message
        );
    }
    let Some(model) = checked.model.filter(|_| !checked.problems.has_errors()) else {
        REJECTED.fetch_add(1, Relaxed);
        return;
    };
    // Bounded by construction: no element without a line of source, no
    // sweep beyond its bound.
    let lines = text.lines().count() + 1;
    assert!(model.parts.len() + model.bushings.len() + model.joints.len() <= lines);
    for ls in &model.load_sets {
        assert!(ls.cases.len() <= 100_000, "{} cases", ls.cases.len());
    }
    let Ok(problem) = axle::statics::Problem::new(&model) else {
        return;
    };
    for (k, ls) in model.load_sets.iter().enumerate() {
        let mut short = model.clone();
        short.load_sets[k].cases.truncate(CASES);
        let Ok(problem) = axle::statics::Problem::new(&short) else {
            continue;
        };
        if let Err(e) = axle::statics::path::solve_path(&problem, LoadSetId(k as u32)) {
            let d = e.error.to_diagnostic(&short);
            assert!(
                !d.labels.is_empty() || !e.error.elements.is_empty(),
                "solve failure of `{}` names nothing: {}",
                ls.name,
                d.message
            );
        }
    }
    drop(problem);
    SOLVED.fetch_add(1, Relaxed);
}

#[test]
fn mutated_examples_never_panic_and_every_diagnostic_is_located() {
    let scratch =
        std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("mutation_mutant.axle");
    let mut runner = TestRunner::new_with_rng(
        Config {
            cases: 500,
            failure_persistence: None,
            ..Config::default()
        },
        TestRng::from_seed(RngAlgorithm::ChaCha, &[15; 32]),
    );
    let strategy = (0..EXAMPLES.len(), prop::collection::vec(mutation(), 1..4));
    runner
        .run(&strategy, |(k, muts)| {
            let mut bytes = EXAMPLES[k].as_bytes().to_vec();
            for m in &muts {
                bytes = apply(&bytes, m);
            }
            exercise(&bytes, &scratch);
            Ok(())
        })
        .expect("no mutant fails");
    // The mutants reach every stage (the seed is fixed: these are exact).
    let (u, r, s) = (
        NOT_UTF8.load(Relaxed),
        REJECTED.load(Relaxed),
        SOLVED.load(Relaxed),
    );
    assert!(
        u > 10 && r > 100 && s > 50,
        "not UTF-8 {u}, rejected {r}, solved {s}"
    );
}
