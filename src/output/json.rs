//! A small streaming JSON writer for the documents `solve` and `kc` print:
//! the bytes serde_json's pretty printer gives for the same tree with its
//! numbers rounded by [`number::round`](super::number::round), written
//! directly (no `serde_json::Value` tree, no re-parse), because the tree cost
//! as much per case as the solve itself. Callers write object keys in sorted
//! order, as serde_json's map (a `BTreeMap`) orders them; the tests compare
//! with the tree's output.

use super::number::{push_json, push_prefix};
use serde_json::Value;
use std::io::Write;

/// Pretty JSON (two-space indent), built as bytes (numbers are written
/// digit by digit; one check that the document is UTF-8 at the end, not one
/// per number) and returned as a `String`.
pub struct Json {
    out: Vec<u8>,
    /// Per open container: whether it has an item yet.
    open: Vec<bool>,
    /// A key was written; its value follows on the same line.
    after_key: bool,
    /// Writing, recording an item's layout, or replaying one.
    mode: Mode,
}

/// An item's bytes and where its values (numbers, integers, booleans and
/// strings) lie in them: the layout of every item with the same keys, the
/// same structure and the same names ([`Json::record`], [`Json::replay`]).
#[derive(Debug, Default)]
pub struct Template {
    bytes: Vec<u8>,
    /// The bytes before each value, and after the last.
    gaps: Vec<std::ops::Range<usize>>,
    tail: usize,
}

enum Mode {
    Write,
    /// From where in `out` the item started, the places of its values.
    Record(usize, Vec<(usize, usize)>),
    /// The layout and the next value's index (past the last: the calls do not
    /// match it).
    Replay(Template, usize),
}

/// [`Json::line`] below the depths of the documents (kept out of its way).
#[cold]
fn deep_line(out: &mut Vec<u8>, comma: bool, depth: usize) {
    out.extend_from_slice(if comma { b",\n" } else { b"\n" });
    out.extend(std::iter::repeat_n(b' ', 2 * depth));
}

/// Whether no byte of `b` needs an escape in a JSON string (a control
/// character, `"` or `\\`), read eight bytes at a time: the word tests of
/// "Bit Twiddling Hacks" (`haszero`, `hasless`), exact for "is there any".
fn plain(b: &[u8]) -> bool {
    const ONES: u64 = 0x0101_0101_0101_0101;
    const HIGH: u64 = 0x8080_8080_8080_8080;
    let zero = |v: u64| v.wrapping_sub(ONES) & !v & HIGH;
    let mut words = b.chunks_exact(8);
    for w in &mut words {
        let x = u64::from_le_bytes(w.try_into().unwrap_or([0; 8]));
        let control = x.wrapping_sub(0x20 * ONES) & !x & HIGH;
        if control | zero(x ^ (u64::from(b'"') * ONES)) | zero(x ^ (u64::from(b'\\') * ONES)) != 0 {
            return false;
        }
    }
    words
        .remainder()
        .iter()
        .all(|&c| c >= 0x20 && c != b'"' && c != b'\\')
}

impl Default for Json {
    fn default() -> Self {
        Json::new()
    }
}

impl Json {
    pub fn new() -> Json {
        Json::with_capacity(0)
    }

    /// An empty document whose text grows into `bytes` before it reallocates.
    pub fn with_capacity(bytes: usize) -> Json {
        Json {
            out: Vec::with_capacity(bytes),
            open: Vec::with_capacity(8),
            after_key: false,
            mode: Mode::Write,
        }
    }

    /// The document (what was not drained of it) with its final newline.
    pub fn finish(mut self) -> String {
        self.out.push(b'\n');
        // Every write is a `&str`, an ASCII byte or a number's ASCII digits.
        String::from_utf8(self.out)
            .unwrap_or_else(|e| String::from_utf8_lossy(e.as_bytes()).into_owned())
    }

    /// Hands the bytes written since the last call to `sink` and forgets
    /// them (keeping the buffer's allocation), for a document written out
    /// piece by piece as it is made; between items only, not while one is
    /// recorded ([`Self::record`] keeps places in the buffer).
    pub fn drain<R>(&mut self, sink: impl FnOnce(&[u8]) -> R) -> R {
        debug_assert!(matches!(self.mode, Mode::Write));
        let r = sink(&self.out);
        self.out.clear();
        r
    }

