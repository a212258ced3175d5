//! Source text → syntax tree with spans. pest stops at the first syntax error;
//! [`parse_collecting`] resumes after it at the next item to report more, and
//! keeps the items that parsed (the language server works on those).

pub mod ast;
pub mod depth;
pub mod keywords;
pub mod parser;
mod partial;
mod pest_error;
pub mod trivia;

use crate::diagnostic::Diagnostic;
use crate::span::FileId;
use parser::{AxleParser, Builder, Rule};
use pest::Parser;

/// Parses one file.
pub fn parse(file: FileId, text: &str) -> Result<ast::File, Diagnostic> {
    depth::check(file, text)?;
    match AxleParser::parse(Rule::file, text) {
        Ok(mut pairs) => {
            #[allow(clippy::expect_used)] // a successful parse of `file` has its root pair
            let root = pairs.next().expect("invariant: `file` matched");
            Ok(Builder { file }.file(root))
        }
        Err(plain) => {
            let e = detailed_error(text).unwrap_or(plain);
            Err(pest_error::to_diagnostic(file, text, &e))
        }
    }
}

/// The error of a text that does not parse, parsed again with pest's
/// token-level detail, which makes errors name the missing `,` instead of a
/// rule. Collecting that detail costs a fifth of `axle check` on a text
/// that parses, so it is collected only for one that does not. The flag is
/// process-global: it is set and cleared under one lock, so the errors of
/// parses on several threads (tests, the language server) always have the
/// detail; a parse elsewhere meanwhile only runs slower.
fn detailed_error(text: &str) -> Option<pest::error::Error<Rule>> {
    static DETAIL: std::sync::Mutex<()> = std::sync::Mutex::new(());
    let _held = DETAIL
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner());
    pest::set_error_detail(true);
    let parsed = AxleParser::parse(Rule::file, text).map(|_| ());
    pest::set_error_detail(false);
    parsed.err()
}

/// At most this many syntax errors are reported per file.
const MAX_SYNTAX_ERRORS: usize = 10;

/// A file's syntax tree and its syntax errors. With errors, the tree holds the
/// items that parsed (those outside every broken item), with their spans in the
/// original text.
#[derive(Debug, Clone)]
pub struct Parsed {
    pub ast: ast::File,
    pub errors: Vec<Diagnostic>,
}

impl Parsed {
    pub fn is_ok(&self) -> bool {
        self.errors.is_empty()
    }
}

/// Parses one file; on a syntax error, resumes at the next line that starts an
/// item (a keyword in the first column) after the error, to report every syntax
/// error of the file, not only the first. Text before the resumption point is
/// blanked (newlines kept), so spans, lines and columns stay those of the file.
/// The tree of the items that parsed comes with the errors.
pub fn parse_collecting(file: FileId, text: &str) -> Parsed {
    match parse(file, text) {
        Ok(ast) => Parsed {
            ast,
            errors: Vec::new(),
        },
        Err(first) => {
            let at = primary_start(&first).unwrap_or(text.len());
            Parsed {
                errors: collect_errors(file, text, first),
                ast: partial::items_that_parse(file, text, at),
            }
        }
    }
}

fn primary_start(d: &Diagnostic) -> Option<usize> {
    d.labels
        .iter()
        .find(|l| l.primary)
        .map(|l| l.span.start as usize)
}

/// Every syntax error of the file after the first (at most [`MAX_SYNTAX_ERRORS`]).
fn collect_errors(file: FileId, text: &str, first: Diagnostic) -> Vec<Diagnostic> {
    let mut errors = vec![first];
    let mut from = 0usize;
    while errors.len() < MAX_SYNTAX_ERRORS {
        let at = errors.last().and_then(primary_start).unwrap_or(text.len());
        let Some(next) = resume_point(text, at.max(from)) else {
            break;
        };
        if next <= from {
            break;
        }
        from = next;
        let blanked: String = text
            .char_indices()
            .map(|(i, c)| {
                if i >= next || c == '\n' || c == '\r' {
                    c.to_string()
                } else {
                    // Same byte length, so every later offset is unchanged.
                    " ".repeat(c.len_utf8())
                }
            })
            .collect();
        match parse(file, &blanked) {
            Ok(_) => break,
            Err(d) => errors.push(d),
        }
    }
    errors
}

