//! The checks a hand-written model passes, run on a model built or changed by a
//! tool (`edit`, import, diagnosis): ids in range, connections between two
//! parts, laws with non-negative stiffnesses and positive lengths, friction on
//! a joint with the axis it needs, then the checker's own geometry and
//! mobility rules. The same codes as the checker, so a user reads one story.

use super::{Checker, Problems, error};
use crate::diagnostic::Diagnostic;
use crate::model::*;
use crate::span::{FileId, Span};

/// Problems of a model that did not come from text (errors and warnings).
pub fn validate(model: &Model) -> Problems {
    let mut c = Checker {
        problems: Problems::default(),
        model: model.clone(),
        library: false,
        file_span: Span::new(FileId(0), 0, 0),
        param_decls: Vec::new(),
        bad_markers: Default::default(),
        failed_params: Vec::new(),
        passes: super::Passes::ALL,
        resolution: Default::default(),
        mirrored_parts: Default::default(),
        mirrored_markers: Default::default(),
    };
    // Out-of-range ids would panic in the geometry pass: stop at them.
    if !c.ids_in_range() {
        return c.problems;
    }
    c.connections();
    c.laws();
    c.geometry();
    if !c.problems.has_errors() {
        c.mobility();
    }
    c.problems
}

/// Below zero or not a number (a tool's NaN is refused like a negative).
fn negative(v: f64) -> bool {
    v.is_nan() || v < 0.0
}

fn positive(v: f64) -> bool {
    v > 0.0
}

impl Checker {
    fn ids_in_range(&mut self) -> bool {
        let m = &self.model;
        let (np, nm, nj) = (m.parts.len(), m.markers.len(), m.joints.len());
        let mut bad: Vec<String> = Vec::new();
        for mk in &m.markers {
            if mk.part.index() >= np {
                bad.push(format!(
                    "marker `{}` is on a part that does not exist",
                    mk.name
                ));
            }
        }
        let mut pair = |what: String, i: MarkerId, j: MarkerId| {
            if i.index() >= nm || j.index() >= nm {
                bad.push(format!("{what} names a marker that does not exist"));
            }
        };
        for j in &m.joints {
            pair(format!("joint `{}`", j.name), j.i, j.j);
        }
        for b in &m.bushings {
            pair(format!("bushing `{}`", b.name), b.i, b.j);
        }
        for s in &m.springs {
            pair(format!("spring `{}`", s.name), s.i, s.j);
        }
        for s in &m.stops {
            pair(format!("stop `{}`", s.name), s.i, s.j);
        }
        for w in &m.wheels {
            pair(format!("wheel `{}`", w.name), w.centre, w.contact);
        }
        for f in &m.frictions {
            if f.joint.index() >= nj {
                bad.push(format!(
                    "friction `{}` names a joint that does not exist",
                    f.name
                ));
            }
        }
        let ok = bad.is_empty();
        for b in bad {
            self.problems.push(Diagnostic::error("E0101", b));
        }
        ok
    }

    fn connections(&mut self) {
        let m = &self.model;
        let mut found = Vec::new();
        let mut each = |id: ElementId, i: MarkerId, j: MarkerId| {
            let (pi, pj) = (m.marker(i).part, m.marker(j).part);
            if pi == pj {
                found.push((id, pi));
            }
        };
        for (id, j) in m.active_joints() {
            each(ElementId::Joint(id), j.i, j.j);
        }
        for (k, b) in m.bushings.iter().enumerate() {
            each(ElementId::Bushing(BushingId(k as u32)), b.i, b.j);
        }
        for (k, s) in m.springs.iter().enumerate() {
            each(ElementId::Spring(SpringId(k as u32)), s.i, s.j);
        }
        for (k, s) in m.stops.iter().enumerate() {
            each(ElementId::Stop(StopId(k as u32)), s.i, s.j);
        }
        for (id, part) in found {
            let what = self.model.describe(id);
            let part = self.model.part(part).name.clone();
            let span = self.span_of(id);
            self.problems.push(
                Diagnostic::error(
                    "E0302",
                    format!("both markers of {what} are on part `{part}`"),
                )
                .primary(span, format!("I and J are on `{part}`"))
                .hint("a connection joins two different parts"),
            );
        }
        for (k, w) in self.model.wheels.iter().enumerate() {
            let (pc, pk) = (
                self.model.marker(w.centre).part,
                self.model.marker(w.contact).part,
            );
            if pc != w.part || pk != w.part {
                let span = self.span_of(ElementId::Wheel(WheelId(k as u32)));
                self.problems.push(
                    Diagnostic::error(
                        "E0409",
                        format!(
                            "the centre and contact markers of wheel `{}` are not both on its part",
                            w.name
                        ),
                    )
                    .primary(span, "wheel markers on two parts"),
                );
            }
        }
    }

