//! Templates and instances (issue 13): an instance expands into the same
//! model as the corner written out by hand, and a mirrored instance under
//! mirrored loads stands in the mirror image of the original.

use axle::check::{check_str, mirror_frame};
use axle::geom::{Mat3, Vec3};
use axle::model::Model;
use axle::statics::Equilibrium;
use axle::statics::newton::FORCE_TOL;

mod common;

use common::{
    example as model, pose_at, reference, share_of_stopping, solve, stopping, stopping_at,
};

fn pose(m: &Model, e: &Equilibrium, part: &str) -> (Vec3, Mat3) {
    e.state
        .part_pose(m.part_named(part).expect("the part exists"))
}

const S: [f64; 3] = [1.0, -1.0, 1.0];

fn reflect() -> Mat3 {
    Mat3::from_diagonal(&Vec3::from(S))
}

#[test]
fn an_instance_expands_to_the_named_parts_and_ground_markers() {
    let m = model("examples/front_axle.axle");
    for side in ["front_left", "front_right"] {
        for part in ["front_arm", "rear_arm", "tie_rod", "strut", "upright"] {
            assert!(
                m.part_named(&format!("{side}.{part}")).is_some(),
                "{side}.{part}"
            );
        }
        assert!(m.wheels.iter().any(|w| w.name == format!("{side}.wheel")));
    }
    // 1 ground + the rack + 2 x 5 corner parts + the bar's 2 halves and 2
    // drop links; each corner adds its 3 mounts to the ground and its tie
    // rod's inner joint L3 to the rack (the part parameter `rack`).
    assert_eq!(m.parts.len(), 16);
    let rack = m.part_named("steering.rack").expect("the rack");
    for side in ["front_left", "front_right"] {
        assert!(m.marker_named(rack, &format!("{side}.L3")).is_some());
    }
    let chassis = m.part_named("chassis").expect("ground");
    let b_left = m.marker_named(chassis, "front_left.B").expect("mount");
    let b_right = m.marker_named(chassis, "front_right.B").expect("mount");
    let (l, r) = (&m.markers[b_left.index()], &m.markers[b_right.index()]);
    // The mirror: y negated, frame reflected (x, z) and right-handed.
    assert_eq!(r.origin(), reflect() * l.origin());
    assert!((r.rotation - mirror_frame(&l.rotation)).norm() < 1e-15);
    assert!((r.rotation.column(0) - reflect() * l.rotation.column(0)).norm() < 1e-15);
    assert!((r.rotation.column(2) - reflect() * l.rotation.column(2)).norm() < 1e-15);
    assert!((r.rotation.determinant() - 1.0).abs() < 1e-12);
    // The left corner is the benchmark's, marker for marker.
    let single = model("examples/mcpherson.axle");
    for mk in &single.markers {
        let part = &single.part(mk.part).name;
        let (p, name) = if single.part(mk.part).ground && mk.name == "L3" {
            ("steering.rack".to_string(), "front_left.L3".to_string())
        } else if single.part(mk.part).ground {
            ("chassis".to_string(), format!("front_left.{}", mk.name))
        } else {
            (format!("front_left.{part}"), mk.name.clone())
        };
        let pid = m.part_named(&p).expect("part");
        let id = m
            .marker_named(pid, &name)
            .unwrap_or_else(|| panic!("{p}.{name}"));
        let x = &m.markers[id.index()];
        assert_eq!(x.origin(), mk.origin(), "{p}.{name}");
        assert_eq!(x.rotation, mk.rotation, "{p}.{name}");
    }
    let corner = |names: Vec<&String>| names.iter().filter(|n| n.starts_with("front_")).count();
    assert_eq!(
        corner(m.bushings.iter().map(|b| &b.name).collect()),
        2 * single.bushings.len()
    );
    assert_eq!(
        corner(m.joints.iter().map(|j| &j.name).collect()),
        2 * single.joints.len()
    );
    assert_eq!(m.springs.len(), 2 * single.springs.len());
}

