//! The items of a file that parse, around its syntax errors: each broken item is
//! blanked (newlines kept, so every offset stays that of the original text) and
//! the rest is parsed again, until it parses.

use super::ast;
use super::parse;
use super::{resume_point, starts_item};
use crate::span::{FileId, Span};

/// Re-parses at most this many times; then everything from the first broken
/// item on is dropped, so a huge file with many errors still costs a few parses.
const MAX_REPARSES: usize = 24;

/// The tree of the items that parse; `first_error` is the byte offset of the
/// first syntax error in `text`.
pub(super) fn items_that_parse(file: FileId, text: &str, first_error: usize) -> ast::File {
    let mut blanked = text.as_bytes().to_vec();
    let mut at = first_error;
    for _ in 0..MAX_REPARSES {
        let (start, end) = broken_item(text, &blanked, at);
        blank(&mut blanked, start, end);
        match parse(file, as_text(&blanked)) {
            Ok(ast) => return ast,
            Err(d) => {
                at = d
                    .labels
                    .iter()
                    .find(|l| l.primary)
                    .map_or(text.len(), |l| l.span.start as usize);
            }
        }
    }
    let start = item_start(text, first_error.min(text.len()));
    blank(&mut blanked, start, text.len());
    parse(file, as_text(&blanked)).unwrap_or_else(|_| ast::File {
        items: Vec::new(),
        span: Span::new(file, 0, text.len()),
    })
}

/// The byte range of the item to drop for an error at `at`. An error at the very
/// start of an item means the item before it was left open (a missing `}`): that
/// one goes. Otherwise the item around the error goes, up to the next item. A
/// range already blank (the error is at the end of the text, after a block that
/// swallowed the rest) grows back to the item before.
fn broken_item(text: &str, blanked: &[u8], at: usize) -> (usize, usize) {
    let at = at.min(text.len());
    let mut start = item_start(text, at);
    let mut end = if start == at && at > 0 {
        let s = at;
        start = item_start(text, at - 1);
        s
    } else {
        resume_point(text, at + 1).unwrap_or(text.len())
    };
    while start > 0 && is_blank(&blanked[start..end]) {
        start = item_start(text, start - 1);
    }
    if is_blank(&blanked[start..end]) {
        end = text.len();
    }
    (start, end)
}

/// The start of the item line at or before `at` (0 when there is none).
fn item_start(text: &str, at: usize) -> usize {
    let mut end = at.min(text.len());
    loop {
        let line = text[..end].rfind('\n').map_or(0, |i| i + 1);
        if line == 0 || starts_item(&text[line..]) {
            return line;
        }
        end = line - 1;
    }
}

fn is_blank(bytes: &[u8]) -> bool {
    bytes.iter().all(|b| b.is_ascii_whitespace())
}

/// Spaces over `start..end`, newlines kept: same length, so spans stay valid.
fn blank(bytes: &mut [u8], start: usize, end: usize) {
    for b in &mut bytes[start..end] {
        if *b != b'\n' && *b != b'\r' {
            *b = b' ';
        }
    }
}

fn as_text(bytes: &[u8]) -> &str {
    // Only whole lines of a valid UTF-8 text are blanked (every range starts at
    // a line start or ends at the end), so the bytes stay valid UTF-8.
    std::str::from_utf8(bytes).unwrap_or("")
}
