//! Joint localisation from motion (thesis chapter 3) on synthetic truth: the
//! McPherson with its joints moved by known offsets, solved along the bump,
//! lateral and longitudinal paths, landmarks with σ = 0.05 mm noise.

mod common;
use axle::geom::Vec3;
use axle::locate::plan::{Located, Options, locate_all};
use axle::measure::poses::fit_poses;
use axle::model::{ElementId, Model, vals};
use common::{axle, landmark_files, scratch};

fn mcpherson() -> Model {
    let (_, c) =
        axle::check::check_str("mcpherson.axle", include_str!("../examples/mcpherson.axle"));
    c.model.expect("the example checks")
}

/// Moves both markers of a joint or bushing by `d` (mm): the truth differs from
/// the nominal model by these offsets.
fn shift(m: &mut Model, name: &str, d: [f64; 3]) {
    let (i, j) = match m.joints.iter().find(|j| j.name == name) {
        Some(j) => (j.i, j.j),
        None => {
            let b = m.bushings.iter().find(|b| b.name == name).expect("element");
            (b.i, b.j)
        }
    };
    for mk in [i, j] {
        let p = m.markers[mk.index()].origin() + Vec3::from(d);
        m.markers[mk.index()].position = vals([p.x, p.y, p.z]);
    }
}

const OFFSETS: [(&str, [f64; 3]); 5] = [
    ("L8", [1.0, -0.8, 0.5]),
    ("L7", [-0.6, 0.9, 0.4]),
    ("L6", [0.7, 0.5, -0.9]),
    ("A", [0.8, -0.5, 0.6]),
    ("B", [-1.2, 0.9, 0.7]),
];

fn truth() -> Model {
    let mut m = mcpherson();
    for (name, d) in OFFSETS {
        shift(&mut m, name, d);
    }
    m
}

/// Landmark CSV rows of several load sets, steps numbered on across the sets.
fn landmarks(m: &Model, sets: &[&str], sigma: f64, seed: u64) -> String {
    let runs: Vec<(&Model, &str)> = sets.iter().map(|s| (m, *s)).collect();
    landmarks_of(&runs, sigma, seed)
}

/// Landmark CSV rows of (model, load set) runs: the model may differ between
/// runs (a steering rack moved), the parts and landmarks do not.
fn landmarks_of(runs: &[(&Model, &str)], sigma: f64, seed: u64) -> String {
    let mut out = String::from("step,part,landmark,x,y,z\n");
    let mut base = 0;
    for (k, (m, name)) in runs.iter().enumerate() {
        let set = m.load_set_named(name).expect("set");
        let csv = axle::measure::synthetic::landmarks_csv(m, set, sigma, seed + k as u64)
            .expect("the truth solves");
        let mut last = 0;
        for line in csv.lines().skip(1) {
            let (step, rest) = line.split_once(',').expect("row");
            let step: usize = step.parse().expect("step");
            last = last.max(step);
            out += &format!("{},{rest}\n", base + step);
        }
        base += last;
    }
    out
}

fn locate(truth: &Model, nominal: &Model, sets: &[&str]) -> Vec<Located> {
    locate_csv(nominal, &landmarks(truth, sets, 0.05, 11))
}

fn locate_csv(nominal: &Model, csv: &str) -> Vec<Located> {
    let (obs, _) = axle::data::landmarks::read(csv, nominal).expect("reads");
    let (steps, issues) = fit_poses(nominal, &obs, 0.5);
    assert!(issues.is_empty());
    locate_all(nominal, &steps, &Options::default())
}

fn truth_point(m: &Model, l: &Located) -> Vec3 {
    match l.element {
        ElementId::Joint(j) => m.marker(m.joints[j.index()].i).origin(),
        ElementId::Bushing(b) => m.marker(m.bushings[b.index()].i).origin(),
        _ => unreachable!("only joints and bushings are located"),
    }
}

