//! Axle K&C metrics (`docs/kc.md`) against hand calculations on a rigid
//! swing axle: two half shafts hinged about x at y = ±e, height h, each
//! held by a vertical spring k at y = ±s, wheels of half-track t/2. For
//! small motions about design (no preload) each half turns by
//! θ = F (t/2 - e) / (k (s - e)²) under a vertical wheel load F, so
//! - the wheel rate is k (s - e)² / (t/2 - e)²,
//! - the camber changes by -θ: -1/(t/2 - e) rad per mm of travel, no toe,
//! - the contact point moves laterally by θ h: the line normal to its path
//!   passes through the hinge, so the roll centre is where the lines from the
//!   two contact points through the hinges cross the centreline, at height
//!   h (t/2) / (t/2 - e),
//! - in roll, the stiffness is 2 k_w (t/2)² (the two wheel rates at ±t/2).
//!
//! The metrics are central differences over load steps of 20 N about
//! design; a half shaft turns by 0.17° a step, so the hand figures (exact in
//! the limit of small steps) hold to well within 1e-4 relative.

use axle::check::check_str;
use axle::kc::{Motion, axle_metrics};
use axle::model::Model;
use axle::statics;

const HALF_TRACK: f64 = 750.0;
const HINGE_Y: f64 = 100.0;
const HINGE_Z: f64 = 300.0;
const SPRING_Y: f64 = 400.0;
const K: f64 = 50.0; // N/mm

fn swing_axle() -> Model {
    let text = r#"model swing_axle

ground body {
    marker hinge_left at (0, 100, 300) mm z (1, 0, 0)
    marker hinge_right at (0, -100, 300) mm z (1, 0, 0)
    marker spring_left at (0, 400, 500) mm
    marker spring_right at (0, -400, 500) mm
}

part shaft_left {
    marker hinge at (0, 100, 300) mm z (1, 0, 0)
    marker spring at (0, 400, 300) mm
    marker WC at (0, 750, 300) mm z (0, 1, 0)
    marker CP at (0, 750, 0) mm
}

part shaft_right {
    marker hinge at (0, -100, 300) mm z (1, 0, 0)
    marker spring at (0, -400, 300) mm
    marker WC at (0, -750, 300) mm z (0, -1, 0)
    marker CP at (0, -750, 0) mm
}

joint hinge_left revolute {
    i shaft_left.hinge
    j body.hinge_left
}

joint hinge_right revolute {
    i shaft_right.hinge
    j body.hinge_right
}

spring spring_left {
    i body.spring_left
    j shaft_left.spring
    k 50 N/mm
    free_length 200 mm
}

spring spring_right {
    i body.spring_right
    j shaft_right.spring
    k 50 N/mm
    free_length 200 mm
}

wheel left {
    centre shaft_left.WC
    contact shaft_left.CP
}

wheel right {
    centre shaft_right.WC
    contact shaft_right.CP
}

loads parallel sweep {
    left.fz -80 N -> 80 N by 20 N
    right.fz -80 N -> 80 N by 20 N
}

loads roll sweep {
    left.fz 0 N -> 80 N -> -80 N -> 0 N by 20 N
    right.fz 0 N -> -80 N -> 80 N -> 0 N by 20 N
}
"#;
    let (_, checked) = check_str("swing_axle.axle", text);
    assert!(!checked.problems.has_errors(), "{:?}", checked.problems);
    checked.model.expect("checks")
}

fn metrics(m: &Model, set: &str) -> axle::kc::AxleMetrics {
    let id = m.load_set_named(set).expect("set");
    let eqs = statics::solve_set(m, id).expect("solves");
    let states: Vec<_> = eqs.iter().map(|e| &e.state).collect();
    let mut all = axle_metrics(m, &axle::kc::kc_rows(m, id, &states));
    assert_eq!(all.len(), 1, "one wheel pair");
    all.pop().expect("one")
}

fn close(what: &str, got: f64, want: f64, rel: f64) {
    eprintln!("{what}: {got:.6} (hand {want:.6})");
    assert!(
        (got - want).abs() <= rel * want.abs(),
        "{what}: {got} against {want}"
    );
}

