//! Small mechanisms against independent results and closed forms: a single
//! bushing, a four-bar, a slider-crank, a tie rod, redundant loops.

use crate::support::*;
use axle::geom::{Mat3, Vec3, frame_from_z_x};
use axle::model::*;
use axle::output::report::case_report;
use axle::statics::{self, Problem, State, StaticsErrorKind};

fn single_bushing() -> (Model, MarkerId) {
    let mut b = Builder::new("single_bushing");
    let g = b.part("ground", true);
    let arm = b.part("arm", false);
    let i = b.point(g, "b", [0.0; 3]);
    let j = b.point(arm, "b", [0.0; 3]);
    let tip = b.point(arm, "tip", [300.0, 0.0, 0.0]);
    b.bushing("b", i, j, [1e4; 3], [1e4; 3]);
    (b.m, tip)
}

fn four_bar() -> (Model, MarkerId) {
    let mut b = Builder::new("four_bar");
    let g = b.part("ground", true);
    let l1 = b.part("link1", false);
    let l2 = b.part("link2", false);
    let c = b.part("coupler", false);
    let axis_y = frame_from_z_x(Vec3::y(), Some(Vec3::x())).expect("frame");
    for (name, part, x) in [("b1", l1, 0.0), ("b2", l2, 250.0)] {
        let i = b.point(g, name, [x, 0.0, 0.0]);
        let j = b.point(part, name, [x, 0.0, 0.0]);
        b.bushing(name, i, j, [1e4; 3], [1e4; 3]);
    }
    for (name, part, x) in [("r1", l1, 0.0), ("r2", l2, 250.0)] {
        let i = b.marker(part, name, [x, 0.0, 450.0], axis_y);
        let j = b.marker(c, name, [x, 0.0, 450.0], axis_y);
        b.joint(name, JointKind::Revolute, i, j);
    }
    let mid = b.point(c, "mid", [125.0, 0.0, 450.0]);
    (b.m, mid)
}

const FOUR_BAR_CASES: [([f64; 3], [f64; 3]); 10] = [
    ([0.0, 0.0, -1000.0], [0.0; 3]),
    ([0.0, 1000.0, 0.0], [0.0; 3]),
    ([300.0, 0.0, 0.0], [0.0; 3]),
    ([0.0; 3], [10000.0, 0.0, 0.0]),
    ([0.0; 3], [0.0, 10000.0, 0.0]),
    ([0.0; 3], [0.0, 0.0, 10000.0]),
    ([200.0, 500.0, -600.0], [3000.0, -4000.0, 5000.0]),
    ([-250.0, -400.0, 700.0], [-6000.0, 2000.0, 4000.0]),
    ([150.0, -600.0, -500.0], [5000.0, 5000.0, -5000.0]),
    ([-100.0, 700.0, 300.0], [-2000.0, -7000.0, -6000.0]),
];

fn slider_crank() -> (Model, MarkerId) {
    let mut b = Builder::new("slider_crank");
    let g = b.part("ground", true);
    let crank = b.part("crank", false);
    let rod = b.part("rod", false);
    let slider = b.part("slider", false);
    let id = Mat3::identity();
    let pin = [50.0, 86.6025, 0.0];
    let sx = 50.0 + (300.0f64 * 300.0 - 86.6025 * 86.6025).sqrt();
    let i = b.marker(crank, "o", [0.0; 3], id);
    let j = b.marker(g, "o", [0.0; 3], id);
    b.joint("crank_rev", JointKind::Revolute, i, j);
    let i = b.point(rod, "pin", pin);
    let j = b.point(crank, "pin", pin);
    b.joint("crank_pin", JointKind::Spherical, i, j);
    let i = b.marker(rod, "slider_pin", [sx, 0.0, 0.0], id);
    let j = b.marker(slider, "slider_pin", [sx, 0.0, 0.0], id);
    b.joint("slider_pin", JointKind::Revolute, i, j);
    let along_x = frame_from_z_x(Vec3::x(), Some(Vec3::y())).expect("frame");
    let i = b.marker(slider, "slide", [sx, 0.0, 0.0], along_x);
    let j = b.marker(g, "slide", [sx, 0.0, 0.0], along_x);
    b.joint("slide", JointKind::Translational, i, j);
    let i = b.point(g, "bs", [sx, 0.0, 0.0]);
    let j = b.point(slider, "bs", [sx, 0.0, 0.0]);
    b.bushing("bs", i, j, [1e4; 3], [1e4; 3]);
    let load_at = b.point(crank, "load", pin);
    (b.m, load_at)
}

