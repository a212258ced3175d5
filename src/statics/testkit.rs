//! Small random models and states for the finite-difference unit tests.

use super::coords::{State, rodrigues};
use super::pattern::Pattern;
use crate::geom::{Mat3, Vec3};
use crate::model::*;

/// A deterministic pseudo-random sequence in [-1, 1) (no extra dependency).
pub struct Lcg(u64);

impl Lcg {
    pub fn new(seed: u64) -> Lcg {
        Lcg(seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407))
    }
    pub fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((self.0 >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    }
    pub fn vec(&mut self, s: f64) -> Vec3 {
        Vec3::new(self.next() * s, self.next() * s, self.next() * s)
    }
}

fn marker(model: &mut Model, part: usize, name: &str, rng: &mut Lcg) -> MarkerId {
    let p = rng.vec(150.0);
    let rot: Mat3 = rodrigues(&rng.vec(1.5));
    model.markers.push(Marker {
        name: name.to_string(),
        part: PartId(part as u32),
        position: vals([p.x, p.y, p.z]),
        orientation: Orientation::Identity,
        rotation: rot,
    });
    MarkerId(model.markers.len() as u32 - 1)
}

fn parts(model: &mut Model) {
    for (n, g) in [("ground", true), ("a", false), ("b", false)] {
        model.parts.push(Part {
            name: n.to_string(),
            ground: g,
        });
    }
}

/// Parts `ground`, `a`, `b`; one joint of `kind` with I on `a` and J on `b`
/// (or on ground), at random markers.
pub fn twin_part_model(kind: JointKind, ground_j: bool, seed: u64) -> Model {
    let mut rng = Lcg::new(seed);
    let mut m = Model::default();
    parts(&mut m);
    let i = marker(&mut m, 1, "i", &mut rng);
    let j = marker(&mut m, if ground_j { 0 } else { 2 }, "j", &mut rng);
    m.joints.push(Joint {
        name: "jt".into(),
        kind,
        i,
        j,
    });
    m
}

/// Parts `ground`, `a`, `b` with a nonlinear bushing (offsets, preloads), a
/// linear and a tabulated spring, and both kinds of stop between `a` and `b`
/// (or `a` and ground), all at random markers.
pub fn force_model(ground_j: bool, seed: u64) -> Model {
    let mut rng = Lcg::new(seed);
    let mut m = Model::default();
    parts(&mut m);
    let jp = if ground_j { 0 } else { 2 };
    let bi = marker(&mut m, 1, "bi", &mut rng);
    let bj = marker(&mut m, jp, "bj", &mut rng);
    let mut b = Bushing::linear("b", bi, bj, [300.0, 2000.0, 900.0], [4e5, 2e5, 7e5]);
    *b.translational.get_mut(1) = AxisLaw::Linear {
        k: Val::lit(500.0),
        k3: Val::lit(3.0),
    };
    *b.rotational.get_mut(2) = AxisLaw::Table(Table {
        points: vec![(-1.0, -9e5), (0.0, 0.0), (0.2, 1e5), (1.0, 9e5)],
    });
    b.offset = vals([0.5, -0.2, 0.1]);
    b.angle_offset = vals([0.01, -0.02, 0.03]);
    b.preload = vals([10.0, -20.0, 5.0]);
    b.torque_preload = vals([100.0, 0.0, -300.0]);
    m.bushings.push(b);
    for (n, law) in [
        (
            "s_lin",
            SpringLaw::Linear {
                k: Val::lit(30.0),
                free_length: Val::lit(290.0),
                preload: Val::lit(12.0),
            },
        ),
        (
            "s_tab",
            SpringLaw::Table(Table {
                points: vec![(0.0, 5000.0), (200.0, 1000.0), (500.0, -200.0)],
            }),
        ),
    ] {
        let i = marker(&mut m, 1, n, &mut rng);
        let j = marker(&mut m, jp, n, &mut rng);
        m.springs.push(Spring {
            name: n.into(),
            i,
            j,
            law,
        });
    }
    for (n, kind) in [
        ("bump", StopKind::Compression),
        ("rebound", StopKind::Rebound),
    ] {
        let i = marker(&mut m, 1, n, &mut rng);
        let j = marker(&mut m, jp, n, &mut rng);
        let l = (m.marker(i).origin() - m.marker(j).origin()).norm();
        m.stops.push(Stop {
            name: n.into(),
            kind,
            i,
            j,
            // Put the contact length so that random states probe both sides.
            contact_length: Val::lit(l),
            law: StopLaw::Polynomial(vec![Val::lit(100.0), Val::lit(5.0)]),
        });
    }
    m
}

