//! Finding what was written where (items, part members) in the syntax tree,
//! and applying replacements to the text without touching anything else.

use crate::span::Span;
use crate::syntax::ast::*;

/// One replacement of `start..end` by `text` (an insertion when empty).
#[derive(Debug, Clone, PartialEq)]
pub struct Splice {
    pub start: usize,
    pub end: usize,
    pub text: String,
}

/// Applies non-overlapping splices; identical ones (one number written once for
/// two fields, as an axisymmetric bushing's radial stiffness) count once.
/// `Err` with the span of two that disagree.
pub fn apply(text: &str, mut splices: Vec<Splice>) -> Result<String, (usize, usize)> {
    // Stable: insertions at one offset keep the order they were planned in.
    splices.sort_by_key(|s| (s.start, s.end));
    splices.dedup_by(|b, a| {
        a.start == b.start && a.end == b.end && a.text == b.text && a.end > a.start
    });
    let mut out = String::with_capacity(text.len());
    let mut at = 0;
    for s in &splices {
        if s.start < at {
            return Err((s.start, s.end));
        }
        out.push_str(&text[at..s.start]);
        out.push_str(&s.text);
        at = s.end;
    }
    out.push_str(&text[at..]);
    Ok(out)
}

pub fn param<'a>(ast: &'a File, name: &str) -> Option<(&'a Item, &'a ParamDecl)> {
    ast.items.iter().find_map(|i| match &i.kind {
        ItemKind::Param(p) if p.name.name == name => Some((i, p)),
        _ => None,
    })
}

pub fn part<'a>(ast: &'a File, name: &str) -> Option<(&'a Item, &'a PartDecl)> {
    ast.items.iter().find_map(|i| match &i.kind {
        ItemKind::Part(p) if p.name.name == name => Some((i, p)),
        _ => None,
    })
}

/// The span of a marker or landmark statement of a part, and the span of its
/// position vector.
pub fn member(ast: &File, part_name: &str, name: &str, landmark: bool) -> Option<(Span, Span)> {
    let (_, p) = part(ast, part_name)?;
    p.items.iter().find_map(|it| match it {
        PartItem::Marker(m) if !landmark && m.name.name == name => Some((m.span, m.at.span)),
        PartItem::Landmark(l) if landmark && l.name.name == name => Some((l.span, l.at.span)),
        _ => None,
    })
}

/// An element block by keyword (`bushing`, `friction`, ...) and name.
pub fn element<'a>(ast: &'a File, keyword: &str, name: &str) -> Option<&'a Item> {
    ast.items.iter().find(|i| match &i.kind {
        ItemKind::Element(e) => e.keyword.keyword() == keyword && e.name.name == name,
        _ => false,
    })
}

/// Where new parameters go: after the last `param` line, else after the
/// header (`model`, `import`, `default loads`), else at the top.
pub fn param_insertion(ast: &File) -> Option<usize> {
    let last = |pred: fn(&ItemKind) -> bool| {
        ast.items
            .iter()
            .filter(|i| pred(&i.kind))
            .map(|i| i.span.end as usize)
            .max()
    };
    last(|k| matches!(k, ItemKind::Param(_))).or_else(|| {
        last(|k| {
            matches!(
                k,
                ItemKind::Model(_) | ItemKind::Import(_) | ItemKind::DefaultLoads(_)
            )
        })
    })
}

/// The end of the code in `start..end`: a statement's span may run on over
/// the blanks and the comment after it, which stay where they are.
pub fn code_end(text: &str, start: usize, end: usize) -> usize {
    let mut slice = &text[start..end];
    loop {
        let trimmed = slice.trim_end();
        let last_line = trimmed.rfind('\n').map_or(0, |n| n + 1);
        let cut = match trimmed[last_line..].find("//") {
            Some(c) => &trimmed[..last_line + c],
            None => trimmed,
        };
        if cut.len() == slice.len() {
            return start + slice.len();
        }
        slice = cut;
    }
}

/// The start of the line holding byte `at`.
pub fn line_start(text: &str, at: usize) -> usize {
    text[..at].rfind('\n').map_or(0, |n| n + 1)
}

/// The blanks before `at` on its line: the indentation of what starts there.
pub fn indent_at(text: &str, at: usize) -> &str {
    let s = line_start(text, at);
    let lead = &text[s..at];
    if lead.trim().is_empty() { lead } else { "" }
}

/// The comments inside `start..end`, each as its text (`// ...`).
pub fn comments_within(text: &str, start: usize, end: usize) -> Vec<String> {
    crate::syntax::trivia::comments(text)
        .into_iter()
        .filter(|c| c.offset >= start && c.offset < end)
        .map(|c| c.text)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sp(start: usize, end: usize, text: &str) -> Splice {
        Splice {
            start,
            end,
            text: text.into(),
        }
    }

    #[test]
    fn splices_replace_only_their_range_and_keep_insertion_order() {
        let t = "k (310, 2400, 180) N/mm // radial\n";
        let out = apply(
            t,
            vec![
                sp(8, 12, "2500.5"),
                sp(3, 6, "300"),
                sp(34, 34, "a\n"),
                sp(34, 34, "b\n"),
            ],
        );
        assert_eq!(out.unwrap(), "k (300, 2500.5, 180) N/mm // radial\na\nb\n");
    }

    #[test]
    fn code_ends_before_the_comment_after_a_statement() {
        let t = "    marker L7 at (1, 2, 3) cm  // centimetres\nnext";
        assert_eq!(&t[4..code_end(t, 4, 45)], "marker L7 at (1, 2, 3) cm");
        let t = "k (1, // a\n 2, 3) N/mm // b\n";
        assert_eq!(&t[..code_end(t, 0, t.len())], "k (1, // a\n 2, 3) N/mm");
    }

    #[test]
    fn one_number_for_two_fields_is_written_once_and_disagreement_is_refused() {
        let t = "k_radial 310 N/mm\n";
        assert_eq!(
            apply(t, vec![sp(9, 12, "320"), sp(9, 12, "320")]).unwrap(),
            "k_radial 320 N/mm\n"
        );
        assert_eq!(
            apply(t, vec![sp(9, 12, "320"), sp(9, 12, "330")]),
            Err((9, 12))
        );
    }
}
