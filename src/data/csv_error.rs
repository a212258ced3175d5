//! Errors of the CSV readers: data with the byte span of the offending line or
//! field, so a diagnostic shows `file:line:column` and the line itself.

use crate::diagnostic::Diagnostic;
use crate::span::{FileId, Span};

/// A problem in a data file, located by byte range.
#[derive(Debug, Clone, PartialEq)]
pub struct CsvError {
    /// `E07xx`, stable for scripts.
    pub code: &'static str,
    pub message: String,
    /// Byte range of the line or field at fault (empty at the end of the file).
    pub start: usize,
    pub end: usize,
    /// What the label under the excerpt says.
    pub label: String,
    pub hint: Option<String>,
}

impl CsvError {
    pub fn new(
        code: &'static str,
        message: impl Into<String>,
        range: (usize, usize),
        label: impl Into<String>,
    ) -> Self {
        CsvError {
            code,
            message: message.into(),
            start: range.0,
            end: range.1,
            label: label.into(),
            hint: None,
        }
    }

    pub fn with_hint(mut self, hint: Option<String>) -> Self {
        self.hint = hint;
        self
    }

    /// The diagnostic, pointing into the data file `file` of the source map.
    pub fn to_diagnostic(&self, file: FileId) -> Diagnostic {
        let d = Diagnostic::error(self.code, self.message.clone())
            .primary(Span::new(file, self.start, self.end), self.label.clone());
        match &self.hint {
            Some(h) => d.hint(h.clone()),
            None => d,
        }
    }
}