    /// Stiffnesses zero or positive, lengths positive, friction on a joint that
    /// has the axis its motion needs.
    fn laws(&mut self) {
        let mut found: Vec<Diagnostic> = Vec::new();
        let span = |c: &Self, id| c.span_of(id);
        for (k, b) in self.model.bushings.iter().enumerate() {
            let id = ElementId::Bushing(BushingId(k as u32));
            for law in b.translational.iter().chain(b.rotational.iter()) {
                if let AxisLaw::Linear { k, k3 } = law
                    && (negative(k.value) || negative(k3.value))
                {
                    {
                        let what = format!("a stiffness ({}, cubic {})", k.value, k3.value);
                        found.push(error::negative_stiffness(
                            &self.model.describe(id),
                            &what,
                            span(self, id),
                        ));
                        break;
                    }
                }
            }
        }
        for (k, s) in self.model.springs.iter().enumerate() {
            let id = ElementId::Spring(SpringId(k as u32));
            if let SpringLaw::Linear { k, free_length, .. } = &s.law {
                if negative(k.value) {
                    found.push(error::negative_stiffness(
                        &self.model.describe(id),
                        "k",
                        span(self, id),
                    ));
                }
                if !positive(free_length.value) {
                    found.push(error::length_not_positive(
                        &self.model.describe(id),
                        "free_length",
                        span(self, id),
                    ));
                }
            }
        }
        for (k, s) in self.model.stops.iter().enumerate() {
            let id = ElementId::Stop(StopId(k as u32));
            if !positive(s.contact_length.value) {
                found.push(error::length_not_positive(
                    &self.model.describe(id),
                    "contact_length",
                    span(self, id),
                ));
            }
            if let StopLaw::Polynomial(c) = &s.law
                && c.iter().any(|v| negative(v.value))
            {
                {
                    found.push(error::negative_stiffness(
                        &self.model.describe(id),
                        "a coefficient",
                        span(self, id),
                    ));
                }
            }
        }
        for (k, f) in self.model.frictions.iter().enumerate() {
            let id = ElementId::Friction(FrictionId(k as u32));
            let describe = self.model.describe(id);
            // The friction checker's codes (E0413, E0414): kf > 0, limit >= 0.
            if !positive(f.stiffness.value) {
                found.push(
                    Diagnostic::error(
                        "E0413",
                        format!("the stick stiffness `kf` of {describe} must be positive"),
                    )
                    .primary(span(self, id), "zero or negative"),
                );
            }
            if negative(f.limit.value) {
                found.push(
                    Diagnostic::error("E0414", format!("the slip limit of {describe} is negative"))
                        .primary(span(self, id), "negative"),
                );
            }
            let kind = self.model.joints[f.joint.index()].kind;
            let retired = self.model.is_retired(f.joint);
            let fits = match f.motion {
                FrictionMotion::Slide => {
                    matches!(kind, JointKind::Cylindrical | JointKind::Translational)
                }
                FrictionMotion::Rotation => matches!(
                    kind,
                    JointKind::Revolute | JointKind::Cylindrical | JointKind::Spherical
                ),
            };
            if retired || !fits {
                let joint = &self.model.joints[f.joint.index()].name;
                let why = if retired {
                    format!("joint `{joint}` was replaced")
                } else {
                    format!(
                        "{} joint `{joint}` has no axis for this motion",
                        kind.keyword()
                    )
                };
                found.push(
                    Diagnostic::error("E0412", format!("{describe} cannot act on joint `{joint}`"))
                        .primary(span(self, id), why)
                        .hint("a slide needs a cylindrical or translational joint, a rotation a revolute, cylindrical or spherical one"),
                );
            }
        }
        for d in found {
            self.problems.push(d);
        }
    }
}