/// The byte offset of the first line after `at` (or the line of `at` itself,
/// when `at` is its first column) that starts with an item keyword.
pub(crate) fn resume_point(text: &str, at: usize) -> Option<usize> {
    let mut offset = 0usize;
    for line in text.split_inclusive('\n') {
        let start = offset;
        offset += line.len();
        if start >= at && starts_item(line) {
            return Some(start);
        }
    }
    None
}

/// Whether a line (or the text from a line start) starts with an item keyword
/// in its first column.
pub(crate) fn starts_item(line: &str) -> bool {
    let word_len = line
        .bytes()
        .take_while(|c| c.is_ascii_alphanumeric() || *c == b'_')
        .count();
    keywords::item_keywords().contains(&&line[..word_len])
        && line[word_len..].starts_with([' ', '\t'])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_broken_item_gets_its_syntax_error() {
        let text = "ground g {\n    marker o at (0, 0, 0) mn\n}\n\npart p {\n    marker o at (0, 0) mm\n}\n\nbushing b {\n    i g.o\n    j p.o\n}\n\nsprng s {\n}\n";
        let parsed = parse_collecting(FileId(0), text);
        let errors = parsed.errors;
        let lines: Vec<usize> = errors
            .iter()
            .map(|d| {
                let start = d.labels[0].span.start as usize;
                text[..start].matches('\n').count() + 1
            })
            .collect();
        assert_eq!(lines, [2, 6, 14]);
    }

    #[test]
    fn a_clean_file_parses() {
        assert!(parse_collecting(FileId(0), "model m\n").is_ok());
    }

    #[test]
    fn the_items_that_parse_survive_a_syntax_error() {
        // The broken bushing and the misspelt spring go; the parts and the
        // joint after them stay, at their offsets in the original text.
        let text = "ground g {\n    marker o at (0, 0, 0) mm\n}\n\nbushing b {\n    i g.o\n    j p.o mn\n}\n\nsprng s {\n}\n\npart p {\n    marker o at (1, 0, 0) mm\n}\njoint r revolute {\n    i g.o\n    j p.o\n}\n";
        let parsed = parse_collecting(FileId(0), text);
        // Recovery resumes at `part`, the next item keyword: `sprng` is in the
        // same cut, so one error.
        assert_eq!(parsed.errors.len(), 1);
        let names: Vec<(&str, &str)> = parsed
            .ast
            .items
            .iter()
            .map(|i| match &i.kind {
                ast::ItemKind::Part(p) => ("part", p.name.name.as_str()),
                ast::ItemKind::Element(e) => (e.keyword.keyword(), e.name.name.as_str()),
                _ => ("other", ""),
            })
            .collect();
        assert_eq!(names, [("part", "g"), ("part", "p"), ("joint", "r")]);
        let p = &parsed.ast.items[1];
        assert_eq!(&text[p.span.range()][..6], "part p");
    }

    #[test]
    fn an_unclosed_block_loses_only_itself() {
        let text = "model m\npart a {\n    marker o at (0, 0, 0) mm\n\njoint r revolute {\n    i g.o\n    j a.o\n}\n";
        let parsed = parse_collecting(FileId(0), text);
        assert!(!parsed.errors.is_empty());
        // The unclosed part goes; the model line and the joint after it stay.
        assert_eq!(parsed.ast.items.len(), 2);
        assert!(matches!(parsed.ast.items[0].kind, ast::ItemKind::Model(_)));
        assert!(matches!(
            parsed.ast.items[1].kind,
            ast::ItemKind::Element(_)
        ));
    }

    #[test]
    fn windows_files_parse() {
        // A byte-order mark and CRLF line ends, as some Windows editors save.
        let text = "\u{feff}model m\r\nground g {\r\n    marker o at (0, 0, 0) mm\r\n}\r\n";
        let ast = parse(FileId(0), text).expect("parses");
        assert_eq!(ast.items.len(), 2);
    }
}
