//! Canonical layout of axle source, keeping every comment. `format_source` is a
//! fixed point: formatting formatted text changes nothing.

pub mod edit;
mod model;
mod print;

pub use edit::{Edited, Request, edit_source};
pub use model::print_model;

use crate::diagnostic::Diagnostic;
use crate::span::{FileId, Span};
use crate::syntax::ast::*;
use crate::syntax::trivia::{Comment, comments};

const INDENT: &str = "    ";

/// Parses and formats a file. Line ends come out as `\n` (a lone `\r` ends a
/// line for the parser, so it does here too). The result is verified before
/// it is returned: it parses, formatting it again changes nothing, and it
/// checks to the same model as the input when the input checks; otherwise
/// E0004, and nothing should be written.
pub fn format_source(file: FileId, text: &str) -> Result<String, Diagnostic> {
    let text = lone_cr_to_lf(text);
    let ast = crate::syntax::parse(file, &text)?;
    let out = format_file(&ast, &text);
    verify(file, &text, &out)?;
    Ok(out)
}

/// `\r` not followed by `\n` becomes `\n`: the same length, so spans into
/// the original text stay valid for diagnostics.
fn lone_cr_to_lf(text: &str) -> std::borrow::Cow<'_, str> {
    let bytes = text.as_bytes();
    let lone = |i: usize| bytes[i] == b'\r' && bytes.get(i + 1) != Some(&b'\n');
    if !(0..bytes.len()).any(lone) {
        return std::borrow::Cow::Borrowed(text);
    }
    let mut out = String::with_capacity(text.len());
    for (i, ch) in text.char_indices() {
        out.push(if ch == '\r' && lone(i) { '\n' } else { ch });
    }
    std::borrow::Cow::Owned(out)
}

/// The formatter's own guarantee, checked on every run (see [`format_source`]).
fn verify(file: FileId, text: &str, out: &str) -> Result<(), Diagnostic> {
    let refuse = |why: &str| {
        Diagnostic::error(
            "E0004",
            format!("the formatter's output {why}; the file is left as it is"),
        )
        .primary(Span::new(file, 0, 0), "not rewritten")
        .note("this is a bug of `axle fmt`: please report it with the file")
    };
    let again = crate::syntax::parse(file, out)
        .map(|ast| format_file(&ast, out))
        .map_err(|_| refuse("does not parse"))?;
    if again != out {
        return Err(refuse("changes when formatted again"));
    }
    let model = |t: &str| {
        crate::check::check_str("fmt", t).1.model.map(|mut m| {
            m.origins = Default::default();
            m
        })
    };
    if let Some(before) = model(text)
        && model(out).as_ref() != Some(&before)
    {
        return Err(refuse("does not check to the same model"));
    }
    Ok(())
}

/// Formats a parsed file; `text` is the source it was parsed from.
pub fn format_file(ast: &File, text: &str) -> String {
    let mut f = Formatter {
        text,
        comments: comments(text),
        next: 0,
        out: String::new(),
        last_end: 0,
        force_blank: false,
    };
    for item in &ast.items {
        f.item(item);
    }
    f.flush_leading(text.len(), "", true);
    let mut out = f.out.trim_end().to_string();
    out.push('\n');
    out
}

struct Formatter<'a> {
    text: &'a str,
    comments: Vec<Comment>,
    next: usize,
    out: String,
    /// Byte offset just after the last thing printed (code or comment).
    last_end: usize,
    /// A blank line must precede the next item (after a block).
    force_blank: bool,
}

