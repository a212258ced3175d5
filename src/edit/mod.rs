//! Validated model edits, the operations tools (diagnosis, identification,
//! import) use to extend a model: add a force element, change a bushing law,
//! move a joint or bushing point, replace a joint by a bushing, split a part
//! into two joined by a six-axis bushing.
//!
//! Arenas are append-only, so every id a caller holds stays valid: a replaced
//! joint is retired (`Model::retired_joints`), not removed. An edit is applied
//! to a copy, the copy goes through [`crate::check::validate::validate`] (the
//! checker's rules), and only a valid result replaces the model; an invalid
//! edit is an [`EditError`] naming the edit. Each edited element records
//! "added by <tool>: <why>" (or "changed by") in its origins, for printers.

mod split;

pub use split::Split;

use crate::diagnostic::Diagnostic;
use crate::geom::Vec3;
use crate::model::*;

/// Who asks for an edit, and why: recorded on the element.
#[derive(Debug, Clone, PartialEq)]
pub struct Why {
    pub tool: String,
    pub reason: String,
}

impl Why {
    pub fn new(tool: &str, reason: &str) -> Why {
        Why {
            tool: tool.into(),
            reason: reason.into(),
        }
    }
}

/// One change to a model.
// Edits are made one at a time, never stored in bulk: their size is no cost.
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Clone, PartialEq)]
pub enum Edit {
    AddBushing(Bushing),
    AddSpring(Spring),
    AddStop(Stop),
    AddFriction(Friction),
    /// The law of one bushing axis (`rotational` picks kt): e.g. linear to
    /// cubic, or to a table. On an axisymmetric family, x and y are one law.
    SetLaw {
        bushing: BushingId,
        rotational: bool,
        axis: Axis,
        law: AxisLaw,
    },
    /// Moves a joint's or bushing's point to `to` (mm, global at design): both
    /// markers, or with `part` only the marker on that part.
    MovePoint {
        element: ElementId,
        part: Option<PartId>,
        to: Vec3,
    },
    /// Retires the joint and joins its two markers by a bushing (stiffnesses
    /// N/mm and N·mm/rad along the J marker's axes).
    JointToBushing {
        joint: JointId,
        k: [f64; 3],
        kt: [f64; 3],
    },
    /// Part compliance: see [`Split`].
    SplitPart(Split),
}

/// What an edit made, by id.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Applied {
    Added(ElementId),
    Changed(ElementId),
    Replaced { joint: JointId, by: BushingId },
    Split { part: PartId, bushing: BushingId },
}

/// An edit the model refused, with the checker's diagnostics.
#[derive(Debug, Clone, PartialEq)]
pub struct EditError {
    /// The edit, as a sentence ("replace joint `L7` by a bushing").
    pub edit: String,
    pub problems: Vec<Diagnostic>,
}

impl std::fmt::Display for EditError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let msgs: Vec<String> = self
            .problems
            .iter()
            .map(|d| format!("{} [{}]", d.message, d.code))
            .collect();
        write!(f, "cannot {}: {}", self.edit, msgs.join("; "))
    }
}

impl Edit {
    /// The edit as a sentence, for errors and notes.
    pub fn describe(&self, m: &Model) -> String {
        let name = |id: ElementId| {
            if valid_id(m, id) {
                m.describe(id)
            } else {
                format!("{id:?} (no such element)")
            }
        };
        match self {
            Edit::AddBushing(b) => format!("add bushing `{}`", b.name),
            Edit::AddSpring(s) => format!("add spring `{}`", s.name),
            Edit::AddStop(s) => format!("add stop `{}`", s.name),
            Edit::AddFriction(f) => format!("add friction `{}`", f.name),
            Edit::SetLaw {
                bushing,
                rotational,
                axis,
                ..
            } => format!(
                "change the {} law of {} along {}",
                if *rotational { "kt" } else { "k" },
                name(ElementId::Bushing(*bushing)),
                axis.name()
            ),
            Edit::MovePoint { element, part, .. } => match part {
                Some(p) if p.index() < m.parts.len() => {
                    format!(
                        "move the point of {} on part `{}`",
                        name(*element),
                        m.part(*p).name
                    )
                }
                _ => format!("move the point of {}", name(*element)),
            },
            Edit::JointToBushing { joint, .. } => {
                format!("replace {} by a bushing", name(ElementId::Joint(*joint)))
            }
            Edit::SplitPart(s) => s.describe(m),
        }
    }
}

