//! The whole car of `examples/vehicle.axle` (issue 13): McPherson front axle
//! with bar and rack, five-link rear corners. With the body fixed the two
//! axles are independent, so each must move as it does alone; the wheels
//! pair front with front and rear with rear; and the rear axle's roll
//! stiffness (opposed travel) must follow from its parallel-travel metrics.

use axle::model::Model;
use axle::statics::coords::reference_points;
use axle::statics::{self, Equilibrium};

mod common;

use common::{checked, example, share_of_stopping, solve, stopping, stopping_at};

fn metrics(m: &Model, set: &str) -> Vec<axle::kc::AxleMetrics> {
    let id = m.load_set_named(set).expect("set");
    let eqs = statics::solve_set(m, id).expect("solves");
    let states: Vec<_> = eqs.iter().map(|e| &e.state).collect();
    axle::kc::axle_metrics(m, &axle::kc::kc_rows(m, id, &states))
}

/// How two solves of the parts named in both `a` (model `ma`) and `b`
/// (model `mb`) differ, case by case.
struct Difference {
    /// Parts compared.
    parts: usize,
    /// Largest difference of a part's reference point (whose stopping error
    /// is bounded: `statics::coords::reference_points`) (mm) and rotation
    /// (Frobenius).
    mm: f64,
    rotation: f64,
    /// Largest share of the two solves' stopping errors (see
    /// `common::share_of_stopping`: at most 1 for the same mechanism).
    share: f64,
    /// Largest stopping error of a compared part (mm): what the share is of.
    stop_mm: f64,
}

fn worst_difference(ma: &Model, ea: &[Equilibrium], mb: &Model, eb: &[Equilibrium]) -> Difference {
    assert_eq!(ea.len(), eb.len());
    let (sa, sb) = (stopping(ma, ea), stopping(mb, eb));
    let (refs_a, refs_b) = (reference_points(ma), reference_points(mb));
    let mut worst = Difference {
        parts: 0,
        mm: 0.0,
        rotation: 0.0,
        share: 0.0,
        stop_mm: 0.0,
    };
    for p in ma.moving_parts() {
        let name = &ma.part(p).name;
        let Some(q) = mb.part_named(name) else {
            continue;
        };
        worst.parts += 1;
        for (k, (x, y)) in ea.iter().zip(eb).enumerate() {
            let (ta, ra) = x.state.part_pose(p);
            let (tb, rb) = y.state.part_pose(q);
            // Both at `a`'s reference point (the car's parts may carry more
            // connections than the corners', so `b`'s may lie elsewhere).
            let (ca, cb) = (refs_a[p.index()], refs_b[q.index()]);
            let (ta, tb) = (ta + ra * ca, tb + rb * ca);
            let (d, r) = ((ta - tb).norm(), (ra - rb).norm());
            let (a, b) = (sa[k][name], sb[k][name]);
            let b = stopping_at(b, &cb, &ca);
            worst.mm = worst.mm.max(d);
            worst.rotation = worst.rotation.max(r);
            worst.share = worst.share.max(share_of_stopping(d, r, a, b));
            worst.stop_mm = worst.stop_mm.max(a.0.max(b.0));
        }
    }
    eprintln!(
        "{} parts: {:.2e} mm, {:.2e} (rotation), {:.2} of the stopping errors (up to {:.2e} mm)",
        worst.parts, worst.mm, worst.rotation, worst.share, worst.stop_mm
    );
    worst
}

#[test]
fn the_wheels_pair_front_with_front_and_rear_with_rear() {
    let m = example("examples/vehicle.axle");
    let pairs: Vec<(&str, &str)> = axle::kc::axle::wheel_pairs(&m)
        .iter()
        .map(|(l, r)| {
            (
                m.wheels[l.index()].name.as_str(),
                m.wheels[r.index()].name.as_str(),
            )
        })
        .collect();
    assert_eq!(
        pairs,
        [
            ("front_left.wheel", "front_right.wheel"),
            ("rear_left.wheel", "rear_right.wheel")
        ]
    );
    // A sweep of one axle gives the metrics of that axle only.
    for (set, left) in [
        ("front_bump", "front_left.wheel"),
        ("rear_roll", "rear_left.wheel"),
    ] {
        let a = metrics(&m, set);
        assert_eq!(a.len(), 1, "{set}");
        assert_eq!(a[0].wheels[0].wheel, left);
    }
}

/// The front axle of the car under `front_bump` is `examples/front_axle.axle`
/// under `parallel_bump` (the same front loads; the rear's static loads act
/// on parts the fixed body separates from the front).
#[test]
fn the_front_axle_of_the_car_moves_as_the_front_axle_example() {
    let car = example("examples/vehicle.axle");
    let front = example("examples/front_axle.axle");
    let (ec, ef) = (solve(&car, "front_bump"), solve(&front, "parallel_bump"));
    let worst = worst_difference(&front, &ef, &car, &ec);
    assert_eq!(worst.parts, 15, "every moving part of the front axle");
    // The same poses up to where each solve stopped (the two models' force
    // scales and lengths differ, so their solves stop at other iterates)...
    assert!(worst.share <= 1.0, "{:.2}", worst.share);
    // ... which is far below any difference of the mechanisms (a hardpoint
    // written 0.01 mm off moves the parts by about that much).
    assert!(worst.stop_mm < 1e-4, "{:.2e}", worst.stop_mm);
}

/// The two rear corners alone, swept as the car's `rear_bump` sweeps them.
const REAR: &str = "model rear

import multilink_corner

ground chassis {
}

instance rear_left = multilink_corner()
instance rear_right = mirror multilink_corner()