/// Parallel wheel travel (the benchmark bump sweep on both wheels in
/// lockstep): the anti-roll bar's halves turn alike, the bar does not twist
/// and carries nothing, so each corner moves as the single corner does.
#[test]
fn in_parallel_bump_each_side_moves_as_the_single_corner() {
    let axle = model("examples/front_axle.axle");
    let single = model("examples/mcpherson.axle");
    let a = solve(&axle, "parallel_bump");
    let s = solve(&single, "bump");
    assert_eq!(a.len(), s.len());
    assert_eq!(a.len(), 57);
    let mirror = reflect();
    let (stop_a, stop_s) = (stopping(&axle, &a), stopping(&single, &s));
    // Largest difference (mm, rotation), bar twist, share of the stopping
    // errors (`common::share_of_stopping`), largest stopping error (mm).
    let mut worst = (0.0f64, 0.0f64, 0.0f64, 0.0f64, 0.0f64);
    for (k, (ea, es)) in a.iter().zip(&s).enumerate() {
        for part in ["front_arm", "rear_arm", "tie_rod", "strut", "upright"] {
            // Both at the single corner's reference point (the axle's parts
            // carry more connections, so theirs lie elsewhere).
            let at = reference(&single, part);
            let (ts, rs) = pose_at(&single, es, part, &at);
            let b = stop_s[k][part];
            for (side, flip) in [("front_left", Mat3::identity()), ("front_right", mirror)] {
                let name = format!("{side}.{part}");
                let (t, r) = pose_at(&axle, ea, &name, &(flip * at));
                let (d, dr) = ((t - flip * ts).norm(), (r - flip * rs * flip).norm());
                let a = stopping_at(stop_a[k][&name], &reference(&axle, &name), &(flip * at));
                worst.0 = worst.0.max(d);
                worst.1 = worst.1.max(dr);
                worst.3 = worst.3.max(share_of_stopping(d, dr, a, b));
                worst.4 = worst.4.max(a.0.max(b.0));
            }
        }
        let twist = bar_angle(&axle, ea, "bar.half_left") - bar_angle(&axle, ea, "bar.half_right");
        worst.2 = worst.2.max(twist.abs());
    }
    eprintln!(
        "largest difference: {:.2e} mm, {:.2e} (rotation), {:.2} of the stopping errors (up to {:.2e} mm); bar twist {:.2e} rad",
        worst.0, worst.1, worst.3, worst.4, worst.2
    );
    // Each side is the single corner (mirrored) up to where the solves
    // stopped, which is far below any difference of the mechanisms.
    assert!(worst.3 <= 1.0 && worst.4 < 1e-4, "{worst:?}");
    assert!(
        worst.2 < 1e-10,
        "the bar twists in parallel travel: {worst:?}"
    );
    // ... yet the bar's halves do turn with the wheels.
    let last = &a[28];
    assert!(bar_angle(&axle, last, "bar.half_left").abs() > 0.1);
}

/// A bar half's rotation about the vehicle y axis (its mount's hinge), rad.
fn bar_angle(m: &Model, e: &Equilibrium, part: &str) -> f64 {
    let (_, r) = pose(m, e, part);
    assert!((r[(1, 1)] - 1.0).abs() < 1e-12, "{part} turns about y only");
    r[(0, 2)].atan2(r[(0, 0)])
}

/// Opposed wheel travel (roll): the bar twists by the difference of its
/// halves' turns, and each half is in moment balance about its hinge: the
/// torsion bushing's moment equals the drop link's force times its arm.
#[test]
fn in_roll_the_bar_twists_and_each_half_balances_about_its_hinge() {
    let m = model("examples/front_axle.axle");
    let set = m.load_set_named("roll").expect("roll");
    let eqs = solve(&m, "roll");
    assert_eq!(eqs.len(), 17);
    let k_torsion = 15000.0; // N*mm/deg, the example's argument
    let length = axle::statics::Problem::new(&m).expect("compiles").length;
    // Twist misfit (deg); moment balance's misfit as a share of what the
    // solve's stopping rule allows.
    let mut worst = (0.0f64, 0.0f64);
    for (k, e) in eqs.iter().enumerate() {
        let name = &m.load_sets[set.index()].cases[k].name;
        let r = axle::output::report::case_report(&m, name, k + 1, e);
        let torsion = &r.bushings["bar.torsion"];
        let twist = bar_angle(&m, e, "bar.half_left") - bar_angle(&m, e, "bar.half_right");
        // The bushing's deformation about y is the twist (deg), its moment k times it.
        worst.0 = worst
            .0
            .max((torsion.deformation[4].abs() - twist.abs().to_degrees()).abs());
        let moment = torsion.force[4];
        assert!(
            (moment.abs() - k_torsion * twist.abs().to_degrees()).abs()
                < 1e-6 * moment.abs().max(1.0)
        );
        // Moment of the drop link's force about the left hinge (y through the mount).
        let link = &r.joints["bar.link_left"];
        let (p, f) = (link.point, link.force);
        let hinge = [-250.0, 400.0, 250.0];
        let my = (p[2] - hinge[2]) * f[0] - (p[0] - hinge[0]) * f[2];
        // The solve stops with the half's residual torque about its origin
        // (the global origin) below FORCE_TOL F L and each residual force
        // component below FORCE_TOL F; about the hinge, d = origin - hinge,
        // the force adds (d x f)_y = d_z f_x - d_x f_z.
        let tol = FORCE_TOL * e.force_scale;
        let allowed = tol * (length + hinge[0].abs() + hinge[2].abs());
        worst.1 = worst.1.max((my.abs() - moment.abs()).abs() / allowed);
    }
    eprintln!(
        "twist misfit {:.2e} deg, moment balance {:.2e} of its tolerance",
        worst.0, worst.1
    );
    assert!(worst.0 < 1e-9, "{worst:?}");
    assert!(worst.1 <= 1.0, "{worst:?}");
    // At the roll's extreme (left +1000 N, right -1000 N) the bar does work.
    let r = axle::output::report::case_report(&m, "roll_005", 5, &eqs[4]);
    assert!(r.bushings["bar.torsion"].deformation[4].abs() > 5.0);
}