#[test]
fn parallel_travel_of_a_swing_axle_matches_the_hand_calculation() {
    let m = swing_axle();
    let a = metrics(&m, "parallel");
    assert_eq!(a.motion, Motion::Parallel);
    assert_eq!(a.loadcase, "parallel_005", "the design step");
    let arm = HALF_TRACK - HINGE_Y;
    let rate = K * (SPRING_Y - HINGE_Y).powi(2) / arm.powi(2);
    let camber = -(1.0 / arm).to_degrees();
    for w in &a.wheels {
        close("wheel rate, N/mm", w.rate.expect("a rate"), rate, 1e-4);
        close("bump camber, deg/mm", w.camber, camber, 1e-4);
        assert!(
            w.toe.abs() < 1e-12,
            "a hinge about x does not steer: {}",
            w.toe
        );
    }
    let [y, z] = a.roll_centre.expect("a roll centre");
    assert!(y.abs() < 1e-9, "on the centreline: {y}");
    close(
        "roll centre height, mm",
        z,
        HINGE_Z * HALF_TRACK / arm,
        1e-4,
    );
}

#[test]
fn roll_of_a_swing_axle_matches_the_hand_calculation() {
    let m = swing_axle();
    let a = metrics(&m, "roll");
    assert_eq!(a.motion, Motion::Opposed);
    let arm = HALF_TRACK - HINGE_Y;
    let rate = K * (SPRING_Y - HINGE_Y).powi(2) / arm.powi(2);
    // N*mm/rad -> N*m/deg
    let k_roll = 2.0 * rate * HALF_TRACK * HALF_TRACK / 1000.0 * std::f64::consts::PI / 180.0;
    close(
        "roll stiffness, N*m/deg",
        a.roll_stiffness.expect("a stiffness"),
        k_roll,
        1e-4,
    );
    // Body roll +1 deg drops the left wheel by (t/2) rad and tilts it by
    // (t/2)/(t/2 - e) deg top-out; the right wheel mirrors it.
    let roll_camber = HALF_TRACK / arm;
    close(
        "left roll camber, deg/deg",
        a.wheels[0].camber,
        roll_camber,
        1e-4,
    );
    close(
        "right roll camber, deg/deg",
        a.wheels[1].camber,
        -roll_camber,
        1e-4,
    );
    assert!(a.wheels.iter().all(|w| w.toe.abs() < 1e-12));
    assert!(a.roll_centre.is_none());
}

mod common;

/// What an engineer reads: the axle blocks at the end of `axle kc` on the
/// front axle (parallel bump and roll), and their JSON.
#[test]
fn front_axle_metrics_as_printed() {
    for sweep in ["parallel_bump", "roll"] {
        let (code, out, err) = common::axle(&["kc", "examples/front_axle.axle", "--sweep", sweep]);
        assert_eq!(code, 0, "{err}");
        let block = &out[out.find("\naxle ").expect("an axle block")..];
        insta::assert_snapshot!(format!("front_axle_{sweep}"), block);
        let (code, json, err) = common::axle(&[
            "kc",
            "examples/front_axle.axle",
            "--sweep",
            sweep,
            "--format",
            "json",
        ]);
        assert_eq!(code, 0, "{err}");
        let v: serde_json::Value = serde_json::from_str(&json).expect("json");
        insta::assert_snapshot!(
            format!("front_axle_{sweep}_json"),
            serde_json::to_string_pretty(&v["axles"]).expect("prints")
        );
    }
}

/// Opposed travel is plotted against the body's roll angle, both wheels on
/// every panel, the branches named by the direction the body rolls.
#[test]
fn roll_is_plotted_against_the_roll_angle() {
    let svg = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("front_axle_roll.svg");
    let svg = svg.to_string_lossy().into_owned();
    let (code, _, err) = common::axle(&[
        "kc",
        "examples/front_axle.axle",
        "--sweep",
        "roll",
        "--plot",
        &svg,
    ]);
    assert_eq!(code, 0, "{err}");
    let text = std::fs::read_to_string(&svg).expect("written");
    assert_eq!(
        text.matches("body roll angle [deg]").count(),
        4,
        "one x label a panel"
    );
    for label in [
        "front_left.wheel, roll increasing",
        "front_right.wheel, roll decreasing",
        "Toe angle",
        "Wheel load",
    ] {
        assert!(text.contains(label), "{label}");
    }
    assert!(!text.contains("load increasing"));
}