#[test]
fn mcpherson_joints_are_located_within_the_thesis_accuracy() {
    let (truth, nominal) = (truth(), mcpherson());
    let found = locate(&truth, &nominal, &["bump", "lateral", "longitudinal"]);
    let by = |n: &str| {
        found
            .iter()
            .find(|l| l.name == n)
            .unwrap_or_else(|| panic!("{n} located"))
    };
    let err = |n: &str| {
        let l = by(n);
        assert!(l.observable, "{n}: {}", l.note);
        (l.center.expect("centre") - truth_point(&truth, l)).norm()
    };
    for (n, limit) in [
        ("L6", 0.5),
        ("L7", 0.5),
        ("L8", 0.5),
        ("L3", 0.5),
        ("B", 3.0),
    ] {
        let e = err(n);
        eprintln!("{n}: {e:.3} mm (limit {limit})");
        assert!(e < limit, "{n} is {e} mm from the truth");
    }
    // Bushing A yields along its link while the arm yaws: along one direction
    // (near its swing axis) that is indistinguishable from a shifted centre. The
    // tool says so and keeps the model's coordinate there; across it, A is
    // located like a ball joint.
    let a = by("A");
    let g = a
        .undetermined
        .expect("A reports its undetermined direction");
    assert!(
        g.dot(&Vec3::new(-0.98, 0.18, 0.0)).abs() > 0.9,
        "near A's axis: {g}"
    );
    let e = a.center.expect("centre") - truth_point(&truth, a);
    let across = (e - g * g.dot(&e)).norm();
    eprintln!(
        "A: {:.3} mm, {across:.3} mm across the undetermined direction",
        e.norm()
    );
    assert!(
        across < 1.0,
        "A across its undetermined direction: {across} mm"
    );
    assert!(e.norm() < 1.5);
    // The reported uncertainty is honest: the error is within a few standard deviations.
    for n in ["L6", "L7", "L8"] {
        assert!(err(n) < 4.0 * by(n).uncertainty + 0.05, "{n}");
    }
}

/// The truth with the rack moved by `dy` mm (the tie rod's inner joint on the chassis).
fn steered(dy: f64) -> Model {
    let mut m = truth();
    let j = m.joints.iter().find(|j| j.name == "L3").expect("L3").j;
    let p = m.markers[j.index()].origin() + Vec3::new(0.0, dy, 0.0);
    m.markers[j.index()].position = vals([p.x, p.y, p.z]);
    m
}

#[test]
fn the_strut_top_is_observable_only_with_steering() {
    let nominal = mcpherson();
    // The thesis' rig programme (Table 4.4, no steering): F is not observable.
    let found = locate(&truth(), &nominal, &["thesis_table_4_4"]);
    let f = found
        .iter()
        .find(|l| l.name == "F")
        .expect("F is attempted");
    eprintln!(
        "F without steering: uncertainty {:.1} mm, note {}",
        f.uncertainty, f.note
    );
    assert!(!f.observable);
    assert!(f.note.contains("not observable"));
    let rep = axle::locate::report::report(&nominal, &[], &found, 1);
    assert!(
        rep.joints["F"].center.is_none(),
        "no number for an unobservable centre"
    );
    // The same programme plus the vertical cases at four rack positions.
    let variants: Vec<Model> = [-20.0, -10.0, 10.0, 20.0]
        .iter()
        .map(|&dy| steered(dy))
        .collect();
    let base = truth();
    let mut runs: Vec<(&Model, &str)> = vec![(&base, "thesis_table_4_4")];
    runs.extend(variants.iter().map(|m| (m, "thesis_table_5_1")));
    let found = locate_csv(&nominal, &landmarks_of(&runs, 0.05, 5));
    let f = found.iter().find(|l| l.name == "F").expect("F");
    let e = (f.center.expect("centre") - truth_point(&base, f)).norm();
    eprintln!(
        "F with steering: error {e:.2} mm, uncertainty {:.2} mm, {}",
        f.uncertainty, f.note
    );
    let ax = f.axis.expect("axis");
    let ev = f.center.expect("c") - truth_point(&base, f);
    let truth_axis = base
        .marker(base.joints.iter().find(|j| j.name == "L5").expect("L5").j)
        .rotation
        .column(2)
        .into_owned();
    eprintln!(
        "  along axis {:.2} mm, across {:.2} mm, axis angle error {:.3} deg (reported ±{:.3} deg)",
        ev.dot(&ax),
        (ev - ax * ev.dot(&ax)).norm(),
        ax.cross(&truth_axis).norm().asin().to_degrees(),
        f.axis_uncertainty.to_degrees()
    );
    assert!(f.observable, "{}", f.note);
    assert!(
        e < 3.0 * f.uncertainty + 1.0,
        "error {e} mm against uncertainty {}",
        f.uncertainty
    );
}

