//! Wheel kinematics-and-compliance quantities of a solved state
//! (`conventions.md`, "Wheel and K&C quantities").

use crate::geom::Vec3;
use crate::model::{LoadSetId, Model, Wheel};
use crate::statics::State;
use serde::Serialize;

/// One wheel's quantities, in boundary units (mm, deg).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct WheelQuantities {
    /// Wheel centre, mm, global.
    pub center: [f64; 3],
    /// Unit spin axis pointing outboard, global.
    pub spin_axis: [f64; 3],
    /// Toe-in positive, deg.
    pub toe_deg: f64,
    /// Top leaning outboard positive, deg.
    pub camber_deg: f64,
    /// Centre height change from design, mm.
    pub travel_mm: f64,
    /// `|contact_y|`, mm (absolute).
    pub half_track_mm: f64,
    /// Change of `|contact_y|` from design, mm (not part of the solve JSON).
    #[serde(skip)]
    pub half_track_change_mm: f64,
    /// The contact marker's origin, mm, global (not part of the solve JSON;
    /// the axle metrics' roll centre and roll moment).
    #[serde(skip)]
    pub contact: [f64; 3],
}

fn centre_axis_contact(model: &Model, state: &State, w: &Wheel) -> (Vec3, Vec3, Vec3) {
    let c = model.marker(w.centre);
    let k = model.marker(w.contact);
    let (xc, rc) = state.part_pose(c.part);
    let (xk, rk) = state.part_pose(k.part);
    let centre = xc + rc * c.origin();
    let spin: Vec3 = (rc * c.rotation).column(2).into();
    (centre, spin, xk + rk * k.origin())
}

/// The wheel's quantities at `state`, travel and half-track change against design.
pub fn wheel_quantities(model: &Model, state: &State, w: &Wheel) -> WheelQuantities {
    wheel_quantities_from(model, &State::design(model), state, w)
}

/// [`wheel_quantities`] with the design state given (built once for many
/// states: it is as large as any state).
pub fn wheel_quantities_from(
    model: &Model,
    design: &State,
    state: &State,
    w: &Wheel,
) -> WheelQuantities {
    let (c, s, cp) = centre_axis_contact(model, state, w);
    let (c0, _, cp0) = centre_axis_contact(model, design, w);
    let right = c.y < 0.0;
    let h = if right {
        Vec3::z().cross(&s)
    } else {
        s.cross(&Vec3::z())
    };
    let steer = h.y.atan2(h.x);
    let toe = if right { steer } else { -steer };
    let camber = (-s.z).clamp(-1.0, 1.0).asin();
    WheelQuantities {
        center: c.into(),
        spin_axis: s.into(),
        toe_deg: toe.to_degrees(),
        camber_deg: camber.to_degrees(),
        travel_mm: c.z - c0.z,
        half_track_mm: cp.y.abs(),
        half_track_change_mm: cp.y.abs() - cp0.y.abs(),
        contact: cp.into(),
    }
}

/// One row of a K&C table: a wheel at one step of a load path, with the wheel
/// loads (N, N·mm, global, at the contact marker) and its quantities.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct KcRow {
    /// 1-based position along the path.
    pub step: usize,
    pub loadcase: String,
    pub wheel: String,
    /// `[fx, fy, fz]`, N.
    pub force: [f64; 3],
    /// `[mx, my, mz]`, N·mm.
    pub torque: [f64; 3],
    /// The force applied at the wheel centre marker (traction through the
    /// hub, `kc::compliance`), N, global (not part of the CSV or JSON rows).
    #[serde(skip)]
    pub centre_force: [f64; 3],
    pub quantities: WheelQuantities,
    /// The body's roll relative to the wheels at this step (deg, ISO 8855,
    /// `docs/kc.md`) when the wheel is one of an axle's pair (not part of
    /// the CSV or JSON rows).
    #[serde(skip)]
    pub roll_deg: Option<f64>,
    /// The travel of the steering rack the path drives (mm, `kc::steer`),
    /// set by `axle kc` for a steering path (not part of the CSV or JSON rows).
    #[serde(skip)]
    pub rack_mm: Option<f64>,
}

/// The K&C rows of solved cases of a load set, one per case and wheel (wheels
/// in declaration order). `states[k]` is the equilibrium of case `k`.
pub fn kc_rows(model: &Model, set: LoadSetId, states: &[&State]) -> Vec<KcRow> {
    let Some(ls) = model.load_sets.get(set.index()) else {
        return Vec::new();
    };
    let pairs = super::axle::wheel_pairs(model);
    let design = State::design(model);
    let mut rows = Vec::new();
    for (k, (case, st)) in ls.cases.iter().zip(states).enumerate() {
        let loads = model.point_loads(set, k);
        let first = rows.len();
        for w in &model.wheels {
            let (mut f, mut t, mut fc) = (Vec3::zeros(), Vec3::zeros(), Vec3::zeros());
            for l in &loads {
                if l.marker == w.contact {
                    f += l.force;
                    t += l.torque;
                } else if l.marker == w.centre {
                    fc += l.force;
                }
            }
            rows.push(KcRow {
                step: k + 1,
                loadcase: case.name.clone(),
                wheel: w.name.clone(),
                force: f.into(),
                torque: t.into(),
                centre_force: fc.into(),
                quantities: wheel_quantities_from(model, &design, st, w),
                roll_deg: None,
                rack_mm: None,
            });
        }
        for &(l, r) in &pairs {
            let (ql, qr) = (
                rows[first + l.index()].quantities,
                rows[first + r.index()].quantities,
            );
            let roll = super::axle::roll_angle(&ql, &qr);
            rows[first + l.index()].roll_deg = Some(roll);
            rows[first + r.index()].roll_deg = Some(roll);
        }
    }
    rows
}
