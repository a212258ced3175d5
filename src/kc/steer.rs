//! Steering K&C (`docs/kc.md`, "Steering"): a load path that drives a
//! steering rack (a part on a translational joint to the ground, pushed
//! along the joint's axis by a load channel of the set), the rack's travel
//! at every step, and each wheel's steering geometry at the step nearest
//! zero travel: the steering axis as the screw axis of the upright's motion
//! between that step's neighbours, and from it caster, kingpin inclination,
//! scrub radius and mechanical trail, and the steer angle per mm of rack
//! travel.
//!
//! The axis is the one the rig sees: the upright's motion under the
//! steering input with the wheel loads held, compliance included. For a
//! knuckle on a kingpin (a revolute joint) it is the kingpin's axis.

use super::axle::reference;
use crate::geom::{Mat3, Vec3};
use crate::model::{
    Component, JointId, JointKind, LoadSet, LoadSetId, LoadTarget, MarkerId, Model,
};
use crate::statics::State;

/// The rack a load path drives: its translational joint to the ground.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Rack {
    pub joint: JointId,
}

/// One wheel's steering geometry at the reference step.
#[derive(Debug, Clone, PartialEq)]
pub struct WheelSteer {
    pub wheel: String,
    /// Side view: the axis's top rearward of its foot positive, deg.
    pub caster_deg: f64,
    /// Front view: the axis's top inboard of its foot positive, deg.
    pub kpi_deg: f64,
    /// Lateral distance from where the axis meets the ground (the plane
    /// through the contact point, normal to z) to the contact point,
    /// positive when the axis meets the ground inboard of it, mm.
    pub scrub_mm: f64,
    /// Longitudinal distance from the contact point to where the axis meets
    /// the ground, positive when that point is ahead (caster trail), mm.
    pub trail_mm: f64,
    /// Steer angle (ISO 8855: positive turning left, about +z) per mm of
    /// rack travel (positive toward +y), deg/mm.
    pub steer_per_travel: f64,
    /// A point of the axis (where it meets the ground) and its direction
    /// (unit, upward), global, mm.
    pub axis_point: [f64; 3],
    pub axis_direction: [f64; 3],
}

/// The steering metrics of one load path.
#[derive(Debug, Clone, PartialEq)]
pub struct SteeringMetrics {
    /// The rack's joint.
    pub rack: String,
    /// 1-based step the geometry is taken at, its case and rack travel (mm).
    pub step: usize,
    pub loadcase: String,
    pub travel_mm: f64,
    /// One per wheel, in declaration order.
    pub wheels: Vec<WheelSteer>,
}

/// The rack `set` drives: a translational joint between the ground and a
/// moving part, with a channel of the set that varies along the path and
/// acts on that part as a force along the joint's axis (within 25°).
pub fn driven_rack(model: &Model, set: LoadSetId) -> Option<Rack> {
    let ls = model.load_sets.get(set.index())?;
    let design = State::design(model);
    for (i, ch) in ls.channels.iter().enumerate() {
        let LoadTarget::Marker(m) = ch.target else {
            continue;
        };
        let axis = match ch.component {
            Component::Fx => Vec3::x(),
            Component::Fy => Vec3::y(),
            Component::Fz => Vec3::z(),
            _ => continue,
        };
        if !varies(ls, i) {
            continue;
        }
        let part = model.marker(m).part;
        for (id, j) in model.active_joints() {
            if j.kind != JointKind::Translational {
                continue;
            }
            let (pi, pj) = (model.marker(j.i).part, model.marker(j.j).part);
            let grounded = |p: crate::model::PartId| model.parts[p.index()].ground;
            let moving = (pi == part && grounded(pj)) || (pj == part && grounded(pi));
            if !moving {
                continue;
            }
            let (_, zj) = frame(model, &design, j.j);
            if zj.column(2).dot(&axis).abs() >= 25f64.to_radians().cos() {
                return Some(Rack { joint: id });
            }
        }
    }
    None
}

fn varies(ls: &LoadSet, i: usize) -> bool {
    ls.cases
        .iter()
        .any(|c| (c.values[i] - ls.cases[0].values[i]).abs() > 0.0)
}

/// A marker's origin and axes at `state`, global.
fn frame(model: &Model, state: &State, m: MarkerId) -> (Vec3, Mat3) {
    let mk = model.marker(m);
    let (x, r) = state.part_pose(mk.part);
    (x + r * mk.origin(), r * mk.rotation)
}

