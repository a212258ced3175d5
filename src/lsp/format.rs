//! `textDocument/formatting`: `axle fmt` on the editor's text, as one edit.

use super::Failure;
use super::document::Document;
use lsp_types::{Position, Range, TextEdit};

pub fn format(doc: &Document) -> Result<Vec<TextEdit>, Failure> {
    let text = doc.text();
    let formatted = crate::fmt::format_source(doc.file, text).map_err(|d| {
        // The file's syntax error is already among its diagnostics.
        Failure::refused(format!(
            "cannot format a file with a syntax error: {}",
            d.message
        ))
    })?;
    if formatted == text {
        return Ok(Vec::new());
    }
    let (line, character) = doc.sources.utf16_position(doc.file, text.len());
    Ok(vec![TextEdit {
        range: Range {
            start: Position::new(0, 0),
            end: Position { line, character },
        },
        new_text: formatted,
    }])
}
