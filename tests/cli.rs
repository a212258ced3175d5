//! The built `axle` binary: exit codes, streams and JSON shapes of interfaces.md.

mod common;
use common::axle;

#[test]
fn check_passes_clean_examples_with_exit_0() {
    let (code, stdout, stderr) =
        axle(&["check", "examples/mcpherson.axle", "examples/four_bar.axle"]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stdout.is_empty() && stderr.is_empty());
}

#[test]
fn check_reports_every_error_with_exit_1() {
    let (code, _, stderr) = axle(&[
        "check",
        "tests/fail/units/angle_in_position.axle",
        "tests/fail/names/unknown_part.axle",
    ]);
    assert_eq!(code, 1);
    assert!(
        stderr.contains("tests/fail/units/angle_in_position.axle:8:31"),
        "{stderr}"
    );
    assert!(
        stderr.contains("tests/fail/names/unknown_part.axle:13:"),
        "{stderr}"
    );
    assert!(!stderr.contains("panicked"));
}

#[test]
fn one_run_reports_errors_of_every_stage() {
    // A unit mistake, a misspelt part and a joint whose markers do not meet: the
    // geometry is still checked on the elements that were read.
    let text = "ground chassis {\n    marker o at (0, 0, 0) mm\n}\n\npart arm {\n    marker o at (0, 0, 0) mm\n    marker tip at (300, 0, 0) mm\n}\n\npart link {\n    marker a at (300, 0, 2) mm\n}\n\nbushing b {\n    i chassis.o\n    j arm.o\n    k (1000, 1000, 1000) N*mm\n    kt (1000, 1000, 1000) N*mm/deg\n}\n\nbushing c {\n    i chasis.o\n    j link.a\n    k (1000, 1000, 1000) N/mm\n    kt (1000, 1000, 1000) N*mm/deg\n}\n\njoint ball spherical {\n    i link.a\n    j arm.tip\n}\n";
    let dir = std::env::temp_dir().join(format!("axle-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let path = dir.join("three_mistakes.axle");
    std::fs::write(&path, text).expect("write");
    let (code, stdout, _) = axle(&["check", "--format", "json", path.to_str().expect("utf-8")]);
    std::fs::remove_dir_all(&dir).ok();
    assert_eq!(code, 1);
    let v: serde_json::Value = serde_json::from_str(&stdout).expect("one JSON document");
    let found: Vec<(String, u64)> = v["diagnostics"]
        .as_array()
        .expect("a list")
        .iter()
        .map(|d| {
            (
                d["code"].as_str().unwrap_or("").to_string(),
                d["line"].as_u64().unwrap_or(0),
            )
        })
        .collect();
    let want = [("E0201", 17), ("E0101", 22), ("E0303", 28)];
    assert_eq!(found, want.map(|(c, l)| (c.to_string(), l)), "{stdout}");
}

#[test]
fn check_json_lists_diagnostics_with_positions() {
    let (code, stdout, _) = axle(&[
        "check",
        "--format",
        "json",
        "tests/fail/names/unknown_part.axle",
    ]);
    assert_eq!(code, 1);
    let v: serde_json::Value = serde_json::from_str(&stdout).expect("one JSON document");
    let d = &v["diagnostics"][0];
    assert_eq!(d["severity"], "error");
    assert_eq!(d["code"], "E0101");
    assert_eq!(d["line"], 13);
    assert_eq!(d["column"], 7);
    assert_eq!(d["file"], "tests/fail/names/unknown_part.axle");
}

#[test]
fn warnings_do_not_fail_check() {
    let (code, _, stderr) = axle(&["check", "tests/fail/geometry/ambiguous_landmarks.axle"]);
    assert_eq!(code, 0);
    assert!(stderr.contains("warning[W0306]"));
}

#[test]
fn missing_file_and_bad_usage_exit_2() {
    let (code, _, stderr) = axle(&["check", "no/such/file.axle"]);
    assert_eq!(code, 2);
    assert!(stderr.contains("cannot read"));
    let (code, _, _) = axle(&["frobnicate"]);
    assert_eq!(code, 2);
}

#[test]
fn fmt_check_accepts_examples_and_rejects_messy_files() {
    let (code, _, stderr) = axle(&[
        "fmt",
        "--check",
        "examples/mcpherson.axle",
        "stdlib/mcpherson_loads.axle",
    ]);
    assert_eq!(code, 0, "{stderr}");
    let dir = std::env::temp_dir().join(format!("axle-fmt-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let file = dir.join("messy.axle");
    std::fs::write(&file, "model   m\nground g {\nmarker o at (0,0,0) mm\n}\n").expect("write");
    let f = file.to_string_lossy().into_owned();
    let (code, _, stderr) = axle(&["fmt", "--check", &f]);
    assert_eq!(code, 1, "{stderr}");
    let (code, _, _) = axle(&["fmt", &f]);
    assert_eq!(code, 0);
    assert_eq!(
        std::fs::read_to_string(&file).expect("read"),
        "model m\n\nground g {\n    marker o at (0, 0, 0) mm\n}\n"
    );
    let (code, _, _) = axle(&["fmt", "--check", &f]);
    assert_eq!(code, 0);
    let _ = std::fs::remove_dir_all(&dir);
}

/// `identify`: `--kc`, `--loads` and `--loadcases` exclude each other, a
/// missing file is exit 2, a wrong set name a usage error listing the sets,
/// and a K&C file that measures other steps than the landmarks an error.
#[test]
fn identify_options_exclude_each_other_and_mismatched_steps_are_errors() {
    let (code, _, stderr) = axle(&["check", "examples/mcpherson.axle"]);
    assert_eq!(code, 0, "{stderr}");
    let (_, checked) = axle::check::check_str(
        "m.axle",
        &std::fs::read_to_string("examples/mcpherson.axle").expect("example"),
    );
    let model = checked.model.expect("checks");
    let set = model.load_set_named("thesis_table_5_1").expect("set");
    let (landmarks, _) = common::landmark_files(&model, set, 0.0, 3, "cli_identify");
    let (code, kc, stderr) = axle(&[
        "kc",
        "examples/mcpherson.axle",
        "--sweep",
        "thesis_table_5_1",
        "--format",
        "csv",
    ]);
    assert_eq!(code, 0, "{stderr}");
    let full = common::scratch("cli_identify_kc.csv", &kc);
    let mut rows: Vec<&str> = kc.lines().collect();
    rows.pop();
    let short = common::scratch("cli_identify_kc_short.csv", &(rows.join("\n") + "\n"));
    let base = [
        "identify",
        "examples/mcpherson.axle",
        "--method",
        "direct",
        "--landmarks",
        &landmarks,
    ];
    let run = |extra: &[&str]| axle(&[&base[..], extra].concat());
    let (code, _, stderr) = run(&["--kc", &full, "--loadcases", "bump"]);
    assert_eq!(code, 2, "{stderr}");
    assert!(stderr.contains("cannot be used with"), "{stderr}");
    let (code, _, stderr) = run(&["--loads", &full, "--loadcases", "bump"]);
    assert_eq!(code, 2, "{stderr}");
    let (code, _, stderr) = run(&["--kc", "no/such.csv"]);
    assert_eq!(code, 2, "{stderr}");
    let (code, _, stderr) = run(&["--loadcases", "thesis_table_51"]);
    assert_eq!(code, 2, "{stderr}");
    assert!(stderr.contains("thesis_table_5_1, bump"), "{stderr}");
    let (code, _, stderr) = run(&["--kc", &short]);
    assert_eq!(code, 1, "{stderr}");
    assert!(
        stderr.contains("the K&C file has 12 steps and the landmarks 13; steps 13 have no K&C row"),
        "{stderr}"
    );
}