const SLIDER_CRANK_CASES: [[f64; 3]; 4] = [
    [500.0, 0.0, 0.0],
    [0.0, 500.0, 0.0],
    [-300.0, 400.0, 0.0],
    [250.0, -250.0, 0.0],
];

#[test]
fn single_bushing_matches_the_independent_solution() {
    let (model, tip) = single_bushing();
    let cases = [
        load(tip, [100.0, 200.0, -300.0], [1000.0, -2000.0, 500.0]),
        load(tip, [-400.0, 50.0, 250.0], [-3000.0, 1500.0, 2500.0]),
        load(tip, [0.0, 0.0, 1000.0], [0.0; 3]),
    ];
    check_against(&model, "single_bushing", &cases, false);
}

/// Small loads: deformation t = F/k and angle = T/kt with the bushing at the tip's
/// load transported to the bushing origin (linear prediction).
#[test]
fn single_bushing_small_loads_follow_the_linear_prediction() {
    let (model, tip) = single_bushing();
    let problem = Problem::new(&model).expect("problem");
    // Rotations couple the axes at second order: at these loads the angles are
    // ~1e-6 rad, so the linear prediction holds to about 1e-6 relative.
    let (f, t) = (Vec3::new(1e-3, -2e-3, 5e-4), Vec3::new(0.03, -0.01, 0.02));
    let eq = statics::solve(
        &problem,
        &load(tip, f.into(), t.into()),
        &State::design(&model),
    )
    .expect("solve");
    let rep = case_report(&model, "c", 1, &eq);
    let b = &rep.bushings["b"];
    // The arm carries J; the bushing pulls J towards I: J moves by F/k, so t = -F/k.
    let m_origin = t + Vec3::new(300.0, 0.0, 0.0).cross(&f);
    for k in 0..3 {
        let t_lin = -f[k] / 1e4;
        let a_lin = -m_origin[k] / 1e4; // deg, since kt is per degree
        assert!(
            (b.deformation[k] - t_lin).abs() < 1e-5 * t_lin.abs(),
            "t{k} {} vs {t_lin}",
            b.deformation[k]
        );
        assert!(
            (b.deformation[k + 3] - a_lin).abs() < 1e-5 * a_lin.abs(),
            "a{k} {} vs {a_lin}",
            b.deformation[k + 3]
        );
    }
}

#[test]
fn four_bar_matches_the_independent_solution() {
    let (model, mid) = four_bar();
    let cases: Vec<_> = FOUR_BAR_CASES
        .iter()
        .map(|(f, t)| load(mid, *f, *t))
        .collect();
    check_against(&model, "four_bar", &cases, true);
}

#[test]
fn slider_crank_matches_the_independent_solution() {
    let (model, pin) = slider_crank();
    let cases: Vec<_> = SLIDER_CRANK_CASES
        .iter()
        .map(|f| load(pin, *f, [0.0; 3]))
        .collect();
    check_against(&model, "slider_crank", &cases, false);
}

#[test]
fn slider_crank_redundancy_is_detected_and_named() {
    let (model, _) = slider_crank();
    let mob = statics::mobility(&model);
    assert_eq!(
        (mob.coordinates, mob.equations, mob.rank, mob.dof),
        (18, 18, 17, 1)
    );
    assert_eq!(mob.grubler, 0);
    assert_eq!(mob.redundant.len(), 1, "{:?}", mob.redundant);
    let r = &mob.redundant[0];
    let names: Vec<&str> = r
        .with
        .iter()
        .map(|j| model.joints[j.index()].name.as_str())
        .collect();
    // The planar loop: the rotations about z of crank, rod and slider are
    // over-determined by the three z-axis joints.
    eprintln!(
        "slider-crank: redundant {} of `{}`, with {names:?}",
        r.equation,
        model.joints[r.joint.index()].name
    );
    assert!(names.len() >= 2, "{names:?}");
    assert!(names.contains(&model.joints[r.joint.index()].name.as_str()));
    assert!(
        mob.unrestrained.is_empty() && mob.nearly_unrestrained.is_empty(),
        "{mob:?}"
    );
    let problem = Problem::new(&model).expect("problem");
    assert_eq!(problem.redundant.len(), 1);
}

