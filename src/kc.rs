//! Wheel kinematics-and-compliance quantities of a solved state
//! (`conventions.md`, "Wheel and K&C quantities").

use crate::geom::Vec3;
use crate::model::{Model, Wheel};
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
    let (c, s, cp) = centre_axis_contact(model, state, w);
    let (c0, _, cp0) = centre_axis_contact(model, &State::design(model), w);
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
    }
}
