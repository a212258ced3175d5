//! Joint primitives (`conventions.md`, "Joints") as scalar equations with
//! analytic gradients.
//!
//! The gradient of each equation with respect to the increments of parts I and J
//! is the generalised force of a "unit reaction" wrench; multiplied by λ it is the
//! joint's reaction, and its tangent is the λ-weighted second derivative the
//! Newton matrix needs. So one [`Wrench`] gives both.

use super::coords::{Layout, MarkerKin, State, marker_kin};
use super::wrench::{RhoMotion, V12, Wrench, generalized};
use crate::geom::{Vec3, skew, skew_times};
use crate::model::{JointId, Model, Primitive};

/// One scalar constraint equation of a joint.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Equation {
    pub joint: JointId,
    pub primitive: Primitive,
}

/// All equations of the model, joint by joint in declaration order.
pub fn equations(model: &Model) -> Vec<Equation> {
    let mut out = Vec::new();
    for (id, j) in model.active_joints() {
        for &p in j.kind.equations() {
            out.push(Equation {
                joint: id,
                primitive: p,
            });
        }
    }
    out
}

/// Whether the equation measures a length (mm) rather than a cosine.
pub fn is_length(p: Primitive) -> bool {
    !matches!(p, Primitive::Perpendicular(..))
}

/// The value of the equation and its unit reaction wrench (whose generalised
/// force is the gradient row).
pub fn evaluate(model: &Model, layout: &Layout, state: &State, eq: &Equation) -> (f64, Wrench) {
    let (mi, mj) = joint_markers(model, layout, state, eq.joint);
    evaluate_at(&mi, &mj, eq.primitive)
}

/// The current frames of a joint's I and J markers.
pub fn joint_markers(
    model: &Model,
    layout: &Layout,
    state: &State,
    joint: JointId,
) -> (MarkerKin, MarkerKin) {
    let joint = &model.joints[joint.index()];
    (
        marker_kin(model, layout, state, joint.i),
        marker_kin(model, layout, state, joint.j),
    )
}

/// [`evaluate`] with the joint's marker frames at hand (a joint's equations
/// share them).
pub fn evaluate_at(mi: &MarkerKin, mj: &MarkerKin, primitive: Primitive) -> (f64, Wrench) {
    let mut w = Wrench::new(None, None, Vec3::zeros(), Vec3::zeros());
    let (v, _) = evaluate_into(mi, mj, primitive, &mut w);
    (v, w)
}