#[test]
fn locate_cli_prints_the_interface_json_and_writes_the_located_model() {
    let csv = scratch(
        "locate_t44.csv",
        &landmarks(&truth(), &["thesis_table_4_4"], 0.05, 2),
    );
    let out = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("located.axle");
    let o = out.to_string_lossy().into_owned();
    let (code, stdout, stderr) = axle(&[
        "locate",
        "examples/mcpherson.axle",
        "--landmarks",
        &csv,
        "--format",
        "json",
        "-o",
        &o,
    ]);
    assert_eq!(code, 0, "{stderr}");
    let v: serde_json::Value = serde_json::from_str(&stdout).expect("one JSON document");
    assert_eq!(v["reference_step"], 1);
    let l8 = &v["joints"]["L8"];
    assert_eq!(l8["kind"], "spherical");
    assert_eq!(l8["observable"], true);
    assert_eq!(l8["center"].as_array().expect("centre").len(), 3);
    assert!(l8["residual_mm"].is_number() && l8["uncertainty_mm"].is_number());
    assert!(l8["method"].as_str().expect("method").contains("3.12"));
    // Every pose fit with the residual of each landmark (σ = 0.05 mm per coordinate).
    let up = &v["poses"]["1"]["upright"];
    let res = up["residuals_mm"].as_object().expect("residuals");
    assert_eq!(res.len(), 4);
    assert!(res.values().all(|r| r.as_f64().expect("mm") < 0.3), "{up}");
    assert!(up["rms_mm"].as_f64().expect("rms") > 0.0);
    // The strut top without steering: a verdict, not a number.
    let f = &v["joints"]["F"];
    assert_eq!(f["observable"], false);
    assert!(f["center"].is_null() && f["uncertainty_mm"].is_null());
    assert!(f["note"].as_str().expect("note").contains("not observable"));
    // Its axis direction is determined all the same (issue 15), with its
    // uncertainty; the cylindrical joint L5 carries the same axis.
    let axis: Vec<f64> = f["axis"]
        .as_array()
        .expect("the strut axis")
        .iter()
        .map(|x| x.as_f64().expect("number"))
        .collect();
    assert!((Vec3::new(axis[0], axis[1], axis[2]).norm() - 1.0).abs() < 1e-9);
    let cone = f["axis_uncertainty_deg"].as_f64().expect("deg");
    assert!(cone > 0.0 && cone < 2.0, "{cone}");
    assert_eq!(f["axis_part"], "upright");
    assert_eq!(v["joints"]["L5"]["axis"], f["axis"]);
    assert!(v["joints"]["L5"]["center"].is_null());
    // Ball joints have no axis, and no axis uncertainty.
    assert!(l8["axis"].is_null() && l8["axis_uncertainty_deg"].is_null());
    // The located model checks, and carries the located ball joint (design coordinates).
    let text = std::fs::read_to_string(&out).expect("written");
    let (_, checked) = axle::check::check_str("located.axle", &text);
    let located = checked.model.expect("the located model checks");
    let truth = truth();
    let at = |m: &Model, joint: &str| {
        m.marker(m.joints.iter().find(|j| j.name == joint).expect("joint").i)
            .origin()
    };
    let e = (at(&located, "L8") - at(&truth, "L8")).norm();
    assert!(
        e < 4.0 * l8["uncertainty_mm"].as_f64().expect("u") + 0.05,
        "L8 {e} mm from the truth"
    );
    assert!(
        (at(&located, "L8") - at(&mcpherson(), "L8")).norm() > 0.5,
        "moved from the nominal"
    );
}

