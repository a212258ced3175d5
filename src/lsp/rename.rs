//! Rename of a part, marker, landmark, parameter, element or load set: its
//! definition and every reference the checker resolved. Refused on a file with a
//! syntax error (a use inside a broken item would be missed), for a name that
//! is not an identifier, and for a name already taken in the same namespace.

use super::Failure;
use super::document::Document;
use super::navigate::symbol_at;
use crate::check::Symbol;
use crate::model::{ElementId, Model};
use lsp_types::{Position, PrepareRenameResponse, TextEdit, WorkspaceEdit};
use std::collections::HashMap;

pub fn prepare(doc: &Document, p: Position) -> Result<Option<PrepareRenameResponse>, Failure> {
    let Some((span, sym)) = symbol_at(doc, p) else {
        return Ok(None);
    };
    check_renamable(doc, sym)?;
    Ok(Some(PrepareRenameResponse::Range(doc.range(span))))
}

pub fn rename(doc: &Document, p: Position, new_name: &str) -> Result<WorkspaceEdit, Failure> {
    let (_, sym) = symbol_at(doc, p).ok_or_else(|| Failure::refused("no name to rename here"))?;
    let id = check_renamable(doc, sym)?;
    let a = doc
        .analysis
        .as_ref()
        .ok_or_else(|| Failure::refused("the file is not checked"))?;
    let valid = new_name.starts_with(|c: char| c.is_ascii_alphabetic() || c == '_')
        && new_name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_');
    if !valid {
        return Err(Failure::invalid(format!(
            "`{new_name}` is not a name: letters, digits and `_`, not starting with a digit"
        )));
    }
    if let Some(what) = taken(&a.model, id, new_name) {
        return Err(Failure::refused(format!(
            "{what} `{new_name}` exists already"
        )));
    }
    let def = a.resolution.definition(sym).into_iter();
    let mut edits: Vec<TextEdit> = def
        .chain(a.resolution.references(sym))
        .map(|s| TextEdit {
            range: doc.range(s),
            new_text: new_name.to_string(),
        })
        .collect();
    edits.sort_by_key(|e| (e.range.start.line, e.range.start.character));
    edits.dedup_by_key(|e| e.range);
    Ok(WorkspaceEdit {
        changes: Some(HashMap::from([(doc.uri.clone(), edits)])),
        ..Default::default()
    })
}

fn check_renamable(doc: &Document, sym: Symbol) -> Result<ElementId, Failure> {
    let Symbol::Element(id) = sym else {
        return Err(Failure::refused("a stdlib module cannot be renamed"));
    };
    if !doc.parsed() {
        return Err(Failure::refused(
            "fix the syntax errors first: a use inside a broken item would not be renamed",
        ));
    }
    let a = doc
        .analysis
        .as_ref()
        .ok_or_else(|| Failure::refused("the file is not checked"))?;
    match a.resolution.definition(sym) {
        Some(d) if d.file == doc.file => Ok(id),
        _ => Err(Failure::refused(
            "it is defined in an imported module, which is read-only",
        )),
    }
}

/// What already has this name in the namespace of `id`.
fn taken(m: &Model, id: ElementId, name: &str) -> Option<&'static str> {
    let element_names = || {
        m.joints
            .iter()
            .map(|e| e.name.as_str())
            .chain(m.bushings.iter().map(|e| e.name.as_str()))
            .chain(m.springs.iter().map(|e| e.name.as_str()))
            .chain(m.stops.iter().map(|e| e.name.as_str()))
            .chain(m.frictions.iter().map(|e| e.name.as_str()))
            .chain(m.wheels.iter().map(|e| e.name.as_str()))
            .any(|n| n == name)
    };
    match id {
        ElementId::Part(_) => m.part_named(name).map(|_| "a part"),
        ElementId::Marker(k) => m
            .marker_named(m.marker(k).part, name)
            .map(|_| "a marker of this part"),
        ElementId::Landmark(k) => {
            let part = m.landmarks[k.index()].part;
            m.landmarks
                .iter()
                .any(|l| l.part == part && l.name == name)
                .then_some("a landmark of this part")
        }
        ElementId::Param(_) => m.param_named(name).map(|_| "a parameter"),
        ElementId::LoadSet(_) => m.load_set_named(name).map(|_| "a load set"),
        ElementId::Joint(_)
        | ElementId::Bushing(_)
        | ElementId::Spring(_)
        | ElementId::Stop(_)
        | ElementId::Friction(_)
        | ElementId::Wheel(_) => element_names().then_some("an element"),
    }
}
