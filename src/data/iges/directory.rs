//! Directory Entries: two records per entity, twenty right-justified fields of
//! eight columns. Read here: the entity type (field 1, repeated in field 11),
//! the parameter data pointer (2), the transformation matrix pointer (7), the
//! parameter line count (14), the form (15), the entity label (18) and its
//! subscript (19). Pointers are checked against the file so a later lookup
//! cannot miss.

use super::IgesError;
use super::records::Record;

/// One directory entry.
#[derive(Debug, Clone, PartialEq)]
pub struct Entry {
    /// Sequence number of its first D record (odd; what pointers name).
    pub seq: usize,
    pub kind: i64,
    /// First P record and number of P records of its parameter data.
    pub data: usize,
    pub data_lines: usize,
    /// Sequence number of a transformation matrix entry (0: none).
    pub transform: usize,
    pub form: i64,
    pub label: String,
    pub subscript: i64,
    /// Byte ranges of the entity type and label fields, for messages.
    pub kind_span: (usize, usize),
    pub label_span: (usize, usize),
}

fn err(message: String, range: (usize, usize), label: &str) -> IgesError {
    IgesError::new("E0723", message, range, label)
}

/// Field `k` (1–20) of an entry's two records.
fn field<'r>(pair: &'r [Record<'r>; 2], k: usize) -> (&'r Record<'r>, usize, usize) {
    let r = &pair[(k - 1) / 10];
    let c = (k - 1) % 10 * 8 + 1;
    (r, c, c + 7)
}

const NAMES: [&str; 20] = [
    "entity type",
    "parameter data pointer",
    "structure",
    "line font pattern",
    "level",
    "view",
    "transformation matrix pointer",
    "label display associativity",
    "status number",
    "sequence number",
    "entity type",
    "line weight",
    "color",
    "parameter line count",
    "form number",
    "reserved",
    "reserved",
    "entity label",
    "entity subscript",
    "sequence number",
];

fn int(pair: &[Record; 2], k: usize) -> Result<i64, IgesError> {
    let (r, a, b) = field(pair, k);
    let t = std::str::from_utf8(r.cols(a, b)).unwrap_or("").trim();
    if t.is_empty() {
        return Ok(0);
    }
    super::params::integer(t).ok_or_else(|| {
        err(
            format!(
                "{}: field {k} ({}) is `{t}`, not an integer",
                r.name(),
                NAMES[k - 1]
            ),
            r.span(a, b),
            "integer expected",
        )
    })
}

/// Reads every entry; `p_count` is the number of P records (for pointer checks).
pub fn parse(d: &[Record], p_count: usize) -> Result<Vec<Entry>, IgesError> {
    if d.len() % 2 == 1 {
        let r = &d[d.len() - 1];
        return Err(err(
            format!(
                "{} starts a directory entry that has no second record (entries take two)",
                r.name()
            ),
            r.span(1, 80),
            "half an entry",
        ));
    }
    let mut out = Vec::with_capacity(d.len() / 2);
    for pair in d.chunks_exact(2) {
        #[allow(clippy::expect_used)] // chunks_exact(2) yields slices of two
        let pair: &[Record; 2] = pair.try_into().expect("chunks of two");
        let kind = int(pair, 1)?;
        let (r1, a1, b1) = field(pair, 1);
        if int(pair, 11)? != kind {
            let (r, a, b) = field(pair, 11);
            return Err(err(
                format!(
                    "{}: the entity type is {kind} on the first record but `{}` on the second",
                    r1.name(),
                    String::from_utf8_lossy(r.cols(a, b)).trim()
                ),
                r.span(a, b),
                "types differ",
            ));
        }
        let data = int(pair, 2)?;
        let lines = int(pair, 14)?;
        let (r, a, b) = field(pair, 2);
        if data < 1 || data as usize > p_count {
            return Err(err(
                format!(
                    "{}: the parameter data pointer is {data}, but the file has P records 1 to {p_count}",
                    r1.name()
                ),
                r.span(a, b),
                "no such P record",
            ));
        }
        if lines < 1 || (data + lines - 1) as usize > p_count {
            let (r, a, b) = field(pair, 14);
            return Err(err(
                format!(
                    "{}: {lines} parameter records from P {data} run past the last, P {p_count}",
                    r1.name()
                ),
                r.span(a, b),
                "bad line count",
            ));
        }
        let transform = int(pair, 7)?;
        if transform != 0 && !valid_pointer(transform, d.len()) {
            let (r, a, b) = field(pair, 7);
            return Err(err(
                format!(
                    "{}: the transformation matrix pointer {transform} names no directory entry",
                    r1.name()
                ),
                r.span(a, b),
                "bad pointer",
            ));
        }
        let (rl, al, bl) = field(pair, 18);
        // The label is right-justified: point at its characters, not the padding.
        let raw = rl.cols(al, bl);
        let lead = raw.iter().take_while(|c| **c == b' ').count();
        let trail = raw.iter().rev().take_while(|c| **c == b' ').count();
        let (ls, le) = rl.span(al, bl);
        let label_span = if lead == raw.len() {
            (ls, le)
        } else {
            (ls + lead, le - trail)
        };
        out.push(Entry {
            seq: r1.seq,
            kind,
            data: data as usize,
            data_lines: lines as usize,
            transform: transform as usize,
            form: int(pair, 15)?,
            label: String::from_utf8_lossy(rl.cols(al, bl)).trim().to_string(),
            subscript: int(pair, 19)?,
            kind_span: r1.span(a1, b1),
            label_span,
        });
    }
    Ok(out)
}

/// A directory pointer names the first record of an entry: odd, within the section.
pub fn valid_pointer(p: i64, d_records: usize) -> bool {
    p >= 1 && p % 2 == 1 && (p as usize) < d_records
}
