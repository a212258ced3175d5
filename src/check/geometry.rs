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

impl Checker {
    pub(super) fn geometry(&mut self) {
        for (n, j) in self.model.joints.iter().enumerate() {
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
                            .hint("a universal joint's two spin axes (the z axes of I and J) must be perpendicular")
                    }
                    Primitive::Perpendicular(a, b) => {
                        let names = ["x", "y", "z"];
                        Diagnostic::error("E0305", format!("the marker axes of {} joint `{}` are not aligned at the design configuration", j.kind.keyword(), j.name))
                            .primary(span, format!("{}_I · {}_J = {residual:.4}, should be 0", names[a.index()], names[b.index()]))
                            .hint("give both markers the same orientation (for a revolute or cylindrical joint, the same z axis)")
                    }
                };
                self.problems.push(d);
            }
        }
        self.landmark_tables();
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
                    diags.push(
                        Diagnostic::warning("W0306", format!("landmarks of part `{}` cannot be told apart by their distances", self.model.parts[part].name))
                            .primary(span(w[1].1), format!("{}–{} is {:.2} mm", name(w[1].1), name(w[1].2), w[1].0))
                            .secondary(span(w[0].1), format!("{}–{} is {:.2} mm", name(w[0].1), name(w[0].2), w[0].0))
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
