//! The stdlib corner and axle templates (issue 13) against independent
//! expectations: a template corner expands to exactly its flat example and
//! solves as it does; a mirrored instance under mirrored loads stands in the
//! mirror image.

use axle::check::check_str;
use axle::geom::{Mat3, Vec3};
use axle::model::Model;
use axle::statics::{self, Equilibrium};

fn checked(name: &str, text: &str) -> Model {
    let (_, c) = check_str(name, text);
    assert!(!c.problems.has_errors(), "{:?}", c.problems);
    c.model.expect("checks clean")
}

fn example(file: &str) -> Model {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(file);
    checked(file, &std::fs::read_to_string(&path).expect("readable"))
}

fn solve(m: &Model, set: &str) -> Vec<Equilibrium> {
    let id = m.load_set_named(set).expect("the set exists");
    statics::solve_set(m, id).expect("solves")
}

fn pose(m: &Model, e: &Equilibrium, part: &str) -> (Vec3, Mat3) {
    e.state
        .part_pose(m.part_named(part).unwrap_or_else(|| panic!("part {part}")))
}

/// A marker's global position in a solved state.
fn point(m: &Model, e: &Equilibrium, part: &str, marker: &str) -> Vec3 {
    let p = m.part_named(part).unwrap_or_else(|| panic!("part {part}"));
    let id = m
        .marker_named(p, marker)
        .unwrap_or_else(|| panic!("{part}.{marker}"));
    let (t, r) = e.state.part_pose(p);
    t + r * m.markers[id.index()].origin()
}

/// The reflection about the vehicle xz plane, y -> -y.
fn reflect() -> Mat3 {
    Mat3::from_diagonal(&Vec3::new(1.0, -1.0, 1.0))
}

/// The largest differences (position mm, rotation) between the poses of
/// `parts` in corner `a` of model `ma` and, reflected by `s` when given,
/// corner `b` of model `mb`, over all cases.
fn worst_pose_difference(
    (ma, ea, a): (&Model, &[Equilibrium], &str),
    (mb, eb, b): (&Model, &[Equilibrium], &str),
    parts: &[&str],
    mirrored: bool,
) -> (f64, f64) {
    let s = if mirrored {
        reflect()
    } else {
        Mat3::identity()
    };
    let mut worst = (0.0f64, 0.0f64);
    assert_eq!(ea.len(), eb.len());
    for (x, y) in ea.iter().zip(eb) {
        for part in parts {
            let (ta, ra) = pose(ma, x, &format!("{a}{part}"));
            let (tb, rb) = pose(mb, y, &format!("{b}{part}"));
            worst.0 = worst.0.max((tb - s * ta).norm());
            worst.1 = worst.1.max((rb - s * ra * s).norm());
        }
    }
    worst
}

// ---------------------------------------------------------------------------
// Double wishbone: the template is examples/double_wishbone.axle.
// ---------------------------------------------------------------------------

const DW_PARTS: [&str; 4] = ["lower_arm", "upper_arm", "tie_rod", "upright"];

/// One template corner, swept like the flat example (its stdlib `bump`).
const DW_SINGLE: &str = "model dw_corner

import double_wishbone_corner

ground chassis {
}

instance front_left = double_wishbone_corner()

loads bump sweep {
    front_left.wheel.fz 1000 N -> 8000 N -> 1000 N by 250 N
}
";

#[test]
fn the_double_wishbone_template_is_the_flat_example_marker_for_marker() {
    let flat = example("examples/double_wishbone.axle");
    let t = checked("dw_corner.axle", DW_SINGLE);
    assert_eq!(t.parts.len(), flat.parts.len());
    assert_eq!(t.markers.len(), flat.markers.len());
    for mk in &flat.markers {
        let part = flat.part(mk.part);
        let (p, name) = if part.ground {
            ("chassis".to_string(), format!("front_left.{}", mk.name))
        } else {
            (format!("front_left.{}", part.name), mk.name.clone())
        };
        let pid = t.part_named(&p).unwrap_or_else(|| panic!("{p}"));
        let id = t
            .marker_named(pid, &name)
            .unwrap_or_else(|| panic!("{p}.{name}"));
        let x = &t.markers[id.index()];
        assert_eq!(x.origin(), mk.origin(), "{p}.{name}");
        assert_eq!(x.rotation, mk.rotation, "{p}.{name}");
    }
    // The same elements with the same laws.
    for b in &flat.bushings {
        let c = t
            .bushings
            .iter()
            .find(|c| c.name == format!("front_left.{}", b.name))
            .expect("bushing");
        assert_eq!(
            rates(&c.translational),
            rates(&b.translational),
            "{}",
            b.name
        );
        assert_eq!(rates(&c.rotational), rates(&b.rotational), "{}", b.name);
    }
    assert_eq!(t.joints.len(), flat.joints.len());
    for j in &flat.joints {
        let c = t
            .joints
            .iter()
            .find(|c| c.name == format!("front_left.{}", j.name))
            .expect("joint");
        assert_eq!(c.kind, j.kind);
    }
    assert_eq!(spring_law(&t.springs[0]), spring_law(&flat.springs[0]));
    assert_eq!(spring_law(&flat.springs[0]), (130.0, 452.0, 0.0));
}