/// IGES files of one measured state each (what the thesis' measuring arm
/// saved) locate every joint exactly as the same numbers in CSV do.
#[test]
fn locate_cli_reads_iges_files_one_per_step_like_the_csv() {
    let (truth, nominal) = (truth(), mcpherson());
    let set = truth.load_set_named("thesis_table_4_4").expect("set");
    let (csv, files) = landmark_files(&truth, set, 0.05, 2, "locate_iges_t44");
    assert_eq!(files.len(), nominal.load_sets[set.index()].cases.len());
    let run = |landmarks: &[String]| {
        let mut args = vec![
            "locate",
            "examples/mcpherson.axle",
            "--format",
            "json",
            "--landmarks",
        ];
        args.extend(landmarks.iter().map(String::as_str));
        let (code, stdout, stderr) = axle(&args);
        assert_eq!(code, 0, "{stderr}");
        let v: serde_json::Value = serde_json::from_str(&stdout).expect("one JSON document");
        (v, stderr)
    };
    let (from_csv, _) = run(&[csv]);
    let (from_iges, notes) = run(&files);
    let last = format!(
        "is step {}: {} landmark points",
        files.len(),
        nominal.landmarks.len()
    );
    assert!(notes.contains(&last), "{notes}");
    assert_eq!(from_iges["reference_step"], from_csv["reference_step"]);
    let (a, b) = (
        from_iges["joints"].as_object().expect("joints"),
        from_csv["joints"].as_object().expect("joints"),
    );
    assert_eq!(a.keys().collect::<Vec<_>>(), b.keys().collect::<Vec<_>>());
    for (name, ji) in a {
        let jc = &b[name];
        assert_eq!(ji["observable"], jc["observable"], "{name}");
        assert_eq!(ji["method"], jc["method"], "{name}");
        for key in ["center", "axis"] {
            match (ji[key].as_array(), jc[key].as_array()) {
                (Some(x), Some(y)) => {
                    for (p, q) in x.iter().zip(y) {
                        let (p, q) = (p.as_f64().expect("n"), q.as_f64().expect("n"));
                        assert!((p - q).abs() < 1e-9, "{name}.{key}: {p} vs {q}");
                    }
                }
                (None, None) => {}
                _ => panic!("{name}.{key} differs: {} vs {}", ji[key], jc[key]),
            }
        }
    }
}

#[test]
fn locate_cli_reports_bad_data_with_its_line() {
    let csv = scratch(
        "bad_landmarks.csv",
        "step,part,landmark,x,y,z\n1,upright,m1,62,749,234\n1,upright,m2,-48,abc,209\n",
    );
    let (code, _, stderr) = axle(&["locate", "examples/mcpherson.axle", "--landmarks", &csv]);
    assert_eq!(code, 1);
    assert!(
        stderr.contains(&format!("{csv}:3:")) && stderr.contains("`abc` is not a number"),
        "{stderr}"
    );
    let (code, _, _) = axle(&[
        "locate",
        "examples/mcpherson.axle",
        "--landmarks",
        "no/such.csv",
    ]);
    assert_eq!(code, 2);
    // An IGES file with a bad number: exit 1, file:line:column and the record.
    let igs = scratch(
        "bad_step.igs",
        &include_str!("data/iges/hand.igs").replacen("116,62.,749.", "116,62.,7r9.", 1),
    );
    let (code, _, stderr) = axle(&["locate", "examples/mcpherson.axle", "--landmarks", &igs]);
    assert_eq!(code, 1);
    assert!(
        stderr.contains(&format!("{igs}:27:9")) && stderr.contains("point D 1: y is `7r9.`"),
        "{stderr}"
    );
    let (code, _, _) = axle(&[
        "locate",
        "examples/mcpherson.axle",
        "--landmarks",
        "no/such.igs",
    ]);
    assert_eq!(code, 2);
}

