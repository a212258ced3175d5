//! Compliance events (issue 13, `docs/kc.md`): compliance steer, camber and
//! wheel-centre compliance under a lateral force, a braking force at the
//! contact point, a traction force at the wheel centre and an aligning
//! torque, per wheel, in phase and opposed. Checked against a knuckle on one
//! bushing (closed form), against the linearised compliance of the Newton
//! matrix (`statics::compliance`, an independent route to the same slopes)
//! on the benchmark McPherson, and on the front axle by superposition: in
//! phase plus opposed is twice the wheel loaded alone.

use axle::kc::{ComplianceMetrics, Input, KcRow, Phase, compliance_metrics, kc_rows};
use axle::model::Model;
use axle::statics::{self, Equilibrium, Problem, compliance};
use nalgebra::Vector3;

mod common;

use common::checked;

fn example(name: &str) -> String {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("examples")
        .join(name);
    std::fs::read_to_string(path).expect("readable")
}

/// A solved set: its equilibria, K&C rows and compliance events.
struct Run {
    eqs: Vec<Equilibrium>,
    rows: Vec<KcRow>,
    events: Vec<ComplianceMetrics>,
}

fn run(m: &Model, set: &str) -> Run {
    let id = m.load_set_named(set).expect("the set exists");
    let eqs = statics::solve_set(m, id).expect("solves");
    let states: Vec<_> = eqs.iter().map(|e| &e.state).collect();
    let rows = kc_rows(m, id, &states);
    let events = compliance_metrics(m, &rows);
    Run { eqs, rows, events }
}

/// `a` and `b` agree to `rel` of the larger, or within 1e-6 (deg/kN,
/// mm/kN: far below any compliance a rig resolves) of zero.
fn close(a: f64, b: f64, rel: f64, what: &str) {
    assert!(
        (a - b).abs() <= rel * a.abs().max(b.abs()) + 1e-6,
        "{what}: {a} against {b}"
    );
}

/// A knuckle held to the ground by one bushing at B, ahead of and inboard
/// of its wheel: a left corner and its mirror, uncoupled.
const KNUCKLE: &str = r#"
model knuckle

ground chassis {
}

template corner() {
    ground chassis {
        marker B at (30, 600, 300) mm
    }
    part knuckle {
        marker B at (30, 600, 300) mm
        marker WC at (0, 750, 300) mm z (0, 1, 0)
        marker CP at (0, 750, 0) mm
    }
    bushing B {
        i knuckle.B
        j chassis.B
        k (2000, 1500, 3000) N/mm
        kt (200000, 300000, 100000) N*mm/deg
    }
    wheel wheel {
        centre knuckle.WC
        contact knuckle.CP
    }
}

instance left = corner()
instance right = mirror corner()

loads lateral_in_phase sweep {
    left.wheel.fy 0 N -> 300 N -> -300 N -> 0 N by 50 N
    right.wheel.fy 0 N -> 300 N -> -300 N -> 0 N by 50 N
}

loads lateral_opposed sweep {
    left.wheel.fy 0 N -> 300 N -> -300 N -> 0 N by 50 N
    right.wheel.fy 0 N -> -300 N -> 300 N -> 0 N by 50 N
}

loads braking sweep {
    left.wheel.fx 0 N -> -300 N -> 300 N -> 0 N by 50 N
    right.wheel.fx 0 N -> -300 N -> 300 N -> 0 N by 50 N
}

loads traction sweep {
    left.knuckle.WC.fx 0 N -> 300 N -> -300 N -> 0 N by 50 N
    right.knuckle.WC.fx 0 N -> 300 N -> -300 N -> 0 N by 50 N
}

loads aligning sweep {
    left.wheel.mz 0 N*mm -> 30000 N*mm -> -30000 N*mm -> 0 N*mm by 5000 N*mm
    right.wheel.mz 0 N*mm -> -30000 N*mm -> 30000 N*mm -> 0 N*mm by 5000 N*mm
}
"#;

