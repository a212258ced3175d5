//! Errors of the statics backend: data naming the model elements responsible
//! (`style.md`: errors are data, wording is rendered late).

use crate::diagnostic::Diagnostic;
use crate::model::{ElementId, Model};
use std::fmt;

/// What went wrong in a static solve or in compiling a problem.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StaticsErrorKind {
    /// The model has no ground part (nothing to hold the mechanism).
    NoGround,
    /// A force element is geometrically degenerate (a spring of zero length).
    DegenerateElement,
    /// A motion is not restrained by any joint or force element: the tangent
    /// system is singular. `elements` names the part that moves most.
    Unrestrained,
    /// Newton did not reach the tolerance even with the smallest load sub-step;
    /// `elements` names the element with the largest residual.
    NotConverged,
    /// A redundant constraint equation that the solver left out is violated at
    /// the solution (the redundant joints disagree).
    InconsistentRedundancy,
    /// A load refers to a marker or load set that does not exist.
    BadInput,
}

/// A statics failure: its kind, the elements responsible, and a detail text.
#[derive(Debug, Clone, PartialEq)]
pub struct StaticsError {
    pub kind: StaticsErrorKind,
    pub elements: Vec<ElementId>,
    pub detail: String,
}

impl StaticsError {
    pub fn new(
        kind: StaticsErrorKind,
        elements: Vec<ElementId>,
        detail: impl Into<String>,
    ) -> Self {
        StaticsError {
            kind,
            elements,
            detail: detail.into(),
        }
    }

    /// A one-line message naming the elements by kind and name.
    pub fn message(&self, model: &Model) -> String {
        let names: Vec<String> = self.elements.iter().map(|&e| model.describe(e)).collect();
        if names.is_empty() {
            self.detail.clone()
        } else {
            format!("{} ({})", self.detail, names.join(", "))
        }
    }
}

impl StaticsErrorKind {
    /// Stable diagnostic code (`E10xx`: statics; `E06xx` is the checker's mobility analysis).
    pub fn code(self) -> &'static str {
        match self {
            StaticsErrorKind::NoGround => "E1001",
            StaticsErrorKind::DegenerateElement => "E1002",
            StaticsErrorKind::Unrestrained => "E1003",
            StaticsErrorKind::NotConverged => "E1004",
            StaticsErrorKind::InconsistentRedundancy => "E1005",
            StaticsErrorKind::BadInput => "E1006",
        }
    }

    /// What the user can try, in one sentence.
    fn hint(self) -> Option<&'static str> {
        match self {
            StaticsErrorKind::NoGround => Some("declare one part with `ground` instead of `part`"),
            StaticsErrorKind::Unrestrained => Some(
                "add a joint or a bushing that holds this motion, or give the bushing a stiffness on that axis",
            ),
            StaticsErrorKind::NotConverged => Some(
                "check the stiffnesses and the load size; a very soft element under a large load may fold the mechanism",
            ),
            StaticsErrorKind::InconsistentRedundancy => {
                Some("make the joints of the loop agree at the design configuration")
            }
            StaticsErrorKind::DegenerateElement | StaticsErrorKind::BadInput => None,
        }
    }
}

impl StaticsError {
    /// The diagnostic of this failure. The first element is the primary label
    /// (the one responsible), the others secondary; an element without an origin
    /// (added by a tool, not written in a file) is named in a note instead, so
    /// the message always names every element responsible.
    pub fn to_diagnostic(&self, model: &Model) -> Diagnostic {
        let mut d = Diagnostic::error(self.kind.code(), self.message(model));
        let mut primary = true;
        for &e in &self.elements {
            let what = model.describe(e);
            match model.origins.get(e) {
                Some(span) if primary => {
                    d = d.primary(span, format!("{what} is responsible"));
                    primary = false;
                }
                Some(span) => d = d.secondary(span, format!("{what} is involved")),
                None => {
                    d = d.note(format!(
                        "{what} has no source location (it was added by a tool)"
                    ))
                }
            }
        }
        match self.kind.hint() {
            Some(h) => d.hint(h),
            None => d,
        }
    }
}

impl fmt::Display for StaticsError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{:?}: {}", self.kind, self.detail)
    }
}

impl std::error::Error for StaticsError {}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{Part, PartId};

    #[test]
    fn elements_without_origin_are_named_in_the_message_and_a_note() {
        let mut model = Model::default();
        model.parts.push(Part {
            name: "added_link".into(),
            ground: false,
        });
        let e = StaticsError::new(
            StaticsErrorKind::Unrestrained,
            vec![ElementId::Part(PartId(0))],
            "nothing restrains it",
        );
        let d = e.to_diagnostic(&model);
        assert_eq!(d.code, "E1003");
        assert!(d.labels.is_empty());
        assert!(d.message.contains("part `added_link`"), "{}", d.message);
        assert!(d.notes.iter().any(|n| n.contains("added by a tool")));
    }

    #[test]
    fn elements_with_origin_get_labels() {
        let (_, c) = crate::check::check_str(
            "t.axle",
            // The bushing holds p: the checker rejects a free part before statics.
            "ground g {\n    marker o at (0, 0, 0) mm\n}\npart p {\n    marker o at (0, 0, 0) mm\n}\n\
             bushing b {\n    i g.o\n    j p.o\n    k (1, 1, 1) N/mm\n    kt (1, 1, 1) N*mm/deg\n}\n",
        );
        let model = c.model.expect("checks");
        let e = StaticsError::new(
            StaticsErrorKind::NotConverged,
            vec![ElementId::Part(PartId(1))],
            "stuck",
        );
        let d = e.to_diagnostic(&model);
        assert_eq!(d.labels.len(), 1);
        assert!(d.labels[0].primary && d.labels[0].message.contains("part `p`"));
    }
}
