//! Dry friction on a joint (`conventions.md`, "Friction"): an elasto-plastic
//! slider, a stick stiffness `kf` in series with a Coulomb limit `Ff`, on the
//! slide `s = (p_I - p_J) · z_J` of the joint or on its rotation about `z_J`.
//!
//! The slip offset `s_p` is history: a trial pose is evaluated against the
//! offset of the last accepted step (a return map, backward Euler on the
//! slip), and [`commit`] moves the offset only once Newton has converged on a
//! step or load sub-step. Within one Newton solve the element is therefore a
//! piecewise-linear spring (stick: `-kf`, slip: constant force), which keeps
//! the equilibrium a function of the pose and Newton's tangent exact.

use super::coords::{Layout, MarkerKin, State, marker_kin};
use super::forces::angle_rates;
use super::wrench::{Blocks, M3x12, RhoMotion, Wrench, blocks, d_axis_j, d_point_i, d_point_j};
use crate::geom::{Mat3, Vec3, skew};
use crate::model::{Friction, FrictionId, FrictionMotion, Marker, Model};

const ZERO: Mat3 = Mat3::new(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0);

/// Stick or slip, as the return map decided it for one trial.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FrictionState {
    Stick,
    Slip,
}

impl FrictionState {
    pub fn word(self) -> &'static str {
        match self {
            FrictionState::Stick => "stick",
            FrictionState::Slip => "slip",
        }
    }
}

/// A friction element at one trial state.
#[derive(Debug, Clone)]
pub struct FrictionEval {
    /// The slide (mm) or the rotation angle about `z_J` (rad).
    pub coordinate: f64,
    /// Force on I along `z_J` (N), or torque on I about `z_J` (N·mm).
    pub force: f64,
    /// The slip offset this trial would commit (mm or rad): the committed one
    /// while sticking, `s + f / kf` while slipping.
    pub slip_offset: f64,
    pub state: FrictionState,
    /// Trial force `-kf (s - s_p)` over the limit (above 1: slipping).
    pub utilisation: f64,
    pub wrench: Wrench,
}

/// The return map of `conventions.md`: force, its derivative by the
/// coordinate, the slip offset it leaves, and stick or slip.
pub fn law(kf: f64, limit: f64, s: f64, sp: f64) -> (f64, f64, f64, FrictionState) {
    let trial = -kf * (s - sp);
    // A zero stiffness is rejected by the checker; it transmits nothing.
    if kf.is_nan() || kf <= 0.0 || trial.abs() <= limit {
        return (trial, -kf.max(0.0), sp, FrictionState::Stick);
    }
    let f = limit.copysign(trial);
    (f, 0.0, s + f / kf, FrictionState::Slip)
}

/// Slide along `z_J` (mm) between two marker frames.
fn slide_of(pi: &Vec3, pj: &Vec3, rj: &Mat3) -> f64 {
    (pi - pj).dot(&rj.column(2).into_owned())
}

/// Rotation of I relative to J about `z_J` (rad): the projected angle `az`
/// of `R_J^T R_I`, as a bushing's AZ (unwrapped within ±180°).
fn angle_of(ri: &Mat3, rj: &Mat3) -> f64 {
    let q = rj.transpose() * ri;
    q[(1, 0)].atan2(q[(0, 0)])
}

fn design_coordinate(mi: &Marker, mj: &Marker, motion: FrictionMotion) -> f64 {
    match motion {
        FrictionMotion::Slide => slide_of(&mi.origin(), &mj.origin(), &mj.rotation),
        FrictionMotion::Rotation => angle_of(&mi.rotation, &mj.rotation),
    }
}

/// The slip offsets at the design configuration: `s_p = s`, no force.
pub fn design_slip(model: &Model) -> Vec<f64> {
    model
        .frictions
        .iter()
        .map(|f| match model.joints.get(f.joint.index()) {
            Some(j) => design_coordinate(model.marker(j.i), model.marker(j.j), f.motion),
            None => 0.0,
        })
        .collect()
}

fn kin(model: &Model, layout: &Layout, state: &State, f: &Friction) -> (MarkerKin, MarkerKin) {
    let j = &model.joints[f.joint.index()];
    (
        marker_kin(model, layout, state, j.i),
        marker_kin(model, layout, state, j.j),
    )
}

