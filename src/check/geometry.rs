//! Geometry at the design configuration: joint equations must hold where the
//! model is written, and landmark distance tables must allow matching.

use super::Checker;
use crate::diagnostic::Diagnostic;
use crate::model::{ElementId, JointId, JointKind, LandmarkId, Primitive, values};

/// A joint whose markers miss by more than this (mm) cannot be assembled as written.
const POSITION_TOL: f64 = 1e-3;
/// Same for axes (rad, about 0.006°).
const ANGLE_TOL: f64 = 1e-4;
/// Two landmark distances closer than this defeat matching by distance table (mm).
const LANDMARK_DISTANCE_TOL: f64 = 1.0;
/// Validity limit of the bushing's projected angles, deg.
const BUSHING_ANGLE_LIMIT: f64 = 15.0;
/// A wheel spin axis tilted further than this from the horizontal is written
/// wrongly, not cambered (deg).
const WHEEL_CAMBER_LIMIT: f64 = 45.0;
/// A bushing whose markers are further apart than this at design starts loaded (mm).
const BUSHING_GAP_LIMIT: f64 = 0.01;

impl Checker {
    pub(super) fn geometry(&mut self) {
        for (n, j) in self.model.joints.iter().enumerate() {
            if self.model.is_retired(JointId(n as u32)) {
                continue;
            }
            if self.bad_markers.contains(&j.i) || self.bad_markers.contains(&j.j) {
                continue;
            }
            let (mi, mj) = (self.model.marker(j.i), self.model.marker(j.j));
            let d = mi.origin() - mj.origin();
            let span = self.span_of(ElementId::Joint(JointId(n as u32)));
            let mut gap_reported = false;
            for eq in j.kind.equations() {
                let (residual, tol) = match *eq {
                    Primitive::Coincident(_) => (d.norm(), POSITION_TOL),
                    Primitive::InPlane(b) => (d.dot(&mj.rotation.column(b.index())), POSITION_TOL),
                    Primitive::Perpendicular(a, b) => (
                        mi.rotation
                            .column(a.index())
                            .dot(&mj.rotation.column(b.index())),
                        ANGLE_TOL,
                    ),
                };
                if residual.abs() <= tol {
                    continue;
                }
                let d = match *eq {
                    Primitive::Coincident(_) | Primitive::InPlane(_) => {
                        if gap_reported {
                            continue;
                        }
                        gap_reported = true;
                        Diagnostic::error("E0303", format!("the markers of {} joint `{}` do not meet at the design configuration", j.kind.keyword(), j.name))
                            .primary(span, format!("`{}` and `{}` are {:.3} mm apart", self.model.marker_path(j.i), self.model.marker_path(j.j), d.norm()))
                            .secondary_opt(self.model.origins.get(ElementId::Marker(j.i)), "I marker")
                            .secondary_opt(self.model.origins.get(ElementId::Marker(j.j)), "J marker")
                            .hint("write both markers at the joint's point")
                    }
                    Primitive::Perpendicular(_, _) if j.kind == JointKind::Universal => {
                        let angle = residual.clamp(-1.0, 1.0).acos().to_degrees();
                        Diagnostic::error("E0304", format!("the axes of universal joint `{}` are not perpendicular", j.name))
                            .primary(span, format!("z axes of I and J are {angle:.3}° apart, not 90°"))
                            .secondary_opt(self.model.origins.get(ElementId::Marker(j.i)), "I marker")
                            .secondary_opt(self.model.origins.get(ElementId::Marker(j.j)), "J marker")
                            .hint("a universal joint's two spin axes (the z axes of I and J) must be perpendicular")
                    }
                    Primitive::Perpendicular(a, b) => {
                        let names = ["x", "y", "z"];
                        Diagnostic::error("E0305", format!("the marker axes of {} joint `{}` are not aligned at the design configuration", j.kind.keyword(), j.name))
                            .primary(span, format!("{}_I · {}_J = {residual:.4}, should be 0", names[a.index()], names[b.index()]))
                            .secondary_opt(self.model.origins.get(ElementId::Marker(j.i)), "I marker")
                            .secondary_opt(self.model.origins.get(ElementId::Marker(j.j)), "J marker")
                            .hint("give both markers the same orientation (for a revolute or cylindrical joint, the same z axis)")
                    }
                };
                self.problems.push(d);
            }
        }
        self.bushing_alignment();
        self.line_elements();
        self.wheel_axes();
        self.landmark_tables();
        self.far_markers();
    }

