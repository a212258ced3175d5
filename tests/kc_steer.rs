//! Steering K&C (issue 13): a rack on a translational joint, driven by a
//! force against the column, the steering axis as the upright's screw axis,
//! and caster, kingpin inclination, scrub radius and trail checked against
//! a knuckle on a kingpin whose axis is written down (closed form), and on
//! the front axle against the McPherson's own geometry.

use axle::check::check_str;
use axle::kc::{SteeringMetrics, driven_rack, steering_metrics};
use axle::model::Model;
use axle::statics;

/// Two knuckles, each on a revolute kingpin through K = (10, ±700, 150) mm
/// with caster 6° and kingpin inclination 12°, steered by a rack through
/// tie rods; the corner written once and mirrored, the rack passed to it as
/// a part parameter.
const KINGPIN: &str = r#"
model kingpin

ground chassis {
    marker slide at (150, 0, 250) mm z (0, 1, 0)
    marker C at (150, 0, 250) mm
}

part rack {
    marker slide at (150, 0, 250) mm z (0, 1, 0)
    marker C at (150, 0, 250) mm
}

joint slide translational {
    i rack.slide
    j chassis.slide
}

bushing column {
    i rack.C
    j chassis.C
    k (10000, 1000, 10000) N/mm
    kt (1000000, 1000000, 1000000) N*mm/deg
}

template corner(rack = chassis) {
    ground chassis {
        marker K at (10, 700, 150) mm z (-tan(6 deg), -tan(12 deg), 1)
    }
    part rack {
        marker TI at (150, 350, 250) mm z (0, 0, 1)
    }
    part tie_rod {
        marker TI at (150, 350, 250) mm z (350, 10, 0)
        marker TO at (140, 700, 240) mm
    }
    part upright {
        marker K at (10, 700, 150) mm z (-tan(6 deg), -tan(12 deg), 1)
        marker TO at (140, 700, 240) mm
        marker WC at (0, 787, 300) mm z (0, 1, 0)
        marker CP at (0, 787, 0) mm
    }
    joint K revolute {
        i upright.K
        j chassis.K
    }
    joint TI universal {
        i tie_rod.TI
        j rack.TI
    }
    joint TO spherical {
        i tie_rod.TO
        j upright.TO
    }
    wheel wheel {
        centre upright.WC
        contact upright.CP
    }
}

instance left = corner(rack = rack)
instance right = mirror corner(rack = rack)

loads steer sweep {
    rack.C.fy 0 N -> 5000 N -> -5000 N -> 0 N by 500 N
}
"#;

fn checked(name: &str, text: &str) -> Model {
    let (_, c) = check_str(name, text);
    assert!(!c.problems.has_errors(), "{:?}", c.problems);
    c.model.expect("checks clean")
}

fn metrics(m: &Model, set: &str) -> SteeringMetrics {
    let id = m.load_set_named(set).expect("the set exists");
    let eqs = statics::solve_set(m, id).expect("solves");
    let states: Vec<_> = eqs.iter().map(|e| &e.state).collect();
    let rack = driven_rack(m, id).expect("the set drives the rack");
    steering_metrics(m, id, rack, &states).expect("the rack moves")
}

#[test]
fn a_kingpin_gives_its_caster_inclination_scrub_and_trail() {
    let m = checked("kingpin.axle", KINGPIN);
    // The corner's marker went onto the rack part passed to it.
    let rack = m.part_named("rack").expect("the rack");
    assert!(m.marker_named(rack, "left.TI").is_some());
    assert!(m.marker_named(rack, "right.TI").is_some());
    let s = metrics(&m, "steer");
    // The reference is the path's middle passage through zero travel.
    assert_eq!(s.step, 21);
    assert!(s.travel_mm.abs() < 1e-9, "{}", s.travel_mm);
    // The kingpin line K + λ(-tan 6°, ∓tan 12°, 1) meets z = 0 at λ = -150:
    // (10 + 150 tan 6°, ±(700 + 150 tan 12°)); the contact point is
    // (0, ±787, 0) at zero rack travel.
    let (t6, t12) = (6f64.to_radians().tan(), 12f64.to_radians().tan());
    let scrub = 787.0 - (700.0 + 150.0 * t12);
    let trail = 10.0 + 150.0 * t6;
    assert_eq!(s.wheels.len(), 2);
    for w in &s.wheels {
        assert!((w.caster_deg - 6.0).abs() < 1e-9, "{w:?}");
        assert!((w.kpi_deg - 12.0).abs() < 1e-9, "{w:?}");
        assert!((w.scrub_mm - scrub).abs() < 1e-7, "{w:?} against {scrub}");
        assert!((w.trail_mm - trail).abs() < 1e-7, "{w:?} against {trail}");
    }
    // Rack toward +y: the left tie rod pushes its steering arm (ahead of
    // the kingpin) outboard and the right one pulls its arm inboard, so both
    // wheels turn left, the left one more (its arm swings toward the rack).
    let (l, r) = (&s.wheels[0], &s.wheels[1]);
    assert!(
        l.steer_per_travel > 0.0 && r.steer_per_travel > 0.0,
        "{l:?} {r:?}"
    );
}

#[test]
fn the_front_axles_steering_axis_runs_through_the_strut_top_mounts() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/front_axle.axle");
    let text = std::fs::read_to_string(&path).expect("readable");
    let m = checked("examples/front_axle.axle", &text);
    let s = metrics(&m, "steer");
    // A McPherson's upright turns about the line from its strut's top mount
    // to its lower ball joints: the axis passes F = (-73.7, ±594.7, 762.6)
    // within the top mount's compliance (2.5 mm measured; 5 mm asserted).
    for (w, side) in s.wheels.iter().zip([1.0, -1.0]) {
        let f = nalgebra::Vector3::new(-73.7, side * 594.7, 762.6);
        let p = nalgebra::Vector3::from(w.axis_point);
        let u = nalgebra::Vector3::from(w.axis_direction);
        let miss = (f - p).cross(&u).norm();
        assert!(miss < 5.0, "{}: the axis misses F by {miss} mm", w.wheel);
    }
    // The two sides mirror each other (the rack's column holds the same
    // force from both at zero travel).
    let (l, r) = (&s.wheels[0], &s.wheels[1]);
    for (a, b) in [
        (l.caster_deg, r.caster_deg),
        (l.kpi_deg, r.kpi_deg),
        (l.scrub_mm, r.scrub_mm),
        (l.trail_mm, r.trail_mm),
    ] {
        assert!((a - b).abs() < 1e-6 * (1.0 + a.abs()), "{a} against {b}");
    }
}

#[test]
fn kc_of_a_steering_path_prints_the_steering_geometry() {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_axle"))
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .args(["kc", "examples/front_axle.axle", "--sweep", "steer"])
        .output()
        .expect("runs");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8_lossy(&out.stdout);
    let block = text
        .split("\nsteering by rack")
        .nth(1)
        .expect("a steering block");
    insta::assert_snapshot!(format!("steering by rack{block}"));
}
