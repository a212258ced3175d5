//! Side table from model elements back to the source spans they were written at,
//! and, for elements a tool added or changed, why ("added by diagnose: ...").
//! Elements added by identification or diagnosis have no span; diagnostics then
//! name the element instead of pointing at text, and printers comment them.

use super::id::ElementId;
use crate::span::Span;
use std::collections::BTreeMap;

#[derive(Debug, Clone, Default, PartialEq)]
pub struct Origins {
    spans: BTreeMap<ElementId, Span>,
    /// "added by <tool>: <why>" / "changed by <tool>: <why>", per element.
    edits: BTreeMap<ElementId, String>,
}

impl Origins {
    pub fn insert(&mut self, id: ElementId, span: Span) {
        self.spans.insert(id, span);
    }

    pub fn get(&self, id: ElementId) -> Option<Span> {
        self.spans.get(&id).copied()
    }

    /// Every element with its span, in id order.
    pub fn iter(&self) -> impl Iterator<Item = (ElementId, Span)> + '_ {
        self.spans.iter().map(|(id, span)| (*id, *span))
    }

    /// Records what a tool did to an element (the latest note wins).
    pub fn note_edit(&mut self, id: ElementId, note: String) {
        self.edits.insert(id, note);
    }

    /// What a tool did to the element, if one did.
    pub fn edit(&self, id: ElementId) -> Option<&str> {
        self.edits.get(&id).map(String::as_str)
    }

    /// Every element a tool added or changed, with its note.
    pub fn edits(&self) -> impl Iterator<Item = (ElementId, &str)> + '_ {
        self.edits.iter().map(|(k, v)| (*k, v.as_str()))
    }
}