/// A wishbone on two bushings (axis along x through y = 300, z = 0), loaded
/// at its outer end: it swings about the bushing axis.
const WISHBONE: &str = "
ground chassis {
    marker front at (150, 300, 0) mm
    marker rear at (-150, 300, 0) mm
    landmark m1 at (200, 250, 40) mm
    landmark m2 at (-180, 260, -30) mm
    landmark m3 at (20, 200, 80) mm
    landmark m4 at (-60, 240, -90) mm
}

part arm {
    marker front at (150, 300, 0) mm
    marker rear at (-150, 300, 0) mm
    marker tip at (0, 650, 0) mm
    landmark m1 at (120, 380, 10) mm
    landmark m2 at (-90, 420, -15) mm
    landmark m3 at (30, 560, 20) mm
    landmark m4 at (-20, 610, -25) mm
}

bushing front {
    i chassis.front
    j arm.front
    k (2000, 2000, 2000) N/mm
    kt (500, 5000, 5000) N*mm/deg
}

bushing rear {
    i chassis.rear
    j arm.rear
    k (2000, 2000, 2000) N/mm
    kt (500, 5000, 5000) N*mm/deg
}

loads swing table (arm.tip.fz N, arm.tip.fy N) {
    c1   -60    0
    c2   -30   20
    c3    30  -20
    c4    60    0
    c5    90   10
}
";

#[test]
fn a_bushing_pair_is_located_as_a_pivot() {
    let (_, c) = axle::check::check_str("wishbone.axle", WISHBONE);
    let m = c.model.expect("the wishbone checks");
    let csv = landmarks(&m, &["swing"], 0.05, 4);
    let found = locate_csv(&m, &csv);
    for name in ["front", "rear"] {
        let l = found.iter().find(|l| l.name == name).expect("located");
        assert!(l.method.contains("pivot"), "{}", l.method);
        assert!(l.observable, "{}", l.note);
        let axis = l.axis.expect("axis");
        assert!(axis.cross(&Vec3::x()).norm() < 0.01, "axis {axis}");
        // The centre lies on the true axis (y = 300, z = 0), at the model's x.
        let c = l.center.expect("centre");
        assert!((c.y - 300.0).abs() < 0.5 && c.z.abs() < 0.5, "{c}");
        assert_eq!(l.undetermined, Some(axis));
    }
}

/// The McPherson with a steering rack: a part without landmarks sliding along y
/// on the chassis (held by a soft mount), carrying the tie rod's inner joint.
fn with_rack() -> String {
    include_str!("../examples/mcpherson.axle")
        .replace(
            "    marker L3 at (73.7, 353.4, 228.3) mm z (0, 0, 1)\n",
            "    marker L3 at (73.7, 353.4, 228.3) mm z (0, 0, 1)\n    marker slide at (73.7, 353.4, 228.3) mm z (0, 1, 0)\n",
        )
        .replace(
            "joint L3 universal {\n    i tie_rod.L3\n    j chassis.L3\n}",
            "joint L3 universal {
    i tie_rod.L3
    j rack.L3
}

part rack {
    marker L3 at (73.7, 353.4, 228.3) mm z (0, 0, 1)
    marker slide at (73.7, 353.4, 228.3) mm z (0, 1, 0)
}

joint R translational {
    i rack.slide
    j chassis.slide
}

bushing rack_mount {
    i rack.slide
    j chassis.slide
    k (1000, 1000, 20) N/mm
    kt (10000, 10000, 10000) N*mm/deg
}

loads steer table (fz N, rack.slide.fy N) {
    c1  1500  -400
    c2  1500     0
    c3  1500   400
    c4  4500  -400
    c5  4500     0
    c6  4500   400
    c7  7500  -400
    c8  7500     0
    c9  7500   400
}",
        )
}

