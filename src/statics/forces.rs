//! Force elements as wrenches with analytic derivatives: bushings (linear,
//! cubic, tabulated, offsets, preloads; projected angles), springs (linear,
//! tabulated), stops (compression, rebound) and point loads (`conventions.md`);
//! friction elements are evaluated by [`super::friction`].

use super::coords::{Layout, MarkerKin, State, marker_kin, marker_kin_inlined};
use super::error::{StaticsError, StaticsErrorKind};
use super::wrench::{Blocks, RhoMotion, Wrench, d_point_i, d_point_j};
use crate::geom::{Mat3, Vec3, projected_angles, skew, times_skew};
use crate::model::{
    Bushing, BushingId, ElementId, FrictionId, Model, PointLoad, Spring, SpringId, SpringLaw, Stop,
    StopId, StopKind, values,
};

/// A bushing's state and its wrench (with the derivatives the Newton
/// matrix needs; [`bushing_state`] when only the state is read).
#[derive(Debug, Clone)]
pub struct BushingEval {
    pub state: BushingState,
    pub wrench: Wrench,
}

/// Rows `d(angle)/dw` of the projected angles for a relative rotation increment
/// `w` in J axes, with `dQ = w~ Q`. A row is zero where its atan2 is undefined.
pub(super) fn angle_rates(q: &Mat3) -> Mat3 {
    // d(column c of Q) = w × q_c = -q_c~ w; each angle is atan2(y, x) of two entries.
    let row = |c: usize, r: usize| -> nalgebra::RowVector3<f64> {
        let qc: Vec3 = q.column(c).into();
        (-skew(&qc)).row(r).into_owned()
    };
    let atan2_rate =
        |y: f64, dy: nalgebra::RowVector3<f64>, x: f64, dx: nalgebra::RowVector3<f64>| {
            let den = x * x + y * y;
            if den > 1e-300 {
                (dy * x - dx * y) / den
            } else {
                nalgebra::RowVector3::zeros()
            }
        };
    let ax = atan2_rate(-q[(1, 2)], -row(2, 1), q[(2, 2)], row(2, 2));
    let ay = atan2_rate(q[(0, 2)], row(2, 0), q[(2, 2)], row(2, 2));
    let az = atan2_rate(q[(1, 0)], row(0, 1), q[(0, 0)], row(0, 0));
    Mat3::from_rows(&[ax, ay, az])
}

/// `t`, the relative rotation `Q = R_J^T R_I` and its projected angles.
fn deformation(mi: &MarkerKin, mj: &MarkerKin) -> (Vec3, Mat3, Vec3) {
    let rj = mj.axes;
    let t = rj.transpose() * (mi.p - mj.p);
    let q = rj.transpose() * mi.axes;
    (t, q, projected_angles(&q))
}

/// A bushing's state without its wrench's derivatives (for reports and
/// warnings): the same deformation, force and torque as [`bushing`]'s.
pub fn bushing_state(model: &Model, layout: &Layout, state: &State, b: &Bushing) -> BushingState {
    let mi = marker_kin(model, layout, state, b.i);
    let mj = marker_kin(model, layout, state, b.j);
    let (t, _, angles) = deformation(&mi, &mj);
    let (force, torque, _, _) = laws(b, &t, &angles);
    BushingState {
        t,
        angles,
        force,
        torque,
    }
}

/// A bushing's deformation, force and torque on I (J axes).
#[derive(Debug, Clone, Copy)]
pub struct BushingState {
    /// Translational deformation `t = R_J^T (p_I - p_J)`, mm.
    pub t: Vec3,
    /// Projected angles `(ax, ay, az)`, rad.
    pub angles: Vec3,
    /// Force on I, J axes, N.
    pub force: Vec3,
    /// Torque on I, J axes, N·mm.
    pub torque: Vec3,
}

/// Force and torque on I (J axes) of a bushing deformed by `t` and
/// `angles`, and their stiffnesses (diagonal).
fn laws(b: &Bushing, t: &Vec3, angles: &Vec3) -> (Vec3, Vec3, Mat3, Mat3) {
    let (t0, a0) = (values(&b.offset), values(&b.angle_offset));
    let (f0, m0) = (values(&b.preload), values(&b.torque_preload));
    let mut force = Vec3::zeros();
    let mut torque = Vec3::zeros();
    let mut kt = Mat3::zeros();
    let mut ka = Mat3::zeros();
    for k in 0..3 {
        let (f, s) = b.translational[k].eval(t[k] - t0[k]);
        force[k] = -f + f0[k];
        kt[(k, k)] = s;
        let (f, s) = b.rotational[k].eval(angles[k] - a0[k]);
        torque[k] = -f + m0[k];
        ka[(k, k)] = s;
    }
    (force, torque, kt, ka)
}

