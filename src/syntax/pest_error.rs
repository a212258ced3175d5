//! pest errors → readable diagnostics: rule names become words ("a unit such as
//! `mm` or `N/mm`"), literal tokens are quoted, and the label says what was found.

use super::parser::Rule;
use crate::diagnostic::Diagnostic;
use crate::span::{FileId, Span};
use pest::error::{Error, ErrorVariant, InputLocation};

/// Words for a rule the parser expected, or `None` for rules that never help.
fn describe(rule: Rule) -> Option<&'static str> {
    use Rule::*;
    Some(match rule {
        unit | unit_name | unit_factor => "a unit such as `mm` or `N/mm`",
        eol | nls => "the end of the line",
        EOI => "the end of the file",
        ident | qname | param_ref => "a name",
        number | signed_number => "a number",
        quantity | expr | term | factor | power | paren | call | neg | bound | open_bound => {
            "a value such as `310 N/mm`"
        }
        vector => "a vector such as `(0, 0, 1) mm`",
        marker_ref => "a marker such as `chassis.B`",
        add_op | mul_op => "an operator",
        value => "a value",
        property => "a property such as `k (310, 2400, 180) N/mm`",
        body => "`{`",
        marker_decl | landmark_decl | kw_marker | kw_landmark => "`marker` or `landmark`",
        model_decl | import_decl | default_decl | param_decl | part_decl | element_decl
        | loads_decl | part_kw | element_kw | kw_model | kw_import | kw_default | kw_param
        | kw_ground | kw_part | kw_joint | kw_bushing | kw_spring | kw_stop | kw_friction
        | kw_wheel | kw_loads | template_decl | instance_decl | kw_template | kw_instance => {
            "an item (`model`, `import`, `default`, `param`, `ground`, `part`, `joint`, `bushing`, `spring`, `stop`, `friction`, `wheel`, `loads`, `template` or `instance`)"
        }
        kw_unknown | unknown => "`unknown`",
        bounds => "bounds such as `[100 N/mm, 900 N/mm]`",
        kw_table => "`table`",
        kw_sweep => "`sweep`",
        load_table => "`table (...)`",
        load_sweep => "`sweep`",
        kw_by => "`by`",
        kw_at => "`at`",
        kw_euler | euler => "`euler`",
        kw_z | directions => "`z`",
        kw_x => "`x`",
        table => "a table such as `table (mm, N) [(0, 0), (5, 5000)]`",
        list => "a list such as `[500 N/mm, 20 N/mm^2]`",
        pair => "a point such as `(5, 5000)`",
        channel => "a load channel such as `fz`, `left.fz` or `arm.tip.fx`",
        column => "a column such as `fz N`",
        row => "a row: a case name and its values",
        sweep_line => "a sweep line such as `fz 1000 N -> 8000 N by 250 N`",
        _ => return None,
    })
}

fn token_words(token: &str) -> Option<String> {
    match token {
        " " | "\t" | "\u{feff}" | "//" | "_" => None,
        "\n" | "\r\n" | "\r" => Some("the end of the line".into()),
        "+" | "-" | "*" | "/" => Some("an operator".into()),
        // Parts of numbers and units, character ranges and built-in rules: noise here.
        "e" | "E" | "." | "^" => None,
        t if crate::units::base_unit(t).is_some() => Some("a unit such as `mm` or `N/mm`".into()),
        t if t.contains("..") || t.is_empty() => None,
        t => Some(format!("`{t}`")),
    }
}

/// The whole word or character at the error position, as a byte range.
fn found_range(text: &str, pos: usize) -> (usize, usize) {
    let pos = pos.min(text.len());
    let is_word = |c: char| c.is_alphanumeric() || c == '_';
    let inside_word = text[pos..].chars().next().is_some_and(is_word);
    let start = if !inside_word {
        pos
    } else {
        text[..pos]
            .char_indices()
            .rev()
            .take_while(|(_, c)| is_word(*c))
            .last()
            .map_or(pos, |(i, _)| i)
    };
    let rest = &text[start..];
    let len = match rest.chars().next() {
        None | Some('\n') | Some('\r') => 0,
        Some(c) if is_word(c) => rest.find(|c: char| !is_word(c)).unwrap_or(rest.len()),
        Some(c) => c.len_utf8(),
    };
    (start, start + len)
}