#[test]
fn the_ball_joint_on_an_unmeasured_rack_is_located_across_the_slide() {
    let (_, c) = axle::check::check_str("rack.axle", &with_rack());
    let nominal = c.model.expect("the rack variant checks");
    let mut truth = nominal.clone();
    for (name, d) in OFFSETS.iter().chain(&[("L3", [0.7, -0.6, 0.8])]) {
        shift(&mut truth, name, *d);
    }
    let found = locate_csv(&nominal, &landmarks(&truth, &["steer"], 0.05, 7));
    let l3 = found
        .iter()
        .find(|l| l.name == "L3")
        .expect("L3 is located");
    assert!(l3.method.contains("sliding"), "{}", l3.method);
    assert!(l3.observable, "{}", l3.note);
    // Relative to the chassis the tie rod turns about x (bump) and z (steer),
    // not about its own axis (the universal joint). Only the displacement
    // across the slide (y) counts, and a turn about z moves a point's x only
    // to second order: along x the centre is not determined. The tool says so
    // and keeps the model's coordinate there.
    let g = l3.undetermined.expect("an undetermined direction");
    assert!(g.dot(&Vec3::x()).abs() > 0.9, "near x: {g}");
    let err = l3.center.expect("centre") - truth_point(&truth, l3);
    let across = (err - g * g.dot(&err)).norm();
    eprintln!(
        "L3 on the rack: {:.3} mm from the truth, {across:.3} mm across ({:.3}, {:.3}, {:.3}), uncertainty {:.3} mm",
        err.norm(),
        g.x,
        g.y,
        g.z,
        l3.uncertainty
    );
    assert!(across < 0.5, "L3 is {across} mm from the truth across {g}");
    assert!(across < 4.0 * l3.uncertainty + 0.05, "honest uncertainty");
    // The spherical fit would not do: the rack travel is not a rotation.
    let moved = (truth_point(&truth, l3) - truth_point(&nominal, l3)).norm();
    assert!(
        moved > 1.0,
        "the truth differs from the nominal by {moved} mm"
    );
}

/// Relative motion of part I in part J (`relative_motions` of the JSON), from
/// the truth's solved part poses: the I marker's point is carried by part I,
/// read in part J's frame, and placed with J's reference pose; the rotation is
/// `R_j(r) R_j(c)ᵀ R_i(c) R_i(r)ᵀ`, split by nalgebra.
fn expected_motion(
    eqs: &[axle::statics::Equilibrium],
    m: &Model,
    (mi, mj): (axle::model::MarkerId, axle::model::MarkerId),
    reference: usize,
    step: usize,
) -> (Vec3, f64, Option<Vec3>) {
    let (pi, pj) = (m.marker(mi).part, m.marker(mj).part);
    let pose = |p, s: usize| eqs[s - 1].state.part_pose(p);
    let in_j_at_ref = |s: usize| {
        let ((ti, ri), (tj, rj)) = (pose(pi, s), pose(pj, s));
        let x = ri * m.marker(mi).origin() + ti;
        let (tjr, rjr) = pose(pj, reference);
        rjr * (rj.transpose() * (x - tj)) + tjr
    };
    let translation = in_j_at_ref(step) - in_j_at_ref(reference);
    let ((_, ri), (_, rj)) = (pose(pi, step), pose(pj, step));
    let ((_, rir), (_, rjr)) = (pose(pi, reference), pose(pj, reference));
    let q = nalgebra::Rotation3::from_matrix_unchecked(rjr * rj.transpose() * ri * rir.transpose());
    match q.axis_angle() {
        Some((axis, angle)) => (translation, angle.to_degrees(), Some(axis.into_inner())),
        None => (translation, 0.0, None),
    }
}

