//! `axle diagnose` on the command line, as an engineer runs it: rig files
//! written by `axle kc --format csv` from a truth model, the corrected file
//! back through `-o` (checked again, the change commented), the report, and
//! bad input as located diagnostics.

mod common;
use common::{axle, scratch};

/// The K&C files of the McPherson with bushing B's x stiffness 775 N/mm.
fn rig(stem: &str) -> Vec<String> {
    let truth = include_str!("../examples/mcpherson.axle")
        .replace("k (310, 2400, 180) N/mm", "k (775, 2400, 180) N/mm");
    let t = scratch(&format!("{stem}_truth.axle"), &truth);
    ["bump", "lateral"]
        .iter()
        .map(|s| {
            let out = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
                .join(format!("{stem}_{s}.csv"))
                .to_string_lossy()
                .into_owned();
            let (code, _, err) = axle(&["kc", &t, "--sweep", s, "--format", "csv", "-o", &out]);
            assert_eq!(code, 0, "{err}");
            out
        })
        .collect()
}

#[test]
fn names_the_stiffer_bushing_and_writes_the_corrected_file() {
    let kc = rig("cli");
    let out = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("cli_fixed.axle");
    let out = out.to_string_lossy().into_owned();
    let report = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("cli_report");
    let report = report.to_string_lossy().into_owned();
    let (code, table, err) = axle(&[
        "diagnose",
        "examples/mcpherson.axle",
        "--kc",
        &kc[0],
        &kc[1],
        "--candidates",
        "stiffness,spring_free_length",
        "-o",
        &out,
        "--report",
        &report,
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(
        table.contains("1. Bushing `B` is, along its x axis, 2.50× stiffer than the model (775 [775, 775] N/mm against 310)"),
        "{table}"
    );
    let fixed = std::fs::read_to_string(&out).expect("written");
    assert!(
        fixed.contains("// changed by diagnose: Bushing `B` is, along its x axis, 2.50× stiffer"),
        "{fixed}"
    );
    assert!(fixed.contains("    k (775, 2400, 180) N/mm"), "{fixed}");
    // Only that line and its comment differ from the engineer's file.
    let before = include_str!("../examples/mcpherson.axle");
    assert_eq!(fixed.lines().count(), before.lines().count() + 1);
    let (code, _, err) = axle(&["check", &out]);
    assert_eq!(code, 0, "{err}");
    let html = std::fs::read_to_string(format!("{report}/diagnose.html")).expect("report");
    assert!(html.starts_with("<!DOCTYPE html>") && html.contains("<svg"));
    assert!(
        !html.contains("<script") && !html.contains("<link") && !html.contains("src=\"http"),
        "self-contained"
    );
}

#[test]
fn json_has_the_interface_keys() {
    let kc = rig("json");
    let (code, out, err) = axle(&[
        "diagnose",
        "examples/mcpherson.axle",
        "--kc",
        &kc[0],
        &kc[1],
        "--candidates",
        "stiffness",
        "--format",
        "json",
        "--noise",
        "toe_deg=0.005",
    ]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).expect("json");
    assert_eq!(v["verdict"]["kind"], "stiffness");
    assert_eq!(v["verdict"]["element"], "B");
    assert!(v["verdict"]["gain"]["wc_x_mm"].as_f64().expect("gain") > 0.99);
    assert_eq!(v["hypotheses"][0]["rank"], 1);
    assert!(v["baseline"]["rms"]["toe_deg"].as_f64().is_some());
    assert_eq!(v["effects"].as_array().map(Vec::len), Some(1));
    assert_eq!(v["noise"]["toe_deg"]["source"], "given");
    assert_eq!(v["noise"]["toe_deg"]["sigma"], 0.005);
}

#[test]
fn bad_input_is_a_located_diagnostic_or_a_usage_error() {
    let kc = rig("bad");
    let text = std::fs::read_to_string(&kc[0]).expect("rig");
    // A wheel the model does not have.
    let wrong = scratch("bad_wheel.csv", &text.replacen(",left,", ",lef,", 1));
    let (code, _, err) = axle(&["diagnose", "examples/mcpherson.axle", "--kc", &wrong]);
    assert_eq!(code, 1, "{err}");
    assert!(
        err.contains("the model has no wheel `lef`") && err.contains("bad_wheel.csv:2:"),
        "{err}"
    );
    assert!(err.contains("did you mean `left`?"), "{err}");
    // Too few steps to hold any out.
    let short: String = text.lines().take(3).map(|l| format!("{l}\n")).collect();
    let short = scratch("bad_short.csv", &short);
    let (code, _, err) = axle(&["diagnose", "examples/mcpherson.axle", "--kc", &short]);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("error[E1304]"), "{err}");
    // A column missing.
    let nocol = scratch("bad_nocol.csv", &text.replace("toe_deg", "toe"));
    let (code, _, err) = axle(&["diagnose", "examples/mcpherson.axle", "--kc", &nocol]);
    assert_eq!(code, 1, "{err}");
    assert!(
        err.contains("no column `toe_deg`") && err.contains("bad_nocol.csv:1:"),
        "{err}"
    );
    // Usage: a channel and a kind that do not exist, a file onto an input.
    let (code, _, err) = axle(&[
        "diagnose",
        "examples/mcpherson.axle",
        "--kc",
        &kc[0],
        "--noise",
        "toe=0.1",
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("no channel `toe`; channels: toe_deg, camber_deg"),
        "{err}"
    );
    let (code, _, err) = axle(&[
        "diagnose",
        "examples/mcpherson.axle",
        "--kc",
        &kc[0],
        "--candidates",
        "bumpstop",
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("no kind `bumpstop`; kinds: stiffness, joint_location, bump_stop"),
        "{err}"
    );
    let (code, _, err) = axle(&[
        "diagnose",
        "examples/mcpherson.axle",
        "--kc",
        &kc[0],
        "-o",
        &kc[0],
    ]);
    assert_eq!(code, 2, "{err}");
}

/// Landmark CSVs of the same truth runs as [`rig`], σ = 0.05 mm.
fn landmark_files(stem: &str) -> Vec<String> {
    let truth = include_str!("../examples/mcpherson.axle")
        .replace("k (310, 2400, 180) N/mm", "k (775, 2400, 180) N/mm");
    let (_, checked) = axle::check::check_str("truth.axle", &truth);
    let model = checked.model.expect("the truth checks");
    ["bump", "lateral"]
        .iter()
        .enumerate()
        .map(|(k, s)| {
            let set = model.load_set_named(s).expect("sweep");
            let csv = axle::measure::synthetic::landmarks_csv(&model, set, 0.05, 40 + k as u64)
                .expect("truth solves");
            scratch(&format!("{stem}_{s}_landmarks.csv"), &csv)
        })
        .collect()
}

#[test]
fn landmarks_are_a_channel_and_must_come_from_the_same_run() {
    let kc = rig("lm");
    let lm = landmark_files("lm");
    let (code, table, err) = axle(&[
        "diagnose",
        "examples/mcpherson.axle",
        "--kc",
        &kc[0],
        &kc[1],
        "--landmarks",
        &lm[0],
        &lm[1],
        "--candidates",
        "stiffness",
    ]);
    assert_eq!(code, 0, "{err}");
    let row = table
        .lines()
        .find(|l| l.trim_start().starts_with("landmarks_mm"))
        .unwrap_or_else(|| panic!("no landmark row: {table}"));
    assert!(row.contains("dof fit"), "{row}");
    // B stiffer along x moves the wheel fore and aft (wc_x is the channel it
    // changes most): the worst landmark is on the upright, along x.
    assert!(
        table.contains("lm_bump: landmark error (largest on `upright.")
            && table.contains("`, along x)"),
        "{table}"
    );
    assert!(
        table.contains("1. Bushing `B` is, along its x axis, 2.50× stiffer"),
        "{table}"
    );
    // The lateral run's landmarks (65 steps) against the bump's K&C (57).
    let (code, _, err) = axle(&[
        "diagnose",
        "examples/mcpherson.axle",
        "--kc",
        &kc[0],
        "--landmarks",
        &lm[1],
    ]);
    assert_eq!(code, 1, "{err}");
    assert!(
        err.contains("error[E1305]") && err.contains("the landmarks hold step 58"),
        "{err}"
    );
    assert!(err.contains("lm_lateral_landmarks.csv:"), "{err}");
    // Two K&C paths and one landmark file: which path it belongs to is unknown.
    let (code, _, err) = axle(&[
        "diagnose",
        "examples/mcpherson.axle",
        "--kc",
        &kc[0],
        &kc[1],
        "--landmarks",
        &lm[0],
    ]);
    assert_eq!(code, 1, "{err}");
    assert!(
        err.contains("error[E1306]") && err.contains("1 landmark files for 2 K&C files"),
        "{err}"
    );
}

/// An axle on the rig (issue 13): one K&C file with a row per wheel and
/// step, both wheels loaded. The truth's right spring is 10 mm longer; the
/// diagnosis replays both wheels' loads, compares each wheel with its own
/// rows, and names the right spring, not the left.
#[test]
fn an_axle_file_of_both_wheels_names_the_cause_on_its_side() {
    let axle_text = include_str!("../examples/front_axle.axle").replace(
        "default loads parallel_bump",
        "loads short_bump sweep {\n    front_left.wheel.fz 2000 N -> 7000 N by 500 N\n    front_right.wheel.fz 2000 N -> 7000 N by 500 N\n}\n\ndefault loads short_bump",
    );
    let model = scratch("axle_model.axle", &axle_text);
    let truth = scratch(
        "axle_truth.axle",
        &axle_text.replace(
            "instance front_right = mirror mcpherson_corner(rack = steering.rack)",
            "instance front_right = mirror mcpherson_corner(rack = steering.rack, free_length = 300 mm)",
        ),
    );
    let csv = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join("axle_short_bump.csv")
        .to_string_lossy()
        .into_owned();
    let (code, _, err) = axle(&[
        "kc",
        &truth,
        "--sweep",
        "short_bump",
        "--format",
        "csv",
        "-o",
        &csv,
    ]);
    assert_eq!(code, 0, "{err}");
    let text = std::fs::read_to_string(&csv).expect("written");
    assert!(text.contains("front_left.wheel") && text.contains("front_right.wheel"));
    let (code, table, err) = axle(&[
        "diagnose",
        &model,
        "--kc",
        &csv,
        "--candidates",
        "spring_free_length,stiffness",
    ]);
    assert_eq!(code, 0, "{err}");
    let first = table.lines().nth(1).expect("a first finding");
    assert!(
        first.starts_with("1. Spring `front_right.spring` has a free length of 300"),
        "{table}"
    );
    assert!(!first.contains("front_left"), "{table}");
    // Each wheel is a path of its own, named after the file and the wheel.
    assert!(
        table.contains("axle_short_bump[front_right.wheel]"),
        "{table}"
    );
}