fn describe_found(text: &str, (s, e): (usize, usize)) -> String {
    if s == e {
        if s >= text.len() {
            "the end of the file".into()
        } else {
            "the end of the line".into()
        }
    } else {
        format!("`{}`", &text[s..e])
    }
}

fn join_or(items: &[String]) -> String {
    match items {
        [] => "something else".into(),
        [a] => a.clone(),
        [init @ .., last] => format!("{}, or {last}", init.join(", ")),
    }
}

pub fn to_diagnostic(file: FileId, text: &str, e: &Error<Rule>) -> Diagnostic {
    let mut pos = match e.location {
        InputLocation::Pos(p) => p,
        InputLocation::Span((s, _)) => s,
    };
    let mut words: Vec<String> = Vec::new();
    let mut push = |w: String| {
        if !words.contains(&w) {
            words.push(w);
        }
    };
    if let Some(att) = e.parse_attempts() {
        pos = pos.max(att.max_position);
        for cs in att.call_stacks() {
            let rule = cs.deepest.get_rule().copied().or(cs.parent);
            if let Some(w) = rule.and_then(describe) {
                push(w.to_string());
            }
        }
        for t in att.expected_tokens() {
            if let Some(w) = token_words(&t.to_string()) {
                push(w);
            }
        }
    }
    if let ErrorVariant::ParsingError { positives, .. } = &e.variant {
        for r in positives {
            if let Some(w) = describe(*r) {
                push(w.to_string());
            }
        }
    }
    // Point at the offending token, not at the blank before it.
    let after = text[pos.min(text.len())..].trim_start_matches([' ', '\t']);
    pos = text.len() - after.len();
    let range = found_range(text, pos);
    // Right after a complete value another value cannot start: drop the noise.
    let before = text[..range.0].trim_end_matches([' ', '\t']);
    if before.ends_with(|c: char| c.is_alphanumeric() || c == ')') {
        words.retain(|w| !w.starts_with("a value such as"));
    }
    // A unit is the most specific thing a number can still take; say it first.
    // Then literal tokens (`=`, `,`, `}`): the most concrete advice.
    words.sort_by_key(|w| {
        (
            !w.starts_with("a unit"),
            !w.starts_with('`'),
            w.starts_with("an operator"),
        )
    });
    // A literal word also inside a longer phrase ("`marker`" beside "`marker` or
    // `landmark`") says nothing new.
    let all = words.clone();
    words.retain(|w| {
        !(w.starts_with('`')
            && w.ends_with('`')
            && all.iter().any(|o| o != w && o.contains(w.as_str())))
    });
    // `=` is only ever expected after `param NAME`: then it is the one thing missing.
    if words.iter().any(|w| w == "`=`") {
        words.retain(|w| w == "`=`");
    }
    let what = describe_found(text, range);
    let expected = join_or(&words);
    let span = Span::new(file, range.0, range.1);
    let mut d = Diagnostic::error("E0001", format!("syntax error: expected {expected}"))
        .primary(span, format!("found {what}"));
    let word = what.starts_with('`') && what[1..].starts_with(|c: char| c.is_alphabetic());
    let found_word = &text[range.0..range.1];
    // Keywords the parser would have taken here, for "did you mean".
    let keywords: Vec<&str> = expected_keywords(e);
    if words.iter().any(|w| w.starts_with("a unit")) && word {
        let units = "units are written right after the number, without spaces inside: `13875 N/mm`, `4000 N*mm/deg`; known units: mm, cm, m, N, kN, deg, rad, kg, s";
        d = match unit_suggestion(found_word) {
            Some(u) => d
                .note(units)
                .hint(crate::diagnostic::suggest::did_you_mean_text(&u))
                .fix(span, u),
            None => d.hint(units),
        };
    } else if let Some(k) = word
        .then(|| crate::diagnostic::suggest::best(found_word, keywords.iter().copied()))
        .flatten()
    {
        d = d
            .hint(crate::diagnostic::suggest::did_you_mean_text(k))
            .fix(span, k);
    } else if words.iter().any(|w| w == "the end of the line") && word {
        d = d.hint("each statement and each property goes on a line of its own");
    } else if words == ["`=`"] {
        d = d.hint("a parameter is written `param NAME = VALUE`, e.g. `param k_spring = 30 N/mm`");
    } else if (what == "`/`" || what == "`*`") && before.ends_with(|c: char| c.is_alphabetic()) {
        d = d.hint("write compound units without spaces: `N/mm`, `N*mm/deg`");
    } else if words.iter().any(|w| w == "`,`") && what == "`)`" {
        d = d.hint("a vector has three components: `(x, y, z)`");
    }
    d
}

