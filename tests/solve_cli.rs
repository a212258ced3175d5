//! `axle solve` and `axle kc` through the built binary: snapshots of what an
//! engineer reads, numbers against the independent results of
//! `tests/data/expected`, the loads CSV round trip, the trim, and the errors.

use serde_json::Value;
use std::path::PathBuf;
mod common;
use common::axle;

/// Runs a command that must succeed; returns stdout.
fn ok(args: &[&str]) -> String {
    let (code, stdout, stderr) = axle(args);
    assert_eq!(code, 0, "{args:?}: {stderr}");
    stdout
}

fn scratch(name: &str, text: &str) -> PathBuf {
    let p = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(name);
    std::fs::write(&p, text).expect("scratch file");
    p
}

fn expected(name: &str) -> String {
    std::fs::read_to_string(format!(
        "{}/tests/data/expected/{name}",
        env!("CARGO_MANIFEST_DIR")
    ))
    .expect("expected file")
}

fn num(v: &Value) -> f64 {
    v.as_f64().unwrap_or_else(|| panic!("not a number: {v}"))
}

fn nums(v: &Value) -> Vec<f64> {
    match v {
        Value::Array(a) => a.iter().flat_map(nums).collect(),
        _ => vec![num(v)],
    }
}

fn max_diff(a: &Value, b: &Value) -> f64 {
    nums(a)
        .iter()
        .zip(nums(b))
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

#[test]
fn solve_single_bushing_table_and_json_snapshots() {
    insta::assert_snapshot!(
        "single_bushing_table",
        ok(&["solve", "examples/single_bushing.axle"])
    );
    insta::assert_snapshot!(
        "single_bushing_json",
        ok(&["solve", "examples/single_bushing.axle", "--format", "json"])
    );
}

#[test]
fn solve_four_bar_table_and_json_snapshots() {
    let (code, table, stderr) = axle(&["solve", "examples/four_bar.axle"]);
    assert_eq!(code, 0);
    // Cases c2 and c9 tip the links by 21°: one warning per bushing, not per case.
    assert_eq!(stderr.matches("warning[W1001]").count(), 2, "{stderr}");
    insta::assert_snapshot!("four_bar_table", table);
    insta::assert_snapshot!(
        "four_bar_json",
        ok(&["solve", "examples/four_bar.axle", "--format", "json"])
    );
    // The JSON run reads each case's bushing tilts off its report, the
    // table run evaluates them at the kept states: the same warnings.
    let (code, _, json_stderr) = axle(&["solve", "examples/four_bar.axle", "--format", "json"]);
    assert_eq!(code, 0);
    assert_eq!(json_stderr, stderr);
}

#[test]
fn redundant_equations_are_reported_once() {
    let (code, _, stderr) = axle(&["solve", "examples/slider_crank.axle"]);
    assert_eq!(code, 0, "{stderr}");
    assert_eq!(stderr.matches("warning[W0601]").count(), 1, "{stderr}");
}

#[test]
fn solve_json_matches_the_independent_four_bar_and_single_bushing_results() {
    for name in ["single_bushing", "four_bar"] {
        let got: Value = serde_json::from_str(&ok(&[
            "solve",
            &format!("examples/{name}.axle"),
            "--format",
            "json",
        ]))
        .expect("JSON");
        let want: Value = serde_json::from_str(&expected(&format!("{name}.json"))).expect("JSON");
        assert_eq!(got["model"], name);
        for (k, w) in want["cases"].as_array().expect("cases").iter().enumerate() {
            let g = &got["cases"][k];
            assert_eq!(g["name"], w["name"]);
            for (part, wp) in w["parts"].as_object().expect("parts") {
                let d = max_diff(&g["parts"][part]["position"], &wp["position"]);
                assert!(d < 1e-6, "{name} {part}: {d} mm");
                let d = max_diff(&g["parts"][part]["rotation"], &wp["rotation"]);
                assert!(d < 1e-8, "{name} {part}: rotation {d}");
            }
        }
    }
}

/// Rows of a K&C CSV as maps from column name to field.
fn kc_csv(text: &str) -> Vec<std::collections::BTreeMap<String, String>> {
    let mut lines = text
        .lines()
        .filter(|l| !l.starts_with('#') && !l.trim().is_empty());
    let header: Vec<String> = lines
        .next()
        .expect("header")
        .split(',')
        .map(str::to_string)
        .collect();
    lines
        .map(|l| {
            header
                .iter()
                .cloned()
                .zip(l.split(',').map(str::to_string))
                .collect()
        })
        .collect()
}

/// Largest wheel-centre (mm) and angle (deg) differences of `kc --format csv` against a file.
fn kc_agreement(sweep: &str) -> (f64, f64) {
    let got_text = ok(&[
        "kc",
        "examples/mcpherson.axle",
        "--sweep",
        sweep,
        "--format",
        "csv",
    ]);
    let want_text = expected(&format!("mcpherson_{sweep}_kc.csv"));
    // Same column order as the rig files, then the extras.
    let want_header = want_text
        .lines()
        .find(|l| !l.starts_with('#'))
        .expect("header");
    assert!(
        got_text.starts_with(&format!("{want_header},travel_mm,half_track_change_mm\n")),
        "{}",
        &got_text[..200]
    );
    let (got, want) = (kc_csv(&got_text), kc_csv(&want_text));
    assert_eq!(got.len(), want.len());
    let (mut dp, mut da) = (0.0f64, 0.0f64);
    let f = |r: &std::collections::BTreeMap<String, String>, c: &str| {
        r[c].parse::<f64>().expect("number")
    };
    for (g, w) in got.iter().zip(&want) {
        for c in ["step", "loadcase", "wheel"] {
            assert_eq!(g[c], w[c]);
        }
        for c in ["fx", "fy", "fz", "mx", "my", "mz"] {
            assert_eq!(f(g, c), f(w, c), "{c}");
        }
        for c in ["wc_x", "wc_y", "wc_z"] {
            dp = dp.max((f(g, c) - f(w, c)).abs());
        }
        for c in ["toe_deg", "camber_deg"] {
            da = da.max((f(g, c) - f(w, c)).abs());
        }
    }
    eprintln!(
        "{sweep}: {} rows, wheel centre within {dp:.2e} mm, angles within {da:.2e} deg",
        got.len()
    );
    (dp, da)
}

#[test]
fn kc_bump_csv_matches_the_independent_sweep() {
    let (dp, da) = kc_agreement("bump");
    assert!(dp < 1e-5 && da < 1e-6, "{dp} mm, {da} deg");
}

#[test]
fn kc_lateral_and_longitudinal_csv_match_the_independent_sweeps() {
    for sweep in ["lateral", "longitudinal"] {
        let (dp, da) = kc_agreement(sweep);
        assert!(dp < 1e-5 && da < 1e-6, "{sweep}: {dp} mm, {da} deg");
    }
}

#[test]
fn solve_mcpherson_table_5_1_json_matches_the_independent_solution() {
    let got: Value = serde_json::from_str(&ok(&[
        "solve",
        "examples/mcpherson.axle",
        "--loadcases",
        "thesis_table_5_1",
        "--format",
        "json",
    ]))
    .expect("JSON");
    let want: Value =
        serde_json::from_str(&expected("mcpherson_thesis_table_5_1.json")).expect("JSON");
    let cases = want["cases"].as_array().expect("cases");
    assert_eq!(got["cases"].as_array().map(Vec::len), Some(cases.len()));
    let (mut wheel_mm, mut wheel_deg, mut part_mm, mut strut_mm) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    for (k, w) in cases.iter().enumerate() {
        let g = &got["cases"][k];
        assert_eq!(g["name"], w["name"]);
        assert_eq!(g["converged"], true);
        let (gw, ww) = (&g["wheels"]["left"], &w["wheels"]["left"]);
        wheel_mm = wheel_mm.max(max_diff(&gw["center"], &ww["center"]));
        for q in ["travel_mm", "half_track_mm"] {
            wheel_mm = wheel_mm.max((num(&gw[q]) - num(&ww[q])).abs());
        }
        for q in ["toe_deg", "camber_deg"] {
            wheel_deg = wheel_deg.max((num(&gw[q]) - num(&ww[q])).abs());
        }
        for (part, wp) in w["parts"].as_object().expect("parts") {
            let d = max_diff(&g["parts"][part]["position"], &wp["position"]);
            // The strut spins about its own axis on a soft mode (expected/README.md).
            if part == "strut" {
                strut_mm = strut_mm.max(d)
            } else {
                part_mm = part_mm.max(d)
            }
        }
    }
    eprintln!(
        "table 5-1: wheel {wheel_mm:.2e} mm, {wheel_deg:.2e} deg; parts {part_mm:.2e} mm; strut {strut_mm:.2e} mm"
    );
    assert!(
        wheel_mm < 1e-5 && wheel_deg < 1e-6 && part_mm < 1e-5,
        "{wheel_mm} {wheel_deg} {part_mm}"
    );
    assert!(strut_mm < 1e-4, "{strut_mm}");
}

#[test]
fn kc_bump_plot_is_svg_with_four_titled_panels() {
    let out = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("bump.svg");
    let out_s = out.to_string_lossy().into_owned();
    let table = ok(&[
        "kc",
        "examples/mcpherson.axle",
        "--sweep",
        "bump",
        "--plot",
        &out_s,
    ]);
    assert!(table.contains("wheel-centre compliance"), "{table}");
    let svg = std::fs::read_to_string(&out).expect("plot written");
    assert!(svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"));
    assert_eq!(svg.matches("<svg").count(), 1);
    for title in [
        "Toe angle",
        "Camber angle",
        "Half-track change",
        "Wheel load",
        "wheel travel [mm]",
        "toe-in [deg]",
    ] {
        assert!(svg.contains(title), "missing {title}");
    }
    assert!(svg.matches("<polyline").count() >= 4);
    let lat = out.with_file_name("lateral.svg");
    ok(&[
        "kc",
        "examples/mcpherson.axle",
        "--sweep",
        "lateral",
        "--plot",
        &lat.to_string_lossy(),
    ]);
    let svg = std::fs::read_to_string(&lat).expect("plot written");
    // A lateral sweep is a compliance event: against the wheel's own
    // (outboard) lateral force, its compliance steer under the toe panel.
    assert!(
        svg.contains("lateral force at the contact point, outboard + [N]")
            && svg.contains("Camber angle")
            && svg.contains("compliance steer left:")
    );
    // Table 5-1 varies fz, fy and fx: drawn against the case, not one force;
    // and no tick reads `-0`.
    let mixed = out.with_file_name("table_5_1.svg");
    ok(&[
        "kc",
        "examples/mcpherson.axle",
        "--sweep",
        "thesis_table_5_1",
        "--plot",
        &mixed.to_string_lossy(),
    ]);
    let svg = std::fs::read_to_string(&mixed).expect("plot written");
    assert!(svg.contains("load case (step)"), "{svg}");
    for s in [&svg, &std::fs::read_to_string(&lat).expect("plot")] {
        // plotters writes each text on its own line between the tags.
        let texts: Vec<&str> = s.lines().filter(|l| !l.starts_with('<')).collect();
        assert!(
            !texts.iter().any(|t| *t == "-0" || *t == "-0.0"),
            "{texts:?}"
        );
    }
    // Ticks without float noise or a trailing `.0` (was `-4000.0`).
    let lat_svg = std::fs::read_to_string(&lat).expect("plot");
    assert!(lat_svg.lines().any(|l| l == "-4000"), "{lat_svg}");
}

#[test]
fn loads_csv_round_trip_reproduces_the_sweep() {
    // The K&C CSV of a sweep, replayed as a loads file, gives the same rows.
    let kc = ok(&[
        "kc",
        "examples/mcpherson.axle",
        "--sweep",
        "longitudinal",
        "--format",
        "csv",
    ]);
    let path = scratch(
        "longitudinal_loads.csv",
        &format!("# replayed K&C run\n{kc}"),
    );
    let solved = ok(&[
        "solve",
        "examples/mcpherson.axle",
        "--loads",
        &path.to_string_lossy(),
        "--format",
        "csv",
    ]);
    assert_eq!(solved, kc);
    // And a hand-written one with spaces and comments.
    let path = scratch(
        "hand.csv",
        "# two cases\nstep, fx, fy, fz, loadcase\n1, 0, 0, 1500, c1\n2, 0, 0, 3000, c2\n",
    );
    let got: Value = serde_json::from_str(&ok(&[
        "solve",
        "examples/mcpherson.axle",
        "--loads",
        &path.to_string_lossy(),
        "--format",
        "json",
    ]))
    .expect("JSON");
    let want: Value =
        serde_json::from_str(&expected("mcpherson_thesis_table_5_1.json")).expect("JSON");
    for k in 0..2 {
        let d = max_diff(
            &got["cases"][k]["wheels"]["left"]["center"],
            &want["cases"][k]["wheels"]["left"]["center"],
        );
        assert!(d < 1e-5, "case {k}: {d} mm");
    }
}

#[test]
fn trim_returns_the_wheel_centre_to_design_height() {
    let args = [
        "solve",
        "examples/mcpherson.axle",
        "--trim",
        "spring.free_length",
        "--trim-case",
        "c3",
        "--format",
        "json",
    ];
    let (code, stdout, stderr) = axle(&args);
    assert_eq!(code, 0, "{stderr}");
    assert!(stderr.contains("trim: spring.free_length = "), "{stderr}");
    let v: Value = serde_json::from_str(&stdout).expect("JSON");
    let l0 = num(&v["trim"]["value"]);
    assert_eq!(v["trim"]["unit"], "mm");
    assert_eq!(num(&v["trim"]["initial"]), 290.0);
    let z = num(&v["cases"][2]["wheels"]["left"]["center"][2]);
    assert!((z - 305.0).abs() < 1e-6, "trimmed solve: wc_z = {z}");
    // Independently: the model written with the trimmed free length, solved afresh.
    let src = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/examples/mcpherson.axle"
    ))
    .expect("example");
    assert!(src.contains("free_length 290 mm"));
    let path = scratch(
        "mcpherson_trimmed.axle",
        &src.replace("free_length 290 mm", &format!("free_length {l0} mm")),
    );
    let v: Value =
        serde_json::from_str(&ok(&["solve", &path.to_string_lossy(), "--format", "json"]))
            .expect("JSON");
    let z = num(&v["cases"][2]["wheels"]["left"]["center"][2]);
    assert!((z - 305.0).abs() < 1e-6, "written back: wc_z = {z}");
    // The untrimmed wheel sits 1.16 mm above design in c3; a longer spring
    // pushes the upright down (30 N/mm, a few mm of free length).
    assert!(l0 > 290.0 && l0 < 300.0, "{l0}");
}

