//! `-o` gives back the engineer's own file: `identify`, `locate` and `correct`
//! on a McPherson written with comments in odd places, a parameter, vectors
//! and units other than the internal ones (m, cm, kN/mm). Each snapshot shows
//! the input lines, the command and the lines it changed; numbers in the
//! snapshot are rounded to 5 significant digits (the assertions check the
//! values themselves against the truth model).

mod common;
use common::{axle, scratch};

const TRUTH: &str = "examples/mcpherson.axle";

/// The McPherson with A's radial rate a parameter started off at 10 kN/mm,
/// B's soft rate started off at 250 N/mm inside a vector broken by a comment,
/// the chassis' B marker in metres and the upright's L7 in centimetres.
fn variant() -> String {
    let text = std::fs::read_to_string(TRUTH).expect("example");
    let swaps = [
        (
            "default loads thesis_table_5_1\n",
            "default loads thesis_table_5_1\n\nparam k_a = 10 kN/mm unknown [1 kN/mm, 50 kN/mm] // A's radial rate, to identify\n",
        ),
        (
            "    marker B at (294.7, 365.1, 246.1) mm euler (309.5, 90.22, 181.7) deg\n    marker A",
            "    marker B at (0.2947, 0.3651, 0.2461) m euler (309.5, 90.22, 181.7) deg // metres\n    marker A",
        ),
        (
            "    marker L7 at (-5.87, 679.9, 164.8) mm\n    marker L8",
            "    marker L7 at (-0.587, 67.99, 16.48) cm // centimetres\n    marker L8",
        ),
        (
            "    k (310, 2400, 180) N/mm\n",
            "    k (250, // soft along the arm\n       2400, 180) N/mm\n",
        ),
        ("    k_radial 13875 N/mm\n", "    k_radial k_a\n"),
    ];
    swaps.iter().fold(text, |t, (from, to)| {
        assert!(t.contains(from), "{from}");
        t.replacen(from, to, 1)
    })
}

fn truth() -> axle::model::Model {
    let (_, c) = axle::check::check_str(
        "mcpherson.axle",
        &std::fs::read_to_string(TRUTH).expect("example"),
    );
    c.model.expect("the example checks")
}

/// Noise-free landmarks of the truth along one of its load sets, as CSV.
fn landmarks(set: &str, name: &str) -> String {
    let m = truth();
    let id = m.load_set_named(set).expect("set");
    scratch(
        name,
        &axle::measure::synthetic::landmarks_csv(&m, id, 0.0, 1).expect("solves"),
    )
}

/// Rounds every number with more than 5 significant digits (for snapshots).
fn round(line: &str) -> String {
    let mut out = String::new();
    let mut num = String::new();
    let flush = |num: &mut String, out: &mut String| {
        if let (true, Ok(v)) = (num.len() > 6, num.parse::<f64>()) {
            let digits = 4 - (v.abs().log10().floor() as i32).min(4);
            out.push_str(&format!("{:.*}", digits.max(0) as usize, v));
        } else {
            out.push_str(num);
        }
        num.clear();
    };
    for c in line.chars() {
        if c.is_ascii_digit() || c == '.' || (c == '-' && num.is_empty()) {
            num.push(c);
        } else {
            flush(&mut num, &mut out);
            out.push(c);
        }
    }
    flush(&mut num, &mut out);
    out
}

/// The changed lines, `-` before and `+` after (the edit keeps the line count).
fn diff(input: &str, output: &str) -> String {
    assert_eq!(input.lines().count(), output.lines().count(), "{output}");
    input
        .lines()
        .zip(output.lines())
        .enumerate()
        .filter(|(_, (a, b))| a != b)
        .map(|(n, (a, b))| format!("{:>4} - {}\n     + {}\n", n + 1, round(a), round(b)))
        .collect()
}