/// Random poses of the moving parts (translations up to 20 mm, rotations up to ~0.5 rad).
pub fn random_state(model: &Model, seed: u64) -> State {
    let mut rng = Lcg::new(seed);
    let mut s = State::design(model);
    for (k, p) in model.parts.iter().enumerate() {
        if !p.ground {
            s.poses[k] = (rng.vec(20.0), rodrigues(&rng.vec(0.3)));
        }
    }
    s
}

/// The McPherson example, checked.
pub fn mcpherson() -> Model {
    let (_, c) = crate::check::check_str(
        "mcpherson.axle",
        include_str!("../../examples/mcpherson.axle"),
    );
    c.model.expect("the example checks")
}

/// `state` moved by `s` along coordinate `c` of `layout`.
pub fn perturbed(layout: &super::coords::Layout, state: &State, c: usize, s: f64) -> State {
    let mut st = state.clone();
    let mut dq = nalgebra::DVector::zeros(layout.n());
    dq[c] = s;
    st.apply(layout, &dq);
    st
}

/// Asserts that `k` is the tangent of the generalised force `q` at `st`:
/// each column against a central difference (step 1e-6 in the layout's
/// coordinates) to 1e-6 of one plus the column's largest entry. `context`
/// opens a failure's message.
pub fn assert_tangent_by_central_differences(
    layout: &super::coords::Layout,
    st: &State,
    k: &nalgebra::DMatrix<f64>,
    q: impl Fn(&State) -> nalgebra::DVector<f64>,
    context: &str,
) {
    let h = 1e-6;
    for c in 0..layout.n() {
        let fd = (q(&perturbed(layout, st, c, h)) - q(&perturbed(layout, st, c, -h))) / (2.0 * h);
        let scale = 1.0 + k.column(c).amax();
        for r in 0..layout.n() {
            assert!(
                (fd[r] - k[(r, c)]).abs() < 1e-6 * scale,
                "{context} ({r},{c}): fd {} vs {}",
                fd[r],
                k[(r, c)]
            );
        }
    }
}

/// Asserts that two solves of the same case reached the same equilibrium,
/// up to where each may have stopped (`stopping_error`): every part's
/// reference point within the sum of their distance bounds, its rotation
/// within the sum of their angle bounds (`‖R_a - R_b‖` is at most √2 times
/// the angle between them). `case` names the case in a failure.
pub fn assert_same_equilibrium(
    p: &super::Problem,
    a: &super::Equilibrium,
    b: &super::Equilibrium,
    case: usize,
) {
    let sa = super::stopping_error(p, a).expect("a bound");
    let sb = super::stopping_error(p, b).expect("a bound");
    for (x, y) in sa.iter().zip(&sb) {
        let ((ta, ra), (tb, rb)) = (a.state.part_pose(x.part), b.state.part_pose(x.part));
        // (The distances are the reference points'.)
        let c = p.layout.reference[x.part.index()];
        let (ta, tb) = (ta + ra * c, tb + rb * c);
        assert!(
            (ta - tb).norm() <= x.distance + y.distance,
            "case {case}: {ta} {tb}"
        );
        assert!(
            (ra - rb).norm() <= 2f64.sqrt() * (x.angle + y.angle),
            "case {case}"
        );
    }
}