#[test]
fn trim_errors_name_the_parameter() {
    let (code, _, stderr) = axle(&[
        "solve",
        "examples/mcpherson.axle",
        "--trim",
        "spring.free_lenght",
    ]);
    assert_eq!(code, 1);
    assert!(stderr.contains("did you mean `free_length`?"), "{stderr}");
    // A bushing stiffness on an axis that does not move the wheel vertically
    // cannot trim ride height: the failure names the parameter.
    let (code, _, stderr) = axle(&[
        "solve",
        "examples/single_bushing.axle",
        "--trim",
        "b.k_x",
        "--trim-marker",
        "arm.tip",
        "--trim-case",
        "c3",
    ]);
    assert_eq!(code, 1);
    assert!(stderr.contains("trimming `b.k_x`"), "{stderr}");
}

#[test]
fn unknown_set_suggests_the_near_name() {
    let (code, stdout, stderr) = axle(&[
        "solve",
        "examples/mcpherson.axle",
        "--loadcases",
        "thesis_table_51",
    ]);
    // A name on the command line the model lacks is a usage error (exit 2,
    // docs/language.md), listing the sets.
    assert_eq!(code, 2);
    assert!(stdout.is_empty());
    assert!(
        stderr.contains("no load-case set `thesis_table_51`")
            && stderr.contains("did you mean `thesis_table_5_1`?")
            && stderr.contains("the model's load-case sets: thesis_table_4_4"),
        "{stderr}"
    );
    let (code, _, stderr) = axle(&["kc", "examples/mcpherson.axle", "--sweep", "bumpp"]);
    assert_eq!(code, 2);
    assert!(stderr.contains("did you mean `bump`?"), "{stderr}");
    let (code, _, stderr) = axle(&[
        "emit",
        "lcf",
        "examples/mcpherson.axle",
        "--loadcases",
        "nope",
    ]);
    assert_eq!(code, 2, "{stderr}");
}

