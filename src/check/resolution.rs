//! The table of definitions and references the checker fills while it resolves
//! names: what an editor needs for go-to-definition, find-references, rename
//! and hover. Spans are those of the names (not of whole items).

use crate::model::{ElementId, Model};
use crate::span::Span;
use std::collections::BTreeMap;

/// What a name denotes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Symbol {
    Element(ElementId),
    /// An imported stdlib module, by the span of its whole file.
    Module(Span),
}

#[derive(Debug, Clone, Default, PartialEq)]
pub struct Resolution {
    /// Where each symbol is defined (its name), in id order.
    pub defs: Vec<(Symbol, Span)>,
    /// Every resolved use of a name, in the order the checker met them.
    pub refs: Vec<(Span, Symbol)>,
    /// Definitions in an imported module, which the model's origins point at the
    /// `import` line instead (where diagnostics about the set belong).
    imported: BTreeMap<ElementId, Span>,
}

impl Resolution {
    pub(super) fn refer(&mut self, span: Span, id: ElementId) {
        self.refs.push((span, Symbol::Element(id)));
    }

    pub(super) fn module(&mut self, name: Span, file: Span) {
        self.refs.push((name, Symbol::Module(file)));
        self.defs.push((Symbol::Module(file), file));
    }

    pub(super) fn defined_in_module(&mut self, id: ElementId, span: Span) {
        self.imported.insert(id, span);
    }

    /// Adds the definitions of every element of the model that has a source span.
    pub(super) fn definitions(&mut self, model: &Model) {
        for (id, span) in model.origins.iter() {
            let span = self.imported.get(&id).copied().unwrap_or(span);
            self.defs.push((Symbol::Element(id), span));
        }
    }

    /// The symbol whose name (a definition or a reference) covers `offset` of
    /// the file of `file_span`, with the span of that name.
    pub fn at(&self, file_span: Span, offset: usize) -> Option<(Span, Symbol)> {
        let hit = |s: &Span| {
            s.file == file_span.file && s.start as usize <= offset && offset <= s.end as usize
        };
        self.refs
            .iter()
            .copied()
            .filter(|(s, _)| hit(s))
            .chain(
                self.defs
                    .iter()
                    .filter(|(sym, s)| hit(s) && !matches!(sym, Symbol::Module(_)))
                    .map(|(sym, s)| (*s, *sym)),
            )
            // The narrowest name wins (a marker inside a channel).
            .min_by_key(|(s, _)| s.end - s.start)
    }

    pub fn definition(&self, symbol: Symbol) -> Option<Span> {
        self.defs
            .iter()
            .find(|(s, _)| *s == symbol)
            .map(|(_, d)| *d)
    }

    /// The uses of a symbol (not its definition), in source order.
    pub fn references(&self, symbol: Symbol) -> Vec<Span> {
        let mut v: Vec<Span> = self
            .refs
            .iter()
            .filter(|(_, s)| *s == symbol)
            .map(|(r, _)| *r)
            .collect();
        v.sort();
        v.dedup();
        v
    }
}

#[cfg(test)]
mod tests {
    use crate::check::{Passes, Symbol, analyse};
    use crate::model::ElementId;
    use crate::source::SourceMap;

    const TEXT: &str = "model m\nimport mcpherson_loads\nparam kb = 10 N/mm\nground g {\n    marker o at (0, 0, 0) mm\n}\npart arm {\n    marker o at (100, 0, 0) mm\n    marker c at (100, 0, -300) mm\n}\nwheel w {\n    centre arm.o\n    contact arm.c\n}\nbushing b {\n    i g.o\n    j arm.o\n    k (kb, kb, kb)\n    kt (1, 1, 1) N*mm/deg\n}\nloads push table (arm.o.fx N) {\n    one 10\n}\ndefault loads push\n";

    fn text_of(span: crate::span::Span) -> &'static str {
        &TEXT[span.range()]
    }

    #[test]
    fn every_name_use_points_at_its_definition() {
        let mut sources = SourceMap::new();
        let id = sources.add("t.axle", TEXT);
        let a = analyse(&mut sources, id, Passes::FAST);
        assert!(!a.problems.has_errors(), "{:?}", a.problems);
        let r = &a.resolution;
        // `arm` in the wheel, in `j arm.o` and in the channel `arm.o.fx`.
        let arm = Symbol::Element(ElementId::Part(a.model.part_named("arm").unwrap()));
        let uses: Vec<usize> = r.references(arm).iter().map(|s| s.start as usize).collect();
        let written: Vec<usize> = TEXT.match_indices("arm.").map(|(i, _)| i).collect();
        assert_eq!(uses, written);
        assert_eq!(uses.len(), 4);
        assert_eq!(text_of(r.definition(arm).unwrap()), "arm");
        // The marker in the channel is the 1-character name after `arm.`.
        let at = TEXT.find("arm.o.fx").unwrap() + 4;
        let (span, sym) = r.at(a.ast.span, at).unwrap();
        assert_eq!((span.start as usize, span.end as usize), (at, at + 1));
        let def = r.definition(sym).unwrap();
        assert_eq!(def.start as usize, TEXT.find("o at (100").unwrap());
        // The parameter, three times in `k (kb, kb, kb)`.
        let kb = Symbol::Element(ElementId::Param(a.model.param_named("kb").unwrap()));
        assert_eq!(r.references(kb).len(), 3);
        // The load set named by `default loads`.
        let (_, push) = r.at(a.ast.span, TEXT.rfind("push").unwrap()).unwrap();
        assert_eq!(
            r.definition(push).unwrap().start as usize,
            TEXT.find("push").unwrap()
        );
        // The module: its definition is the stdlib file.
        let (_, module) = r
            .at(a.ast.span, TEXT.find("mcpherson_loads").unwrap())
            .unwrap();
        let file = r.definition(module).unwrap();
        assert_eq!(sources.name(file.file), "stdlib/mcpherson_loads.axle");
    }

    #[test]
    fn a_file_with_errors_keeps_what_was_checked() {
        // A syntax error in the bushing: only the syntax error is reported (as
        // `axle check` does), but the parts are still in the partial model.
        let broken = TEXT.replace("k (kb, kb, kb)", "k (kb, kb)");
        let mut sources = SourceMap::new();
        let id = sources.add("t.axle", broken.as_str());
        let a = analyse(&mut sources, id, Passes::FAST);
        let codes: Vec<&str> = a.problems.list.iter().map(|d| d.code).collect();
        assert_eq!(codes, ["E0001"]);
        assert!(a.model.part_named("arm").is_some());
        assert!(a.model.param_named("kb").is_some());
        assert!(a.model.bushings.is_empty());
        // A misspelt part: the did-you-mean candidate is data, for quick fixes.
        let misspelt = TEXT.replace("j arm.o", "j amr.o");
        let id = sources.add("u.axle", misspelt.as_str());
        let a = analyse(&mut sources, id, Passes::FAST);
        let d = &a.problems.list[0];
        assert_eq!(d.code, "E0101");
        let fixes: Vec<_> = d.fixes().collect();
        assert_eq!(fixes.len(), 1);
        assert_eq!(fixes[0].1, "arm");
        assert_eq!(&misspelt[fixes[0].0.range()], "amr");
    }
}