/// `m d` for the diagonal matrix `d`: `m`'s columns scaled, the same bits
/// as the product but for the sign of a zero.
fn scale_columns(m: &Mat3, d: &Mat3) -> Mat3 {
    Mat3::from_columns(&[
        m.column(0) * d[(0, 0)],
        m.column(1) * d[(1, 1)],
        m.column(2) * d[(2, 2)],
    ])
}

pub fn bushing(model: &Model, layout: &Layout, state: &State, b: &Bushing) -> BushingEval {
    let mi = marker_kin_inlined(model, layout, state, b.i);
    let mj = marker_kin_inlined(model, layout, state, b.j);
    let rj = mj.axes;
    let (t, q, angles) = deformation(&mi, &mj);
    let (force, torque, kt, ka) = laws(b, &t, &angles);
    // The force acts at p_I on both parts; on J that point is at rho from J's origin.
    let rho = mi.p - mj.x;
    let mut w = Wrench::new(mi.block, mj.block, mi.r, rho);
    // drho = d_point_i(r_I) - [0, 0, I, 0] = [I, -r_I~, -I, 0].
    w.rho_motion = RhoMotion::PointOfI;
    w.g = rj * force;
    w.m = rj * torque;
    // Block by block (a product with a 3×12 matrix of identity and zero
    // blocks is mostly multiplications by 0 and 1; each block of the product
    // is the product with that block, so the values are the same):
    //   dt = R_J^T [I, -r_I~, -I, rho~],
    //   da = A R_J^T [0, I, 0, -I]  (A: the angles' rates),
    //   g = R_J F: R_J turns with theta_J, and F changes with t, so
    //   dg = [0, 0, 0, -g~] - R_J K_t dt, and likewise dm with K_a and da.
    let rt = rj.transpose();
    let ra = angle_rates(&q) * rt;
    // `K_t` and `K_a` are diagonal (one law an axis): `R_J K` scales R_J's
    // columns, the generic product's other terms being exact zeros.
    let (pt, pa) = (scale_columns(&rj, &kt), scale_columns(&rj, &ka));
    let dg0 = -(pt * rt);
    w.dg.set(0, dg0);
    w.dg.set(1, -(pt * times_skew(&rt, &-mi.r)));
    // dt's third block is minus its first: the same products, negated.
    w.dg.set(2, -dg0);
    w.dg.set(3, -skew(&w.g) - pt * times_skew(&rt, &rho));
    let pra = pa * ra;
    w.dm.set(1, -pra);
    w.dm.set(3, -skew(&w.m) + pra);
    BushingEval {
        state: BushingState {
            t,
            angles,
            force,
            torque,
        },
        wrench: w,
    }
}

/// A push-apart force `f(l)` along the I–J separation, with `df/dl`.
fn along(
    model: &Model,
    layout: &Layout,
    state: &State,
    i: crate::model::MarkerId,
    j: crate::model::MarkerId,
    law: impl Fn(f64) -> (f64, f64),
) -> Option<(f64, f64, Wrench)> {
    let mi = marker_kin(model, layout, state, i);
    let mj = marker_kin(model, layout, state, j);
    let d = mi.p - mj.p;
    let l = d.norm();
    // Zero length: no direction, so no force can be defined.
    if !(l > 1e-9) {
        return None;
    }
    let u = d / l;
    let (f, df) = law(l);
    let mut w = Wrench::new(mi.block, mj.block, mi.r, mj.r);
    w.g = u * f;
    let uu = u * u.transpose();
    let dd = d_point_i(&mi.r) - d_point_j(&mj.r);
    w.dg = Blocks::of_matrix(&((uu * df + (Mat3::identity() - uu) * (f / l)) * dd));
    Some((l, f, w))
}

