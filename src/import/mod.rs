//! ADAMS dataset (`.adm`) → axle model and canonical axle source. Statements
//! that axle cannot represent are reported with their line and skipped, never
//! silently. Mapping: `docs/adams.md`.

mod adm;
pub mod expr;
mod forces;
mod friction;
pub mod reader;
mod vocab;

use crate::diagnostic::Diagnostic;
use crate::model::Model;
use crate::source::SourceMap;
use crate::span::{FileId, Span};

/// The outcome of an import: the model and its source when the deck maps onto
/// a valid model, and every warning or error (spans in the `.adm` file, or in
/// the generated source for checker errors).
pub struct Imported {
    pub model: Option<Model>,
    pub source: Option<String>,
    /// The axle source printed from a deck that was read but that the checker
    /// rejects: the user can fix it (the diagnostics point into it).
    pub draft: Option<String>,
    pub problems: Vec<Diagnostic>,
    pub sources: SourceMap,
}

/// A problem at a statement of the deck.
pub(crate) fn at(
    file: FileId,
    span: (usize, usize),
    line: usize,
    error: bool,
    msg: impl Into<String>,
) -> Diagnostic {
    let msg = format!("line {line}: {}", msg.into());
    let d = if error {
        Diagnostic::error("E0901", msg)
    } else {
        Diagnostic::warning("W0901", msg)
    };
    d.primary(
        Span {
            file,
            start: span.0 as u32,
            end: span.1 as u32,
        },
        "here",
    )
}

/// Imports the dataset `text` named `name`.
pub fn import_adm(name: &str, text: &str) -> Imported {
    let mut sources = SourceMap::new();
    let file = sources.add(name, text);
    let stem = std::path::Path::new(name)
        .file_stem()
        .map_or("imported".into(), |s| s.to_string_lossy().into_owned());
    let (model, mut problems) = adm::build(file, &stem, text);
    let has_error = problems
        .iter()
        .any(|d| d.severity == crate::diagnostic::Severity::Error);
    let Some(model) = model.filter(|_| !has_error) else {
        return Imported {
            model: None,
            source: None,
            draft: None,
            problems,
            sources,
        };
    };
    // The printed source goes through the normal checker, so an imported model
    // obeys every rule a hand-written one does.
    let printed = crate::fmt::print_model(&model);
    let gen_name = format!("{}.axle", model.name);
    let (gen_sources, checked) = crate::check::check_str(&gen_name, &printed);
    let gen_file = sources.add(gen_name, printed.clone());
    for mut d in checked.problems.list {
        for l in &mut d.labels {
            if gen_sources.name(l.span.file) == sources.name(gen_file) {
                l.span.file = gen_file;
            }
        }
        problems.push(d);
    }
    match checked.model {
        Some(m) => {
            let source = crate::fmt::print_model(&m);
            Imported {
                model: Some(m),
                source: Some(source),
                draft: None,
                problems,
                sources,
            }
        }
        None => Imported {
            model: None,
            source: None,
            draft: Some(printed),
            problems,
            sources,
        },
    }
}