    /// Springs and stops act along the line from J to I: two markers at one
    /// point leave it undefined (the solver could not even start).
    fn line_elements(&mut self) {
        let springs = self.model.springs.iter().enumerate().map(|(n, s)| {
            (
                "spring",
                &s.name,
                s.i,
                s.j,
                ElementId::Spring(crate::model::SpringId(n as u32)),
            )
        });
        let stops = self.model.stops.iter().enumerate().map(|(n, s)| {
            (
                "stop",
                &s.name,
                s.i,
                s.j,
                ElementId::Stop(crate::model::StopId(n as u32)),
            )
        });
        let mut diags = Vec::new();
        for (what, name, i, j, id) in springs.chain(stops) {
            if self.bad_markers.contains(&i) || self.bad_markers.contains(&j) {
                continue;
            }
            let gap = (self.model.marker(i).origin() - self.model.marker(j).origin()).norm();
            if gap < POSITION_TOL {
                diags.push(
                    Diagnostic::error("E0309", format!("the markers of {what} `{name}` are at one point"))
                        .primary(self.span_of(id), format!("`{}` and `{}` coincide", self.model.marker_path(i), self.model.marker_path(j)))
                        .secondary_opt(self.model.origins.get(ElementId::Marker(i)), "I marker")
                        .secondary_opt(self.model.origins.get(ElementId::Marker(j)), "J marker")
                        .note(format!("a {what} acts along the line between its two markers, which two coincident points do not define"))
                        .hint("put I and J at the two seats, e.g. the spring's upper and lower seats"),
                );
            }
        }
        self.problems.list.extend(diags);
    }

    /// A wheel centre's z axis is the spin axis pointing outboard (conventions.md):
    /// one pointing inboard or up turns toe and camber by about 180° or 90°.
    fn wheel_axes(&mut self) {
        let mut diags = Vec::new();
        for (n, w) in self.model.wheels.iter().enumerate() {
            if self.bad_markers.contains(&w.centre) {
                continue;
            }
            let c = self.model.marker(w.centre);
            let s = c.rotation.column(2);
            let side = c.origin().y;
            // A wheel on the centre plane has no inboard side to check against.
            if side.abs() < POSITION_TOL {
                continue;
            }
            let outboard = s.y * side.signum();
            let camber = (-s.z).clamp(-1.0, 1.0).asin().to_degrees();
            if outboard > 0.0 && camber.abs() < WHEEL_CAMBER_LIMIT {
                continue;
            }
            let (left, want) = if side > 0.0 {
                ("left", "+y")
            } else {
                ("right", "-y")
            };
            diags.push(
                Diagnostic::warning("W0310", format!("the spin axis of wheel `{}` does not point outboard", w.name))
                    .primary(self.span_of(ElementId::Wheel(crate::model::WheelId(n as u32))), format!("z of `{}` is ({:.3}, {:.3}, {:.3})", self.model.marker_path(w.centre), s.x, s.y, s.z))
                    .secondary_opt(self.model.origins.get(ElementId::Marker(w.centre)), "the centre marker")
                    .note(format!(
                        "a {left} wheel (centre y = {side:.1} mm) spins about an axis near {want}; toe and camber are measured from the centre marker's z axis, {}",
                        if camber.abs() >= WHEEL_CAMBER_LIMIT {
                            format!("so camber would read {camber:.0}°")
                        } else {
                            "which points inboard here, so toe would read about 180° off".to_string()
                        }
                    ))
                    .hint(if side > 0.0 {
                        "write the centre marker with `euler (180, 90, 0) deg` or `z (0, 1, 0)` (a left wheel)"
                    } else {
                        "write the centre marker with `euler (0, 90, 0) deg` or `z (0, -1, 0)` (a right wheel)"
                    }),
            );
        }
        self.problems.list.extend(diags);
    }