loads rear_bump sweep {
    rear_left.wheel.fz 1000 N -> 6000 N -> 1000 N by 250 N
    rear_right.wheel.fz 1000 N -> 6000 N -> 1000 N by 250 N
}
";

#[test]
fn the_rear_axle_of_the_car_moves_as_the_two_corners_alone() {
    let car = example("examples/vehicle.axle");
    let rear = checked("rear.axle", REAR);
    let (ec, er) = (solve(&car, "rear_bump"), solve(&rear, "rear_bump"));
    let worst = worst_difference(&rear, &er, &car, &ec);
    assert_eq!(worst.parts, 12);
    // As for the front axle: the same poses up to where each solve stopped.
    assert!(worst.share <= 1.0, "{:.2}", worst.share);
    assert!(worst.stop_mm < 1e-4, "{:.2e}", worst.stop_mm);
}

/// The car of 35 moving parts the speed bench solves (`benches/vehicle.rs`):
/// the example with `benches/vehicle_35.axle` spliced in.
fn car_of_35_parts() -> Model {
    let car = include_str!("../examples/vehicle.axle");
    let more = include_str!("../benches/vehicle_35.axle");
    assert!(car.contains("ground chassis {\n}\n"));
    let text = car.replace("ground chassis {\n}\n", "").replace(
        "\ndefault loads vehicle",
        &format!("\n{more}\ndefault loads vehicle"),
    );
    checked("vehicle_35.axle", &text)
}

/// The bench's car of 35 parts adds a rear anti-roll bar and four braked
/// hubs, none loaded in parallel travel: the bar's halves turn alike and
/// its torsion bushing stays undeformed, the hubs carry nothing. So in
/// the rear axle's bump sweep its 27 parts stand where the example's do,
/// up to where each solve stopped.
#[test]
fn the_car_of_35_parts_moves_as_the_example_in_parallel_travel() {
    let car = example("examples/vehicle.axle");
    let big = car_of_35_parts();
    assert_eq!(big.moving_parts().count(), 35);
    let (e27, e35) = (solve(&car, "rear_bump"), solve(&big, "rear_bump"));
    let worst = worst_difference(&car, &e27, &big, &e35);
    assert_eq!(worst.parts, 27);
    assert!(worst.share <= 1.0, "{:.2}", worst.share);
    assert!(worst.stop_mm < 1e-4, "{:.2e}", worst.stop_mm);
}

/// The curb loads are the design position's: every wheel within 3 mm of
/// its design height.
#[test]
fn at_the_curb_loads_the_car_stands_at_its_design_position() {
    let m = example("examples/vehicle.axle");
    let e = solve(&m, "vehicle");
    let curb = &e[0];
    let r = axle::output::report::case_report(&m, "curb", 1, curb);
    assert_eq!(r.wheels.len(), 4);
    for (name, w) in &r.wheels {
        eprintln!("{name}: travel {:.2} mm at curb", w.travel_mm);
        assert!(w.travel_mm.abs() < 3.0, "{name}: {}", w.travel_mm);
    }
}

/// For a pair of independent corners (no bar), body roll φ moves the wheels
/// by ∓(t/2)φ; the loads change by ±k_w (t/2)φ and the contact points move
/// laterally by d(half-track)/dz = z_rc/(t/2) (the roll centre's height
/// over the half-track), so with the static load f0 on each wheel
/// Mx = y_l f_l + y_r f_r changes by
/// -dMx/dφ = 2 k_w (t/2)² + 2 f0 z_rc:
/// the opposed-travel metric from the parallel-travel ones.
#[test]
fn the_rear_roll_stiffness_follows_from_the_wheel_rate_and_the_roll_centre() {
    let m = example("examples/vehicle.axle");
    let bump = metrics(&m, "rear_bump");
    let roll = metrics(&m, "rear_roll");
    assert_eq!((bump.len(), roll.len()), (1, 1));
    let k_w = bump[0].wheels[0].rate.expect("a rate");
    assert_eq!(bump[0].wheels[1].rate, Some(k_w), "mirror");
    let [y_rc, z_rc] = bump[0].roll_centre.expect("a roll centre");
    assert!(y_rc.abs() < 1e-6, "{y_rc}");
    let half_track = 750.0; // the template's wheel and contact y
    let f0 = 3500.0; // N, the reference step of both sweeps
    assert_eq!(roll[0].loadcase, "rear_roll_009");
    let hand = (2.0 * k_w * half_track * half_track + 2.0 * f0 * z_rc) * std::f64::consts::PI
        / 180.0
        / 1000.0;
    let got = roll[0].roll_stiffness.expect("a roll stiffness");
    eprintln!(
        "rear roll stiffness {got:.2} N*m/deg, from k_w = {k_w:.3} N/mm and z_rc = {z_rc:.2} mm: {hand:.2} ({:.1e} relative)",
        (got - hand) / hand
    );
    // Central differences over 250 N steps on both sweeps: 5e-4.
    assert!((got - hand).abs() < 5e-4 * hand, "{got} against {hand}");
}

/// What an engineer reads: the axle blocks of `axle kc` for the four axle
/// sweeps of the car.
#[test]
fn vehicle_axle_metrics_as_printed() {
    let mut all = String::new();
    for sweep in ["front_bump", "rear_bump", "front_roll", "rear_roll"] {
        let (code, out, err) = common::axle(&["kc", "examples/vehicle.axle", "--sweep", sweep]);
        assert_eq!(code, 0, "{err}");
        all += &out[out.find("\naxle ").expect("an axle block")..];
    }
    insta::assert_snapshot!("vehicle_axles", all);
}
