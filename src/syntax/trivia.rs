//! Comments, read straight from the text (the language has no string literals,
//! so every `//` starts a comment). The formatter puts them back.

/// A comment: its byte offset, its 0-based line, its text (with `//`), and
/// whether code stands before it on the same line.
#[derive(Debug, Clone, PartialEq)]
pub struct Comment {
    pub offset: usize,
    pub line: usize,
    pub text: String,
    pub trailing: bool,
}

pub fn comments(text: &str) -> Vec<Comment> {
    let mut out = Vec::new();
    let mut offset = 0;
    for (line_no, line) in text.split_inclusive('\n').enumerate() {
        if let Some(i) = line.find("//") {
            out.push(Comment {
                offset: offset + i,
                line: line_no,
                text: line[i..].trim_end().to_string(),
                trailing: !line[..i].trim().is_empty(),
            });
        }
        offset += line.len();
    }
    out
}

/// 0-based line of a byte offset.
pub fn line_of(text: &str, offset: usize) -> usize {
    text.as_bytes()[..offset.min(text.len())]
        .iter()
        .filter(|&&b| b == b'\n')
        .count()
}
