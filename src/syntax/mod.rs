//! Source text → syntax tree with spans. pest stops at the first syntax error;
//! [`parse_collecting`] resumes after it at the next item to report more.

pub mod ast;
pub mod depth;
pub mod parser;
mod pest_error;
pub mod trivia;

use crate::diagnostic::Diagnostic;
use crate::span::FileId;
use parser::{AxleParser, Builder, Rule};
use pest::Parser;

/// Parses one file.
pub fn parse(file: FileId, text: &str) -> Result<ast::File, Diagnostic> {
    // Token-level detail makes errors name the missing `,` instead of a rule.
    pest::set_error_detail(true);
    depth::check(file, text)?;
    match AxleParser::parse(Rule::file, text) {
        Ok(mut pairs) => {
            #[allow(clippy::expect_used)] // a successful parse of `file` has its root pair
            let root = pairs.next().expect("invariant: `file` matched");
            Ok(Builder { file }.file(root))
        }
        Err(e) => Err(pest_error::to_diagnostic(file, text, &e)),
    }
}

/// Words that start an item at the beginning of a line: where parsing can resume.
const ITEM_KEYWORDS: &[&str] = &[
    "model", "import", "default", "param", "ground", "part", "joint", "bushing", "spring", "stop",
    "friction", "wheel", "loads",
];

/// At most this many syntax errors are reported per file.
const MAX_SYNTAX_ERRORS: usize = 10;

/// Parses one file; on a syntax error, resumes at the next line that starts an
/// item (a keyword in the first column) after the error, to report every syntax
/// error of the file, not only the first. Text before the resumption point is
/// blanked (newlines kept), so spans, lines and columns stay those of the file.
pub fn parse_collecting(file: FileId, text: &str) -> Result<ast::File, Vec<Diagnostic>> {
    let first = match parse(file, text) {
        Ok(ast) => return Ok(ast),
        Err(d) => d,
    };
    let mut errors = vec![first];
    let mut from = 0usize;
    while errors.len() < MAX_SYNTAX_ERRORS {
        let at = errors
            .last()
            .and_then(|d| d.labels.iter().find(|l| l.primary))
            .map_or(text.len(), |l| l.span.start as usize);
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
    Err(errors)
}

/// The byte offset of the first line after `at` (or the line of `at` itself,
/// when `at` is its first column) that starts with an item keyword.
fn resume_point(text: &str, at: usize) -> Option<usize> {
    let mut offset = 0usize;
    for line in text.split_inclusive('\n') {
        let start = offset;
        offset += line.len();
        if start < at {
            continue;
        }
        let word: String = line
            .chars()
            .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
            .collect();
        if ITEM_KEYWORDS.contains(&word.as_str()) && line[word.len()..].starts_with([' ', '\t']) {
            return Some(start);
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_broken_item_gets_its_syntax_error() {
        let text = "ground g {\n    marker o at (0, 0, 0) mn\n}\n\npart p {\n    marker o at (0, 0) mm\n}\n\nbushing b {\n    i g.o\n    j p.o\n}\n\nsprng s {\n}\n";
        let errors = parse_collecting(FileId(0), text).expect_err("three mistakes");
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
    fn windows_files_parse() {
        // A byte-order mark and CRLF line ends, as some Windows editors save.
        let text = "\u{feff}model m\r\nground g {\r\n    marker o at (0, 0, 0) mm\r\n}\r\n";
        let ast = parse(FileId(0), text).expect("parses");
        assert_eq!(ast.items.len(), 2);
    }
}
