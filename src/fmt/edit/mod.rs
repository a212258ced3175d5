//! Source-preserving output of a changed model: the engineer's file comes back
//! with its comments, order, layout and spelling; only what a tool changed is
//! rewritten. Every `-o` of `identify`, `locate`, `correct` (and `diagnose`)
//! goes through [`edit_source`].
//!
//! - A changed value is rewritten at the span the checker read it from
//!   ([`crate::model::Written`]), in the unit the user wrote it in; a parameter
//!   on its `param` line.
//! - An element whose shape changed (a new orientation form, a law written
//!   differently, a field that was not written) is printed again in place by
//!   the model printer, keeping the comments that were inside it.
//! - New elements are appended (markers inside their part) after a comment
//!   saying which tool added them and why.
//!
//! The result is checked again and must print the same model as the one asked
//! for; otherwise nothing is returned but an [`EditError`].

mod append;
mod error;
mod fields;
mod splice;
#[cfg(test)]
mod tests;

pub use error::EditError;

use super::model::{element, landmark_line, marker_line, number, orientation, param_line};
use crate::model::*;
use crate::span::FileId;
use crate::syntax::ast::File;
use crate::units::to_boundary;
use fields::*;
use splice::Splice;

/// What a tool asks for: the model it computed from the file's model, and why
/// it added each new element.
pub struct Request<'a> {
    /// The command, for the comments on added elements: `identify`, `diagnose`.
    pub tool: &'a str,
    /// Why each added element is there; elements without a reason get "added by TOOL".
    pub reasons: &'a [(ElementId, String)],
}

/// The edited text and what changed in it.
#[derive(Debug, Clone, PartialEq)]
pub struct Edited {
    pub text: String,
    pub changes: Vec<Change>,
}

#[derive(Debug, Clone, PartialEq)]
pub enum Change {
    /// A number rewritten in place: the text it replaced and its new text.
    Value {
        element: ElementId,
        from: String,
        to: String,
    },
    /// An element printed again in place.
    Reprinted { element: ElementId },
    /// A new element (or parameter) written into the file.
    Added { element: ElementId },
}

/// Rewrites `text` (file `file` named `name`, whose checked model is `old`) so
/// that it holds `new`, a model a tool derived from `old` by changing values,
/// changing elements and appending elements (never removing any).
pub fn edit_source(
    file: FileId,
    name: &str,
    text: &str,
    old: &Model,
    new: &Model,
    req: &Request,
) -> Result<Edited, EditError> {
    let ast = crate::syntax::parse(file, text).map_err(|d| EditError::Input(Box::new(d)))?;
    let target = keep_unchanged_frames(old, new);
    let mut e = Editor {
        file,
        text,
        ast: &ast,
        old,
        new: &target,
        req,
        splices: Vec::new(),
        changes: Vec::new(),
    };
    e.model_level()?;
    e.params()?;
    e.members()?;
    e.elements()?;
    e.added()?;
    e.commented();
    let out = splice::apply(text, e.splices).map_err(|(start, end)| EditError::Conflict {
        span: crate::span::Span::new(file, start, end),
    })?;
    verify(name, &out, &target)?;
    Ok(Edited {
        text: out,
        changes: e.changes,
    })
}

/// A tool that re-poses markers (as `correct`) may give an unmoved marker a new
/// orientation form with the same frame; its orientation is kept as written.
fn keep_unchanged_frames(old: &Model, new: &Model) -> Model {
    let mut m = new.clone();
    for (a, b) in old.markers.iter().zip(m.markers.iter_mut()) {
        let same_frame = (a.rotation - b.rotation).abs().max() < 1e-12;
        if same_frame && !same_marker_shape(a, b) {
            let position = b.position;
            *b = a.clone();
            b.position = position;
        }
    }
    m
}

