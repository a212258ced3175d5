//! The language's keywords, read from the grammar itself (`grammar/axle.pest`),
//! so that error recovery, completion and highlighting tests learn a new element
//! (such as `friction`) the moment the grammar has it.

use std::sync::OnceLock;

const GRAMMAR: &str = include_str!("../../grammar/axle.pest");

/// The body of a rule: the text between its `{` and the line's last `}`.
fn rule_body(rule: &str) -> Option<&'static str> {
    GRAMMAR.lines().find_map(|line| {
        let rest = line.strip_prefix(rule)?.trim_start().strip_prefix('=')?;
        let open = rest.find('{')?;
        let close = rest.rfind('}')?;
        (close > open).then(|| rest[open + 1..close].trim())
    })
}

/// The keyword a `kw_*` rule matches: `kw_joint = @{ "joint" ~ !ident_char }`.
fn keyword_of(rule: &str) -> Option<&'static str> {
    let body = rule_body(rule)?;
    let body = body.strip_prefix('"')?;
    Some(&body[..body.find('"')?])
}

/// The keywords a rule can start with: its first symbol's, or each
/// alternative's for a rule that is a choice of named rules.
fn first_keywords(rule: &str, depth: usize, out: &mut Vec<&'static str>) {
    if depth > 8 {
        return;
    }
    if rule.starts_with("kw_") {
        out.extend(keyword_of(rule));
        return;
    }
    let Some(body) = rule_body(rule) else {
        return;
    };
    let is_name =
        |s: &str| !s.is_empty() && s.chars().all(|c| c.is_ascii_alphanumeric() || c == '_');
    let alternatives: Vec<&str> = body.split('|').map(str::trim).collect();
    if alternatives.len() > 1 && alternatives.iter().all(|a| is_name(a)) {
        for a in alternatives {
            first_keywords(a, depth + 1, out);
        }
    } else if let Some(first) = body.split([' ', '~']).find(|s| !s.is_empty())
        && is_name(first)
    {
        first_keywords(first, depth + 1, out);
    }
}

fn list(cell: &'static OnceLock<Vec<&'static str>>, rule: &str) -> &'static [&'static str] {
    cell.get_or_init(|| {
        let mut out = Vec::new();
        first_keywords(rule, 0, &mut out);
        out.dedup();
        out
    })
}

/// Words that start an item (`model`, `part`, `joint`, ...), in grammar order.
pub fn item_keywords() -> &'static [&'static str] {
    static CELL: OnceLock<Vec<&'static str>> = OnceLock::new();
    list(&CELL, "item")
}

/// Words that start an element block (`joint`, `bushing`, ...).
pub fn element_keywords() -> &'static [&'static str] {
    static CELL: OnceLock<Vec<&'static str>> = OnceLock::new();
    list(&CELL, "element_kw")
}

/// Words that start a line inside a part block (`marker`, `landmark`).
pub fn part_item_keywords() -> &'static [&'static str] {
    static CELL: OnceLock<Vec<&'static str>> = OnceLock::new();
    list(&CELL, "part_item")
}

/// Every keyword of the grammar (every `kw_*` rule).
pub fn all_keywords() -> &'static [&'static str] {
    static CELL: OnceLock<Vec<&'static str>> = OnceLock::new();
    CELL.get_or_init(|| {
        GRAMMAR
            .lines()
            .filter_map(|l| l.split_whitespace().next())
            .filter(|r| r.starts_with("kw_"))
            .filter_map(keyword_of)
            .collect()
    })
}

/// Unit names the grammar accepts (`unit_name`).
pub fn unit_names() -> &'static [&'static str] {
    static CELL: OnceLock<Vec<&'static str>> = OnceLock::new();
    CELL.get_or_init(|| {
        let body = rule_body("unit_name").unwrap_or("");
        body.split('"').skip(1).step_by(2).collect()
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keywords_come_from_the_grammar() {
        // Only the start of the lists is fixed: new elements join at the end.
        assert_eq!(
            item_keywords()[..6],
            ["model", "import", "default", "param", "ground", "part"]
        );
        for e in ["joint", "bushing", "spring", "stop", "wheel"] {
            assert!(element_keywords().contains(&e), "{e}");
        }
        for e in element_keywords() {
            assert!(item_keywords().contains(e), "{e} starts an item");
        }
        // Every element keyword of the grammar has its kind in the tree.
        let kinds: Vec<&str> = crate::syntax::ast::ElementKw::ALL
            .iter()
            .map(|k| k.keyword())
            .collect();
        assert_eq!(kinds, element_keywords());
        assert!(item_keywords().contains(&"loads"));
        assert_eq!(part_item_keywords(), ["marker", "landmark"]);
        assert!(all_keywords().contains(&"unknown"));
        assert!(all_keywords().contains(&"euler"));
        assert_eq!(
            unit_names(),
            ["mm", "cm", "m", "kN", "N", "deg", "rad", "kg", "s"]
        );
    }
}
