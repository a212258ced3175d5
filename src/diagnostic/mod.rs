//! Diagnostics as data: every stage's errors become [`Diagnostic`]s, worded once
//! in that stage's error module and rendered late by [`render`].

pub mod render;
pub mod suggest;

use crate::span::Span;
use serde::Serialize;

#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Severity {
    Error,
    Warning,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Label {
    pub span: Span,
    pub message: String,
    pub primary: bool,
    /// A machine-applicable correction of the labelled text (the did-you-mean
    /// candidate in place of a misspelt name), for editors' quick fixes; the
    /// diagnostic's hint words it.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fix: Option<String>,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Diagnostic {
    pub severity: Severity,
    /// Stable code (`E0101`), so scripts and the docs can refer to a diagnostic.
    pub code: &'static str,
    pub message: String,
    pub labels: Vec<Label>,
    pub notes: Vec<String>,
    pub hint: Option<String>,
}

impl Diagnostic {
    pub fn error(code: &'static str, message: impl Into<String>) -> Diagnostic {
        Diagnostic {
            severity: Severity::Error,
            code,
            message: message.into(),
            labels: Vec::new(),
            notes: Vec::new(),
            hint: None,
        }
    }

    pub fn warning(code: &'static str, message: impl Into<String>) -> Diagnostic {
        Diagnostic {
            severity: Severity::Warning,
            ..Diagnostic::error(code, message)
        }
    }

    pub fn primary(mut self, span: Span, message: impl Into<String>) -> Self {
        self.labels.push(Label {
            span,
            message: message.into(),
            primary: true,
            fix: None,
        });
        self
    }

    pub fn secondary(mut self, span: Span, message: impl Into<String>) -> Self {
        self.labels.push(Label {
            span,
            message: message.into(),
            primary: false,
            fix: None,
        });
        self
    }

    /// Adds a secondary label when the span is known (elements added by tools have none).
    pub fn secondary_opt(self, span: Option<Span>, message: impl Into<String>) -> Self {
        match span {
            Some(s) => self.secondary(s, message),
            None => self,
        }
    }

    pub fn note(mut self, note: impl Into<String>) -> Self {
        self.notes.push(note.into());
        self
    }

    pub fn hint(mut self, hint: impl Into<String>) -> Self {
        self.hint = Some(hint.into());
        self
    }

    /// Offers `replacement` for the text of the label at `span` as a quick fix
    /// (nothing when no label has that span: a fix always replaces labelled text).
    pub fn fix(mut self, span: Span, replacement: impl Into<String>) -> Self {
        if let Some(l) = self.labels.iter_mut().find(|l| l.span == span) {
            l.fix = Some(replacement.into());
        }
        self
    }

    /// The quick fixes: a span and its replacement.
    pub fn fixes(&self) -> impl Iterator<Item = (Span, &str)> + '_ {
        self.labels
            .iter()
            .filter_map(|l| Some((l.span, l.fix.as_deref()?)))
    }

    /// The did-you-mean hint for the closest candidate, with its quick fix when
    /// `span` is the name itself (not a longer text such as a load channel).
    pub fn did_you_mean<'a>(
        self,
        span: Span,
        name: &str,
        candidates: impl IntoIterator<Item = &'a str>,
    ) -> Self {
        match suggest::best(name, candidates) {
            Some(c) if span.range().len() == name.len() => {
                self.hint(suggest::did_you_mean_text(c)).fix(span, c)
            }
            Some(c) => self.hint(suggest::did_you_mean_text(c)),
            None => self,
        }
    }

    pub fn is_error(&self) -> bool {
        self.severity == Severity::Error
    }
}

/// The diagnostics of one run, in the order they were found.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Problems {
    pub list: Vec<Diagnostic>,
}

impl Problems {
    pub fn push(&mut self, d: Diagnostic) {
        self.list.push(d);
    }

    pub fn has_errors(&self) -> bool {
        self.list.iter().any(Diagnostic::is_error)
    }

    pub fn extend(&mut self, other: Problems) {
        self.list.extend(other.list);
    }
}