/// Small-motion theory of the left knuckle: a wrench `(F, M)` at a point
/// `p` turns the knuckle by `θ = (r × F + M) / kt` about B (`r = p - B`,
/// kt per axis, global = the bushing's axes) and moves B by `F / k`; the
/// wheel centre moves by `u_B + θ × (WC - B)`. The spin axis `(0, 1, 0)`
/// turns by `θ × ŷ = (-θz, 0, θx)`: toe-in `-dsteer = -θz`, camber
/// `asin(-s_z)`: `-θx`. Returns (toe deg, camber deg, centre mm) per unit load.
fn knuckle_theory(
    force: Vector3<f64>,
    torque: Vector3<f64>,
    at: Vector3<f64>,
) -> (f64, f64, Vector3<f64>) {
    let b = Vector3::new(30.0, 600.0, 300.0);
    let wc = Vector3::new(0.0, 750.0, 300.0);
    let k = Vector3::new(2000.0, 1500.0, 3000.0);
    let kt = Vector3::new(200000.0, 300000.0, 100000.0) * (180.0 / std::f64::consts::PI);
    let m = (at - b).cross(&force) + torque;
    let th = m.component_div(&kt);
    let u = force.component_div(&k) + th.cross(&(wc - b));
    (-th.z.to_degrees(), -th.x.to_degrees(), u)
}

#[test]
fn a_knuckle_on_one_bushing_gives_its_closed_form_compliances() {
    let m = checked("knuckle.axle", KNUCKLE);
    let cp = Vector3::new(0.0, 750.0, 0.0);
    let wc = Vector3::new(0.0, 750.0, 300.0);
    let x = Vector3::x();
    let z = Vector3::z();
    let zero = Vector3::zeros();
    // Per kN of outboard (left: +y) or forward force, per N·m of torque
    // turning the front outboard (left: +z).
    let cases = [
        (
            "lateral_in_phase",
            Input::Lateral,
            knuckle_theory(Vector3::y() * 1000.0, zero, cp),
            1,
        ),
        (
            "lateral_opposed",
            Input::Lateral,
            knuckle_theory(Vector3::y() * 1000.0, zero, cp),
            1,
        ),
        (
            "braking",
            Input::Braking,
            knuckle_theory(x * 1000.0, zero, cp),
            0,
        ),
        (
            "traction",
            Input::Traction,
            knuckle_theory(x * 1000.0, zero, wc),
            0,
        ),
        (
            "aligning",
            Input::AligningTorque,
            knuckle_theory(zero, z * 1000.0, cp),
            9,
        ),
    ];
    for (set, input, (toe, camber, u), axis) in cases {
        let r = run(&m, set);
        assert_eq!(r.events.len(), 1, "{set}: one event on the pair");
        let e = &r.events[0];
        assert_eq!(e.input, input, "{set}");
        // Each set starts at zero and passes zero again half-way, monotonically.
        assert_eq!(e.step, 13, "{set}");
        let phase = if set == "lateral_opposed" || set == "aligning" {
            Phase::Opposed
        } else {
            Phase::InPhase
        };
        assert_eq!(e.phase, Some(phase), "{set}");
        assert_eq!(e.wheels.len(), 2);
        // The right corner is the left one mirrored: the same numbers in
        // each wheel's own frame, whichever the phase (they are uncoupled).
        for w in &e.wheels {
            close(w.toe, toe, 1e-4, &format!("{set} {} toe", w.wheel));
            close(w.camber, camber, 1e-4, &format!("{set} {} camber", w.wheel));
            match axis {
                9 => assert_eq!(w.centre, None),
                a => close(
                    w.centre.expect("a force moves the centre"),
                    u[a],
                    1e-4,
                    &format!("{set} {} centre", w.wheel),
                ),
            }
        }
    }
    // The theory's numbers are not all zero: each input steers and the
    // lateral force cambers (toe 30/kt_z per N of lateral force, etc.).
    let (toe, camber, _) = knuckle_theory(Vector3::y() * 1000.0, zero, cp);
    assert!(toe > 0.01 && camber < -0.05, "{toe} {camber}");
}