/// Under mirrored wheel loads (fy -> -fy) the right corner's pose is the
/// mirror image of the left's: t_r = S t_l, R_r = S R_l S, S = diag(1, -1, 1).
#[test]
fn the_mirrored_corner_under_mirrored_loads_is_the_mirror_image() {
    let m = model("examples/front_axle.axle");
    let cases = solve(&m, "mirrored");
    assert_eq!(cases.len(), 3);
    let s = reflect();
    let mut worst = (0.0f64, 0.0f64, 0.0f64);
    for e in &cases {
        for part in ["front_arm", "rear_arm", "tie_rod", "strut", "upright"] {
            let (tl, rl) = pose(&m, e, &format!("front_left.{part}"));
            let (tr, rr) = pose(&m, e, &format!("front_right.{part}"));
            worst.0 = worst.0.max((tr - s * tl).norm());
            worst.1 = worst.1.max((rr - s * rl * s).norm());
        }
        // The wheel centre itself, and that the case moved it.
        let up = m.part_named("front_left.upright").expect("part");
        let wc = m.marker_named(up, "WC").expect("marker");
        let p0 = m.markers[wc.index()].origin();
        let (tl, rl) = pose(&m, e, "front_left.upright");
        let (tr, rr) = pose(&m, e, "front_right.upright");
        let left = tl + rl * p0;
        let right = tr + rr * (s * p0);
        worst.2 = worst.2.max((right - s * left).norm());
        assert!((left - p0).norm() > 1.0, "the load moves the wheel");
    }
    eprintln!(
        "mirror misfit: {:.2e} mm, {:.2e} (rotation), wheel centre {:.2e} mm",
        worst.0, worst.1, worst.2
    );
    assert!(
        worst.0 < 1e-8 && worst.1 < 1e-10 && worst.2 < 1e-8,
        "{worst:?}"
    );
}

/// A template parameter is per instance (an argument overrides the default
/// for its own instance only) and an argument may name a top-level `param`.
#[test]
fn an_argument_overrides_the_default_for_its_instance_only() {
    let text = "model m\n\nimport mcpherson_corner\n\nparam k_right = 25 N/mm\n\nground chassis {\n}\n\ninstance front_left = mcpherson_corner()\ninstance front_right = mirror mcpherson_corner(k_spring = k_right, free_length = 300 mm)\n";
    let (_, checked) = check_str("m.axle", text);
    assert!(!checked.problems.has_errors(), "{:?}", checked.problems);
    let m = checked.model.expect("checks");
    let law = |name: &str| {
        let s = m.springs.iter().find(|s| s.name == name).expect("spring");
        match &s.law {
            axle::model::SpringLaw::Linear { k, free_length, .. } => (k.value, free_length.value),
            _ => panic!("a linear spring"),
        }
    };
    assert_eq!(law("front_left.spring"), (30.0, 290.0));
    assert_eq!(law("front_right.spring"), (25.0, 300.0));
}
