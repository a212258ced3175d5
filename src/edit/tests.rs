//! Each edit on the McPherson, solved along Table 5-1, against an independent
//! expectation; invalid edits are errors that name the edit and leave the
//! model as it was.

use super::*;
use crate::model::address::Address;
use crate::statics::solve_set;

fn mcpherson_from(src: &str) -> Model {
    let (_, c) = crate::check::check_str("mcpherson.axle", src);
    c.model.expect("checks")
}

fn mcpherson() -> Model {
    mcpherson_from(include_str!("../../examples/mcpherson.axle"))
}

fn why() -> Why {
    Why::new("test", "an edit under test")
}

/// Wheel-centre positions (mm, global) along the default set.
fn wheel_centres(m: &Model) -> Vec<Vec3> {
    let set = m.default_load_set.expect("default set");
    let wc = m.wheels[0].centre;
    let part = m.marker(wc).part;
    solve_set(m, set)
        .expect("solves")
        .iter()
        .map(|eq| {
            let (p, r) = eq.state.part_pose(part);
            p + r * m.marker(wc).origin()
        })
        .collect()
}

fn max_diff(a: &[Vec3], b: &[Vec3]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).norm())
        .fold(0.0, f64::max)
}

fn joint(m: &Model, name: &str) -> JointId {
    JointId(m.joints.iter().position(|j| j.name == name).expect("joint") as u32)
}

fn marker(m: &Model, part: &str, name: &str) -> MarkerId {
    m.marker_named(m.part_named(part).expect("part"), name)
        .expect("marker")
}

fn replaced(m0: &Model, joint: JointId, k: f64) -> (Model, Applied) {
    let mut m = m0.clone();
    // A ball joint carries force, not torque: kt = 0.
    let r = apply(
        &mut m,
        Edit::JointToBushing {
            joint,
            k: [k; 3],
            kt: [0.0; 3],
        },
        &why(),
    )
    .expect("valid edit");
    (m, r)
}

/// The compliance a stiff element adds is first order in 1/k: ten times
/// stiffer, ten times closer to the rigid model.
fn converges_as_one_over_k(d_soft: f64, d_stiff: f64) {
    let ratio = d_soft / d_stiff;
    eprintln!("1/k convergence: {d_soft} mm -> {d_stiff} mm (ratio {ratio})");
    assert!(
        (8.0..12.5).contains(&ratio),
        "{d_soft} / {d_stiff} = {ratio}"
    );
    // Joint loads of about 10 kN over 1e5 N/mm, levered to the wheel centre.
    assert!(d_stiff < 0.5, "stiff: {d_stiff} mm");
}

#[test]
fn a_joint_replaced_by_a_stiff_bushing_reproduces_the_joint() {
    let m0 = mcpherson();
    let base = wheel_centres(&m0);
    let l7 = joint(&m0, "L7");
    let l8_addr = Address::parse(&m0, "L8.x").expect("L8");
    let (m, r) = replaced(&m0, l7, 1e5);
    let Applied::Replaced { by, .. } = r else {
        panic!("{r:?}")
    };
    assert_eq!(m.bushings[by.index()].name, "L7_bushing");
    // Ids held before the edit still name the same elements.
    assert_eq!(m.joints[l7.index()].name, "L7");
    assert_eq!(Address::parse(&m, "L8.x"), Ok(l8_addr));
    assert_eq!(
        m.origins.edit(ElementId::Bushing(by)),
        Some("added by test: an edit under test")
    );
    let stiff = wheel_centres(&m);
    let soft = wheel_centres(&replaced(&m0, l7, 1e4).0);
    converges_as_one_over_k(max_diff(&base, &soft), max_diff(&base, &stiff));
    // The printer skips the retired joint: the printed model checks and solves alike.
    let printed = crate::fmt::print_model(&m);
    assert!(!printed.contains("joint L7 "), "{printed}");
    let again = mcpherson_from(&printed);
    assert!(max_diff(&wheel_centres(&again), &stiff) < 1e-6);
}