/// Noise-free landmarks of the truth along the rig programme: `locate` reports
/// the relative displacement of every measured pair of jointed parts exactly
/// as the truth's own part poses give it.
#[test]
fn locate_cli_reports_the_relative_motion_of_jointed_parts() {
    let truth = truth();
    let set = truth.load_set_named("thesis_table_4_4").expect("set");
    let csv = scratch(
        "locate_exact_t44.csv",
        &axle::measure::synthetic::landmarks_csv(&truth, set, 0.0, 1).expect("solves"),
    );
    let reference = 5;
    let (code, stdout, stderr) = axle(&[
        "locate",
        "examples/mcpherson.axle",
        "--landmarks",
        &csv,
        "--format",
        "json",
        "--reference",
        &reference.to_string(),
    ]);
    assert_eq!(code, 0, "{stderr}");
    let v: serde_json::Value = serde_json::from_str(&stdout).expect("one JSON document");
    let motions = v["relative_motions"].as_object().expect("relative_motions");
    // The strut carries no landmarks: L5 and F have no relative motion to show.
    let names: Vec<&str> = motions.keys().map(String::as_str).collect();
    assert_eq!(names, ["A", "B", "L3", "L6", "L7", "L8"]);
    let eqs = axle::statics::solve_set(&truth, set).expect("the truth solves");
    let nominal = mcpherson();
    let markers = |name: &str| match nominal.joints.iter().find(|j| j.name == name) {
        Some(j) => (j.i, j.j),
        None => {
            let b = nominal
                .bushings
                .iter()
                .find(|b| b.name == name)
                .expect("element");
            (b.i, b.j)
        }
    };
    let num = |x: &serde_json::Value| x.as_f64().expect("a number");
    let vec3 = |x: &serde_json::Value| {
        let a = x.as_array().expect("three numbers");
        Vec3::new(num(&a[0]), num(&a[1]), num(&a[2]))
    };
    let (mut worst_t, mut worst_r, mut largest) = (0.0f64, 0.0f64, 0.0f64);
    for (name, rel) in motions {
        let (mi, mj) = markers(name);
        let parts = [mi, mj].map(|mk| nominal.part(nominal.marker(mk).part).name.clone());
        assert_eq!(rel["parts"], serde_json::json!(parts), "{name}");
        let steps = rel["steps"].as_array().expect("steps");
        assert_eq!(steps.len(), eqs.len(), "{name}: every step");
        for s in steps {
            let step = s["step"].as_u64().expect("step") as usize;
            let (t, deg, axis) = expected_motion(&eqs, &nominal, (mi, mj), reference, step);
            worst_t = worst_t.max((vec3(&s["translation_mm"]) - t).norm());
            worst_r = worst_r.max((num(&s["rotation_deg"]) - deg).abs());
            largest = largest.max(deg);
            match (&s["axis"], axis) {
                (a, Some(axis)) if !a.is_null() => {
                    if deg > 1e-3 {
                        assert!((vec3(a) - axis).norm() < 1e-6, "{name} step {step}");
                    }
                }
                (a, _) => assert!(a.is_null() && deg < 1e-6, "{name} step {step}: {a}"),
            }
        }
        assert!(
            steps[reference - 1]["axis"].is_null(),
            "{name}: no motion at the reference"
        );
    }
    eprintln!(
        "relative motion vs truth: translation {worst_t:.2e} mm, rotation {worst_r:.2e} deg (largest rotation {largest:.2} deg)"
    );
    assert!(worst_t < 1e-6 && worst_r < 1e-6);
    assert!(largest > 1.0, "the programme moves the parts");
    // The universal joint L3 is where the truth has it: its centre, fixed in
    // both parts, does not move relative to the chassis.
    for s in motions["L3"]["steps"].as_array().expect("steps") {
        assert!(vec3(&s["translation_mm"]).norm() < 1e-6, "{s}");
    }
    // The table shows the largest rotation and translation of every pair; with
    // seeded noise (σ = 0.05 mm), so that the largest values do not hang on
    // rounding of exact data.
    let noisy = scratch(
        "locate_noisy_t44.csv",
        &axle::measure::synthetic::landmarks_csv(&truth, set, 0.05, 2).expect("solves"),
    );
    let (code, table, stderr) = axle(&[
        "locate",
        "examples/mcpherson.axle",
        "--landmarks",
        &noisy,
        "--reference",
        &reference.to_string(),
    ]);
    assert_eq!(code, 0, "{stderr}");
    insta::assert_snapshot!("locate_table_with_relative_motion", table);
}

/// The strut axis of a model: the z axis of the cylindrical joint L5 (design).
fn strut_axis(m: &Model) -> Vec3 {
    let l5 = m.joints.iter().find(|j| j.name == "L5").expect("L5");
    m.marker(l5.j).rotation.column(2).into_owned()
}