/// Toe and camber slopes (deg per unit load) of a wheel whose spin axis
/// `s` turns by `θ` (rad per unit load): `ds = θ × s`, toe-in `∓ d steer`
/// with `steer = atan2(-s_x, s_y)` (left) or `atan2(s_x, -s_y)` (right),
/// camber `asin(-s_z)`.
fn toe_camber(s: Vector3<f64>, th: Vector3<f64>, left: bool) -> (f64, f64) {
    let ds = th.cross(&s);
    let dsteer = (-s.y * ds.x + s.x * ds.y) / (s.x * s.x + s.y * s.y);
    let dcamber = -ds.z / (1.0 - s.z * s.z).sqrt();
    let toe = if left { -dsteer } else { dsteer };
    (toe.to_degrees(), dcamber.to_degrees())
}

/// The slopes of the linearised compliance at the reference equilibrium of
/// a one-wheel event: the column of the loaded marker (contact point, or
/// the centre for traction), turned into toe, camber and the centre's
/// displacement along the load, per kN (or N·m).
fn linearised(
    m: &Model,
    r: &Run,
    wheel: usize,
    input: Input,
    step: usize,
) -> (f64, f64, Option<f64>) {
    let p = Problem::new(m).expect("problem");
    let w = &m.wheels[wheel];
    let eq = &r.eqs[step - 1];
    let row = r
        .rows
        .iter()
        .find(|x| x.step == step && x.wheel == w.name)
        .expect("row");
    let q = &row.quantities;
    let left = q.center[1] > 0.0;
    let side = if left { 1.0 } else { -1.0 };
    let (marker, col, sign) = match input {
        Input::Lateral => (w.contact, 1, side),
        Input::Braking => (w.contact, 0, 1.0),
        Input::Traction => (w.centre, 0, 1.0),
        Input::AligningTorque => (w.contact, 5, side),
    };
    let c = compliance(&p, eq, marker).expect("compliance");
    // Per kN (N·m) of the wheel's own load: a unit global load is `sign`
    // units of it, 1e-3 kN (N·m per N·mm).
    let per = 1000.0 * sign;
    let th = Vector3::new(c[3][col], c[4][col], c[5][col]) * per;
    let dp = Vector3::new(c[0][col], c[1][col], c[2][col]) * per;
    let at = match input {
        Input::Traction => Vector3::from(q.center),
        _ => Vector3::from(q.contact),
    };
    let u = dp + th.cross(&(Vector3::from(q.center) - at));
    let (toe, camber) = toe_camber(Vector3::from(q.spin_axis), th, left);
    let centre = match input {
        Input::Lateral => Some(side * u.y),
        Input::Braking | Input::Traction => Some(u.x),
        Input::AligningTorque => None,
    };
    (toe, camber, centre)
}

/// The benchmark McPherson with one-wheel compliance events: its vertical
/// design load held, one horizontal load swept ±500 N (±50 N·m) in small
/// steps so the path's difference is the tangent to 1e-5.
fn mcpherson_events() -> String {
    example("mcpherson.axle")
        + r#"
loads ev_lateral sweep {
    fz 4500 N
    fy 0 N -> 500 N -> -500 N -> 0 N by 50 N
}

loads ev_braking sweep {
    fz 4500 N
    fx 0 N -> -500 N -> 500 N -> 0 N by 50 N
}

loads ev_traction sweep {
    fz 4500 N
    upright.WC.fx 0 N -> 500 N -> -500 N -> 0 N by 50 N
}

loads ev_aligning sweep {
    fz 4500 N
    mz 0 N*mm -> 50000 N*mm -> -50000 N*mm -> 0 N*mm by 5000 N*mm
}
"#
}

