//! Go to definition and find references, from the checker's resolution table.

use super::document::Document;
use crate::check::Symbol;
use crate::span::Span;
use lsp_types::{Location, Position};

/// The symbol under the cursor with the span of its name there.
pub fn symbol_at(doc: &Document, p: Position) -> Option<(Span, Symbol)> {
    let a = doc.analysis.as_ref()?;
    a.resolution.at(doc.file_span(), doc.offset(p))
}

/// A location in this file or in a stdlib module.
pub fn location(doc: &Document, span: Span) -> Option<Location> {
    let uri = if span.file == doc.file {
        doc.uri.clone()
    } else {
        super::stdlib::uri(doc.sources.name(span.file))?
    };
    Some(Location {
        uri,
        range: crate::diagnostic::render::lsp_range(&doc.sources, span),
    })
}

pub fn definition(doc: &Document, p: Position) -> Option<Location> {
    let (_, sym) = symbol_at(doc, p)?;
    let def = doc.analysis.as_ref()?.resolution.definition(sym)?;
    // A module's definition is its whole file: open it at the top.
    let def = match sym {
        Symbol::Module(_) => Span {
            end: def.start,
            ..def
        },
        Symbol::Element(_) => def,
    };
    location(doc, def)
}

pub fn references(doc: &Document, p: Position, include_declaration: bool) -> Vec<Location> {
    let Some((_, sym)) = symbol_at(doc, p) else {
        return Vec::new();
    };
    let Some(a) = doc.analysis.as_ref() else {
        return Vec::new();
    };
    let mut spans = a.resolution.references(sym);
    if include_declaration
        && let (Some(d), Symbol::Element(_)) = (a.resolution.definition(sym), sym)
    {
        spans.insert(0, d);
    }
    spans.iter().filter_map(|s| location(doc, *s)).collect()
}