impl Formatter<'_> {
    fn blank_in_source(&self, from: usize, to: usize) -> bool {
        from < to && self.text[from..to].matches('\n').count() >= 2
    }

    fn blank_line(&mut self) {
        if !self.out.is_empty() && !self.out.ends_with("\n\n") && !self.out.ends_with("{\n") {
            self.out.push('\n');
        }
    }

    /// Prints the own-line comments before `start`, keeping single blank lines.
    fn flush_leading(&mut self, start: usize, indent: &str, keep_blank: bool) {
        while let Some(c) = self.comments.get(self.next) {
            if c.offset >= start {
                break;
            }
            let c = c.clone();
            self.next += 1;
            if keep_blank && (self.force_blank || self.blank_in_source(self.last_end, c.offset)) {
                self.blank_line();
                self.force_blank = false;
            }
            self.out.push_str(indent);
            self.out.push_str(&c.text);
            self.out.push('\n');
            self.last_end = c.offset + c.text.len();
        }
        if keep_blank && (self.force_blank || self.blank_in_source(self.last_end, start)) {
            self.blank_line();
        }
        self.force_blank = false;
    }

    /// Appends the comment that ends the line of `end`, if any, then a newline.
    fn end_line(&mut self, end: usize) {
        let line = crate::syntax::trivia::line_of(self.text, end.saturating_sub(1).max(0));
        if let Some(c) = self.comments.get(self.next) {
            if c.trailing && c.line == line && c.offset >= end {
                self.out.push(' ');
                self.out.push_str(&c.text);
                self.last_end = c.offset + c.text.len();
                self.next += 1;
                self.out.push('\n');
                return;
            }
        }
        self.last_end = end;
        self.out.push('\n');
    }

    /// Whether a comment lies inside a span (then the span is printed as written).
    fn has_inner_comment(&self, span: Span) -> bool {
        self.comments[self.next..]
            .iter()
            .take_while(|c| c.offset < span.end as usize)
            .any(|c| c.offset > span.start as usize)
    }

    /// One statement on its own line(s): canonical text, or the source text when
    /// a comment sits inside it.
    /// A span without the blanks and comments pest may have swallowed at its end.
    fn code_span(&self, span: Span) -> Span {
        let mut end = span.end as usize;
        loop {
            let src = &self.text[span.start as usize..end];
            let trimmed = src.trim_end();
            let line_start = trimmed.rfind('\n').map_or(0, |i| i + 1);
            match trimmed[line_start..].find("//") {
                Some(i) => end = span.start as usize + line_start + i,
                None => {
                    end = span.start as usize + trimmed.len();
                    break;
                }
            }
        }
        Span {
            end: end as u32,
            ..span
        }
    }

    fn statement(
        &mut self,
        span: Span,
        indent: &str,
        keep_blank: bool,
        canonical: impl FnOnce() -> String,
    ) {
        let span = self.code_span(span);
        self.flush_leading(span.start as usize, indent, keep_blank);
        self.out.push_str(indent);
        if self.has_inner_comment(span) {
            let src = &self.text[span.range()];
            self.out.push_str(src.trim_end());
            // Comments inside were printed with the text.
            while self
                .comments
                .get(self.next)
                .is_some_and(|c| c.offset < span.end as usize)
            {
                self.next += 1;
            }
        } else {
            self.out.push_str(&canonical());
        }
        self.end_line(span.end as usize);
    }

    /// Opens a block; `head_end` is where its head ends in the source (the
    /// `{` follows it; a head printed as written carries its own comments).
    fn open_block(&mut self, span: Span, head: String, head_end: usize) {
        // A block always stands apart from what precedes it (and its leading comments with it).
        self.force_blank = !self.out.is_empty();
        // Its comments are indented as the head is (inside a template).
        let indent: String = head.chars().take_while(|c| *c == ' ').collect();
        self.flush_leading(span.start as usize, &indent, true);
        self.out.push_str(&head);
        self.out.push_str(" {");
        while self
            .comments
            .get(self.next)
            .is_some_and(|c| c.offset < head_end)
        {
            self.next += 1;
        }
        // The `{` is the first `{` after the head; a comment may follow it.
        let from = head_end.max(span.start as usize);
        let brace = self.text[from..span.end as usize]
            .find('{')
            .map_or(span.start as usize, |i| from + i + 1);
        self.end_line(brace);
    }

    fn close_block(&mut self, span: Span, base: &str) {
        let close = (span.end as usize).saturating_sub(1);
        self.flush_leading(close, &format!("{base}{INDENT}"), false);
        self.out.push_str(base);
        self.out.push('}');
        self.end_line(span.end as usize);
        self.force_blank = true;
    }

    fn item(&mut self, item: &Item) {
        self.item_at(item, "");
    }

    /// One item at an indentation (`""` at top level, one [`INDENT`] inside a
    /// template).
    fn item_at(&mut self, item: &Item, base: &str) {
        let inner = format!("{base}{INDENT}");
        let inner = inner.as_str();
        match &item.kind {
            ItemKind::Model(n) => {
                self.statement(item.span, base, true, || format!("model {}", n.name))
            }
            ItemKind::Import(n) => {
                self.statement(item.span, base, true, || format!("import {}", n.name))
            }
            ItemKind::DefaultLoads(n) => self.statement(item.span, base, true, || {
                format!("default loads {}", n.name)
            }),
            ItemKind::Param(p) => self.statement(item.span, base, true, || print::param(p)),
            ItemKind::Part(p) => {
                let kw = if p.ground { "ground" } else { "part" };
                self.open_block(item.span, format!("{base}{kw} {}", p.name.name), 0);
                for (n, pi) in p.items.iter().enumerate() {
                    let keep = n > 0;
                    match pi {
                        PartItem::Marker(m) => {
                            self.statement(m.span, inner, keep, || print::marker(m))
                        }
                        PartItem::Landmark(l) => self.statement(l.span, inner, keep, || {
                            format!("landmark {} at {}", l.name.name, print::vector(&l.at))
                        }),
                    }
                }
                self.close_block(item.span, base);
            }
            ItemKind::Element(e) => {
                let mut head = format!("{base}{} {}", e.keyword.keyword(), e.name.name);
                if let Some(k) = &e.kind {
                    head += &format!(" {}", k.name);
                }
                self.open_block(item.span, head, 0);
                for (n, p) in e.props.iter().enumerate() {
                    self.statement(p.span, inner, n > 0, || {
                        format!("{} {}", p.key.name, print::value(&p.value, inner))
                    });
                }
                self.close_block(item.span, base);
            }
            ItemKind::Loads(l) => self.loads(item.span, l),
            ItemKind::Template(t) => {
                let head_end = t.params_span.end as usize;
                let head = if self.has_inner_comment(t.params_span) {
                    let src = &self.text[item.span.start as usize..head_end];
                    format!("{base}{}", src.trim_end())
                } else {
                    format!(
                        "{base}template {}({})",
                        t.name.name,
                        print::template_params(t)
                    )
                };
                self.open_block(item.span, head, head_end);
                for (n, i) in t.items.iter().enumerate() {
                    if n == 0 {
                        // The first item follows the `{` without a blank line.
                        self.force_blank = false;
                    }
                    self.item_at(i, inner);
                }
                self.close_block(item.span, base);
            }
            ItemKind::Instance(i) => self.statement(item.span, base, true, || print::instance(i)),
        }
    }

    fn loads(&mut self, span: Span, l: &LoadsDecl) {
        match &l.body {
            LoadsBody::Table { columns, rows } => {
                let cols: Vec<String> = columns
                    .iter()
                    .map(|c| format!("{} {}", c.channel.text(), c.unit.text))
                    .collect();
                let head_span = Span {
                    end: columns.last().map_or(span.end, |c| c.span.end),
                    ..span
                };
                let head = format!("loads {} table ({})", l.name.name, cols.join(", "));
                if self.has_inner_comment(head_span) {
                    // Keep a commented header as written, up to its `)`: the
                    // comments in it are printed with it, once.
                    let end = head_span.end as usize;
                    let rest = &self.text[end..span.end as usize];
                    let close = rest.find(')').map_or(end, |i| end + i + 1);
                    let src = &self.text[head_span.start as usize..close];
                    self.open_block(span, src.trim_end().to_string(), close);
                } else {
                    self.open_block(span, head, 0);
                }
                let lines = print::table_rows(rows, columns.len());
                for (n, (row, line)) in rows.iter().zip(lines).enumerate() {
                    self.statement(row.span, INDENT, n > 0, || line);
                }
            }
            LoadsBody::Sweep { lines } => {
                self.open_block(span, format!("loads {} sweep", l.name.name), 0);
                for (n, line) in lines.iter().enumerate() {
                    self.statement(line.span, INDENT, n > 0, || print::sweep_line(line));
                }
            }
        }
        self.close_block(span, "");
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const SRC: &str = include_str!("../../examples/four_bar.axle");

    /// The safety net behind `fmt`: an output that checks to another model
    /// (a value changed), or does not parse, is refused.
    #[test]
    fn an_output_that_changes_the_model_or_does_not_parse_is_refused() {
        let f = FileId(0);
        assert!(verify(f, SRC, SRC).is_ok());
        let moved = SRC.replace("(250, 0, 0)", "(251, 0, 0)");
        let e = verify(f, SRC, &moved).expect_err("another model");
        assert_eq!(e.code, "E0004");
        assert!(e.message.contains("same model"), "{}", e.message);
        let e = verify(f, SRC, "ground g {").expect_err("does not parse");
        assert!(e.message.contains("does not parse"), "{}", e.message);
    }
}