/// Checks the edited text again and compares the model it holds with `target`.
fn verify(name: &str, out: &str, target: &Model) -> Result<(), EditError> {
    let (_, checked) = crate::check::check_str(name, out);
    let Some(again) = checked.model else {
        let first = checked
            .problems
            .list
            .iter()
            .find(|d| d.is_error())
            .cloned()
            .map(Box::new);
        return Err(EditError::DoesNotCheck {
            text: out.to_string(),
            first,
        });
    };
    let (want, got) = (super::print_model(target), super::print_model(&again));
    match want.lines().zip(got.lines()).find(|(a, b)| a != b) {
        None if want.lines().count() == got.lines().count() => Ok(()),
        found => Err(EditError::DoesNotReproduce {
            expected: found.map_or("(a line)".into(), |(a, _)| a.trim().to_string()),
            found: found.map_or("(no line)".into(), |(_, b)| b.trim().to_string()),
        }),
    }
}

/// A quantity in boundary units with its unit: what replaces an expression.
fn quantity(v: f64, dim: crate::units::Dim) -> String {
    let n = number(to_boundary(v, dim));
    match dim.boundary_unit() {
        u if u.is_empty() => n,
        u => format!("{n} {u}"),
    }
}

struct Editor<'a> {
    file: FileId,
    text: &'a str,
    ast: &'a File,
    old: &'a Model,
    new: &'a Model,
    req: &'a Request<'a>,
    splices: Vec<Splice>,
    changes: Vec<Change>,
}

