//! Why an edit was refused. Nothing is written then: the user's file is never
//! replaced by one that does not check or does not hold the model asked for.

use crate::diagnostic::Diagnostic;
use crate::span::Span;

#[derive(Debug, Clone, PartialEq)]
pub enum EditError {
    /// The input text no longer parses (it was checked before, so it changed).
    Input(Box<Diagnostic>),
    /// A change this file cannot take in place (a removed element, new load sets).
    Unsupported {
        /// The element, as `Model::describe` names it, and where it is written.
        element: Option<(String, Option<Span>)>,
        what: String,
    },
    /// One number in the file stands for two fields that now differ.
    Conflict { span: Span },
    /// The edited text does not check; its first error.
    DoesNotCheck {
        text: String,
        first: Option<Box<Diagnostic>>,
    },
    /// The edited text checks but prints another model: the first line that differs.
    DoesNotReproduce { expected: String, found: String },
}

impl EditError {
    pub fn to_diagnostic(&self) -> Diagnostic {
        const NOTHING: &str = "nothing was written; the input file is unchanged";
        match self {
            EditError::Input(d) => (**d).clone(),
            EditError::Unsupported { element, what } => {
                let mut d = Diagnostic::error(
                    "E1201",
                    format!("cannot write this change into the file: {what}"),
                );
                if let Some((name, span)) = element {
                    d = match span {
                        Some(s) => d.primary(*s, format!("{name} is written here")),
                        None => d.note(format!("the change is to {name}")),
                    };
                }
                d.note(NOTHING)
            }
            EditError::Conflict { span } => Diagnostic::error(
                "E1202",
                "one number in the file stands for two fields that now have different values",
            )
            .primary(*span, "written once here")
            .note(NOTHING)
            .hint("write the fields separately (e.g. `k_x`, `k_y` instead of `k_radial`)"),
            EditError::DoesNotCheck { first, .. } => {
                let d = Diagnostic::error("E1203", "the edited file would not check");
                let d = match first {
                    Some(f) => d.note(format!("its first error: {} [{}]", f.message, f.code)),
                    None => d,
                };
                d.note(NOTHING)
            }
            EditError::DoesNotReproduce { expected, found } => Diagnostic::error(
                "E1204",
                "the edited file would not hold the model the command computed",
            )
            .note(format!("expected `{expected}`"))
            .note(format!("found    `{found}`"))
            .note(NOTHING),
        }
    }
}

impl std::fmt::Display for EditError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.to_diagnostic().message)
    }
}
