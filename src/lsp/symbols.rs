//! The outline (`textDocument/documentSymbol`): every item of the syntax tree
//! that parsed, with the markers and landmarks of parts and the cases of load
//! tables as children.

use super::document::Document;
use crate::syntax::ast::{ElementKw, ItemKind, LoadsBody, PartItem};
use lsp_types::{DocumentSymbol, SymbolKind};

#[allow(deprecated)] // `DocumentSymbol::deprecated` must be written out.
fn symbol(
    doc: &Document,
    name: &str,
    detail: String,
    kind: SymbolKind,
    whole: crate::span::Span,
    name_span: crate::span::Span,
    children: Vec<DocumentSymbol>,
) -> DocumentSymbol {
    DocumentSymbol {
        name: name.to_string(),
        detail: Some(detail),
        kind,
        tags: None,
        deprecated: None,
        range: doc.range(whole),
        selection_range: doc.range(name_span),
        children: (!children.is_empty()).then_some(children),
    }
}

pub fn symbols(doc: &Document) -> Vec<DocumentSymbol> {
    let Some(a) = doc.analysis.as_ref() else {
        return Vec::new();
    };
    let mut out = Vec::new();
    for item in &a.ast.items {
        let s = match &item.kind {
            ItemKind::Model(n) => symbol(
                doc,
                &n.name,
                "model".into(),
                SymbolKind::MODULE,
                item.span,
                n.span,
                Vec::new(),
            ),
            ItemKind::Import(n) => symbol(
                doc,
                &n.name,
                "import".into(),
                SymbolKind::NAMESPACE,
                item.span,
                n.span,
                Vec::new(),
            ),
            ItemKind::DefaultLoads(n) => symbol(
                doc,
                &n.name,
                "default loads".into(),
                SymbolKind::KEY,
                item.span,
                n.span,
                Vec::new(),
            ),
            ItemKind::Param(p) => {
                let detail = format!("param = {}", &doc.text()[p.value.span.range()]);
                symbol(
                    doc,
                    &p.name.name,
                    detail,
                    SymbolKind::CONSTANT,
                    item.span,
                    p.name.span,
                    Vec::new(),
                )
            }
            ItemKind::Part(p) => {
                let children = p
                    .items
                    .iter()
                    .map(|pi| match pi {
                        PartItem::Marker(m) => symbol(
                            doc,
                            &m.name.name,
                            "marker".into(),
                            SymbolKind::FIELD,
                            m.span,
                            m.name.span,
                            Vec::new(),
                        ),
                        PartItem::Landmark(l) => symbol(
                            doc,
                            &l.name.name,
                            "landmark".into(),
                            SymbolKind::PROPERTY,
                            l.span,
                            l.name.span,
                            Vec::new(),
                        ),
                    })
                    .collect();
                let detail = if p.ground { "ground" } else { "part" };
                symbol(
                    doc,
                    &p.name.name,
                    detail.into(),
                    SymbolKind::CLASS,
                    item.span,
                    p.name.span,
                    children,
                )
            }
            ItemKind::Element(e) => {
                let mut detail = e.keyword.keyword().to_string();
                if let Some(k) = &e.kind {
                    detail = format!("{detail} {}", k.name);
                }
                let kind = match e.keyword {
                    ElementKw::Joint => SymbolKind::INTERFACE,
                    ElementKw::Wheel => SymbolKind::OBJECT,
                    _ => SymbolKind::STRUCT,
                };
                symbol(
                    doc,
                    &e.name.name,
                    detail,
                    kind,
                    item.span,
                    e.name.span,
                    Vec::new(),
                )
            }
            ItemKind::Loads(l) => {
                let (detail, children) = match &l.body {
                    LoadsBody::Table { rows, .. } => (
                        format!("loads table, {} cases", rows.len()),
                        rows.iter()
                            .map(|r| {
                                symbol(
                                    doc,
                                    &r.name.name,
                                    "case".into(),
                                    SymbolKind::EVENT,
                                    r.span,
                                    r.name.span,
                                    Vec::new(),
                                )
                            })
                            .collect(),
                    ),
                    LoadsBody::Sweep { lines } => {
                        (format!("loads sweep, {} channels", lines.len()), Vec::new())
                    }
                };
                symbol(
                    doc,
                    &l.name.name,
                    detail,
                    SymbolKind::ARRAY,
                    item.span,
                    l.name.span,
                    children,
                )
            }
            ItemKind::Template(t) => symbol(
                doc,
                &t.name.name,
                format!("template, {} parameters", t.params.len()),
                SymbolKind::CLASS,
                item.span,
                t.name.span,
                Vec::new(),
            ),
            ItemKind::Instance(i) => symbol(
                doc,
                &i.name.name,
                format!(
                    "instance of {}{}",
                    if i.mirror { "mirror " } else { "" },
                    i.template.name
                ),
                SymbolKind::OBJECT,
                item.span,
                i.name.span,
                Vec::new(),
            ),
        };
        out.push(s);
    }
    out
}
