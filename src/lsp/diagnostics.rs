//! `textDocument/publishDiagnostics`: exactly the diagnostics of `axle check`
//! (the mobility analysis only after a save), converted by `render::to_lsp`.

use super::document::{Document, LIVE_LIMIT};
use crate::diagnostic::render;
use lsp_types::{Diagnostic, DiagnosticSeverity, PublishDiagnosticsParams, Uri};

pub fn publish(doc: &Document, version: Option<i32>) -> PublishDiagnosticsParams {
    let uri_of = |f: crate::span::FileId| -> Option<Uri> {
        if f == doc.file {
            Some(doc.uri.clone())
        } else {
            super::stdlib::uri(doc.sources.name(f))
        }
    };
    let diagnostics: Vec<Diagnostic> = match &doc.analysis {
        Some(a) => a
            .problems
            .list
            .iter()
            .map(|d| render::to_lsp(&doc.sources, doc.file, d, &uri_of))
            .collect(),
        None => vec![Diagnostic {
            severity: Some(DiagnosticSeverity::INFORMATION),
            source: Some("axle lsp".into()),
            message: format!(
                "this file has {} bytes, more than the {} checked as you type; run `axle check` on it",
                doc.text().len(),
                LIVE_LIMIT
            ),
            ..Default::default()
        }],
    };
    PublishDiagnosticsParams {
        uri: doc.uri.clone(),
        diagnostics,
        version,
    }
}