/// A linear bushing law's (k, k3) per axis.
fn rates(laws: &axle::model::AxisLaws) -> Vec<(f64, f64)> {
    laws.to_three()
        .iter()
        .map(|l| match l {
            axle::model::AxisLaw::Linear { k, k3 } => (k.value, k3.value),
            axle::model::AxisLaw::Table(_) => panic!("linear laws"),
        })
        .collect()
}

/// A linear spring's (k, free length, preload).
fn spring_law(s: &axle::model::Spring) -> (f64, f64, f64) {
    match &s.law {
        axle::model::SpringLaw::Linear {
            k,
            free_length,
            preload,
        } => (k.value, free_length.value, preload.value),
        axle::model::SpringLaw::Table(_) => panic!("a linear spring"),
    }
}

#[test]
fn the_double_wishbone_template_solves_the_bump_sweep_as_the_flat_example() {
    let flat = example("examples/double_wishbone.axle");
    let t = checked("dw_corner.axle", DW_SINGLE);
    let ef = solve(&flat, "bump");
    let et = solve(&t, "bump");
    assert_eq!(ef.len(), 57);
    let worst = worst_pose_difference((&flat, &ef, ""), (&t, &et, "front_left."), &DW_PARTS, false);
    eprintln!(
        "template vs flat: {:.2e} mm, {:.2e} (rotation)",
        worst.0, worst.1
    );
    assert!(worst.0 < 1e-9 && worst.1 < 1e-12, "{worst:?}");
    // ... and the sweep moves the wheel: 7000 N of load change.
    let wc = |e: &Equilibrium| point(&t, e, "front_left.upright", "WC");
    assert!((wc(&et[28]) - wc(&et[0])).norm() > 20.0);
}

/// Both corners of an axle, the right the mirror of the left, loaded by
/// mirrored wheel loads (fy -> -fy).
const DW_AXLE: &str = "model dw_axle

import double_wishbone_corner

ground chassis {
}

instance front_left = double_wishbone_corner()
instance front_right = mirror double_wishbone_corner()

loads mirrored table (front_left.wheel.fz N, front_left.wheel.fy N, front_left.wheel.fx N, front_right.wheel.fz N, front_right.wheel.fy N, front_right.wheel.fx N) {
    c1  4500   1000      0  4500  -1000      0
    c2  6000  -1000   1000  6000   1000   1000
    c3  3000      0  -1000  3000      0  -1000
    c4  7500   2500  -2000  7500  -2500  -2000
}
";

#[test]
fn the_mirrored_double_wishbone_under_mirrored_loads_is_the_mirror_image() {
    let m = checked("dw_axle.axle", DW_AXLE);
    let e = solve(&m, "mirrored");
    let worst = worst_pose_difference(
        (&m, &e, "front_left."),
        (&m, &e, "front_right."),
        &DW_PARTS,
        true,
    );
    let mut wheel = 0.0f64;
    for c in &e {
        let l = point(&m, c, "front_left.upright", "WC");
        let r = point(&m, c, "front_right.upright", "WC");
        wheel = wheel.max((r - reflect() * l).norm());
        assert!(r.y < 0.0 && l.y > 0.0);
    }
    eprintln!(
        "mirror misfit: {:.2e} mm, {:.2e} (rotation), wheel centre {wheel:.2e} mm",
        worst.0, worst.1
    );
    assert!(
        worst.0 < 1e-9 && worst.1 < 1e-12 && wheel < 1e-9,
        "{worst:?}"
    );
}