/// The friction element `id` at `state`, against the state's committed slip offset.
pub fn evaluate(model: &Model, layout: &Layout, state: &State, id: FrictionId) -> FrictionEval {
    let f = &model.frictions[id.index()];
    let (mi, mj) = kin(model, layout, state, f);
    let sp = state.slip_offset(model, id);
    let (kf, limit) = (f.stiffness.value, f.limit.value);
    let z: Vec3 = mj.axes.column(2).into_owned();
    // The rate of `z_J` with J's rotation increment, `dz = theta_J × z`.
    let dz = d_axis_j(&z);
    let (coordinate, rate, mut w) = match f.motion {
        FrictionMotion::Slide => {
            let d = mi.p - mj.p;
            // ds = z · (dp_I - dp_J) + d · dz.
            let ds: nalgebra::RowSVector<f64, 12> =
                z.transpose() * (d_point_i(&mi.r) - d_point_j(&mj.r)) + d.transpose() * dz;
            // The force acts at p_I on both parts, as a bushing's.
            let rho = mi.p - mj.x;
            let mut w = Wrench::new(mi.block, mj.block, mi.r, rho);
            w.rho_motion = RhoMotion::PointOfI;
            (d.dot(&z), ds, w)
        }
        FrictionMotion::Rotation => {
            let q = mj.axes.transpose() * mi.axes;
            let da: M3x12 = angle_rates(&q)
                * mj.axes.transpose()
                * blocks([ZERO, Mat3::identity(), ZERO, -Mat3::identity()]);
            let w = Wrench::new(mi.block, mj.block, mi.r, mj.r);
            (q[(1, 0)].atan2(q[(0, 0)]), da.row(2).into_owned(), w)
        }
    };
    let (force, dforce, slip_offset, st) = law(kf, limit, coordinate, sp);
    let turn_j = blocks([ZERO, ZERO, ZERO, Mat3::identity()]);
    match f.motion {
        FrictionMotion::Slide => {
            w.g = z * force;
            w.dg = Blocks::of_matrix(&(z * (rate * dforce) + dz * force));
        }
        FrictionMotion::Rotation => {
            w.m = z * force;
            w.dm = Blocks::of_matrix(&(-skew(&w.m) * turn_j + z * (rate * dforce)));
        }
    }
    let utilisation = if limit > 0.0 {
        (kf * (coordinate - sp)).abs() / limit
    } else if kf * (coordinate - sp) != 0.0 {
        f64::INFINITY
    } else {
        0.0
    };
    FrictionEval {
        coordinate,
        force,
        slip_offset,
        state: st,
        utilisation,
        wrench: w,
    }
}

/// Commits the slip of every friction element at an accepted (converged)
/// state: the one call a load step or sub-step makes once it is accepted.
/// The force is unchanged by it (a slipping element moves its offset to where
/// the limit force is exactly `-kf (s - s_p)`), so the state stays in equilibrium.
pub fn commit(model: &Model, layout: &Layout, state: &mut State) {
    if model.frictions.is_empty() {
        return;
    }
    if state.slip.len() != model.frictions.len() {
        state.slip = design_slip(model);
    }
    for (k, f) in model.frictions.iter().enumerate() {
        let (mi, mj) = kin(model, layout, state, f);
        let s = match f.motion {
            FrictionMotion::Slide => slide_of(&mi.p, &mj.p, &mj.axes),
            FrictionMotion::Rotation => angle_of(&mi.axes, &mj.axes),
        };
        let (.., sp, _) = law(f.stiffness.value, f.limit.value, s, state.slip[k]);
        state.slip[k] = sp;
    }
}

/// Stick or slip at a committed state, from its force: a step that slipped
/// leaves the force at the limit (to rounding), a sticking one inside it.
pub fn committed_state(f: &Friction, force: f64) -> FrictionState {
    if force.abs() >= f.limit.value * (1.0 - 1e-9) {
        FrictionState::Slip
    } else {
        FrictionState::Stick
    }
}

