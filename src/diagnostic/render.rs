//! The only place that talks to codespan-reporting: diagnostics as coloured or
//! plain text, as JSON for `--format json`, and as LSP diagnostics for
//! `axle lsp` (the same values, so every wording is shared).

use super::{Diagnostic, Severity};
use crate::source::SourceMap;
use codespan_reporting::diagnostic::{
    Diagnostic as CsDiagnostic, Label as CsLabel, Severity as CsSeverity,
};
use codespan_reporting::term::{self, Config};
use serde::Serialize;

fn to_codespan(d: &Diagnostic) -> CsDiagnostic<crate::span::FileId> {
    let sev = match d.severity {
        Severity::Error => CsSeverity::Error,
        Severity::Warning => CsSeverity::Warning,
    };
    let labels = d
        .labels
        .iter()
        .map(|l| {
            let lab = if l.primary {
                CsLabel::primary(l.span.file, l.span.range())
            } else {
                CsLabel::secondary(l.span.file, l.span.range())
            };
            lab.with_message(l.message.clone())
        })
        .collect();
    let mut notes = d.notes.clone();
    if let Some(h) = &d.hint {
        notes.push(format!("help: {h}"));
    }
    CsDiagnostic::new(sev)
        .with_code(d.code)
        .with_message(d.message.clone())
        .with_labels(labels)
        .with_notes(notes)
}

/// Plain text, as printed to a pipe and stored in snapshots.
pub fn to_string(sources: &SourceMap, d: &Diagnostic) -> String {
    term::emit_into_string(&Config::default(), sources, &to_codespan(d))
        .unwrap_or_else(|e| format!("{}: {} (could not render: {e})\n", d.code, d.message))
}

/// Writes to stderr, coloured only when stderr is a terminal.
#[allow(clippy::print_stderr)] // the renderer is where diagnostics reach stderr
pub fn to_stderr(sources: &SourceMap, diags: &[Diagnostic]) {
    use codespan_reporting::term::termcolor::{ColorChoice, StandardStream};
    use std::io::IsTerminal;
    let choice = if std::io::stderr().is_terminal() && std::env::var_os("NO_COLOR").is_none() {
        ColorChoice::Auto
    } else {
        ColorChoice::Never
    };
    let w = StandardStream::stderr(choice);
    let mut lock = w.lock();
    for d in diags {
        if term::emit_to_write_style(&mut lock, &Config::default(), sources, &to_codespan(d))
            .is_err()
        {
            eprintln!("{}", to_string(sources, d));
        }
    }
}

#[derive(Serialize)]
struct JsonLabel<'a> {
    file: &'a str,
    line: usize,
    column: usize,
    end_line: usize,
    end_column: usize,
    message: &'a str,
    primary: bool,
}

#[derive(Serialize)]
struct JsonDiagnostic<'a> {
    severity: Severity,
    code: &'a str,
    message: &'a str,
    file: Option<&'a str>,
    line: Option<usize>,
    column: Option<usize>,
    labels: Vec<JsonLabel<'a>>,
    notes: &'a [String],
    hint: Option<&'a str>,
}

/// One JSON value per diagnostic, with 1-based lines and columns.
pub fn to_json(sources: &SourceMap, diags: &[Diagnostic]) -> serde_json::Value {
    let list: Vec<JsonDiagnostic> = diags
        .iter()
        .map(|d| {
            let labels: Vec<JsonLabel> = d
                .labels
                .iter()
                .map(|l| {
                    let (line, column) = sources.line_col(l.span.file, l.span.start as usize);
                    let (end_line, end_column) = sources.line_col(l.span.file, l.span.end as usize);
                    JsonLabel {
                        file: sources.name(l.span.file),
                        line,
                        column,
                        end_line,
                        end_column,
                        message: &l.message,
                        primary: l.primary,
                    }
                })
                .collect();
            let first = labels.iter().find(|l| l.primary).or(labels.first());
            JsonDiagnostic {
                severity: d.severity,
                code: d.code,
                message: &d.message,
                file: first.map(|l| l.file),
                line: first.map(|l| l.line),
                column: first.map(|l| l.column),
                notes: &d.notes,
                hint: d.hint.as_deref(),
                labels,
            }
        })
        .collect();
    serde_json::json!({ "diagnostics": list })
}

/// An LSP range (0-based lines, UTF-16 columns) of a span.
pub fn lsp_range(sources: &SourceMap, span: crate::span::Span) -> lsp_types::Range {
    let pos = |b: u32| {
        let (line, character) = sources.utf16_position(span.file, b as usize);
        lsp_types::Position { line, character }
    };
    lsp_types::Range {
        start: pos(span.start),
        end: pos(span.end),
    }
}

/// A diagnostic for an editor showing `file`: the primary label's range (the
/// file's start when the primary label is in another file, such as an imported
/// module), every label as related information, notes and the hint in the
/// message as `axle check` prints them, and the quick fixes as `data`.
/// `uri` names the files the labels point into (`None`: the label is left out).
pub fn to_lsp(
    sources: &SourceMap,
    file: crate::span::FileId,
    d: &Diagnostic,
    uri: &dyn Fn(crate::span::FileId) -> Option<lsp_types::Uri>,
) -> lsp_types::Diagnostic {
    use lsp_types::{DiagnosticRelatedInformation, DiagnosticSeverity, Location, NumberOrString};
    let primary = d.labels.iter().find(|l| l.primary).or(d.labels.first());
    let range = match primary {
        Some(l) if l.span.file == file => lsp_range(sources, l.span),
        _ => lsp_types::Range::default(),
    };
    let mut message = d.message.clone();
    for n in &d.notes {
        message.push_str(&format!("\nnote: {n}"));
    }
    if let Some(h) = &d.hint {
        message.push_str(&format!("\nhelp: {h}"));
    }
    let related: Vec<DiagnosticRelatedInformation> = d
        .labels
        .iter()
        .filter_map(|l| {
            Some(DiagnosticRelatedInformation {
                location: Location {
                    uri: uri(l.span.file)?,
                    range: lsp_range(sources, l.span),
                },
                message: l.message.clone(),
            })
        })
        .collect();
    let fixes: Vec<serde_json::Value> = d
        .fixes()
        .filter(|(span, _)| span.file == file)
        .map(|(span, text)| serde_json::json!({ "range": lsp_range(sources, span), "newText": text }))
        .collect();
    lsp_types::Diagnostic {
        range,
        severity: Some(match d.severity {
            Severity::Error => DiagnosticSeverity::ERROR,
            Severity::Warning => DiagnosticSeverity::WARNING,
        }),
        code: Some(NumberOrString::String(d.code.to_string())),
        source: Some("axle".into()),
        message,
        related_information: (!related.is_empty()).then_some(related),
        data: (!fixes.is_empty()).then(|| serde_json::json!({ "fixes": fixes })),
        ..Default::default()
    }
}