#[test]
fn four_bar_counts_match_the_thesis() {
    let (model, _) = four_bar();
    let mob = statics::mobility(&model);
    assert_eq!((mob.coordinates, mob.equations, mob.dof), (18, 10, 8));
    assert!(mob.redundant.is_empty());
    assert!(mob.unrestrained.is_empty());
}

fn tie_rod_model() -> (Model, MarkerId) {
    let mut b = Builder::new("tie_rod");
    let g = b.part("chassis", true);
    let rod = b.part("tie_rod", false);
    let (p, q) = ([73.7, 353.4, 228.3], [135.3, 694.6, 207.4]);
    for (n, x) in [("L3", p), ("L6", q)] {
        let i = b.point(rod, n, x);
        let j = b.point(g, n, x);
        b.joint(n, JointKind::Spherical, i, j);
    }
    let mid = b.point(rod, "mid", [104.5, 524.0, 217.85]);
    (b.m, mid)
}

#[test]
fn tie_rod_with_two_ball_joints_spins_freely() {
    let (model, mid) = tie_rod_model();
    let mob = statics::mobility(&model);
    assert_eq!(mob.dof, 1);
    assert_eq!(mob.unrestrained.len(), 1, "{mob:?}");
    let m = &mob.unrestrained[0];
    assert_eq!(model.part(m.part).name, "tie_rod");
    assert!(m.rotation, "{}", m.words);
    let axis = (Vec3::new(135.3, 694.6, 207.4) - Vec3::new(73.7, 353.4, 228.3)).normalize();
    assert!(
        Vec3::from(m.axis).cross(&axis).norm() < 1e-9,
        "{:?}",
        m.axis
    );
    assert!(m.words.contains("tie_rod"), "{}", m.words);
    // The solver refuses too, naming the part.
    let problem = Problem::new(&model).expect("problem");
    let err = statics::solve(
        &problem,
        &load(mid, [0.0, 0.0, -100.0], [0.0; 3]),
        &State::design(&model),
    )
    .expect_err("singular");
    assert_eq!(err.kind, StaticsErrorKind::Unrestrained);
    assert_eq!(err.elements, vec![ElementId::Part(PartId(1))]);
}

#[test]
fn a_model_without_ground_is_an_error_not_a_panic() {
    let mut b = Builder::new("floating");
    b.part("a", false);
    let err = Problem::new(&b.m).expect_err("no ground");
    assert_eq!(err.kind, StaticsErrorKind::NoGround);
    let mob = statics::mobility(&b.m);
    assert_eq!(mob.unrestrained.len(), 6);
}

/// A planar loop of four revolutes is over-constrained in 3-D: 20 equations,
/// one mobility, so three equations are redundant, each naming loop joints.
#[test]
fn planar_four_bar_of_revolutes_has_three_redundant_equations() {
    let mut b = Builder::new("planar");
    let g = b.part("ground", true);
    let l1 = b.part("l1", false);
    let c = b.part("c", false);
    let l2 = b.part("l2", false);
    let ax = frame_from_z_x(Vec3::y(), Some(Vec3::x())).expect("frame");
    let pts = [
        (g, l1, [0.0, 0.0, 0.0]),
        (l1, c, [0.0, 0.0, 450.0]),
        (c, l2, [250.0, 0.0, 450.0]),
        (l2, g, [250.0, 0.0, 0.0]),
    ];
    for (k, (pi, pj, x)) in pts.into_iter().enumerate() {
        let i = b.marker(pi, "i", x, ax);
        let j = b.marker(pj, "j", x, ax);
        b.joint(&format!("r{k}"), JointKind::Revolute, i, j);
    }
    let mob = statics::mobility(&b.m);
    assert_eq!(
        (mob.equations, mob.rank, mob.dof, mob.grubler),
        (20, 17, 1, -2)
    );
    assert_eq!(mob.redundant.len(), 3, "{:?}", mob.redundant);
    for r in &mob.redundant {
        assert!(r.with.len() >= 2, "{r:?}");
    }
    // With a torsion spring-free loop the remaining mobility is unrestrained.
    assert_eq!(mob.unrestrained.len(), 1);
}