/// The friction elements at or beyond their limit at a (failed) trial state:
/// the ones a step that would not converge names.
pub fn near_limit(model: &Model, layout: &Layout, state: &State) -> Vec<FrictionId> {
    (0..model.frictions.len())
        .map(|k| FrictionId(k as u32))
        .filter(|&id| evaluate(model, layout, state, id).utilisation >= 0.9)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::super::testkit::{
        assert_tangent_by_central_differences, random_state, twin_part_model,
    };
    use super::*;
    use crate::model::{JointKind, Val};
    use nalgebra::{DMatrix, DVector};

    fn with_friction(
        kind: JointKind,
        motion: FrictionMotion,
        ground_j: bool,
        seed: u64,
        limit: f64,
    ) -> Model {
        let mut m = twin_part_model(kind, ground_j, seed);
        m.frictions.push(Friction {
            name: "fr".into(),
            joint: crate::model::JointId(0),
            motion,
            stiffness: Val::lit(if motion == FrictionMotion::Slide {
                1000.0
            } else {
                3e6
            }),
            limit: Val::lit(limit),
        });
        m
    }

    fn generalized(
        m: &Model,
        layout: &Layout,
        st: &State,
    ) -> (DVector<f64>, DMatrix<f64>, FrictionEval) {
        let e = evaluate(m, layout, st, FrictionId(0));
        let mut q = DVector::zeros(layout.n());
        let mut k = DMatrix::zeros(layout.n(), layout.n());
        e.wrench.add_force(&mut q);
        e.wrench.add_tangent(&mut k);
        (q, k, e)
    }

    /// The analytic tangent of the friction's generalised force equals a
    /// central difference, sticking (limit out of reach) and slipping (limit
    /// far below the trial force), for the slide and the rotation, with both
    /// parts moving and with J on ground.
    #[test]
    fn tangent_matches_finite_differences_in_stick_and_slip() {
        let cases = [
            (JointKind::Cylindrical, FrictionMotion::Slide),
            (JointKind::Revolute, FrictionMotion::Rotation),
        ];
        for (kind, motion) in cases {
            for (limit, want) in [(1e12, FrictionState::Stick), (1e-3, FrictionState::Slip)] {
                for seed in 0..4u64 {
                    let m = with_friction(kind, motion, seed % 2 == 1, seed, limit);
                    let layout = Layout::new(&m);
                    let st = random_state(&m, 40 + seed);
                    let (_, k, e) = generalized(&m, &layout, &st);
                    assert_eq!(e.state, want, "{motion:?} seed {seed}");
                    assert!(e.force.abs() > 1e-4, "the probe must load the element");
                    assert_tangent_by_central_differences(
                        &layout,
                        &st,
                        &k,
                        |s| generalized(&m, &layout, s).0,
                        &format!("{motion:?} {want:?} seed {seed}"),
                    );
                }
            }
        }
    }

    /// The return map of `conventions.md` on numbers worked by hand
    /// (kf = 1000 N/mm, Ff = 150 N, committed s_p = 2 mm).
    #[test]
    fn return_map_sticks_inside_the_limit_and_slips_outside() {
        // s = 2.1: trial -100 N, inside: stick with tangent -kf.
        assert_eq!(
            law(1000.0, 150.0, 2.1, 2.0),
            (-100.00000000000009, -1000.0, 2.0, FrictionState::Stick)
        );
        // s = 2.5: trial -500 N, beyond: f = -150, s_p = 2.5 - 0.15 = 2.35.
        let (f, df, sp, st) = law(1000.0, 150.0, 2.5, 2.0);
        assert_eq!((f, df, st), (-150.0, 0.0, FrictionState::Slip));
        assert!((sp - 2.35).abs() < 1e-15);
        // s = 1.0: trial +1000 N: f = +150, s_p = 1.15.
        let (f, _, sp, _) = law(1000.0, 150.0, 1.0, 2.0);
        assert_eq!(f, 150.0);
        assert!((sp - 1.15).abs() < 1e-15);
    }

    /// Committing keeps the force (the offset moves to where the limit force is
    /// exactly `-kf (s - s_p)`), and the design offset gives no force.
    #[test]
    fn commit_keeps_the_force_and_design_has_none() {
        for seed in 0..4u64 {
            let m = with_friction(
                JointKind::Cylindrical,
                FrictionMotion::Slide,
                false,
                seed,
                50.0,
            );
            let layout = Layout::new(&m);
            let design = State::design(&m);
            assert!(evaluate(&m, &layout, &design, FrictionId(0)).force.abs() < 1e-9);
            let mut st = random_state(&m, 90 + seed);
            let before = evaluate(&m, &layout, &st, FrictionId(0));
            commit(&m, &layout, &mut st);
            let after = evaluate(&m, &layout, &st, FrictionId(0));
            assert!((after.force - before.force).abs() < 1e-9);
            assert_eq!(st.slip[0], before.slip_offset);
        }
    }

    /// The analytic slider: a part on a translational joint along z between
    /// a spring (k = 10 N/mm) and friction (kf = 1000 N/mm, Ff = 150 N) on the
    /// joint, loaded up to +1000 N, down to -1000 N and back. Once slipping,
    /// `x = (F ∓ Ff) / k` exactly: the loading and unloading branches are
    /// `2 Ff / k = 30 mm` apart, and a case solved alone from design lies on
    /// the loading branch.
    #[test]
    fn slider_loop_is_two_ff_over_k_wide() {
        use crate::model::{
            Joint, JointId, MarkerId, Orientation, Part, PartId, PointLoad, Spring, SpringLaw, vals,
        };
        use crate::statics::{Problem, solve};
        let mut m = Model::default();
        for (name, ground) in [("ground", true), ("slider", false)] {
            m.parts.push(Part {
                name: name.into(),
                ground,
            });
        }
        for (name, part, z) in [
            ("i", 1, 0.0),
            ("j", 0, 0.0),
            ("top", 1, 0.0),
            ("base", 0, -200.0),
        ] {
            m.markers.push(Marker {
                name: name.into(),
                part: PartId(part),
                position: vals([0.0, 0.0, z]),
                orientation: Orientation::Identity,
                rotation: Mat3::identity(),
            });
        }
        m.joints.push(Joint {
            name: "slide".into(),
            kind: JointKind::Translational,
            i: MarkerId(0),
            j: MarkerId(1),
        });
        m.springs.push(Spring {
            name: "s".into(),
            i: MarkerId(2),
            j: MarkerId(3),
            law: SpringLaw::Linear {
                k: Val::lit(10.0),
                free_length: Val::lit(200.0),
                preload: Val::lit(0.0),
            },
        });
        m.frictions.push(Friction {
            name: "fr".into(),
            joint: JointId(0),
            motion: FrictionMotion::Slide,
            stiffness: Val::lit(1000.0),
            limit: Val::lit(150.0),
        });
        let p = Problem::new(&m).expect("grounded");
        let load = |fz: f64| {
            [PointLoad {
                marker: MarkerId(0),
                force: Vec3::new(0.0, 0.0, fz),
                torque: Vec3::zeros(),
            }]
        };
        let x = |st: &State| st.part_pose(PartId(1)).0.z;
        // 0 -> 1000 -> -1000 -> 1000 N in 100 N steps.
        let mut path: Vec<f64> = (0..=10).map(|k| 100.0 * k as f64).collect();
        path.extend((0..=20).map(|k| 1000.0 - 100.0 * k as f64));
        path.extend((0..=20).map(|k| -1000.0 + 100.0 * k as f64));
        let mut st = State::design(&m);
        let (mut up, mut down) = (Vec::new(), Vec::new());
        for (n, &fz) in path.iter().enumerate() {
            st = solve(&p, &load(fz), &st).expect("converges").state;
            let e = evaluate(&m, &Layout::new(&m), &st, FrictionId(0));
            // Equilibrium of the slider: F - k x + f = 0.
            assert!((fz - 10.0 * x(&st) + e.force).abs() < 1e-6, "step {n}");
            if fz == 500.0 {
                if !(11..=31).contains(&n) {
                    up.push(x(&st))
                } else {
                    down.push(x(&st))
                }
            }
        }
        // Loading: x = (500 - 150)/10 = 35 mm; unloading: (500 + 150)/10 = 65 mm.
        for u in &up {
            assert!((u - 35.0).abs() < 1e-8, "loading branch {u}");
        }
        assert!(
            (down[0] - 65.0).abs() < 1e-8,
            "unloading branch {}",
            down[0]
        );
        assert!((down[0] - up[0] - 2.0 * 150.0 / 10.0).abs() < 1e-8);
        // Alone from design, 500 N is a first loading: the loading branch.
        let alone = solve(&p, &load(500.0), &State::design(&m)).expect("converges");
        assert!((x(&alone.state) - 35.0).abs() < 1e-8);
    }
}
