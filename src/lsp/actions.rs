//! Quick fixes: the checker's did-you-mean candidates (carried as data on the
//! diagnostics' labels), offered for the diagnostics the range touches.

use super::document::Document;
use lsp_types::{CodeAction, CodeActionKind, CodeActionOrCommand, Range, TextEdit, WorkspaceEdit};
use std::collections::HashMap;

pub fn quick_fixes(doc: &Document, range: Range) -> Vec<CodeActionOrCommand> {
    let Some(a) = doc.analysis.as_ref() else {
        return Vec::new();
    };
    let uri_of = |f: crate::span::FileId| (f == doc.file).then(|| doc.uri.clone());
    let mut out = Vec::new();
    for d in &a.problems.list {
        for (span, text) in d.fixes() {
            if span.file != doc.file {
                continue;
            }
            let r = doc.range(span);
            if r.end < range.start || r.start > range.end {
                continue;
            }
            let edit = TextEdit {
                range: r,
                new_text: text.to_string(),
            };
            out.push(CodeActionOrCommand::CodeAction(CodeAction {
                title: format!("replace `{}` with `{text}`", &doc.text()[span.range()]),
                kind: Some(CodeActionKind::QUICKFIX),
                diagnostics: Some(vec![crate::diagnostic::render::to_lsp(
                    &doc.sources,
                    doc.file,
                    d,
                    &uri_of,
                )]),
                edit: Some(WorkspaceEdit {
                    changes: Some(HashMap::from([(doc.uri.clone(), vec![edit])])),
                    ..Default::default()
                }),
                is_preferred: Some(true),
                ..Default::default()
            }));
        }
    }
    out
}