#[test]
fn the_mcpherson_compliance_events_are_the_linearised_compliance() {
    let m = checked("mcpherson_events.axle", &mcpherson_events());
    for (set, input) in [
        ("ev_lateral", Input::Lateral),
        ("ev_braking", Input::Braking),
        ("ev_traction", Input::Traction),
        ("ev_aligning", Input::AligningTorque),
    ] {
        let r = run(&m, set);
        assert_eq!(r.events.len(), 1, "{set}");
        let e = &r.events[0];
        // 0 -> 500 -> -500 -> 0 by 50: zero again at step 21.
        assert_eq!((e.input, e.phase, e.step), (input, None, 21), "{set}");
        let w = &e.wheels[0];
        let (toe, camber, centre) = linearised(&m, &r, 0, input, e.step);
        close(w.toe, toe, 2e-4, &format!("{set} toe"));
        close(w.camber, camber, 2e-4, &format!("{set} camber"));
        match (w.centre, centre) {
            (Some(a), Some(b)) => close(a, b, 2e-4, &format!("{set} centre")),
            (a, b) => assert_eq!(a, b, "{set}"),
        }
    }
}

/// The front axle with its events swept in small steps (±500 N or ±50 N·m
/// by a tenth), both phases, named `fine_INPUT_PHASE`.
fn front_axle_fine() -> String {
    let mut text = example("front_axle.axle");
    for (stem, left, right, top, by, unit) in [
        (
            "lateral",
            "front_left.wheel.fy",
            "front_right.wheel.fy",
            500,
            50,
            "N",
        ),
        (
            "braking",
            "front_left.wheel.fx",
            "front_right.wheel.fx",
            500,
            50,
            "N",
        ),
        (
            "traction",
            "front_left.upright.WC.fx",
            "front_right.upright.WC.fx",
            500,
            50,
            "N",
        ),
        (
            "aligning",
            "front_left.wheel.mz",
            "front_right.wheel.mz",
            50000,
            5000,
            "N*mm",
        ),
    ] {
        for (phase, sign) in [("in_phase", 1), ("opposed", -1)] {
            let path = |s: i32| {
                format!(
                    "0 {unit} -> {} {unit} -> {} {unit} -> 0 {unit} by {by} {unit}",
                    s * top,
                    -s * top
                )
            };
            text += &format!(
                "\nloads fine_{stem}_{phase} sweep {{\n    front_left.wheel.fz 4500 N\n    front_right.wheel.fz 4500 N\n    {left} {}\n    {right} {}\n}}\n",
                path(1),
                path(sign)
            );
        }
    }
    text
}

#[test]
fn in_phase_and_opposed_events_of_the_front_axle_add_up_to_one_wheel_loaded_alone() {
    let m = checked("front_axle_fine.axle", &front_axle_fine());
    for (stem, input) in [
        ("lateral", Input::Lateral),
        ("braking", Input::Braking),
        ("traction", Input::Traction),
        ("aligning", Input::AligningTorque),
    ] {
        let inp = run(&m, &format!("fine_{stem}_in_phase"));
        let opp = run(&m, &format!("fine_{stem}_opposed"));
        let (ei, eo) = (&inp.events[0], &opp.events[0]);
        assert_eq!(
            (ei.input, ei.phase),
            (input, Some(Phase::InPhase)),
            "{stem}"
        );
        assert_eq!(
            (eo.input, eo.phase),
            (input, Some(Phase::Opposed)),
            "{stem}"
        );
        assert_eq!((ei.step, eo.step), (21, 21), "{stem}");
        for k in 0..2 {
            let (a, b) = (&ei.wheels[k], &eo.wheels[k]);
            // The mirrored corners give the same numbers in their own frames.
            let other = &ei.wheels[1 - k];
            close(
                a.toe,
                other.toe,
                1e-6,
                &format!("{stem} toe, the two sides"),
            );
            close(
                a.camber,
                other.camber,
                1e-6,
                &format!("{stem} camber, the two sides"),
            );
            // Linear superposition at the reference: in phase = own + cross,
            // opposed = own - cross (each wheel's own frame), so their mean
            // is the wheel's response to its own load alone, the linearised
            // compliance of its loaded marker.
            let (toe, camber, centre) = linearised(&m, &inp, k, input, ei.step);
            let mean = |x: f64, y: f64| 0.5 * (x + y);
            close(
                mean(a.toe, b.toe),
                toe,
                2e-4,
                &format!("{stem} {} toe", a.wheel),
            );
            close(
                mean(a.camber, b.camber),
                camber,
                2e-4,
                &format!("{stem} {} camber", a.wheel),
            );
            if let (Some(x), Some(y), Some(c)) = (a.centre, b.centre, centre) {
                close(mean(x, y), c, 2e-4, &format!("{stem} {} centre", a.wheel));
            }
        }
        // The rack couples the wheels: in phase and opposed differ in steer.
        let d = (ei.wheels[0].toe - eo.wheels[0].toe).abs();
        assert!(
            d > 1e-3 * ei.wheels[0].toe.abs().max(1e-4),
            "{stem}: no coupling {d}"
        );
    }
}