#[test]
fn bad_loads_csv_line_is_located() {
    let path = scratch("bad_loads.csv", "step,fx,fy,fz\n1,0,0,1500\n2,0,abc,3000\n");
    let p = path.to_string_lossy().into_owned();
    let (code, _, stderr) = axle(&["solve", "examples/mcpherson.axle", "--loads", &p]);
    assert_eq!(code, 1);
    assert!(
        stderr.contains(&format!("{p}:3:5")) && stderr.contains("`abc` is not a number"),
        "{stderr}"
    );
    let (code, _, stderr) = axle(&["solve", "examples/mcpherson.axle", "--loads", "no/such.csv"]);
    assert_eq!(code, 2, "{stderr}");
}

#[test]
fn unrestrained_model_fails_naming_the_part() {
    let path = scratch(
        "unrestrained.axle",
        "model unrestrained\nground g {\n    marker o at (0, 0, 0) mm\n}\npart arm {\n    marker o at (0, 0, 0) mm\n    marker tip at (300, 0, 0) mm\n}\nspring s {\n    i g.o\n    j arm.tip\n    k 10 N/mm\n    free_length 300 mm\n}\nloads cases table (arm.tip.fz N) {\n    c1 100\n}\n",
    );
    let (code, stdout, stderr) = axle(&["solve", &path.to_string_lossy()]);
    assert_eq!(code, 1);
    assert!(stdout.is_empty());
    assert!(
        // The checker's mobility analysis stops it before any solve.
        stderr.contains("error[E0601]") && stderr.contains("part `arm`") && stderr.contains(":5:6"),
        "{stderr}"
    );
}