impl Editor<'_> {
    fn splice(&mut self, start: usize, end: usize, text: String) {
        self.splices.push(Splice { start, end, text });
    }

    fn unsupported(&self, element: Option<ElementId>, what: &str) -> EditError {
        EditError::Unsupported {
            element: element.map(|e| (self.old.describe(e), self.old.origins.get(e))),
            what: what.to_string(),
        }
    }

    /// The model name, imports and load sets are not tools' to change here.
    fn model_level(&self) -> Result<(), EditError> {
        let (a, b) = (self.old, self.new);
        if a.name != b.name || a.imports != b.imports {
            return Err(self.unsupported(None, "a new model name or imports"));
        }
        if a.load_sets != b.load_sets || a.default_load_set != b.default_load_set {
            return Err(self.unsupported(None, "changed load sets"));
        }
        if a.parts.len() > b.parts.len()
            || a.parts.iter().zip(&b.parts).any(|(x, y)| x != y)
            || a.markers.len() > b.markers.len()
            || a.landmarks.len() > b.landmarks.len()
            || a.params.len() > b.params.len()
            || a.joints.len() > b.joints.len()
            || a.bushings.len() > b.bushings.len()
            || a.springs.len() > b.springs.len()
            || a.stops.len() > b.stops.len()
            || a.frictions.len() > b.frictions.len()
            || a.wheels.len() > b.wheels.len()
        {
            return Err(self.unsupported(None, "removed or renamed parts or elements"));
        }
        Ok(())
    }

    /// Rewrites one changed field at its span; `false` when it was not written
    /// as something that can be rewritten (the element is then printed again).
    fn value(&mut self, element: ElementId, old: &Val, new: &Val) -> bool {
        if old == new {
            // Unchanged: claim its text as is, so that another field written
            // at the same place (`k_radial` for x and y) cannot change it alone.
            if let Some(w) = old.written.filter(|w| w.span.file == self.file) {
                let (s, e) = (w.span.start as usize, w.span.end as usize);
                self.splice(s, e, self.text[s..e].to_string());
            }
            return true;
        }
        if new.param.is_some() && new.param == old.param {
            // Bound to a parameter whose line carries the change.
            return true;
        }
        let Some(w) = old.written.filter(|w| w.span.file == self.file) else {
            return false;
        };
        let to = match (new.param, w.factor) {
            (Some(p), _) => self.new.params[p.index()].name.clone(),
            (None, Some(f)) => number(new.value / f),
            (None, None) => quantity(new.value, w.dim),
        };
        let from = &self.text[w.span.range()];
        let same = matches!((from.parse::<f64>(), to.parse::<f64>()), (Ok(a), Ok(b)) if a == b);
        if !same {
            self.changes.push(Change::Value {
                element,
                from: from.to_string(),
                to: to.clone(),
            });
            self.splice(w.span.start as usize, w.span.end as usize, to);
        }
        true
    }

    /// Rewrites the fields of one element of the same shape (`same`, see
    /// [`fields::same_shape`]); `false` (and nothing planned) when the element
    /// must be printed again.
    fn fields<T: Clone + PartialEq>(
        &mut self,
        id: ElementId,
        (a, b): (&T, &T),
        walk: Walk<T>,
        same: bool,
    ) -> bool {
        if !same {
            return false;
        }
        let (splices, changes) = (self.splices.len(), self.changes.len());
        for (x, y) in collect(a, walk).iter().zip(&collect(b, walk)) {
            if !self.value(id, x, y) {
                self.splices.truncate(splices);
                self.changes.truncate(changes);
                return false;
            }
        }
        true
    }

    fn params(&mut self) -> Result<(), EditError> {
        let (o, n) = (self.old, self.new);
        for (i, (a, b)) in o.params.iter().zip(&n.params).enumerate() {
            if a == b {
                continue;
            }
            let id = ElementId::Param(ParamId(i as u32));
            let Some((item, decl)) = splice::param(self.ast, &a.name) else {
                return Err(self.unsupported(Some(id), "a parameter not declared in this file"));
            };
            if a.name != b.name || a.dim != b.dim || a.unknown != b.unknown {
                // Bounds or kind changed: the whole line is the tool's.
                self.changes.push(Change::Reprinted { element: id });
                let s = item.span.start as usize;
                let e = splice::code_end(self.text, s, item.span.end as usize);
                self.splice(s, e, param_line(b));
                continue;
            }
            let (start, end, to) = match crate::check::plain_number(&decl.value, 1.0) {
                Some((span, f)) => (span.start, span.end, number(b.value / f)),
                None => (
                    decl.value.span.start,
                    decl.value.span.end,
                    quantity(b.value, b.dim),
                ),
            };
            let from = self.text[start as usize..end as usize].to_string();
            self.changes.push(Change::Value {
                element: id,
                from,
                to: to.clone(),
            });
            self.splice(start as usize, end as usize, to);
        }
        Ok(())
    }

    /// Markers and landmarks: values in place, else the statement printed again.
    fn members(&mut self) -> Result<(), EditError> {
        let (o, n) = (self.old, self.new);
        for i in 0..o.markers.len() {
            let (a, b) = (&o.markers[i], &n.markers[i]);
            let id = ElementId::Marker(MarkerId(i as u32));
            if a.name != b.name || a.part != b.part {
                return Err(self.unsupported(Some(id), "a renamed or moved marker"));
            }
            if self.fields(id, (a, b), marker_vals, same_marker_shape(a, b)) {
                continue;
            }
            // A new frame form: the position in place, the orientation after it.
            let walk: Walk<Marker> = |m, f| m.position.iter_mut().for_each(f);
            let span = splice::member(self.ast, &o.part(a.part).name, &a.name, false);
            let marks = (self.splices.len(), self.changes.len());
            if let (Some((decl, at)), true) = (span, self.fields(id, (a, b), walk, true)) {
                let from = splice::code_end(self.text, at.start as usize, at.end as usize);
                let to = splice::code_end(self.text, decl.start as usize, decl.end as usize);
                if splice::comments_within(self.text, from, to).is_empty() {
                    self.changes.push(Change::Reprinted { element: id });
                    self.splice(from, to, orientation(n, b));
                    continue;
                }
            }
            self.splices.truncate(marks.0);
            self.changes.truncate(marks.1);
            let line = marker_line(n, b);
            self.restate(id, &o.part(a.part).name, &a.name, false, line)?;
        }
        for i in 0..o.landmarks.len() {
            let (a, b) = (&o.landmarks[i], &n.landmarks[i]);
            let id = ElementId::Landmark(LandmarkId(i as u32));
            if a.name != b.name || a.part != b.part {
                return Err(self.unsupported(Some(id), "a renamed or moved landmark"));
            }
            let walk: Walk<Landmark> = |l, f| l.position.iter_mut().for_each(f);
            if !self.fields(id, (a, b), walk, same_shape(a, b, walk)) {
                let line = landmark_line(n, b);
                self.restate(id, &o.part(a.part).name, &a.name, true, line)?;
            }
        }
        Ok(())
    }

    /// Replaces a marker or landmark statement by `line`, keeping the
    /// comments written inside it above it.
    fn restate(
        &mut self,
        id: ElementId,
        part: &str,
        name: &str,
        landmark: bool,
        line: String,
    ) -> Result<(), EditError> {
        let Some((span, _)) = splice::member(self.ast, part, name, landmark) else {
            return Err(self.unsupported(Some(id), "an element not written in this file"));
        };
        let (s, e) = (span.start as usize, span.end as usize);
        self.replace_keeping_comments(id, s, e, line);
        Ok(())
    }

    fn replace_keeping_comments(&mut self, id: ElementId, s: usize, e: usize, printed: String) {
        let e = splice::code_end(self.text, s, e);
        let indent = splice::indent_at(self.text, s).to_string();
        let mut text = String::new();
        for c in splice::comments_within(self.text, s, e) {
            text.push_str(&c);
            text.push('\n');
            text.push_str(&indent);
        }
        text.push_str(printed.trim_end());
        self.changes.push(Change::Reprinted { element: id });
        self.splice(s, e, text);
    }

    /// Joints, bushings, springs, stops, frictions, wheels.
    fn elements(&mut self) -> Result<(), EditError> {
        let (o, n) = (self.old, self.new);
        for i in 0..o.joints.len() {
            if o.joints[i] != n.joints[i] {
                self.reprint(
                    ElementId::Joint(JointId(i as u32)),
                    "joint",
                    &o.joints[i].name,
                )?;
            }
        }
        for i in 0..o.wheels.len() {
            if o.wheels[i] != n.wheels[i] {
                self.reprint(
                    ElementId::Wheel(WheelId(i as u32)),
                    "wheel",
                    &o.wheels[i].name,
                )?;
            }
        }
        for i in 0..o.bushings.len() {
            let id = ElementId::Bushing(BushingId(i as u32));
            let (a, b) = (&o.bushings[i], &n.bushings[i]);
            if !self.fields(id, (a, b), bushing_vals, same_shape(a, b, bushing_vals)) {
                self.reprint(id, "bushing", &o.bushings[i].name)?;
            }
        }
        for i in 0..o.springs.len() {
            let id = ElementId::Spring(SpringId(i as u32));
            let (a, b) = (&o.springs[i], &n.springs[i]);
            if !self.fields(id, (a, b), spring_vals, same_shape(a, b, spring_vals)) {
                self.reprint(id, "spring", &o.springs[i].name)?;
            }
        }
        for i in 0..o.stops.len() {
            let id = ElementId::Stop(StopId(i as u32));
            let (a, b) = (&o.stops[i], &n.stops[i]);
            if !self.fields(id, (a, b), stop_vals, same_shape(a, b, stop_vals)) {
                self.reprint(id, "stop", &o.stops[i].name)?;
            }
        }
        for i in 0..o.frictions.len() {
            let id = ElementId::Friction(FrictionId(i as u32));
            let (a, b) = (&o.frictions[i], &n.frictions[i]);
            if !self.fields(id, (a, b), friction_vals, same_shape(a, b, friction_vals)) {
                self.reprint(id, "friction", &o.frictions[i].name)?;
            }
        }
        Ok(())
    }

    /// Prints an element block again in place of the one written.
    fn reprint(&mut self, id: ElementId, keyword: &str, name: &str) -> Result<(), EditError> {
        let (Some(item), Some(printed)) = (
            splice::element(self.ast, keyword, name),
            element(self.new, id),
        ) else {
            return Err(
                self.unsupported(Some(id), "an element this file does not write as a block")
            );
        };
        let (s, e) = (item.span.start as usize, item.span.end as usize);
        self.replace_keeping_comments(id, s, e, printed);
        Ok(())
    }
}
