//! The text of a model a command changed (`identify -o`, `locate -o`,
//! `correct -o`): the user's own file with only the changes (`fmt::edit`),
//! never generated source. Written by the caller through `write`.

use super::Exit;
use crate::diagnostic::render;
use crate::fmt::{Request, edit_source};
use crate::model::{ElementId, Model};
use crate::source::SourceMap;
use crate::span::FileId;

/// Edits the text of `file` (whose checked model is `old`) to hold `new`;
/// renders the refusal as a diagnostic (exit 1, nothing to write) otherwise.
pub fn edited(
    sources: &SourceMap,
    file: FileId,
    old: &Model,
    new: &Model,
    tool: &str,
    reasons: &[(ElementId, String)],
) -> Result<String, Exit> {
    let req = Request { tool, reasons };
    let name = sources.name(file);
    match edit_source(file, name, sources.text(file), old, new, &req) {
        Ok(e) => Ok(e.text),
        Err(e) => {
            render::to_stderr(sources, &[e.to_diagnostic()]);
            Err(Exit::Input)
        }
    }
}
