//! Parts, markers (frames) and landmarks.

use super::Checker;
use super::error;
use crate::geom::{FrameError, Mat3, euler_zxz, frame_from_z_x};
use crate::model::{
    ElementId, Landmark, LandmarkId, Marker, MarkerId, Orientation, Part, PartId, Val, values,
};
use crate::span::Span;
use crate::syntax::ast::{File, Ident, ItemKind, MarkerRef, Orient, PartItem};
use crate::units::Dim;

impl Checker {
    pub(super) fn parts(&mut self, ast: &File) {
        let mut ground_span = None;
        for item in &ast.items {
            let ItemKind::Part(p) = &item.kind else {
                continue;
            };
            if let Some(first) = self.model.part_named(&p.name.name) {
                let span = self.span_of(ElementId::Part(first));
                self.problems
                    .push(error::duplicate("part", &p.name.name, p.name.span, span));
                continue;
            }
            if p.ground {
                match ground_span {
                    Some(first) => {
                        self.problems
                            .push(error::second_ground(p.keyword_span.to(p.name.span), first));
                    }
                    None => ground_span = Some(p.keyword_span.to(p.name.span)),
                }
            }
            let part = PartId(self.model.parts.len() as u32);
            self.model
                .origins
                .insert(ElementId::Part(part), p.name.span);
            self.model.parts.push(Part {
                name: p.name.name.clone(),
                ground: p.ground && ground_span == Some(p.keyword_span.to(p.name.span)),
            });
            for pi in &p.items {
                match pi {
                    PartItem::Marker(m) => self.marker(part, m),
                    PartItem::Landmark(l) => {
                        if let Some(first) = self
                            .model
                            .landmarks
                            .iter()
                            .position(|x| x.part == part && x.name == l.name.name)
                        {
                            let span = self.span_of(ElementId::Landmark(LandmarkId(first as u32)));
                            self.problems.push(error::duplicate(
                                "landmark",
                                &l.name.name,
                                l.name.span,
                                span,
                            ));
                            continue;
                        }
                        let Some(position) = self.vector(&l.at, Dim::LENGTH, "(310, 330, 270) mm")
                        else {
                            continue;
                        };
                        let id = LandmarkId(self.model.landmarks.len() as u32);
                        self.model
                            .origins
                            .insert(ElementId::Landmark(id), l.name.span);
                        self.model.landmarks.push(Landmark {
                            name: l.name.name.clone(),
                            part,
                            position,
                        });
                    }
                }
            }
        }
        if ground_span.is_none() && !self.library {
            self.problems.push(error::missing_ground(self.file_span));
        }
    }

    fn marker(&mut self, part: PartId, m: &crate::syntax::ast::MarkerDecl) {
        if let Some(first) = self.model.marker_named(part, &m.name.name) {
            let span = self.span_of(ElementId::Marker(first));
            self.problems
                .push(error::duplicate("marker", &m.name.name, m.name.span, span));
            return;
        }
        let position = self.vector(&m.at, Dim::LENGTH, "(294.7, 365.1, 246.1) mm");
        let frame = self.orientation(m);
        // A marker whose values failed still exists for later references (the
        // error already prevents a model), so they are not reported as unknown.
        let id = MarkerId(self.model.markers.len() as u32);
        let (position, (orientation, rotation)) = match (position, frame) {
            (Some(p), Some(f)) => (p, f),
            (p, f) => {
                self.bad_markers.insert(id);
                (
                    p.unwrap_or([Val::ZERO; 3]),
                    f.unwrap_or((Orientation::Identity, Mat3::identity())),
                )
            }
        };
        self.model
            .origins
            .insert(ElementId::Marker(id), m.name.span);
        self.model.markers.push(Marker {
            name: m.name.name.clone(),
            part,
            position,
            orientation,
            rotation,
        });
    }