    /// How many bytes [`Self::drain`] would hand over.
    pub fn pending(&self) -> usize {
        self.out.len()
    }

    /// A newline, after a `,` if `comma`, and the indent of `depth` levels,
    /// in one copy for the depths documents have (a copy per piece cost more
    /// than the bytes).
    fn line(&mut self, comma: bool, depth: usize) {
        /// A newline (after `,` or not), then the spaces of the deepest
        /// indent, copied whole and cut ([`push_prefix`]).
        const COMMA: &[u8; 2 + 2 * 16] = b",\n                                ";
        const NEWLINE: &[u8; 1 + 2 * 16] = b"\n                                ";
        match (depth <= 16, comma) {
            (true, true) => push_prefix(&mut self.out, COMMA, 2 + 2 * depth),
            (true, false) => push_prefix(&mut self.out, NEWLINE, 1 + 2 * depth),
            (false, _) => deep_line(&mut self.out, comma, depth),
        }
    }

    /// Before a value: the separator and indent of an array item.
    fn item(&mut self) {
        if self.after_key {
            self.after_key = false;
            return;
        }
        if let Some(has) = self.open.last_mut() {
            let first = !*has;
            *has = true;
            let depth = self.open.len();
            self.line(!first, depth);
        }
    }

    pub fn key(&mut self, k: &str) -> &mut Json {
        if self.replaying() {
            return self;
        }
        self.item();
        self.string_contents(k);
        self.out.extend_from_slice(b": ");
        self.after_key = true;
        self
    }

    fn begin(&mut self, c: u8) {
        if self.replaying() {
            return;
        }
        self.item();
        self.out.push(c);
        self.open.push(false);
    }

    fn end(&mut self, c: u8) {
        if self.replaying() {
            return;
        }
        if self.open.pop() == Some(true) {
            self.line(false, self.open.len());
        }
        self.out.push(c);
    }

    pub fn begin_object(&mut self) {
        self.begin(b'{');
    }
    pub fn end_object(&mut self) {
        self.end(b'}');
    }
    pub fn begin_array(&mut self) {
        self.begin(b'[');
    }
    pub fn end_array(&mut self) {
        self.end(b']');
    }

    /// A float, rounded as every number of `solve` and `kc` output.
    pub fn num(&mut self, v: f64) {
        self.value_start();
        push_json(&mut self.out, v);
        self.value_end();
    }

    pub fn int(&mut self, v: u64) {
        self.value_start();
        let _ = write!(self.out, "{v}");
        self.value_end();
    }

    pub fn bool(&mut self, v: bool) {
        self.value_start();
        self.out
            .extend_from_slice(if v { b"true" } else { b"false" });
        self.value_end();
    }

    pub fn str(&mut self, s: &str) {
        self.value_start();
        self.string_contents(s);
        self.value_end();
    }

    fn replaying(&self) -> bool {
        matches!(self.mode, Mode::Replay(..))
    }

    /// Before a value: its separator and indent, or in a replay the
    /// layout's bytes since the last value.
    #[inline]
    fn value_start(&mut self) {
        if let Mode::Replay(layout, next) = &self.mode {
            if let Some(gap) = layout.gaps.get(*next) {
                self.out.extend_from_slice(&layout.bytes[gap.clone()]);
            }
            return;
        }
        self.item();
        let len = self.out.len();
        if let Mode::Record(start, values) = &mut self.mode {
            values.push((len - *start, len - *start));
        }
    }

    /// After a value: where it ended, or in a replay the next gap.
    #[inline]
    fn value_end(&mut self) {
        let len = self.out.len();
        match &mut self.mode {
            Mode::Write => {}
            Mode::Record(start, values) => {
                if let Some(v) = values.last_mut() {
                    v.1 = len - *start;
                }
            }
            Mode::Replay(_, next) => *next += 1,
        }
    }