/// The keywords among the tokens the parser expected at the error.
fn expected_keywords(e: &Error<Rule>) -> Vec<&'static str> {
    const KEYWORDS: &[&str] = &[
        "model", "import", "param", "ground", "part", "marker", "landmark", "joint", "bushing",
        "spring", "stop", "friction", "wheel", "loads", "default", "unknown", "table", "sweep",
        "by", "at", "euler",
    ];
    let Some(att) = e.parse_attempts() else {
        return Vec::new();
    };
    let tokens: Vec<String> = att
        .expected_tokens()
        .iter()
        .map(|t| t.to_string())
        .collect();
    KEYWORDS
        .iter()
        .copied()
        .filter(|k| tokens.iter().any(|t| t == k))
        .collect()
}

/// A unit the author probably meant by a word that is not one: a misspelt name
/// (`mn` → `mm`) or names run together without `*` (`Nmm` → `N*mm`).
fn unit_suggestion(word: &str) -> Option<String> {
    use crate::units::UNIT_NAMES;
    // Split into known unit names, longest first (`Nmm` → N, mm).
    fn split<'a>(w: &'a str, out: &mut Vec<&'a str>) -> bool {
        if w.is_empty() {
            return true;
        }
        // Mass and time are in no stiffness or load: `degs` is a plural, not deg*s.
        let mut names: Vec<&str> = UNIT_NAMES
            .iter()
            .map(|(n, _)| *n)
            .filter(|n| !matches!(*n, "s" | "kg"))
            .collect();
        names.sort_by_key(|n| std::cmp::Reverse(n.len()));
        for n in names {
            if let Some(rest) = w.strip_prefix(n) {
                out.push(&w[..n.len()]);
                if split(rest, out) {
                    return true;
                }
                out.pop();
            }
        }
        false
    }
    let mut parts = Vec::new();
    if split(word, &mut parts) && parts.len() > 1 {
        return Some(parts.join("*"));
    }
    // Prefer a name of the same length among equally close ones (`mn` → `mm`, not `m`).
    UNIT_NAMES
        .iter()
        .map(|(n, _)| *n)
        .map(|n| {
            let d = crate::diagnostic::suggest::distance(word, n);
            (d, n.len().abs_diff(word.len()), n)
        })
        .filter(|(d, _, _)| *d <= 1.max(word.len() / 3))
        .min()
        .map(|(_, _, n)| n.to_string())
}

#[cfg(test)]
mod tests {
    use super::unit_suggestion;

    #[test]
    fn suggests_units() {
        assert_eq!(unit_suggestion("mn").as_deref(), Some("mm"));
        assert_eq!(unit_suggestion("Nmm").as_deref(), Some("N*mm"));
        assert_eq!(unit_suggestion("Nm").as_deref(), Some("N*m"));
        assert_eq!(unit_suggestion("xyz"), None);
        assert_eq!(unit_suggestion("degs").as_deref(), Some("deg"));
        assert_eq!(unit_suggestion("chassis"), None);
    }
}
