//! Side table from model elements back to the source spans they were written at.
//! Elements added by identification or diagnosis have no origin; diagnostics then
//! name the element instead of pointing at text.

use super::id::ElementId;
use crate::span::Span;
use std::collections::BTreeMap;

#[derive(Debug, Clone, Default, PartialEq)]
pub struct Origins {
    spans: BTreeMap<ElementId, Span>,
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
}