/// The rack's travel at `state`: its slide along the joint's axis, from
/// design, signed toward the vehicle's +y (or +x, +z: the global axis the
/// joint's axis is nearest), mm.
pub fn rack_travel(model: &Model, state: &State, rack: Rack) -> f64 {
    let j = &model.joints[rack.joint.index()];
    let slide = |st: &State| {
        let (pi, _) = frame(model, st, j.i);
        let (pj, rj) = frame(model, st, j.j);
        let z: Vec3 = rj.column(2).into();
        // The global axis nearest z gives the sign.
        let k = z.iamax();
        let sign = if z[k] < 0.0 { -1.0 } else { 1.0 };
        // Travel of the moving part: I from J if I moves, else J from I.
        let ground_i = model.parts[model.marker(j.i).part.index()].ground;
        let d = if ground_i { pj - pi } else { pi - pj };
        sign * d.dot(&z)
    };
    slide(state) - slide(&State::design(model))
}

/// The screw axis of the rigid motion `y -> r y + t` (a rotation that is not
/// the identity): a point of it and its unit direction.
fn screw_axis(r: &Mat3, t: &Vec3) -> Option<(Vec3, Vec3)> {
    let w = Vec3::new(
        r[(2, 1)] - r[(1, 2)],
        r[(0, 2)] - r[(2, 0)],
        r[(1, 0)] - r[(0, 1)],
    ) * 0.5;
    let s = w.norm();
    if s < 1e-12 {
        return None;
    }
    let u = w / s;
    let c = ((r.trace() - 1.0) * 0.5).clamp(-1.0, 1.0);
    let theta = s.atan2(c);
    // The point of the axis nearest the origin (Chasles):
    // p = (t_perp + cot(θ/2) u × t) / 2.
    let tp = t - u * u.dot(t);
    let p = (tp + u.cross(t) / (theta * 0.5).tan()) * 0.5;
    Some((p, u))
}

/// The steering metrics of a solved path (`states[k]` of case k) driving
/// `rack`; `None` when the rack does not move.
pub fn steering_metrics(
    model: &Model,
    set: LoadSetId,
    rack: Rack,
    states: &[&State],
) -> Option<SteeringMetrics> {
    let ls = model.load_sets.get(set.index())?;
    let travel: Vec<f64> = states.iter().map(|s| rack_travel(model, s, rack)).collect();
    let (k, a, b) = reference(&travel)?;
    let ds = travel[b] - travel[a];
    let mut wheels = Vec::new();
    for w in &model.wheels {
        let upright = model.marker(w.centre).part;
        let (xa, ra) = states[a].part_pose(upright);
        let (xb, rb) = states[b].part_pose(upright);
        let r = rb * ra.transpose();
        let t = xb - r * xa;
        let (p, mut u) = screw_axis(&r, &t)?;
        if u.z < 0.0 {
            u = -u;
        }
        let (contact, _) = frame(model, states[k], w.contact);
        let side = if contact.y < 0.0 { -1.0 } else { 1.0 };
        // Where the axis meets the ground plane through the contact point.
        let g = p + u * ((contact.z - p.z) / u.z);
        let steer = |st: &State| {
            let q = super::wheel_quantities(model, st, w);
            // Toe-in is a right turn of a left wheel and a left turn of a right one.
            -side * q.toe_deg
        };
        wheels.push(WheelSteer {
            wheel: w.name.clone(),
            caster_deg: (-u.x).atan2(u.z).to_degrees(),
            kpi_deg: (-side * u.y).atan2(u.z).to_degrees(),
            scrub_mm: side * (contact.y - g.y),
            trail_mm: g.x - contact.x,
            steer_per_travel: (steer(states[b]) - steer(states[a])) / ds,
            axis_point: g.into(),
            axis_direction: u.into(),
        });
    }
    Some(SteeringMetrics {
        rack: model.joints[rack.joint.index()].name.clone(),
        step: k + 1,
        loadcase: ls.cases[k].name.clone(),
        travel_mm: travel[k],
        wheels,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_screw_axis_of_a_rotation_about_an_offset_line_is_that_line() {
        let u = Vec3::new(-0.1, -0.2, 1.0).normalize();
        let c = Vec3::new(10.0, 700.0, 150.0);
        let r: Mat3 = nalgebra::Rotation3::from_axis_angle(&nalgebra::Unit::new_normalize(u), 0.3)
            .into_inner();
        // Rotation about the line through c, plus a slide of 2 mm along it.
        let t = c - r * c + u * 2.0;
        let (p, v) = screw_axis(&r, &t).expect("a rotation");
        assert!((v - u).norm() < 1e-12, "{v:?}");
        // p lies on the line: (p - c) parallel to u.
        assert!((p - c).cross(&u).norm() < 1e-9, "{p:?}");
        assert!(screw_axis(&Mat3::identity(), &Vec3::x()).is_none());
    }
}
