//! Completion from the text before the cursor and the block it is in (read from
//! the text, so the item being typed need not parse): item keywords at the top
//! level, `marker`/`landmark` in a part, an element's properties in its block,
//! parts after `i `/`j ` and markers after `part.`, units after a number, load
//! sets after `default loads`, joint kinds after `joint NAME`, and parameters
//! in values. Keyword and property lists come from the grammar and the checker.

use super::document::Document;
use crate::model::{JointKind, Model};
use crate::syntax::ast::ElementKw;
use crate::syntax::keywords;
use lsp_types::{CompletionItem, CompletionItemKind, Position};

/// Compound units offered besides the grammar's unit names.
const COMPOUND_UNITS: &[&str] = &["N/mm", "N*mm/deg", "N*mm/rad", "N/mm^2", "N/mm^3"];

pub fn complete(doc: &Document, p: Position) -> Vec<CompletionItem> {
    let text = doc.text();
    let offset = doc.offset(p);
    let line_start = text[..offset].rfind('\n').map_or(0, |i| i + 1);
    let before = &text[line_start..offset];
    let empty = Model::default();
    let model = doc.analysis.as_ref().map_or(&empty, |a| &a.model);
    // The word being typed is replaced by the editor; what is before it decides.
    let word_start = before
        .rfind(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
        .map_or(0, |i| i + 1);
    let head = &before[..word_start];
    let words: Vec<&str> = head.split_whitespace().collect();
    let block = enclosing_block(&text[..line_start]);

    // `part.` → its markers; `part.marker.` → load components.
    if let Some(path) = head.strip_suffix('.') {
        let path = path.rsplit([' ', '\t', '(', ',']).next().unwrap_or("");
        let names: Vec<&str> = path.split('.').collect();
        return match names.as_slice() {
            [part] => match model.part_named(part) {
                Some(pid) => items(
                    model
                        .markers
                        .iter()
                        .filter(|m| m.part == pid)
                        .map(|m| m.name.as_str()),
                    CompletionItemKind::FIELD,
                    "marker",
                ),
                None => match model.wheels.iter().any(|w| &w.name == part) {
                    true => components(),
                    false => Vec::new(),
                },
            },
            [_, _] => components(),
            _ => Vec::new(),
        };
    }
    // `default loads ` → load sets.
    if words == ["default", "loads"] {
        return items(
            model.load_sets.iter().map(|s| s.name.as_str()),
            CompletionItemKind::VALUE,
            "load set",
        );
    }
    if words == ["default"] {
        return items(["loads"], CompletionItemKind::KEYWORD, "keyword");
    }
    // A number just before: units.
    if head.ends_with(' ')
        && words
            .last()
            .is_some_and(|w| w.trim_start_matches(['(', '-']).parse::<f64>().is_ok())
    {
        let units = keywords::unit_names().iter().chain(COMPOUND_UNITS).copied();
        return items(units, CompletionItemKind::UNIT, "unit");
    }
    match block {
        Block::Top if words.is_empty() => items(
            keywords::item_keywords().iter().copied(),
            CompletionItemKind::KEYWORD,
            "keyword",
        ),
        Block::Top if words.len() == 2 && words[0] == "joint" => items(
            JointKind::ALL.iter().map(|k| k.keyword()),
            CompletionItemKind::ENUM_MEMBER,
            "joint kind",
        ),
        Block::Top if words.len() == 2 && words[0] == "stop" => items(
            ["compression", "rebound"],
            CompletionItemKind::ENUM_MEMBER,
            "stop kind",
        ),
        Block::Top => params(model),
        Block::Part if words.is_empty() => items(
            keywords::part_item_keywords().iter().copied(),
            CompletionItemKind::KEYWORD,
            "keyword",
        ),
        Block::Part if words.len() == 2 && words[0] == "marker" => {
            items(["at"], CompletionItemKind::KEYWORD, "keyword")
        }
        Block::Part => items(["euler", "z", "x"], CompletionItemKind::KEYWORD, "keyword"),
        Block::Element(kw) if words.is_empty() => items(
            crate::check::properties(kw).into_iter(),
            CompletionItemKind::PROPERTY,
            kw.keyword(),
        ),
        Block::Element(_) if words.len() == 1 && is_marker_property(words[0]) => items(
            model.parts.iter().map(|p| p.name.as_str()),
            CompletionItemKind::CLASS,
            "part",
        ),
        Block::Element(_) => params(model),
        Block::Loads => {
            let mut v = items(
                model.parts.iter().map(|p| p.name.as_str()),
                CompletionItemKind::CLASS,
                "part",
            );
            v.extend(items(
                model.wheels.iter().map(|w| w.name.as_str()),
                CompletionItemKind::STRUCT,
                "wheel",
            ));
            v.extend(components());
            v
        }
    }
}

/// Properties whose value is a `part.marker` reference.
fn is_marker_property(key: &str) -> bool {
    matches!(key, "i" | "j" | "centre" | "center" | "contact")
}

fn components() -> Vec<CompletionItem> {
    items(
        ["fx", "fy", "fz", "mx", "my", "mz"],
        CompletionItemKind::FIELD,
        "load component",
    )
}

fn params(model: &Model) -> Vec<CompletionItem> {
    items(
        model.params.iter().map(|p| p.name.as_str()),
        CompletionItemKind::CONSTANT,
        "param",
    )
}

fn items<'a>(
    labels: impl IntoIterator<Item = &'a str>,
    kind: CompletionItemKind,
    detail: &str,
) -> Vec<CompletionItem> {
    labels
        .into_iter()
        .map(|l| CompletionItem {
            label: l.to_string(),
            kind: Some(kind),
            detail: Some(detail.to_string()),
            ..Default::default()
        })
        .collect()
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Block {
    Top,
    Part,
    Element(ElementKw),
    Loads,
}

/// The block the text before the cursor's line leaves open: a line starting
/// with an item keyword and ending in `{` opens one, a line `}` closes it.
fn enclosing_block(before: &str) -> Block {
    let mut block = Block::Top;
    for line in before.lines() {
        let code = line.split("//").next().unwrap_or("").trim_end();
        if code.trim() == "}" {
            block = Block::Top;
            continue;
        }
        if !code.ends_with('{') {
            continue;
        }
        let first = code.split_whitespace().next().unwrap_or("");
        block = match first {
            "part" | "ground" => Block::Part,
            "loads" => Block::Loads,
            w => match ElementKw::from_keyword(w) {
                Some(kw) => Block::Element(kw),
                None => block,
            },
        };
    }
    block
}