fn split(m0: &Model, k: f64, kt: f64) -> Model {
    let mut m = m0.clone();
    let arm = m.part_named("rear_arm").expect("arm");
    let (a, l7) = (marker(&m, "rear_arm", "A"), marker(&m, "rear_arm", "L7"));
    let at = (m.marker(a).origin() + m.marker(l7).origin()) / 2.0;
    let outer: Vec<LandmarkId> = (0..m.landmarks.len())
        .filter(|&n| {
            let l = &m.landmarks[n];
            l.part == arm && (l.name == "m3" || l.name == "m4")
        })
        .map(|n| LandmarkId(n as u32))
        .collect();
    let r = apply(
        &mut m,
        Edit::SplitPart(Split {
            part: arm,
            name: "rear_arm_outer".into(),
            at,
            markers: vec![l7],
            landmarks: outer,
            k: [k; 3],
            kt: [kt; 3],
        }),
        &why(),
    )
    .expect("valid split");
    let Applied::Split { part, .. } = r else {
        panic!("{r:?}")
    };
    assert_eq!(m.marker(l7).part, part);
    m
}

#[test]
fn a_part_split_with_a_stiff_bushing_reproduces_the_rigid_part() {
    let m0 = mcpherson();
    let base = wheel_centres(&m0);
    let m = split(&m0, 1e5, 1e10);
    let stiff = wheel_centres(&m);
    let soft = wheel_centres(&split(&m0, 1e4, 1e9));
    converges_as_one_over_k(max_diff(&base, &soft), max_diff(&base, &stiff));
    let again = mcpherson_from(&crate::fmt::print_model(&m));
    assert!(max_diff(&wheel_centres(&again), &stiff) < 1e-6);
}

fn stop(m: &Model, contact: f64, k: f64) -> Stop {
    Stop {
        name: "bump".into(),
        kind: StopKind::Compression,
        i: marker(m, "chassis", "F"),
        j: marker(m, "upright", "L5"),
        contact_length: Val::lit(contact),
        law: StopLaw::Polynomial(vec![Val::lit(k)]),
    }
}

#[test]
fn an_added_stop_that_never_engages_changes_nothing() {
    let m0 = mcpherson();
    let mut m = m0.clone();
    apply(&mut m, Edit::AddStop(stop(&m0, 1.0, 100.0)), &why()).expect("valid");
    assert_eq!(m.stops.len(), 1);
    assert!(max_diff(&wheel_centres(&m0), &wheel_centres(&m)) < 1e-12);
}

#[test]
fn an_engaged_stop_on_the_spring_line_adds_its_law_to_the_spring() {
    // Stop k_s (c - l) plus spring k (L0 - l) + F0 is one spring of rate
    // k + k_s and free length (k L0 + k_s c) / (k + k_s) while l < c.
    let m0 = mcpherson();
    let (ks, c) = (20.0, 400.0);
    let mut m = m0.clone();
    apply(&mut m, Edit::AddStop(stop(&m0, c, ks)), &why()).expect("valid");
    let mut merged = m0.clone();
    let k = Address::parse(&merged, "spring.k").expect("k");
    let l0 = Address::parse(&merged, "spring.free_length").expect("L0");
    let (k0, len0) = (k.get(&merged), l0.get(&merged));
    k.set(&mut merged, k0 + ks);
    l0.set(&mut merged, (k0 * len0 + ks * c) / (k0 + ks));
    let d = max_diff(&wheel_centres(&merged), &wheel_centres(&m));
    eprintln!("stop + spring vs merged spring: {d} mm");
    assert!(d < 1e-6, "stop + spring vs merged spring: {d} mm");
    assert!(max_diff(&wheel_centres(&m0), &wheel_centres(&m)) > 0.1);
}

#[test]
fn a_cubic_law_equals_its_dense_table() {
    let m0 = mcpherson();
    let b = BushingId(m0.bushings.iter().position(|b| b.name == "B").expect("B") as u32);
    let (k, k3) = (310.0, 50.0);
    let law = |l: AxisLaw| Edit::SetLaw {
        bushing: b,
        rotational: false,
        axis: Axis::X,
        law: l,
    };
    let mut cubic = m0.clone();
    let cubic_law = AxisLaw::Linear {
        k: Val::lit(k),
        k3: Val::lit(k3),
    };
    apply(&mut cubic, law(cubic_law), &why()).expect("valid");
    let points = (0..=6000)
        .map(|n| {
            let d = -30.0 + n as f64 * 0.01;
            (d, k * d + k3 * d * d * d)
        })
        .collect();
    let mut table = m0.clone();
    apply(&mut table, law(AxisLaw::Table(Table { points })), &why()).expect("valid");
    let (wc, wt) = (wheel_centres(&cubic), wheel_centres(&table));
    let d = max_diff(&wc, &wt);
    eprintln!("cubic vs table: {d} mm");
    assert!(d < 1e-3, "cubic vs 0.01 mm table: {d} mm");
    assert!(
        max_diff(&wc, &wheel_centres(&m0)) > 1e-3,
        "the cubic term acts"
    );
}

