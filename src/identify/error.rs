//! Failures of identification as data: a kind with a stable code (E11xx), the
//! sentence of the site that failed, the elements responsible, and the statics
//! failure underneath when a solve failed. Worded once here; rendered late.

use crate::diagnostic::Diagnostic;
use crate::model::{ElementId, Model};
use crate::statics::StaticsError;

/// What kind of failure; each has its code (`docs/language.md`, "codes").
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum IdentifyErrorKind {
    /// The measured data and the model do not fit together (steps without
    /// loads, case counts, no pose).
    Data,
    /// Command-line choices that cannot work (an unknown load set, no loads,
    /// a non-positive tolerance or start value).
    Options,
    /// Nothing to identify, or an unknown that names no field.
    Unknowns,
    /// The chosen method cannot identify this (iterative beyond bushings,
    /// direct with geometric unknowns, a part without a measured pose).
    Method,
    /// The data cannot determine the unknowns (too few observations, no
    /// admissible motion, an undetermined registration).
    Undetermined,
    /// The model does not solve; `source` holds the statics failure.
    Solve,
    /// An iteration did not converge.
    NotConverged,
    /// A matrix or a Jacobian is not finite or singular.
    Numeric,
    /// The `--report` plots cannot be drawn from these data.
    Report,
}

impl IdentifyErrorKind {
    pub fn code(self) -> &'static str {
        match self {
            IdentifyErrorKind::Data => "E1101",
            IdentifyErrorKind::Options => "E1102",
            IdentifyErrorKind::Unknowns => "E1103",
            IdentifyErrorKind::Method => "E1104",
            IdentifyErrorKind::Undetermined => "E1105",
            IdentifyErrorKind::Solve => "E1106",
            IdentifyErrorKind::NotConverged => "E1107",
            IdentifyErrorKind::Numeric => "E1108",
            IdentifyErrorKind::Report => "E1109",
        }
    }

    /// What the user can try, in one sentence.
    fn hint(self) -> Option<&'static str> {
        match self {
            IdentifyErrorKind::Method => Some("`--method lsq` identifies any addressable field"),
            IdentifyErrorKind::Undetermined => Some(
                "measure more load cases or more parts, or identify fewer unknowns (`--unknown`)",
            ),
            IdentifyErrorKind::NotConverged => {
                Some("start nearer (`--initial`) or loosen `--tolerance`")
            }
            _ => None,
        }
    }
}

/// A numeric or data failure of identification, naming the elements at fault.
#[derive(Debug, Clone, PartialEq)]
pub struct IdentifyError {
    pub kind: IdentifyErrorKind,
    /// What happened, in the words of the site that found it.
    pub message: String,
    pub elements: Vec<ElementId>,
    /// The statics failure underneath, when a solve failed.
    pub source: Option<StaticsError>,
    /// The diagnostic itself, when the failure is a bad address on the
    /// command line (`--unknown`), worded once by `AddressError`.
    pub address: Option<Box<Diagnostic>>,
}

impl IdentifyError {
    pub fn of(
        kind: IdentifyErrorKind,
        message: impl Into<String>,
        elements: Vec<ElementId>,
    ) -> IdentifyError {
        IdentifyError {
            kind,
            message: message.into(),
            elements,
            source: None,
            address: None,
        }
    }

    /// A bad address (`--unknown A.k_raidal`): its diagnostic is the one
    /// every command that takes an address gives (E0803).
    pub fn address(d: Diagnostic) -> IdentifyError {
        IdentifyError {
            address: Some(Box::new(d.clone())),
            ..IdentifyError::of(IdentifyErrorKind::Unknowns, d.message, vec![])
        }
    }

    /// A solve that failed: `context` says which (`step 3 at the trial values`).
    pub fn statics(context: impl Into<String>, e: StaticsError, model: &Model) -> IdentifyError {
        let context = context.into();
        let message = match context.is_empty() {
            true => e.message(model),
            false => format!("{context}: {}", e.message(model)),
        };
        IdentifyError {
            kind: IdentifyErrorKind::Solve,
            message,
            elements: e.elements.clone(),
            source: Some(e),
            address: None,
        }
    }

    /// The diagnostic: the code of the kind, the statics code underneath in a
    /// note, the first element with a source location as the primary label.
    pub fn to_diagnostic(&self, model: &Model) -> Diagnostic {
        if let Some(d) = &self.address {
            return (**d).clone();
        }
        let mut d = Diagnostic::error(self.kind.code(), self.message.clone());
        let mut primary = true;
        for &e in &self.elements {
            let what = model.describe(e);
            match model.origins.get(e) {
                Some(span) if primary => {
                    d = d.primary(span, format!("{what} is responsible"));
                    primary = false;
                }
                Some(span) => d = d.secondary(span, format!("{what} is involved")),
                None => d = d.note(format!("{what} has no source location (added by a tool)")),
            }
        }
        if let Some(s) = &self.source {
            d = d.note(format!(
                "the statics failure underneath is {}",
                s.kind.code()
            ));
        }
        match self.kind.hint() {
            Some(h) => d.hint(h),
            None => d,
        }
    }
}

impl std::fmt::Display for IdentifyError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.message)
    }
}