/// Length (mm), push-apart force (N) and wrench of a spring.
pub fn spring(
    model: &Model,
    layout: &Layout,
    state: &State,
    id: SpringId,
    s: &Spring,
) -> Result<(f64, f64, Wrench), StaticsError> {
    along(model, layout, state, s.i, s.j, |l| match &s.law {
        SpringLaw::Linear {
            k,
            free_length,
            preload,
        } => (k.value * (free_length.value - l) + preload.value, -k.value),
        SpringLaw::Table(t) => t.eval(l),
    })
    .ok_or_else(|| degenerate(ElementId::Spring(id), "spring"))
}

/// Length (mm), push-apart force (N) and wrench of a stop (zero when not in contact).
pub fn stop(
    model: &Model,
    layout: &Layout,
    state: &State,
    id: StopId,
    s: &Stop,
) -> Result<(f64, f64, Wrench), StaticsError> {
    let lc = s.contact_length.value;
    along(model, layout, state, s.i, s.j, |l| match s.kind {
        StopKind::Compression if l < lc => {
            let (f, df) = s.law.eval(lc - l);
            (f, -df)
        }
        StopKind::Rebound if l > lc => {
            let (f, df) = s.law.eval(l - lc);
            (-f, -df)
        }
        _ => (0.0, 0.0),
    })
    .ok_or_else(|| degenerate(ElementId::Stop(id), "stop"))
}

fn degenerate(e: ElementId, what: &str) -> StaticsError {
    StaticsError::new(
        StaticsErrorKind::DegenerateElement,
        vec![e],
        format!("the {what}'s two markers coincide, so its line of action is undefined"),
    )
}

/// The wrench of a point load (global force and torque at a marker origin);
/// None when the marker is on ground (the load goes straight into the ground).
pub fn point_load(model: &Model, layout: &Layout, state: &State, l: &PointLoad) -> Option<Wrench> {
    let mut w = Wrench::new(None, None, Vec3::zeros(), Vec3::zeros());
    point_load_into(model, layout, state, l, &mut w).then_some(w)
}

/// [`point_load`] written into `w` (all of it); false, `w` unspecified,
/// for a load on the ground.
pub fn point_load_into(
    model: &Model,
    layout: &Layout,
    state: &State,
    l: &PointLoad,
    w: &mut Wrench,
) -> bool {
    let mk = marker_kin(model, layout, state, l.marker);
    if mk.block.is_none() {
        return false;
    }
    w.reset(mk.block, None, mk.r, Vec3::zeros());
    w.g = l.force;
    w.m = l.torque;
    true
}

/// Every force-element wrench of the model (bushings, springs, stops,
/// frictions against the state's committed slip) at a state.
pub fn element_wrenches(
    model: &Model,
    layout: &Layout,
    state: &State,
) -> Result<Vec<(ElementId, Wrench)>, StaticsError> {
    let mut out = Vec::new();
    for_each_element(model, layout, state, |id, w| out.push((id, w.clone())))?;
    Ok(out)
}

/// Calls `f` with every force-element wrench, in the order of
/// [`element_wrenches`], without collecting them (the Newton loop's path).
pub fn for_each_element(
    model: &Model,
    layout: &Layout,
    state: &State,
    mut f: impl FnMut(ElementId, &Wrench),
) -> Result<(), StaticsError> {
    for (k, b) in model.bushings.iter().enumerate() {
        let id = ElementId::Bushing(BushingId(k as u32));
        f(id, &bushing(model, layout, state, b).wrench);
    }
    // (Each wrench borrowed where the element's result holds it: moved out
    // of the `Result` by `?`, its 700 bytes would be copied.)
    for (k, s) in model.springs.iter().enumerate() {
        let id = SpringId(k as u32);
        match spring(model, layout, state, id, s) {
            Ok(ref e) => f(ElementId::Spring(id), &e.2),
            Err(e) => return Err(e),
        }
    }
    for (k, s) in model.stops.iter().enumerate() {
        let id = StopId(k as u32);
        match stop(model, layout, state, id, s) {
            Ok(ref e) => f(ElementId::Stop(id), &e.2),
            Err(e) => return Err(e),
        }
    }
    for k in 0..model.frictions.len() {
        let id = FrictionId(k as u32);
        let e = super::friction::evaluate(model, layout, state, id);
        f(ElementId::Friction(id), &e.wrench);
    }
    Ok(())
}

#[cfg(test)]
#[path = "forces_tests.rs"]
mod tests;
