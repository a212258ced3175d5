//! New elements written into the file: parameters after the last `param`
//! line, markers and landmarks at the end of their part, parts and elements at
//! the end of the file, each after a comment naming the tool and its reason.

use super::{Change, EditError, Editor, splice};
use crate::fmt::model::{element, landmark_line, marker_line, param_line, part_block};
use crate::model::*;

impl Editor<'_> {
    fn why(&self, id: ElementId) -> String {
        let reason = self.req.reasons.iter().find(|(e, _)| *e == id);
        match reason {
            Some((_, why)) => format!("// added by {}: {why}", self.req.tool),
            None => format!("// added by {}", self.req.tool),
        }
    }

    /// A comment line `// changed by <tool>: <why>` above each element of
    /// the old file the request gives a reason for (an element changed in
    /// place keeps its layout; the comment says who changed it and why).
    pub(super) fn commented(&mut self) {
        let o = self.old;
        for (id, why) in self.req.reasons {
            let (keyword, name) = match *id {
                ElementId::Bushing(b) if b.index() < o.bushings.len() => {
                    ("bushing", &o.bushings[b.index()].name)
                }
                ElementId::Spring(s) if s.index() < o.springs.len() => {
                    ("spring", &o.springs[s.index()].name)
                }
                ElementId::Joint(j) if j.index() < o.joints.len() => {
                    ("joint", &o.joints[j.index()].name)
                }
                ElementId::Stop(s) if s.index() < o.stops.len() => {
                    ("stop", &o.stops[s.index()].name)
                }
                ElementId::Friction(f) if f.index() < o.frictions.len() => {
                    ("friction", &o.frictions[f.index()].name)
                }
                _ => continue,
            };
            let Some(item) = splice::element(self.ast, keyword, name) else {
                continue;
            };
            let at = splice::line_start(self.text, item.span.start as usize);
            let indent = splice::indent_at(self.text, item.span.start as usize).to_string();
            self.splice(
                at,
                at,
                format!("{indent}// changed by {}: {why}\n", self.req.tool),
            );
        }
    }

    /// New parameters after the last `param` line; new markers and landmarks
    /// of written parts at the end of their part; new parts and elements at
    /// the end of the file.
    pub(super) fn added(&mut self) -> Result<(), EditError> {
        let (o, n) = (self.old, self.new);
        let at = splice::param_insertion(self.ast);
        for i in o.params.len()..n.params.len() {
            let id = ElementId::Param(ParamId(i as u32));
            let text = format!("{}\n{}", self.why(id), param_line(&n.params[i]));
            match at {
                Some(at) => self.splice(at, at, format!("\n{text}")),
                None => self.splice(0, 0, format!("{text}\n")),
            }
            self.changes.push(Change::Added { element: id });
        }
        let members = (o.markers.len()..n.markers.len())
            .map(|i| {
                let mk = &n.markers[i];
                (
                    ElementId::Marker(MarkerId(i as u32)),
                    mk.part,
                    marker_line(n, mk),
                )
            })
            .chain((o.landmarks.len()..n.landmarks.len()).map(|i| {
                let l = &n.landmarks[i];
                (
                    ElementId::Landmark(LandmarkId(i as u32)),
                    l.part,
                    landmark_line(n, l),
                )
            }));
        for (id, part, line) in members.collect::<Vec<_>>() {
            if part.index() >= o.parts.len() {
                continue; // printed with its new part
            }
            let Some((item, _)) = splice::part(self.ast, &o.part(part).name) else {
                return Err(self.unsupported(
                    Some(ElementId::Part(part)),
                    "a part not written in this file",
                ));
            };
            let close = splice::line_start(self.text, item.span.end as usize - 1);
            let text = format!("    {}\n    {line}\n", self.why(id));
            self.splice(close, close, text);
            self.changes.push(Change::Added { element: id });
        }
        let end = self.text.len();
        let mut tail = String::new();
        if !self.text.ends_with('\n') {
            tail.push('\n');
        }
        let blocks = (o.parts.len()..n.parts.len())
            .map(|i| ElementId::Part(PartId(i as u32)))
            .chain((o.joints.len()..n.joints.len()).map(|i| ElementId::Joint(JointId(i as u32))))
            .chain(
                (o.bushings.len()..n.bushings.len())
                    .map(|i| ElementId::Bushing(BushingId(i as u32))),
            )
            .chain(
                (o.springs.len()..n.springs.len()).map(|i| ElementId::Spring(SpringId(i as u32))),
            )
            .chain((o.stops.len()..n.stops.len()).map(|i| ElementId::Stop(StopId(i as u32))))
            .chain(
                (o.frictions.len()..n.frictions.len())
                    .map(|i| ElementId::Friction(FrictionId(i as u32))),
            )
            .chain((o.wheels.len()..n.wheels.len()).map(|i| ElementId::Wheel(WheelId(i as u32))));
        for id in blocks.collect::<Vec<_>>() {
            let printed = match id {
                ElementId::Part(p) => Some(part_block(n, p)),
                _ => element(n, id),
            };
            let Some(printed) = printed else {
                return Err(EditError::Unsupported {
                    element: Some((n.describe(id), None)),
                    what: "a new element of a kind the printer cannot write yet".into(),
                });
            };
            tail.push_str(&format!("\n{}\n{printed}", self.why(id)));
            self.changes.push(Change::Added { element: id });
        }
        if tail.trim().is_empty() {
            return Ok(());
        }
        self.splice(end, end, tail);
        Ok(())
    }
}