    fn orientation(&mut self, m: &crate::syntax::ast::MarkerDecl) -> Option<(Orientation, Mat3)> {
        Some(match &m.orient {
            None => (Orientation::Identity, Mat3::identity()),
            Some(Orient::Euler(v)) => {
                let a = self.vector(v, Dim::ANGLE, "(309.5, 90.22, 181.7) deg")?;
                let r = euler_zxz(a[0].value, a[1].value, a[2].value);
                (Orientation::Euler(a), r)
            }
            Some(Orient::Directions { z, x }) => {
                let zv = self.vector(z, Dim::NONE, "(0, 0, 1)")?;
                let xv = match x {
                    Some(x) => Some(values(&self.vector(x, Dim::NONE, "(1, 0, 0)")?)),
                    None => None,
                };
                let zv = values(&zv);
                match frame_from_z_x(zv, xv) {
                    Ok(r) => (Orientation::Directions { z: zv, x: xv }, r),
                    Err(e) => {
                        let (what, span) = match e {
                            FrameError::ZeroZ => ("the z direction is zero", z.span),
                            FrameError::ZeroX => (
                                "the x direction is zero",
                                x.as_ref().map_or(z.span, |x| x.span),
                            ),
                            FrameError::ParallelX => (
                                "the x direction is parallel to z",
                                x.as_ref().map_or(z.span, |x| x.span),
                            ),
                        };
                        self.problems.push(error::degenerate_direction(what, span));
                        return None;
                    }
                }
            }
        })
    }

    /// Resolves `part.marker`, reporting an unknown part or marker.
    pub(super) fn marker_ref(&mut self, r: &MarkerRef) -> Option<MarkerId> {
        self.marker_ref_at(r, (r.part.span, r.marker.span))
    }

    /// [`Self::marker_ref`], with the spans of the two names for the table of
    /// references (a load channel `arm.tip.fx` reports on the whole channel).
    pub(super) fn marker_ref_at(&mut self, r: &MarkerRef, at: (Span, Span)) -> Option<MarkerId> {
        // `chassis.front_left.B`, `steering.rack.front_left.L3`: a marker an
        // instance added to a part outside it (the ground, a part
        // parameter's part): the longest leading name that is a part.
        let split = (self.model.part_named(&r.part.name).is_none())
            .then(|| {
                r.part
                    .name
                    .rmatch_indices('.')
                    .map(|(k, _)| (&r.part.name[..k], &r.part.name[k + 1..]))
                    .find(|(head, _)| self.model.part_named(head).is_some())
            })
            .flatten();
        if let Some((head, rest)) = split {
            let r = MarkerRef {
                part: Ident {
                    name: head.to_string(),
                    span: r.part.span,
                },
                marker: Ident {
                    name: format!("{rest}.{}", r.marker.name),
                    span: r.marker.span,
                },
                span: r.span,
            };
            return self.marker_ref_at(&r, at);
        }
        let Some(part) = self.model.part_named(&r.part.name) else {
            let d = error::unknown_name(
                "part",
                &r.part.name,
                r.part.span,
                self.model.parts.iter().map(|p| p.name.as_str()),
            );
            self.problems.push(d);
            return None;
        };
        self.resolution.refer(at.0, ElementId::Part(part));
        if let Some(m) = self.model.marker_named(part, &r.marker.name) {
            self.resolution.refer(at.1, ElementId::Marker(m));
            return Some(m);
        }
        let owners: Vec<String> = self
            .model
            .markers
            .iter()
            .filter(|m| m.name == r.marker.name)
            .map(|m| self.model.part(m.part).name.clone())
            .collect();
        let is_landmark = self
            .model
            .landmarks
            .iter()
            .any(|l| l.part == part && l.name == r.marker.name);
        let d = if is_landmark {
            error::unknown_name(
                "marker",
                &format!("{}.{}", r.part.name, r.marker.name),
                r.marker.span,
                [],
            )
            .note(format!(
                "`{}` is a landmark of `{}`: a measured point without axes, which elements and loads cannot attach to",
                r.marker.name, r.part.name
            ))
            .hint(format!(
                "declare a marker at that point: `marker {} at (x, y, z) mm`",
                r.marker.name
            ))
        } else if owners.is_empty() {
            let names: Vec<&str> = self
                .model
                .markers
                .iter()
                .filter(|m| m.part == part)
                .map(|m| m.name.as_str())
                .collect();
            let best = crate::diagnostic::suggest::best(&r.marker.name, names.iter().copied());
            let d = error::unknown_name(
                "marker",
                &format!("{}.{}", r.part.name, r.marker.name),
                r.marker.span,
                [],
            )
            .hint(match best {
                Some(b) => format!("did you mean `{}.{b}`?", r.part.name),
                None if names.is_empty() => format!("part `{}` has no markers", r.part.name),
                None => format!("markers of `{}`: {}", r.part.name, names.join(", ")),
            });
            match best {
                Some(b) => d.fix(at.1, b),
                None => d,
            }
        } else {
            error::marker_on_other_part(&r.part.name, &r.marker.name, r.marker.span, &owners)
        };
        self.problems.push(d);
        None
    }
}