#[test]
fn output_file_and_csv_without_wheels() {
    let out = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("single.csv");
    let stdout = ok(&[
        "solve",
        "examples/single_bushing.axle",
        "--format",
        "csv",
        "-o",
        &out.to_string_lossy(),
    ]);
    assert!(stdout.is_empty());
    let csv = std::fs::read_to_string(&out).expect("written");
    assert!(
        csv.starts_with("step,loadcase,part,x,y,z,rx_deg,ry_deg,rz_deg\n1,c1,arm,"),
        "{csv}"
    );
    assert_eq!(csv.lines().count(), 4);
}

/// The README's main job is clean: A's -18.7° in case c1 is torsion about its
/// own axis, which projected angles represent exactly (no W1001).
#[test]
fn the_readme_main_job_prints_no_warning() {
    let (code, stdout, stderr) = axle(&[
        "solve",
        "examples/mcpherson.axle",
        "--loadcases",
        "thesis_table_5_1",
    ]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stderr.is_empty(), "{stderr}");
    assert!(stdout.contains("13 cases"), "{stdout}");
}

/// A path whose third case has no equilibrium (the bushing's vertical law is
/// flat beyond 600 N): `solve` prints the two converged cases, marks the
/// failing one with the diagnostic naming the part that runs away, and exits
/// 1; `kc` tabulates and plots the converged steps. The converged cases are
/// checked against the table law: tz = -F / (600 N/mm) below 1 mm.
#[test]
fn a_failing_case_keeps_the_converged_ones_and_exits_1() {
    let file = "tests/data/saturating.axle";
    let (code, table, stderr) = axle(&["solve", file]);
    assert_eq!(code, 1, "{stderr}");
    assert_eq!(stderr.matches("error[E1003]").count(), 1, "{stderr}");
    insta::assert_snapshot!(
        "saturating_table",
        format!("{table}\n--- stderr ---\n{stderr}")
    );
    let (code, json, _) = axle(&["solve", file, "--format", "json"]);
    assert_eq!(code, 1);
    let v: Value = serde_json::from_str(&json).expect("one JSON document");
    let cases = v["cases"].as_array().expect("cases");
    assert_eq!(cases.len(), 3, "two converged cases and the failing one");
    for (c, f) in cases.iter().zip([300.0, 500.0]) {
        assert_eq!(c["converged"], true);
        let tz = num(&c["bushings"]["b"]["deformation"][2]);
        assert!((tz + f / 600.0).abs() < 1e-9, "{tz}");
    }
    let failed = &cases[2];
    assert_eq!(failed["converged"], false);
    assert_eq!(failed["name"], "over");
    assert_eq!(failed["step"], 3);
    assert_eq!(failed["code"], "E1003");
    assert_eq!(failed["elements"][0], "part `arm`");

    let plot = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("saturating.svg");
    let (code, kc, stderr) = axle(&[
        "kc",
        file,
        "--sweep",
        "ramp",
        "--plot",
        &plot.to_string_lossy(),
    ]);
    assert_eq!(code, 1, "{stderr}");
    assert!(kc.contains("K&C along ramp: 2 of 4 steps"), "{kc}");
    assert!(
        kc.contains("case over (step 3): no equilibrium (E1003)"),
        "{kc}"
    );
    let svg = std::fs::read_to_string(&plot).expect("the plot of the converged steps");
    assert!(svg.contains("ramp (2 of 4 steps)"), "title");
    let (code, kc_json, _) = axle(&["kc", file, "--sweep", "ramp", "--format", "json"]);
    assert_eq!(code, 1);
    let v: Value = serde_json::from_str(&kc_json).expect("one JSON document");
    assert_eq!(v["rows"].as_array().map(Vec::len), Some(2));
    assert_eq!(v["failed"]["name"], "over");
}