fn valid_id(m: &Model, id: ElementId) -> bool {
    match id {
        ElementId::Part(x) => x.index() < m.parts.len(),
        ElementId::Marker(x) => x.index() < m.markers.len(),
        ElementId::Landmark(x) => x.index() < m.landmarks.len(),
        ElementId::Joint(x) => x.index() < m.joints.len(),
        ElementId::Bushing(x) => x.index() < m.bushings.len(),
        ElementId::Spring(x) => x.index() < m.springs.len(),
        ElementId::Stop(x) => x.index() < m.stops.len(),
        ElementId::Friction(x) => x.index() < m.frictions.len(),
        ElementId::Wheel(x) => x.index() < m.wheels.len(),
        ElementId::Param(x) => x.index() < m.params.len(),
        ElementId::LoadSet(x) => x.index() < m.load_sets.len(),
    }
}

/// A refusal before validation (the edit cannot even be made).
fn refuse(edit: &str, why: String) -> EditError {
    EditError {
        edit: edit.to_string(),
        problems: vec![Diagnostic::error("E0420", why)],
    }
}

/// Applies `edit` to `model` if the result passes the checker's rules;
/// otherwise leaves `model` unchanged and says why.
pub fn apply(model: &mut Model, edit: Edit, why: &Why) -> Result<Applied, EditError> {
    let text = edit.describe(model);
    let mut work = model.clone();
    let applied = make(&mut work, edit, &text)?;
    let (id, verb) = match applied {
        Applied::Added(id) => (id, "added"),
        Applied::Changed(id) => (id, "changed"),
        Applied::Replaced { by, .. } => (ElementId::Bushing(by), "added"),
        Applied::Split { bushing, .. } => (ElementId::Bushing(bushing), "added"),
    };
    let note = format!("{verb} by {}: {}", why.tool, why.reason);
    work.origins.note_edit(id, note.clone());
    if let Applied::Split { part, .. } = applied {
        work.origins.note_edit(ElementId::Part(part), note);
    }
    let problems = crate::check::validate::validate(&work);
    if problems.has_errors() {
        return Err(EditError {
            edit: text,
            problems: problems.list.into_iter().filter(|d| d.is_error()).collect(),
        });
    }
    *model = work;
    Ok(applied)
}

fn unique(m: &Model, name: &str, text: &str) -> Result<(), EditError> {
    let taken = m.bushings.iter().any(|b| b.name == name)
        || m.springs.iter().any(|b| b.name == name)
        || m.stops.iter().any(|b| b.name == name)
        || m.frictions.iter().any(|b| b.name == name)
        || m.joints.iter().any(|b| b.name == name);
    if taken {
        return Err(refuse(
            text,
            format!("an element is already called `{name}`"),
        ));
    }
    Ok(())
}

fn markers_exist(m: &Model, ids: &[MarkerId], text: &str) -> Result<(), EditError> {
    match ids.iter().find(|i| i.index() >= m.markers.len()) {
        Some(i) => Err(refuse(text, format!("marker #{} does not exist", i.0))),
        None => Ok(()),
    }
}

