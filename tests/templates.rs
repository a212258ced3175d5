//! Templates and instances (issue 13): an instance expands into the same
//! model as the corner written out by hand, and a mirrored instance under
//! mirrored loads stands in the mirror image of the original.

use axle::check::{check_str, mirror_frame};
use axle::geom::{Mat3, Vec3};
use axle::model::Model;
use axle::statics::{self, Equilibrium};

fn model(file: &str) -> Model {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(file);
    let text = std::fs::read_to_string(&path).expect("readable");
    let (_, checked) = check_str(file, &text);
    assert!(!checked.problems.has_errors(), "{:?}", checked.problems);
    checked.model.expect("checks clean")
}

fn solve(m: &Model, set: &str) -> Vec<Equilibrium> {
    let id = m.load_set_named(set).expect("the set exists");
    statics::solve_set(m, id).expect("solves")
}

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
    // 1 ground + 2 x 5 parts; each corner adds its 4 mounts to the ground.
    assert_eq!(m.parts.len(), 11);
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
        let (p, name) = if single.part(mk.part).ground {
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
    assert_eq!(m.bushings.len(), 2 * single.bushings.len());
    assert_eq!(m.joints.len(), 2 * single.joints.len());
    assert_eq!(m.springs.len(), 2 * single.springs.len());
}

/// The corners share only the ground: the left corner of the axle under the
/// benchmark bump sweep moves as the single corner does.
#[test]
fn the_left_corner_of_the_axle_solves_as_the_single_corner() {
    let axle = model("examples/front_axle.axle");
    let single = model("examples/mcpherson.axle");
    let a = solve(&axle, "bump");
    let s = solve(&single, "bump");
    assert_eq!(a.len(), s.len());
    assert_eq!(a.len(), 57);
    let mut worst = (0.0f64, 0.0f64);
    for (ea, es) in a.iter().zip(&s) {
        for part in ["front_arm", "rear_arm", "tie_rod", "strut", "upright"] {
            let (ta, ra) = pose(&axle, ea, &format!("front_left.{part}"));
            let (ts, rs) = pose(&single, es, part);
            worst.0 = worst.0.max((ta - ts).norm());
            worst.1 = worst.1.max((ra - rs).norm());
        }
    }
    eprintln!(
        "largest difference: {:.2e} mm, {:.2e} (rotation)",
        worst.0, worst.1
    );
    assert!(worst.0 < 1e-9 && worst.1 < 1e-12, "{worst:?}");
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