/// [`evaluate_at`] into a wrench kept by the caller (refilled in place, see
/// [`Wrench::reset`]); returns the value of the equation and the wrench's
/// generalised force ([`Wrench::generalized`], the same bits).
///
/// Inlined into the evaluation's loop, which reads the wrench back at once
/// (called, the reads waited on the stores of the call's last fields). The
/// force is computed from the vectors at hand, not read back from the
/// wrench: `reset` stores an arm as 16 and 8 bytes, and the cross product's
/// 16-byte load of its last two entries waited on both stores (a tenth of
/// the evaluation loop's own time).
#[inline(always)]
pub fn evaluate_into(
    mi: &MarkerKin,
    mj: &MarkerKin,
    primitive: Primitive,
    w: &mut Wrench,
) -> (f64, V12) {
    let d = mi.p - mj.p;
    let zero = Vec3::zeros();
    match primitive {
        Primitive::Coincident(k) => {
            // (`Vec3::ith` stored the one over a zeroed vector on the stack
            // and read the vector back whole: a load waiting on a narrower
            // store, which stalls; a third of this function's time.)
            let e = match k.index() {
                0 => Vec3::x(),
                1 => Vec3::y(),
                _ => Vec3::z(),
            };
            w.reset(mi.block, mj.block, mi.r, mj.r);
            w.g = e;
            (d[k.index()], generalized(&e, &zero, &mi.r, &mj.r))
        }
        Primitive::InPlane(b) => {
            // The normal turns with J, and the reaction acts at p_I on both parts.
            let a: Vec3 = mj.axes.column(b.index()).into();
            let rho = mi.p - mj.x;
            w.reset(mi.block, mj.block, mi.r, rho);
            w.g = a;
            // d_axis_j(a) = [0, 0, 0, -a~].
            w.dg.set(3, -skew(&a));
            w.rho_motion = RhoMotion::PointOfI;
            (a.dot(&d), generalized(&a, &zero, &mi.r, &rho))
        }
        Primitive::Perpendicular(pa, pb) => {
            let a: Vec3 = mi.axes.column(pa.index()).into();
            let b: Vec3 = mj.axes.column(pb.index()).into();
            w.reset(mi.block, mj.block, mi.r, mj.r);
            let m = a.cross(&b);
            w.m = m;
            // d(a × b) = (theta_I × a) × b + a × (theta_J × b).
            w.dm.set(1, skew_times(&b, &skew(&a)));
            w.dm.set(3, skew_times(&-a, &skew(&b)));
            (a.dot(&b), generalized(&zero, &m, &mi.r, &mj.r))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::testkit::{random_state, twin_part_model};
    use super::*;
    use crate::model::JointKind;

    /// The gradient (generalised force of the unit wrench) equals a central
    /// difference of the value, and its tangent a central difference of the
    /// gradient, for every primitive at random poses.
    #[test]
    fn gradients_and_second_derivatives_match_finite_differences() {
        for seed in 0..4u64 {
            for kind in JointKind::ALL {
                for ground_j in [false, true] {
                    let model = twin_part_model(kind, ground_j, seed);
                    let layout = Layout::new(&model);
                    let state = random_state(&model, seed + 11);
                    for eq in equations(&model) {
                        let (value, w) = evaluate(&model, &layout, &state, &eq);
                        // The force `evaluate_into` returns is the wrench's
                        // own, to the bit (the assembly takes it instead),
                        // also into a wrench that held another equation's.
                        let (mi, mj) = joint_markers(&model, &layout, &state, eq.joint);
                        let mut kept = Wrench::new(Some(0), None, Vec3::x(), Vec3::y());
                        kept.m = Vec3::z();
                        let (v, force) = evaluate_into(&mi, &mj, eq.primitive, &mut kept);
                        assert_eq!(v.to_bits(), value.to_bits());
                        for (a, b) in force.iter().zip(w.generalized().iter()) {
                            assert_eq!(a.to_bits(), b.to_bits(), "{kind:?} {:?}", eq.primitive);
                        }
                        let mut grad = nalgebra::DVector::zeros(layout.n());
                        w.add_force(&mut grad);
                        let mut hess = nalgebra::DMatrix::zeros(layout.n(), layout.n());
                        w.add_tangent(&mut hess);
                        let h = 1e-6;
                        for c in 0..layout.n() {
                            let f = |s: f64| {
                                let mut st = state.clone();
                                let mut dq = nalgebra::DVector::zeros(layout.n());
                                dq[c] = s;
                                st.apply(&layout, &dq);
                                let (v, w) = evaluate(&model, &layout, &st, &eq);
                                let mut g = nalgebra::DVector::zeros(layout.n());
                                w.add_force(&mut g);
                                (v, g)
                            };
                            let (vp, gp) = f(h);
                            let (vm, gm) = f(-h);
                            let fd = (vp - vm) / (2.0 * h);
                            assert!(
                                (fd - grad[c]).abs() < 1e-6 * (1.0 + fd.abs()),
                                "{kind:?} {eq:?} col {c}: {fd} vs {}",
                                grad[c]
                            );
                            let fdg = (gp - gm) / (2.0 * h);
                            for r in 0..layout.n() {
                                let e = (fdg[r] - hess[(r, c)]).abs();
                                assert!(
                                    e < 1e-5 * (1.0 + fdg[r].abs()),
                                    "{kind:?} {eq:?} ({r},{c}): {} vs {}",
                                    fdg[r],
                                    hess[(r, c)]
                                );
                            }
                        }
                    }
                }
            }
        }
    }
}