    /// Writes an array item with `write` and returns its layout, for
    /// [`Self::replay`] to write items of the same shape by their values.
    pub fn record(&mut self, write: impl FnOnce(&mut Json)) -> Template {
        self.item();
        self.after_key = true;
        let start = self.out.len();
        self.mode = Mode::Record(start, Vec::new());
        write(self);
        let values = match std::mem::replace(&mut self.mode, Mode::Write) {
            Mode::Record(_, values) => values,
            _ => Vec::new(),
        };
        let mut from = 0;
        let gaps = values
            .iter()
            .map(|&(a, b)| std::mem::replace(&mut from, b)..a)
            .collect();
        Template {
            bytes: self.out[start..].to_vec(),
            gaps,
            tail: from,
        }
    }

    /// Writes an array item with `write` along `layout`, which a call of
    /// [`Self::record`] with the same keys, structure and names made: only
    /// the values are formatted, the rest copied. False, and nothing
    /// written, if `write` gives another number of values (the caller
    /// writes the item afresh then).
    pub fn replay(&mut self, layout: &mut Template, write: impl FnOnce(&mut Json)) -> bool {
        let mark = (self.out.len(), self.open.last().copied());
        self.item();
        self.mode = Mode::Replay(std::mem::take(layout), 0);
        write(self);
        let Mode::Replay(done, next) = std::mem::replace(&mut self.mode, Mode::Write) else {
            return false;
        };
        *layout = done;
        if next != layout.gaps.len() {
            self.out.truncate(mark.0);
            if let (Some(has), Some(was)) = (self.open.last_mut(), mark.1) {
                *has = was;
            }
            return false;
        }
        self.out.extend_from_slice(&layout.bytes[layout.tail..]);
        true
    }

    pub fn nums(&mut self, vs: &[f64]) {
        self.begin_array();
        for &v in vs {
            self.num(v);
        }
        self.end_array();
    }

    /// A quoted string with serde_json's escapes.
    fn string_contents(&mut self, s: &str) {
        let bytes = s.as_bytes();
        // Keys and names rarely need an escape: copy those whole.
        if plain(bytes) {
            self.out.reserve(bytes.len() + 2);
            self.out.push(b'"');
            self.out.extend_from_slice(bytes);
            self.out.push(b'"');
            return;
        }
        self.out.push(b'"');
        let mut run = 0;
        for (i, &b) in bytes.iter().enumerate() {
            let esc: &[u8] = match b {
                b'"' => b"\\\"",
                b'\\' => b"\\\\",
                b'\n' => b"\\n",
                b'\r' => b"\\r",
                b'\t' => b"\\t",
                0x08 => b"\\b",
                0x0c => b"\\f",
                0..=0x1f => b"",
                _ => continue,
            };
            self.out.extend_from_slice(&bytes[run..i]);
            if esc.is_empty() {
                const HEX: &[u8; 16] = b"0123456789abcdef";
                self.out.extend_from_slice(b"\\u00");
                self.out.push(HEX[usize::from(b >> 4)]);
                self.out.push(HEX[usize::from(b & 0xf)]);
            } else {
                self.out.extend_from_slice(esc);
            }
            run = i + 1;
        }
        self.out.extend_from_slice(&bytes[run..]);
        self.out.push(b'"');
    }

    /// A whole serde_json value (floats rounded, integers as they are), for
    /// the small parts of a document kept as values (trim, failures).
    pub fn value(&mut self, v: &Value) {
        match v {
            Value::Null => {
                self.value_start();
                self.out.extend_from_slice(b"null");
                self.value_end();
            }
            Value::Bool(b) => self.bool(*b),
            Value::Number(n) => match n.as_f64() {
                Some(f) if n.is_f64() => self.num(f),
                _ => {
                    // integers print as serde_json prints them (Display)
                    self.value_start();
                    let _ = write!(self.out, "{n}");
                    self.value_end();
                }
            },
            Value::String(s) => self.str(s),
            Value::Array(a) => {
                self.begin_array();
                a.iter().for_each(|x| self.value(x));
                self.end_array();
            }
            Value::Object(o) => {
                self.begin_object();
                for (k, x) in o {
                    self.key(k);
                    self.value(x);
                }
                self.end_object();
            }
        }
    }
}

#[cfg(test)]
#[path = "json_tests.rs"]
mod tests;