/// Makes the edit on `m` (a working copy), without validating it.
fn make(m: &mut Model, edit: Edit, text: &str) -> Result<Applied, EditError> {
    let id_of = |n: usize| n as u32;
    match edit {
        Edit::AddBushing(b) => {
            unique(m, &b.name, text)?;
            markers_exist(m, &[b.i, b.j], text)?;
            m.bushings.push(b);
            Ok(Applied::Added(ElementId::Bushing(BushingId(id_of(
                m.bushings.len() - 1,
            )))))
        }
        Edit::AddSpring(s) => {
            unique(m, &s.name, text)?;
            markers_exist(m, &[s.i, s.j], text)?;
            m.springs.push(s);
            Ok(Applied::Added(ElementId::Spring(SpringId(id_of(
                m.springs.len() - 1,
            )))))
        }
        Edit::AddStop(s) => {
            unique(m, &s.name, text)?;
            markers_exist(m, &[s.i, s.j], text)?;
            m.stops.push(s);
            Ok(Applied::Added(ElementId::Stop(StopId(id_of(
                m.stops.len() - 1,
            )))))
        }
        Edit::AddFriction(f) => {
            unique(m, &f.name, text)?;
            if f.joint.index() >= m.joints.len() {
                return Err(refuse(text, format!("joint #{} does not exist", f.joint.0)));
            }
            m.frictions.push(f);
            Ok(Applied::Added(ElementId::Friction(FrictionId(id_of(
                m.frictions.len() - 1,
            )))))
        }
        Edit::SetLaw {
            bushing,
            rotational,
            axis,
            law,
        } => {
            let Some(b) = m.bushings.get_mut(bushing.index()) else {
                return Err(refuse(
                    text,
                    format!("bushing #{} does not exist", bushing.0),
                ));
            };
            let laws = if rotational {
                &mut b.rotational
            } else {
                &mut b.translational
            };
            *laws.get_mut(axis.index()) = law;
            Ok(Applied::Changed(ElementId::Bushing(bushing)))
        }
        Edit::MovePoint { element, part, to } => {
            let (i, j) = match element {
                ElementId::Joint(x) if x.index() < m.joints.len() => {
                    (m.joints[x.index()].i, m.joints[x.index()].j)
                }
                ElementId::Bushing(x) if x.index() < m.bushings.len() => {
                    (m.bushings[x.index()].i, m.bushings[x.index()].j)
                }
                _ => {
                    return Err(refuse(
                        text,
                        "only a joint's or a bushing's point can be moved".into(),
                    ));
                }
            };
            let moved: Vec<MarkerId> = match part {
                None => vec![i, j],
                Some(p) => {
                    let on: Vec<MarkerId> = [i, j]
                        .into_iter()
                        .filter(|x| m.marker(*x).part == p)
                        .collect();
                    if on.is_empty() {
                        return Err(refuse(
                            text,
                            format!("{} has no marker on that part", m.describe(element)),
                        ));
                    }
                    on
                }
            };
            for mk in moved {
                for a in Axis::ALL {
                    let at = crate::model::address::Address {
                        element: ElementId::Marker(mk),
                        field: crate::model::schema::FieldId::Position,
                        axis: Some(a),
                    };
                    at.set(m, to[a.index()]);
                }
            }
            Ok(Applied::Changed(element))
        }
        Edit::JointToBushing { joint, k, kt } => {
            let Some(jt) = m.joints.get(joint.index()).cloned() else {
                return Err(refuse(text, format!("joint #{} does not exist", joint.0)));
            };
            if m.is_retired(joint) {
                return Err(refuse(
                    text,
                    format!("joint `{}` was already replaced", jt.name),
                ));
            }
            if let Some(f) = m.frictions.iter().find(|f| f.joint == joint) {
                return Err(refuse(
                    text,
                    format!(
                        "friction `{}` acts on joint `{}`; a bushing has no slider for it",
                        f.name, jt.name
                    ),
                ));
            }
            let name = format!("{}_bushing", jt.name);
            unique(m, &name, text)?;
            m.retired_joints.insert(joint);
            m.bushings.push(Bushing::linear(&name, jt.i, jt.j, k, kt));
            let by = BushingId(id_of(m.bushings.len() - 1));
            Ok(Applied::Replaced { joint, by })
        }
        Edit::SplitPart(s) => s.make(m, text),
    }
}

#[cfg(test)]
#[path = "tests.rs"]
mod tests;
