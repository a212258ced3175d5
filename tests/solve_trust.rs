//! Issue 15, "never a wrong number printed as a result": what `solve` prints
//! is an equilibrium or says precisely why not. Absurd loads are refused
//! naming the value, a failed case never lets a later one print a stale pose,
//! and converged states that are physically implausible are warned about.

use axle::geom::Vec3;
use axle::model::PointLoad;
use axle::statics::{Problem, State, StaticsErrorKind, path, solve};
use serde_json::Value;
mod common;
use common::{axle, scratch};

fn mcpherson() -> axle::model::Model {
    let (_, c) =
        axle::check::check_str("mcpherson.axle", include_str!("../examples/mcpherson.axle"));
    c.model.expect("the example checks")
}

fn wheel_load(m: &axle::model::Model, fz: f64) -> Vec<PointLoad> {
    vec![PointLoad {
        marker: m.wheels[0].contact,
        force: Vec3::new(0.0, 0.0, fz),
        torque: Vec3::zeros(),
    }]
}

/// A 1e200 N load once overflowed the force scale to infinity, so every
/// residual looked negligible: "converged in 0 iterations" with the design
/// pose, and the next case (whose scale still held the 1e200 N it started
/// from) printed that stale pose too, exit 0. Now the cell is E0214 at its
/// line and column, naming the value; 1e30 N likewise.
#[test]
fn an_absurd_load_in_a_loads_file_is_refused_at_its_cell() {
    for (value, shown) in [("1e200", "1e200 N"), ("1e30", "1e30 N")] {
        let csv = scratch(
            &format!("absurd_{value}.csv"),
            &format!("step,fx,fy,fz\n1,0,0,1500\n2,0,0,{value}\n3,0,0,3000\n"),
        );
        let (code, stdout, stderr) = axle(&["solve", "examples/mcpherson.axle", "--loads", &csv]);
        assert_eq!(code, 1, "{stdout}{stderr}");
        assert!(!stdout.contains("converged in 0"), "{stdout}");
        assert!(stderr.contains("error[E0214]"), "{stderr}");
        assert!(
            stderr.contains(&format!("{shown} in column `fz` is beyond any suspension")),
            "{stderr}"
        );
        assert!(
            stderr.contains(&format!("absurd_{value}.csv:3:7")),
            "{stderr}"
        );
    }
}

/// The same limit guards the statics for every caller (API users, sweeps,
/// identification): the load is a BadInput error naming the marker it acts
/// at and its value, and a path stops at that case with the cases before
/// it converged.
#[test]
fn an_absurd_load_given_to_the_statics_is_an_error_naming_its_marker() {
    let m = mcpherson();
    let p = Problem::new(&m).expect("problem");
    for fz in [1e200, 1e30, -2e7] {
        let e = solve(&p, &wheel_load(&m, fz), &State::design(&m)).expect_err("refused");
        assert_eq!(e.kind, StaticsErrorKind::BadInput, "{e:?}");
        assert_eq!(
            e.elements,
            vec![axle::model::ElementId::Marker(m.wheels[0].contact)]
        );
        let text = e.message(&m);
        assert!(text.contains(&format!("{:e} N", fz.abs())), "{text}");
    }
    let cases = [1500.0, 1e200, 3000.0].map(|f| wheel_load(&m, f));
    let run = path::simulate(&p, &cases, &State::design(&m));
    assert_eq!(run.steps.len(), 1);
    assert!(run.steps[0].iterations > 0);
    assert_eq!(run.failure.map(|f| f.case), Some(1));
}

/// After a failed case the path stops: the later cases are named as not
/// solved (table and JSON), never printed with the pose of an earlier case.
#[test]
fn the_cases_after_a_failure_are_listed_as_not_solved() {
    let file = "tests/data/saturating.axle";
    let (code, table, _) = axle(&["solve", file]);
    assert_eq!(code, 1);
    assert!(
        table.ends_with("not solved: back (the path stops at the first case that fails)\n"),
        "{table}"
    );
    assert!(!table.contains("case back"), "{table}");
    let (code, json, _) = axle(&["solve", file, "--format", "json"]);
    assert_eq!(code, 1);
    let v: Value = serde_json::from_str(&json).expect("one JSON document");
    assert_eq!(v["cases"].as_array().map(Vec::len), Some(3));
    assert_eq!(
        v["not_solved"],
        serde_json::json!([{ "name": "back", "step": 4 }])
    );
}

/// Convergence is judged against the forces of the case itself, not those of
/// the case before: the four-bar's case c4 (a pure 10 000 N·mm moment about
/// x after a 300 N force) is carried by torsion of the two identical
/// bushings, 5000 N·mm and -0.5° each with no force (symmetry, kt = 10 000
/// N·mm/deg). Judged against c3's scale the path stopped with force and
/// torque residues up to 1.1e-7 N·mm in the printed bushing loads.
#[test]
fn a_case_is_converged_to_its_own_force_scale() {
    let (code, json, stderr) = axle(&["solve", "examples/four_bar.axle", "--format", "json"]);
    assert_eq!(code, 0, "{stderr}");
    let v: Value = serde_json::from_str(&json).expect("one JSON document");
    let c4 = &v["cases"][3];
    assert_eq!(c4["name"], "c4");
    for b in ["b1", "b2"] {
        let force: Vec<f64> = (0..6)
            .map(|i| c4["bushings"][b]["force"][i].as_f64().expect("number"))
            .collect();
        let want = [0.0, 0.0, 0.0, 5000.0, 0.0, 0.0];
        for (f, w) in force.iter().zip(want) {
            assert!((f - w).abs() < 1e-9, "{b}: {force:?}");
        }
        let ax = c4["bushings"][b]["deformation"][3]
            .as_f64()
            .expect("number");
        assert!((ax + 0.5).abs() < 1e-12, "{b}: {ax}");
    }
}

/// `tests/data/soft_arm.axle`: W1002 names a bushing deformed beyond 25 mm (3000 N / 100 N/mm = 30 mm),
/// W1003 a wheel centre below the ground plane (-6000 N: 60 mm down from
/// 50 mm, 10 mm below its contact point's design height), each once with
/// its worst value and cases; a case within both (1000 N: 10 mm) is silent.
#[test]
fn implausible_states_are_warned_naming_the_element() {
    let file = "tests/data/soft_arm.axle";
    let (code, table, stderr) = axle(&["solve", file]);
    assert_eq!(code, 0, "{stderr}");
    insta::assert_snapshot!("implausible_state_warnings", stderr);
    assert!(table.contains("case big"), "{table}");
    assert_eq!(stderr.matches("warning[W1002]").count(), 1, "{stderr}");
    assert!(
        stderr.contains("bushing `soft` is deformed 60.0 mm at most"),
        "{stderr}"
    );
    assert!(stderr.contains("in cases big, down"), "{stderr}");
    assert_eq!(stderr.matches("warning[W1003]").count(), 1, "{stderr}");
    assert!(
        stderr.contains("the centre of wheel `w` goes 10.0 mm below the ground plane"),
        "{stderr}"
    );
    assert!(stderr.contains("in case down"), "{stderr}");
    let (_, _, quiet) = axle(&["solve", file, "--loadcases", "path", "--format", "json"]);
    assert!(quiet.contains("W1002"), "json runs warn too: {quiet}");
    let small = scratch("soft_small.csv", "step,fx,fy,fz\n1,0,0,1000\n");
    let (code, _, stderr) = axle(&["solve", file, "--loads", &small]);
    assert_eq!(code, 0, "{stderr}");
    assert!(!stderr.contains("warning"), "{stderr}");
}