/// Angle between two directions, degrees (sign-blind).
fn angle_deg(a: &Vec3, b: &Vec3) -> f64 {
    a.normalize()
        .cross(&b.normalize())
        .norm()
        .asin()
        .to_degrees()
}

/// Issue 15: without steering the strut top is not observable (tens of mm
/// across its axis), but the slide axis direction is: every point near the
/// top slides along nearly the same line. It is reported with its
/// uncertainty, and the truth lies within it over several noise seeds.
#[test]
fn the_strut_axis_is_determined_without_steering_within_its_uncertainty() {
    let (truth, nominal) = (truth(), mcpherson());
    let true_axis = strut_axis(&truth);
    let (mut within, mut n) = (0, 0);
    for seed in 0..6 {
        let found = locate_csv(
            &nominal,
            &landmarks(&truth, &["thesis_table_4_4"], 0.05, 20 + seed),
        );
        let f = found.iter().find(|l| l.name == "F").expect("F");
        assert!(!f.observable, "F without steering: {}", f.note);
        assert!(f.axis_determined, "{}", f.note);
        let a = f.axis.expect("axis");
        assert!(a.dot(&true_axis) > 0.0, "the model's sense: {a}");
        let (err, cone) = (angle_deg(&a, &true_axis), f.axis_uncertainty.to_degrees());
        eprintln!(
            "seed {seed}: axis error {err:.3}°, reported ±{cone:.3}°, centre uncertainty {:.1} mm",
            f.uncertainty
        );
        assert!(err < 2.0 * cone, "seed {seed}: {err}° against ±{cone}°");
        within += usize::from(err < cone);
        n += 1;
        // In the report: no centre, the axis with its uncertainty.
        let rep = axle::locate::report::report(&nominal, &[], &found, 1);
        let e = &rep.joints["F"];
        assert!(e.center.is_none() && e.axis.is_some());
        assert_eq!(e.axis_uncertainty_deg, Some(cone));
        assert_eq!(rep.joints["L5"].axis_design, e.axis_design);
    }
    assert!(
        within * 2 >= n,
        "{within} of {n} within one standard deviation"
    );
}

/// With a top mount that does not yield (the hypothesis of eq. 3.22–3.25
/// holds), the axis uncertainty follows the landmark noise: four times less
/// noise, a much narrower cone, and the truth still within it.
#[test]
fn the_strut_axis_uncertainty_shrinks_with_the_noise() {
    let src = include_str!("../examples/mcpherson.axle")
        .replace("k_radial 1285 N/mm", "k_radial 1000000 N/mm")
        .replace("k_axial 647 N/mm", "k_axial 1000000 N/mm");
    let (_, c) = axle::check::check_str("stiff_top.axle", &src);
    let mut stiff = c.model.expect("checks");
    for (name, d) in OFFSETS {
        shift(&mut stiff, name, d);
    }
    let nominal = mcpherson();
    let true_axis = strut_axis(&stiff);
    let cone_at = |sigma: f64, seed: u64| {
        let csv = landmarks(&stiff, &["thesis_table_4_4"], sigma, seed);
        let (obs, _) = axle::data::landmarks::read(&csv, &nominal).expect("reads");
        let (steps, _) = fit_poses(&nominal, &obs, 0.5);
        let opt = Options {
            sigma,
            ..Options::default()
        };
        let found = locate_all(&nominal, &steps, &opt);
        let f = found.iter().find(|l| l.name == "F").expect("F").clone();
        let err = angle_deg(&f.axis.expect("axis"), &true_axis);
        let cone = f.axis_uncertainty.to_degrees();
        eprintln!(
            "σ {sigma} mm, seed {seed}: error {err:.4}°, ±{cone:.4}°, residual {:.3} mm",
            f.residual
        );
        assert!(err < 3.0 * cone, "σ {sigma}: {err}° against ±{cone}°");
        cone
    };
    for seed in [3, 4] {
        let (wide, narrow) = (cone_at(0.05, seed), cone_at(0.0125, seed));
        assert!(narrow < 0.5 * wide, "±{narrow}° at σ/4 against ±{wide}°");
    }
}