#[test]
fn a_moved_joint_point_equals_the_model_written_there() {
    let mut m = mcpherson();
    let l7 = joint(&m, "L7");
    let p = m.marker(m.joints[l7.index()].j).origin();
    apply(
        &mut m,
        Edit::MovePoint {
            element: ElementId::Joint(l7),
            part: None,
            to: p + Vec3::new(0.0, 0.0, 2.0),
        },
        &why(),
    )
    .expect("valid");
    let text = include_str!("../../examples/mcpherson.axle").replace(
        "marker L7 at (-5.87, 679.9, 164.8) mm",
        "marker L7 at (-5.87, 679.9, 166.8) mm",
    );
    let written = mcpherson_from(&text);
    assert!(max_diff(&wheel_centres(&written), &wheel_centres(&m)) < 1e-9);
}

#[test]
fn invalid_edits_are_errors_naming_the_edit_and_change_nothing() {
    let m0 = mcpherson();
    let mut m = m0.clone();
    let l7 = joint(&m, "L7");
    let upright = m.part_named("upright").expect("upright");
    let err = |m: &mut Model, e: Edit| apply(m, e, &why()).expect_err("invalid");
    // One side of a ball joint moved: the joint no longer closes.
    let e = err(
        &mut m,
        Edit::MovePoint {
            element: ElementId::Joint(l7),
            part: Some(upright),
            to: Vec3::new(0.0, 700.0, 170.0),
        },
    );
    assert_eq!(
        e.edit,
        "move the point of spherical joint `L7` on part `upright`"
    );
    assert!(e.problems.iter().any(|d| d.code == "E0303"), "{e}");
    // A spring with both ends on one part.
    let s = Spring {
        name: "extra".into(),
        i: marker(&m, "upright", "L5"),
        j: marker(&m, "upright", "L6"),
        law: SpringLaw::Linear {
            k: Val::lit(10.0),
            free_length: Val::lit(300.0),
            preload: Val::ZERO,
        },
    };
    let e = err(&mut m, Edit::AddSpring(s));
    assert!(
        e.to_string()
            .starts_with("cannot add spring `extra`: both markers"),
        "{e}"
    );
    // A negative stiffness.
    let b = Bushing::linear(
        "neg",
        marker(&m, "chassis", "L3"),
        marker(&m, "tie_rod", "L3"),
        [-1.0, 1.0, 1.0],
        [0.0; 3],
    );
    assert!(
        err(&mut m, Edit::AddBushing(b))
            .problems
            .iter()
            .any(|d| d.code == "E0205")
    );
    // Friction on a ball joint along a slide it does not have.
    let f = |joint| Friction {
        name: "seal".into(),
        joint,
        motion: FrictionMotion::Slide,
        stiffness: Val::lit(1000.0),
        limit: Val::lit(150.0),
    };
    assert!(
        err(&mut m, Edit::AddFriction(f(l7)))
            .problems
            .iter()
            .any(|d| d.code == "E0412")
    );
    // A split taking a marker of another part.
    let split = Split {
        part: m.part_named("rear_arm").expect("arm"),
        name: "outer".into(),
        at: Vec3::zeros(),
        markers: vec![marker(&m, "upright", "L7")],
        landmarks: vec![],
        k: [1.0; 3],
        kt: [1.0; 3],
    };
    let e = err(&mut m, Edit::SplitPart(split));
    assert_eq!(
        e.to_string(),
        "cannot split part `rear_arm` into `outer`: marker `upright.L7` is not on part `rear_arm` [E0420]"
    );
    assert_eq!(m, m0, "a refused edit leaves the model as it was");
    // A joint with friction cannot become a bushing (the slider would be lost).
    let l5 = joint(&m, "L5");
    apply(&mut m, Edit::AddFriction(f(l5)), &why()).expect("a slide on the cylindrical L5");
    let e = err(
        &mut m,
        Edit::JointToBushing {
            joint: l5,
            k: [1.0; 3],
            kt: [1.0; 3],
        },
    );
    assert!(
        e.to_string().contains("friction `seal` acts on joint `L5`"),
        "{e}"
    );
}