    /// Projected angles are meaningful while |ax|, |ay| stay under ~15°
    /// (methods.md §4.2); a bushing that starts beyond that is almost surely a
    /// marker orientation mistake.
    fn bushing_alignment(&mut self) {
        for (n, b) in self.model.bushings.iter().enumerate() {
            if self.bad_markers.contains(&b.i) || self.bad_markers.contains(&b.j) {
                continue;
            }
            let span = self.span_of(ElementId::Bushing(crate::model::BushingId(n as u32)));
            let gap = (self.model.marker(b.i).origin() - self.model.marker(b.j).origin()).norm();
            if gap > BUSHING_GAP_LIMIT {
                self.problems.push(
                    Diagnostic::warning("W0308", format!("the markers of bushing `{}` are {gap:.2} mm apart at the design configuration", b.name))
                        .primary(span, format!("starts deformed by {gap:.2} mm"))
                        .secondary_opt(self.model.origins.get(ElementId::Marker(b.i)), "I marker")
                        .secondary_opt(self.model.origins.get(ElementId::Marker(b.j)), "J marker")
                        .note("a bushing's deformation is the position of I relative to J, so this gap is a built-in load of stiffness times gap")
                        .hint("write both markers at the bushing's centre, and use `offset` or `preload` for a built-in deformation or force"),
                );
            }
            let q = self.model.marker(b.j).rotation.transpose() * self.model.marker(b.i).rotation;
            let a = crate::geom::projected_angles(&q).map(f64::to_degrees);
            let tilt = q[(2, 2)].clamp(-1.0, 1.0).acos().to_degrees();
            if a.x.abs() > BUSHING_ANGLE_LIMIT
                || a.y.abs() > BUSHING_ANGLE_LIMIT
                || tilt > BUSHING_ANGLE_LIMIT
            {
                self.problems.push(
                    Diagnostic::warning("W0307", format!("the markers of bushing `{}` are not aligned at the design configuration", b.name))
                        .primary(span, format!("the z axes of I and J are {tilt:.1}° apart"))
                        .note(format!("projected angles at design: ax {:.1}°, ay {:.1}°, az {:.1}°; they describe the bushing's torsion only while |ax| and |ay| stay below about {BUSHING_ANGLE_LIMIT}°", a.x, a.y, a.z))
                        .hint("give the I and J markers of a bushing the same orientation, and use `angle_offset` for a built-in twist"),
                );
            }
        }
    }

    fn landmark_tables(&mut self) {
        for part in 0..self.model.parts.len() {
            let lms: Vec<(usize, &crate::model::Landmark)> = self
                .model
                .landmarks
                .iter()
                .enumerate()
                .filter(|(_, l)| l.part.index() == part)
                .collect();
            let mut dists = Vec::new();
            for a in 0..lms.len() {
                for b in a + 1..lms.len() {
                    let d = (values(&lms[a].1.position) - values(&lms[b].1.position)).norm();
                    dists.push((d, lms[a].0, lms[b].0));
                }
            }
            dists.sort_by(|x, y| x.0.total_cmp(&y.0));
            let mut diags = Vec::new();
            for w in dists.windows(2) {
                if w[1].0 - w[0].0 < LANDMARK_DISTANCE_TOL {
                    let name = |i: usize| self.model.landmarks[i].name.clone();
                    let span = |i: usize| self.span_of(ElementId::Landmark(LandmarkId(i as u32)));
                    // Label each distance at a landmark of its pair, two different
                    // landmarks where the pairs allow it (m1–m2 at m2, m1–m3 at m3).
                    let (a, b) = (w[1], w[0]);
                    let at_a = a.2;
                    let at_b = if b.2 != at_a { b.2 } else { b.1 };
                    diags.push(
                        Diagnostic::warning("W0306", format!("landmarks of part `{}` cannot be told apart by their distances", self.model.parts[part].name))
                            .primary(span(at_a), format!("{}–{} is {:.2} mm", name(a.1), name(a.2), a.0))
                            .secondary(span(at_b), format!("{}–{} is {:.2} mm", name(b.1), name(b.2), b.0))
                            .note(format!("measured points are matched to landmarks by their pairwise distances; two distances closer than {LANDMARK_DISTANCE_TOL} mm make the match ambiguous"))
                            .hint("move one landmark so that all pairwise distances differ by more than 1 mm"),
                    );
                    break;
                }
            }
            self.problems.list.extend(diags);
        }
    }
}
