//! Errors of the statics backend: data naming the model elements responsible
//! (`style.md`: errors are data, wording is rendered late).

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

impl fmt::Display for StaticsError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{:?}: {}", self.kind, self.detail)
    }
}

impl std::error::Error for StaticsError {}