/// Runs a command writing `-o`; returns the written text, checked again.
fn run(args: &[&str], out: &str) -> String {
    let mut all: Vec<&str> = args.to_vec();
    all.extend(["-o", out]);
    let (code, _, stderr) = axle(&all);
    assert_eq!(code, 0, "{stderr}");
    let text = std::fs::read_to_string(out).expect("-o written");
    let (code, _, stderr) = axle(&["check", out]);
    assert_eq!(code, 0, "axle check rejects the output: {stderr}");
    text
}

fn number_after(text: &str, key: &str) -> f64 {
    let at = text.find(key).unwrap_or_else(|| panic!("{key}")) + key.len();
    let n: String = text[at..]
        .chars()
        .take_while(|c| c.is_ascii_digit() || *c == '.' || *c == '-')
        .collect();
    n.parse().expect("a number")
}

#[test]
fn identify_o_rewrites_only_the_identified_values_in_their_units() {
    let input = scratch("edits_identify_in.axle", &variant());
    let csv = landmarks("thesis_table_5_1", "edits_identify.csv");
    let out = scratch("edits_identify_out.axle", "");
    let args = [
        "identify",
        &input,
        "--landmarks",
        &csv,
        "--method",
        "lsq",
        "--unknown",
        "k_a",
        "B.k_x",
        "--format",
        "json",
    ];
    let text = run(&args, &out);
    // The truth: A radial 13875 N/mm, B along the arm 310 N/mm (noise-free data).
    let k_a = number_after(&text, "param k_a = ");
    let b_x = number_after(&text, "    k (");
    assert!((k_a - 13.875).abs() < 1e-3 * 13.875, "k_a = {k_a} kN/mm");
    assert!((b_x - 310.0).abs() < 1e-3 * 310.0, "B.k_x = {b_x} N/mm");
    insta::assert_snapshot!(format!(
        "axle identify IN --landmarks CSV --method lsq --unknown k_a B.k_x -o OUT\n----- CHANGED LINES\n{}",
        diff(&variant(), &text)
    ));
}

#[test]
fn locate_o_moves_the_located_markers_in_the_units_they_were_written_in() {
    let input = scratch("edits_locate_in.axle", &variant());
    let csv = landmarks("thesis_table_4_4", "edits_locate.csv");
    let out = scratch("edits_locate_out.axle", "");
    let text = run(
        &["locate", &input, "--landmarks", &csv, "--format", "json"],
        &out,
    );
    // The located ball joint L7, in centimetres on the upright, within 0.1 mm of the truth.
    let line = text
        .lines()
        .find(|l| l.contains("marker L7") && l.contains("cm"))
        .expect("L7");
    let nums: Vec<f64> = line[line.find('(').unwrap() + 1..line.find(')').unwrap()]
        .split(',')
        .map(|x| x.trim().parse().expect("number"))
        .collect();
    for (got, want) in nums.iter().zip([-5.87, 679.9, 164.8]) {
        assert!((got * 10.0 - want).abs() < 0.1, "{line}");
    }
    insta::assert_snapshot!(format!(
        "axle locate IN --landmarks CSV -o OUT\n----- CHANGED LINES\n{}",
        diff(&variant(), &text)
    ));
}

#[test]
fn correct_o_keeps_comments_and_units_and_restates_moved_frames() {
    let input = scratch("edits_correct_in.axle", &variant());
    let csv = landmarks("thesis_table_5_1", "edits_correct.csv");
    let out = scratch("edits_correct_out.axle", "");
    let args = [
        "correct",
        &input,
        "--landmarks",
        &csv,
        "--loadcases",
        "thesis_table_5_1",
        "--case",
        "c3",
        "--step",
        "3",
    ];
    let text = run(&args, &out);
    // Every comment of the input is still there, in order.
    let comments = |t: &str| -> Vec<String> {
        t.lines()
            .filter_map(|l| l.find("//").map(|i| l[i..].to_string()))
            .collect()
    };
    assert_eq!(comments(&text), comments(&variant()));
    insta::assert_snapshot!(format!(
        "axle correct IN --landmarks CSV --loadcases thesis_table_5_1 --case c3 --step 3 -o OUT\n----- CHANGED LINES\n{}",
        diff(&variant(), &text)
    ));
}

