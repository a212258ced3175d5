//! Issue 15: `locate` on data that cannot determine anything says what is
//! missing (E0810: fewer than two states with relative motion; E0811: a part
//! with landmarks in the model absent from the data) instead of printing
//! tables of NaN and 1e14 mm.

mod common;
use common::{axle, scratch};

const DATA: &str =
    include_str!("data/expected/mcpherson_thesis_table_4_4_landmarks_sigma0.05_seed1.csv");

/// The header and the rows of `DATA` that `keep` accepts (step, part).
fn rows(keep: impl Fn(&str, &str) -> bool) -> String {
    let mut out = String::new();
    for l in DATA.lines().filter(|l| !l.starts_with('#')) {
        let mut f = l.split(',');
        let (step, part) = (f.next().unwrap_or(""), f.next().unwrap_or(""));
        if step == "step" || keep(step, part) {
            out += l;
            out += "\n";
        }
    }
    out
}

fn locate(name: &str, csv: &str) -> (i32, String, String) {
    let path = scratch(name, csv);
    axle(&["locate", "examples/mcpherson.axle", "--landmarks", &path])
}

#[test]
fn one_measured_state_is_an_error_not_a_table_of_nan() {
    let (code, out, err) = locate("locate_one_step.csv", &rows(|s, _| s == "1"));
    assert_eq!(code, 1, "{out}{err}");
    assert!(out.is_empty(), "{out}");
    assert!(
        err.contains("error[E0810]: locate needs at least two measured states with relative motion: the data has 1 (step 1)"),
        "{err}"
    );
}

#[test]
fn two_identical_states_are_no_motion() {
    let first = rows(|s, _| s == "1");
    let again: String = first
        .lines()
        .skip(1)
        .map(|l| format!("2{}\n", &l[1..]))
        .collect();
    let (code, out, err) = locate("locate_same_twice.csv", &format!("{first}{again}"));
    assert_eq!(code, 1, "{out}{err}");
    assert!(
        err.contains("no two connected parts move relative to each other between steps 1, 2"),
        "{err}"
    );
}

#[test]
fn a_measured_part_missing_from_the_data_is_named() {
    let (code, out, err) = locate("locate_no_tie_rod.csv", &rows(|_, p| p != "tie_rod"));
    assert_eq!(code, 1, "{out}{err}");
    assert!(out.is_empty(), "{out}");
    assert!(
        err.contains("error[E0811]: the landmark data measures no pose of part `tie_rod`"),
        "{err}"
    );
    assert!(err.contains("these cannot be located: `L3`, `L6`"), "{err}");
    assert!(
        err.contains("examples/mcpherson.axle"),
        "located at the part: {err}"
    );
}

/// The full data set still locates, and no table cell is NaN or absurd.
#[test]
fn complete_data_prints_no_nan_and_no_absurd_number() {
    let (code, out, err) = locate("locate_all.csv", &rows(|_, _| true));
    assert_eq!(code, 0, "{err}");
    assert!(!out.contains("NaN") && !out.contains("inf"), "{out}");
    for word in out.split(|c: char| c.is_whitespace() || "(),".contains(c)) {
        if let Ok(v) = word.parse::<f64>() {
            assert!(v.abs() < 1e5, "{word} in {out}");
        }
    }
}
