//! Bad parameter addresses on the command line: one diagnostic (E0803, with
//! did-you-mean), worded once, for `solve --trim` and `identify --unknown`.

use std::process::Command;

fn stderr_of(args: &[&str]) -> (i32, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_axle"))
        .args(args)
        .output()
        .expect("runs");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// Noise-free landmarks of the McPherson along Table 5-1, written once.
fn landmarks() -> String {
    let (_, c) = axle::check::check_str(
        "mcpherson.axle",
        &std::fs::read_to_string("examples/mcpherson.axle").expect("example"),
    );
    let truth = c.model.expect("checks");
    let id = truth.load_set_named("thesis_table_5_1").expect("set");
    let csv = axle::measure::synthetic::landmarks_csv(&truth, id, 0.0, 1).expect("solves");
    let dir = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("addresses");
    std::fs::create_dir_all(&dir).expect("tmp dir");
    let lm = dir.join("landmarks.csv");
    std::fs::write(&lm, csv).expect("write landmarks");
    lm.to_string_lossy().into_owned()
}

#[test]
fn trim_with_a_misspelt_field_or_element() {
    let (code, err) = stderr_of(&[
        "solve",
        "examples/mcpherson.axle",
        "--trim",
        "spring.free_lenght",
    ]);
    assert_eq!(code, 1);
    insta::assert_snapshot!("trim_field", err);
    let (code, err) = stderr_of(&["solve", "examples/mcpherson.axle", "--trim", "sprng.k"]);
    assert_eq!(code, 1);
    insta::assert_snapshot!("trim_element", err);
}

#[test]
fn identify_with_a_misspelt_field_or_marker() {
    let lm = landmarks();
    let run = |unknown: &str| {
        stderr_of(&[
            "identify",
            "examples/mcpherson.axle",
            "--landmarks",
            &lm,
            "--method",
            "lsq",
            "--unknown",
            unknown,
        ])
    };
    let (code, err) = run("A.k_raidal");
    assert_eq!(code, 1);
    insta::assert_snapshot!("identify_field", err);
    let (code, err) = run("upright.L77.z");
    assert_eq!(code, 1);
    insta::assert_snapshot!("identify_marker", err);
    // The trim and identify diagnostics are worded alike: only the option differs.
    let (_, trim) = stderr_of(&["solve", "examples/mcpherson.axle", "--trim", "A.k_raidal"]);
    let (_, ident) = run("A.k_raidal");
    assert_eq!(trim.replace("--trim", "--unknown"), ident);
}
