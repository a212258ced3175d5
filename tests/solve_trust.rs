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
    // JSON gathers the warnings case by case as it writes the cases (it
    // keeps no states): the same warnings, the same cases named.
    let (_, _, table_warnings) = axle(&["solve", file, "--loadcases", "path"]);
    assert_eq!(quiet, table_warnings);
    let small = scratch("soft_small.csv", "step,fx,fy,fz\n1,0,0,1000\n");
    let (code, _, stderr) = axle(&["solve", file, "--loads", &small]);
    assert_eq!(code, 0, "{stderr}");
    assert!(!stderr.contains("warning"), "{stderr}");
}

/// Newton-Euler balance of every moving part at an equilibrium, from the
/// reported pieces: element wrenches (force on I at its arm, the opposite on
/// J), the joint reactions of the report (force at the I marker and torque
/// on I, the opposite on J) and the applied loads. Returns the largest
/// residual force (N) and moment about the origin over the length (N).
fn worst_imbalance(
    model: &axle::model::Model,
    eq: &axle::statics::Equilibrium,
    report: &axle::output::report::CaseReport,
) -> (f64, f64) {
    use axle::statics::coords::Layout;
    let layout = Layout::new(model);
    let st = &eq.state;
    let nparts = model.parts.len();
    let mut f = vec![Vec3::zeros(); nparts];
    let mut m = vec![Vec3::zeros(); nparts];
    let mut add = |part: axle::model::PartId, force: Vec3, at: Vec3, torque: Vec3| {
        f[part.index()] += force;
        m[part.index()] += at.cross(&force) + torque;
    };
    let part_of_block = |b: Option<usize>| b.map(|b| layout.moving[b]);
    let origin = |p: axle::model::PartId| st.part_pose(p).0;
    for (_, w) in axle::statics::forces::element_wrenches(model, &layout, st).expect("wrenches") {
        if let Some(p) = part_of_block(w.i) {
            add(p, w.g, origin(p) + w.r_i, w.m);
        }
        if let Some(p) = part_of_block(w.j) {
            add(p, -w.g, origin(p) + w.rho, -w.m);
        }
    }
    for j in &model.joints {
        let Some(r) = report.joints.get(j.name.as_str()) else {
            continue;
        };
        let (force, torque, at) = (
            Vec3::from(r.force),
            Vec3::from(r.torque),
            Vec3::from(r.point),
        );
        add(model.marker(j.i).part, force, at, torque);
        add(model.marker(j.j).part, -force, at, -torque);
    }
    for l in st.loads() {
        let mk = model.marker(l.marker);
        let (x, rot) = st.part_pose(mk.part);
        add(mk.part, l.force, x + rot * mk.origin(), l.torque);
    }
    let length = 1000.0;
    layout.moving.iter().fold((0.0f64, 0.0f64), |(a, b), p| {
        (
            a.max(f[p.index()].norm()),
            b.max(m[p.index()].norm() / length),
        )
    })
}

/// Joint reactions against a conservation law: on every moving part of the
/// McPherson axle (ball joints, the strut's cylindrical joint, the tie rod's
/// universal) in all 13 cases of the thesis' Table 5-1, the reactions, the
/// element forces and the applied loads sum to zero, force and moment, to
/// 1e-6 of the wheel loads (kN).
#[test]
fn joint_reactions_balance_every_part() {
    use axle::output::report::case_report;
    let m = mcpherson();
    let set = m.load_set_named("thesis_table_5_1").expect("set");
    let p = Problem::new(&m).expect("problem");
    let run = path::run_set(&p, set, &State::design(&m));
    assert!(run.failure.is_none());
    assert_eq!(run.steps.len(), 13);
    for (k, eq) in run.steps.iter().enumerate() {
        let rep = case_report(&m, "c", k + 1, eq);
        assert_eq!(rep.joints.len(), m.joints.len(), "every joint reports");
        let (f, mo) = worst_imbalance(&m, eq, &rep);
        assert!(f < 1e-3 && mo < 1e-3, "case {}: {f:e} N, {mo:e} N", k + 1);
        // The reactions are not all zero: the ball joints carry kN.
        let biggest = rep
            .joints
            .values()
            .map(|j| Vec3::from(j.force).norm())
            .fold(0.0, f64::max);
        assert!(biggest > 100.0, "{biggest}");
    }
}

/// A hand-solvable case: the four-bar's c1 (1000 N down at the coupler's
/// midpoint, symmetric) loads each link through its revolute with 500 N
/// down and no torque; the coupler's marker centroid (its midpoint) moves
/// down by the bushings' deflection, 500 N / 10 000 N/mm = 0.05 mm, and the
/// case lists its load. In the table and in `solve --format json`.
#[test]
fn the_solve_report_shows_loads_reactions_and_centroid_displacements() {
    let (code, json, stderr) = axle(&["solve", "examples/four_bar.axle", "--format", "json"]);
    assert_eq!(code, 0, "{stderr}");
    let v: Value = serde_json::from_str(&json).expect("one JSON document");
    let c1 = &v["cases"][0];
    let get = |x: &Value| -> Vec<f64> {
        x.as_array()
            .expect("array")
            .iter()
            .map(|n| n.as_f64().expect("number"))
            .collect()
    };
    for j in ["r1", "r2"] {
        let f = get(&c1["joints"][j]["force"]);
        let t = get(&c1["joints"][j]["torque"]);
        let want = [0.0, 0.0, -500.0];
        for k in 0..3 {
            assert!((f[k] - want[k]).abs() < 1e-6, "{j}: {f:?}");
            assert!(t[k].abs() < 1e-6, "{j}: {t:?}");
        }
    }
    assert_eq!(c1["loads"][0]["marker"], "coupler.mid");
    assert_eq!(get(&c1["loads"][0]["force"]), vec![0.0, 0.0, -1000.0]);
    let d = get(&c1["parts"]["coupler"]["displacement"]);
    assert!(
        d[0].abs() < 1e-9 && d[1].abs() < 1e-9 && (d[2] + 0.05).abs() < 1e-9,
        "{d:?}"
    );
    let (_, table, _) = axle(&["solve", "examples/four_bar.axle"]);
    assert!(
        table.contains("  r1     0.0  0.0  -500.0     0     0     0\n"),
        "{table}"
    );
    assert!(
        table.contains("  coupler.mid  0.0  0.0  -1000.0"),
        "{table}"
    );
    assert!(table.contains("  coupler  0.000  0.000  -0.050"), "{table}");
}