#[test]
fn a_swept_vertical_load_or_two_horizontal_ones_are_no_compliance_event() {
    let m = checked("examples/front_axle.axle", &example("front_axle.axle"));
    for set in ["parallel_bump", "roll", "steer", "mirrored"] {
        assert!(run(&m, set).events.is_empty(), "{set}");
    }
}

#[test]
fn kc_prints_the_compliance_events_in_its_table_json_and_plots() {
    let kc = |args: &[&str]| {
        let (code, out, err) = common::axle(args);
        assert_eq!(code, 0, "{err}");
        out
    };
    let table = kc(&[
        "kc",
        "examples/front_axle.axle",
        "--sweep",
        "lateral_in_phase",
    ]);
    let block = table
        .split("\ncompliance: ")
        .nth(1)
        .expect("a compliance block");
    insta::assert_snapshot!("lateral_in_phase_table", format!("compliance: {block}"));
    let json = kc(&[
        "kc",
        "examples/front_axle.axle",
        "--sweep",
        "aligning_opposed",
        "--format",
        "json",
    ]);
    let v: serde_json::Value = serde_json::from_str(&json).expect("json");
    insta::assert_json_snapshot!("aligning_opposed_json", v["compliance_events"]);
    let svg = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("kc_traction.svg");
    kc(&[
        "kc",
        "examples/front_axle.axle",
        "--sweep",
        "traction_opposed",
        "--plot",
        svg.to_str().expect("utf-8 path"),
    ]);
    let text = std::fs::read_to_string(&svg).expect("the plot");
    // Drawn against the force at the wheel centre, with the metrics written
    // under the toe and camber panels.
    assert!(
        text.contains("longitudinal force fx at the wheel centre [N]"),
        "x label"
    );
    assert!(
        text.contains("compliance steer front_left.wheel (opposed):"),
        "notes"
    );
    assert!(
        text.contains("compliance camber front_right.wheel (opposed):"),
        "notes"
    );
}

/// The car's lateral event gives an event per axle. With the body fixed the
/// axles do not touch, so the front one is the front axle's own event (the
/// same corners, bar and rack), and the mirrored rear corners agree.
#[test]
fn the_cars_lateral_event_is_each_axles_own() {
    let car = checked("examples/vehicle.axle", &example("vehicle.axle"));
    let axle = checked("examples/front_axle.axle", &example("front_axle.axle"));
    let ev = run(&car, "lateral_in_phase").events;
    assert_eq!(ev.len(), 2, "front and rear");
    assert!(ev.iter().all(|e| e.phase == Some(Phase::InPhase)));
    let front = &run(&axle, "lateral_in_phase").events[0];
    for (a, b) in ev[0].wheels.iter().zip(&front.wheels) {
        assert_eq!(a.wheel, b.wheel);
        close(a.toe, b.toe, 1e-9, "front toe, car and axle");
        close(a.camber, b.camber, 1e-9, "front camber, car and axle");
    }
    let [l, r] = [&ev[1].wheels[0], &ev[1].wheels[1]];
    assert_eq!(
        (l.wheel.as_str(), r.wheel.as_str()),
        ("rear_left.wheel", "rear_right.wheel")
    );
    close(l.toe, r.toe, 1e-6, "rear toe, the two sides");
    close(l.camber, r.camber, 1e-6, "rear camber, the two sides");
}