/// `n` copies of the McPherson example's corner on its one ground, corner
/// `k`'s front arm held to corner `k + 1`'s by a soft bushing (100 N/mm,
/// 1e5 N·mm/rad), with table 5-1 at every wheel (the coupled-corners bench
/// of `benches/statics.rs`, smaller): one mechanism, no independent blocks.
pub fn coupled_corners(n: usize) -> (Model, LoadSetId) {
    let base = mcpherson();
    let set = base.load_set_named("thesis_table_5_1").expect("stdlib set");
    let ground = base.ground().expect("ground");
    let mut m = base.clone();
    let per = base.markers.len();
    for k in 1..n {
        let parts: Vec<PartId> = base
            .parts
            .iter()
            .map(|p| {
                if p.ground {
                    return ground;
                }
                let mut q = p.clone();
                q.name = format!("{}_{k}", p.name);
                m.parts.push(q);
                PartId(m.parts.len() as u32 - 1)
            })
            .collect();
        let off = (k * per) as u32;
        for mk in &base.markers {
            let mut c = mk.clone();
            c.name = format!("{}_{k}", mk.name);
            c.part = parts[mk.part.index()];
            m.markers.push(c);
        }
        let mid = |id: MarkerId| MarkerId(id.0 + off);
        for j in &base.joints {
            let mut c = j.clone();
            (c.name, c.i, c.j) = (format!("{}_{k}", j.name), mid(j.i), mid(j.j));
            m.joints.push(c);
        }
        for b in &base.bushings {
            let mut c = b.clone();
            (c.name, c.i, c.j) = (format!("{}_{k}", b.name), mid(b.i), mid(b.j));
            m.bushings.push(c);
        }
        for s in &base.springs {
            let mut c = s.clone();
            (c.name, c.i, c.j) = (format!("{}_{k}", s.name), mid(s.i), mid(s.j));
            m.springs.push(c);
        }
        for w in &base.wheels {
            let mut c = w.clone();
            (c.name, c.part, c.centre, c.contact) = (
                format!("{}_{k}", w.name),
                parts[w.part.index()],
                mid(w.centre),
                mid(w.contact),
            );
            m.wheels.push(c);
        }
    }
    let arm = base.part_named("front_arm").expect("part");
    let b = base
        .markers
        .iter()
        .position(|mk| mk.part == arm && mk.name == "B")
        .expect("front_arm.B");
    let soft = |k: f64| AxisLaws::from_three([0; 3].map(|_| AxisLaw::linear(k)), false);
    for k in 0..n.saturating_sub(1) {
        let mut c = base.bushings[0].clone();
        c.name = format!("link_{k}");
        c.i = MarkerId((k * per + b) as u32);
        c.j = MarkerId(((k + 1) * per + b) as u32);
        c.translational = soft(100.0);
        c.rotational = soft(1e5);
        m.bushings.push(c);
    }
    let src = &base.load_sets[set.index()];
    let channels: Vec<Channel> = (0..m.wheels.len())
        .flat_map(|w| {
            src.channels.iter().map(move |c| Channel {
                target: LoadTarget::Wheel(WheelId(w as u32)),
                component: c.component,
            })
        })
        .collect();
    let mut cases = src.cases.clone();
    for c in &mut cases {
        c.values = c.values.repeat(m.wheels.len());
    }
    m.load_sets = vec![LoadSet {
        name: "corners".into(),
        channels,
        cases,
        form: src.form.clone(),
    }];
    (m, LoadSetId(0))
}

/// Random values in a Newton matrix pattern's slots (a KKT matrix: the
/// pattern has no multiplier-multiplier slots), `K`'s diagonal (the first
/// `n` unknowns) made dominant enough to be regular, and the values under
/// `zero_below` in magnitude exact zeros (as a real matrix's structural
/// zeros are; 0: none).
pub(crate) fn kkt_values(pat: &Pattern, n: usize, rng: &mut Lcg, zero_below: f64) -> Vec<f64> {
    let mut v: Vec<f64> = (0..pat.nnz())
        .map(|_| {
            let x = rng.next();
            if x.abs() < zero_below { 0.0 } else { x }
        })
        .collect();
    for j in 0..n {
        if let Some(s) = pat.slot(j, j) {
            v[s] += 4.0;
        }
    }
    v
}

/// A load at the McPherson's wheel contact point.
pub fn wheel_load(m: &Model, fx: f64, fy: f64, fz: f64) -> Vec<PointLoad> {
    vec![PointLoad {
        marker: m.wheels[0].contact,
        force: Vec3::new(fx, fy, fz),
        torque: Vec3::zeros(),
    }]
}

/// 30 McPherson cases of a random walk of the wheel load (`Lcg(12)`):
/// steps of up to 1 500 N, `fx`, `fy` within ±2 500 N, `fz` 2 000-7 000 N.
pub fn random_walk(m: &Model) -> Vec<Vec<PointLoad>> {
    let mut rng = Lcg::new(12);
    let mut f = Vec3::new(0.0, 0.0, 4000.0);
    let mut loads = Vec::new();
    for _ in 0..30 {
        let step = rng.vec(1.0);
        f += step * (1500.0 / step.norm().max(1.0)) * (0.6 + 0.4 * rng.next());
        f = Vec3::new(
            f.x.clamp(-2500.0, 2500.0),
            f.y.clamp(-2500.0, 2500.0),
            f.z.clamp(2000.0, 7000.0),
        );
        loads.push(wheel_load(m, f.x, f.y, f.z));
    }
    loads
}