/// `--without bar.torsion` gives the front axle's roll stiffness without its
/// anti-roll bar: the same as the file with the bar's rate written as zero
/// (`anti_roll_bar(k_torsion = 0 N*mm/deg)`, checked from source: another
/// route to the same model), and half or so of the stiffness with it.
#[test]
fn roll_stiffness_without_the_bar_is_the_file_with_a_bar_of_zero_rate() {
    let text = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/front_axle.axle"),
    )
    .expect("readable");
    let bar = "instance bar = anti_roll_bar(k_torsion = 15000 N*mm/deg)";
    assert!(text.contains(bar), "the example's bar line");
    let zero = text.replace(bar, "instance bar = anti_roll_bar(k_torsion = 0 N*mm/deg)");
    let (with, edited) = (
        common::checked("front_axle.axle", &text),
        common::checked("front_axle.axle", &zero),
    );
    let bare = axle::kc::without::without(&with, &["bar.torsion".to_string()]).expect("exists");
    let k_with = metrics(&with, "roll").roll_stiffness.expect("roll");
    let k_bare = metrics(&bare, "roll").roll_stiffness.expect("roll");
    let k_edited = metrics(&edited, "roll").roll_stiffness.expect("roll");
    close("roll stiffness without the bar", k_bare, k_edited, 1e-6);
    assert!(k_bare < 0.6 * k_with, "{k_bare} against {k_with}");

    // Through the binary: table, JSON, and what is refused.
    let without = |sweep: &str, elements: &[&str]| {
        let mut args = vec![
            "kc",
            "examples/front_axle.axle",
            "--sweep",
            sweep,
            "--without",
        ];
        args.extend_from_slice(elements);
        common::axle(&args)
    };
    let (code, out, err) = common::axle(&[
        "kc",
        "examples/front_axle.axle",
        "--sweep",
        "roll",
        "--without",
        "bar.torsion",
        "--format",
        "json",
    ]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).expect("json");
    let w = &v["axles"][0]["roll_stiffness_without"];
    assert_eq!(w["elements"], serde_json::json!(["bar.torsion"]));
    close(
        "JSON",
        w["nm_per_deg"].as_f64().expect("a number"),
        k_edited,
        1e-6,
    );
    let (code, _, err) = without("roll", &["bar.mount_left"]);
    assert_eq!(code, 2);
    assert!(err.contains("E0812") && err.contains("is a joint"), "{err}");
    let (code, _, err) = without("parallel_bump", &["bar.torsion"]);
    assert_eq!(code, 0);
    assert!(err.contains("W0812"), "{err}");
    // Without its top mount the left strut turns freely about its axis:
    // the solver's error names it, in the model without the mount.
    let (code, _, err) = without("roll", &["front_left.F"]);
    assert_eq!(code, 1, "{err}");
    assert!(
        err.contains("E1003")
            && err.contains("`front_left.strut`")
            && err.contains("in the model without front_left.F"),
        "{err}"
    );
    // Without the springs the wheels ride up (152 mm) until the arm
    // bushings carry the load: the figure comes with a warning that it is
    // another ride height's.
    let (code, _, err) = without("roll", &["front_left.spring", "front_right.spring"]);
    assert_eq!(code, 0, "{err}");
    assert!(
        err.contains("W0813") && err.contains("mm higher at the reference step"),
        "{err}"
    );
}

/// A table of manoeuvres (curb, laden, turn, braking) moves the wheels'
/// vertical loads together with their horizontal ones: its differences are
/// no wheel travel, and it gets no axle block; the bump and roll sets of
/// the same car get one per axle.
#[test]
fn a_table_of_manoeuvres_gives_no_axle_metrics() {
    let (code, out, err) = common::axle(&["kc", "examples/vehicle.axle", "--sweep", "vehicle"]);
    assert_eq!(code, 0, "{err}");
    assert!(!out.contains("\naxle "), "{out}");
    for set in ["front_roll", "rear_roll"] {
        let (code, out, err) = common::axle(&["kc", "examples/vehicle.axle", "--sweep", set]);
        assert_eq!(code, 0, "{err}");
        assert_eq!(out.matches("\naxle ").count(), 1, "{set}: {out}");
    }
}