/// `identify` failures are diagnostics with codes, on stderr for the table and
/// as `{"diagnostics": [...]}` on stdout with `--format json` (exit 1 both).
#[test]
fn identify_failures_are_coded_diagnostics_in_both_formats() {
    let csv = landmarks("thesis_table_5_1", "edits_fail.csv");
    let tmp = env!("CARGO_TARGET_TMPDIR");
    let redact = |s: &str| s.replace(tmp, "TMP");
    let base = ["identify", TRUTH, "--landmarks", &csv, "--method", "lsq"];
    let with = |extra: &[&str]| {
        let mut v = base.to_vec();
        v.extend(extra);
        axle(&v)
    };
    // A misspelt load set: E0801 with a did-you-mean, a usage error (exit 2,
    // issue 15 and docs/language.md).
    let (code, stdout, stderr) = with(&["--loadcases", "thesis_table_5_2"]);
    assert_eq!(code, 2);
    assert!(stdout.is_empty());
    // 17 cases of Table 4.4 against the landmarks of Table 5.1's steps: E1101.
    let (code2, _, stderr2) = with(&["--loadcases", "thesis_table_4_4"]);
    assert_eq!(code2, 1);
    let (code3, json, _) = with(&["--loadcases", "thesis_table_4_4", "--format", "json"]);
    assert_eq!(code3, 1);
    let v: serde_json::Value = serde_json::from_str(&json).expect("one JSON document");
    assert_eq!(v["diagnostics"][0]["code"], "E1101");
    assert_eq!(v["diagnostics"][0]["severity"], "error");
    insta::assert_snapshot!(format!(
        "----- --loadcases thesis_table_5_2 (stderr)\n{}----- --loadcases thesis_table_4_4 (stderr)\n{}----- --loadcases thesis_table_4_4 --format json (stdout)\n{}",
        redact(&stderr),
        redact(&stderr2),
        redact(&json)
    ));
}

/// A friction's limit changed by a tool is rewritten on its own line, and a
/// friction added by a tool is appended with its reason; both check again.
#[test]
fn friction_fields_are_edited_in_place_and_new_frictions_appended() {
    use axle::fmt::{Request, edit_source};
    use axle::model::{ElementId, FrictionId};
    let path = "examples/mcpherson_friction.axle";
    let text = std::fs::read_to_string(path).expect("example");
    let (_, c) = axle::check::check_str(path, &text);
    let old = c.model.expect("the example checks");
    let mut new = old.clone();
    new.frictions[0].limit.value = 180.0;
    let mut added = new.frictions[0].clone();
    added.name = "L5_friction_2".into();
    added.limit.value = 20.0;
    new.frictions.push(added);
    let reasons = [(
        ElementId::Friction(FrictionId(1)),
        "a second, lighter friction explains the small loops".to_string(),
    )];
    let req = Request {
        tool: "diagnose",
        reasons: &reasons,
    };
    let out = edit_source(axle::span::FileId(0), path, &text, &old, &new, &req).expect("edits");
    let changed: Vec<(&str, &str)> = text
        .lines()
        .zip(out.text.lines())
        .filter(|(a, b)| a != b)
        .collect();
    assert_eq!(changed.len(), 1, "{changed:?}");
    assert!(
        changed[0].0.contains("150") && changed[0].1.contains("180"),
        "{changed:?}"
    );
    let tail = &out.text[text.len()..];
    assert!(
        tail.starts_with("\n// added by diagnose: a second, lighter friction explains the small loops\nfriction L5_friction_2 {"),
        "{tail}"
    );
    let (_, again) = axle::check::check_str(path, &out.text);
    let again = again.model.expect("the edited file checks");
    assert_eq!(again.frictions.len(), 2);
    assert_eq!(again.frictions[0].limit.value, 180.0);
    assert_eq!(again.frictions[1].limit.value, 20.0);
}
