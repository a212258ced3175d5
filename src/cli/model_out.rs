//! Writing a model a command changed (`identify -o`, `locate -o`, `correct -o`):
//! the user's own file with only the changes (`fmt::edit`), never generated
//! source; nothing is written when the edit is refused.

use super::Exit;
use crate::diagnostic::render;
use crate::fmt::{Request, edit_source};
use crate::model::{ElementId, Model};
use crate::source::SourceMap;
use crate::span::FileId;
use std::path::Path;

/// Edits the text of `file` (whose checked model is `old`) to hold `new` and
/// writes it to `out`; renders the refusal as a diagnostic otherwise.
pub fn write_model(
    sources: &SourceMap,
    file: FileId,
    old: &Model,
    new: &Model,
    tool: &str,
    reasons: &[(ElementId, String)],
    out: &Path,
) -> Result<(), Exit> {
    let req = Request { tool, reasons };
    let edited = edit_source(file, sources.name(file), sources.text(file), old, new, &req)
        .map_err(|e| {
            render::to_stderr(sources, &[e.to_diagnostic()]);
            Exit::Input
        })?;
    std::fs::write(out, edited.text).map_err(|e| {
        eprintln!("error: cannot write {}: {e}", out.display());
        Exit::Io
    })
}
