//! The fixed layout of an ASCII IGES file: 80-column records, the section
//! letter in column 73 and the sequence number right-justified in columns
//! 74–80, sections in the order Start, Global, Directory, Parameter, Terminate.
//! Records are numbered by position in their section; that is what the
//! Directory's pointers count, so a record whose printed number disagrees (a
//! lost or moved line) is an error here rather than a wrong point later.

use super::IgesError;

/// The five sections, in file order.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Section {
    Start,
    Global,
    Directory,
    Parameter,
    Terminate,
}

impl Section {
    pub fn letter(self) -> char {
        match self {
            Section::Start => 'S',
            Section::Global => 'G',
            Section::Directory => 'D',
            Section::Parameter => 'P',
            Section::Terminate => 'T',
        }
    }
}

/// One record (line) of the file.
#[derive(Debug, Clone, PartialEq)]
pub struct Record<'a> {
    pub section: Section,
    /// Sequence number within the section, from 1.
    pub seq: usize,
    /// Byte offset of the record's first column in the file.
    pub start: usize,
    /// The record without its line end (at least 73 columns, at most 80).
    pub text: &'a [u8],
}

impl Record<'_> {
    /// Byte range of columns `from..=to` (1-based), clipped to the record.
    pub fn span(&self, from: usize, to: usize) -> (usize, usize) {
        let a = (from - 1).min(self.text.len());
        let b = to.min(self.text.len());
        (self.start + a, self.start + b)
    }

    /// The bytes of columns `from..=to` (1-based), clipped to the record.
    pub fn cols(&self, from: usize, to: usize) -> &[u8] {
        let a = (from - 1).min(self.text.len());
        let b = to.min(self.text.len());
        &self.text[a..b]
    }

    /// "D 7": how IGES users name a record.
    pub fn name(&self) -> String {
        format!("{} {}", self.section.letter(), self.seq)
    }
}

/// The records of each section.
#[derive(Debug, Clone, Default)]
pub struct Sections<'a> {
    pub start: Vec<Record<'a>>,
    pub global: Vec<Record<'a>>,
    pub directory: Vec<Record<'a>>,
    pub parameter: Vec<Record<'a>>,
    pub terminate: Vec<Record<'a>>,
}

impl<'a> Sections<'a> {
    fn of(&mut self, s: Section) -> &mut Vec<Record<'a>> {
        match s {
            Section::Start => &mut self.start,
            Section::Global => &mut self.global,
            Section::Directory => &mut self.directory,
            Section::Parameter => &mut self.parameter,
            Section::Terminate => &mut self.terminate,
        }
    }
}

fn err(message: String, range: (usize, usize), label: &str) -> IgesError {
    IgesError::new("E0720", message, range, label)
}

/// Splits the file into its sections. Blank lines are skipped (editors add
/// them at the end); everything else must be an IGES record.
pub fn split(text: &str) -> Result<Sections<'_>, IgesError> {
    let mut out = Sections::default();
    let mut last: Option<Section> = None;
    let mut offset = 0;
    for raw in text.split_inclusive('\n') {
        let start = offset;
        offset += raw.len();
        let line = raw.trim_end_matches(['\n', '\r']);
        if line.trim().is_empty() {
            continue;
        }
        if let Some((k, c)) = line.char_indices().find(|(_, c)| !c.is_ascii()) {
            return Err(err(
                format!("`{c}` is not an ASCII character; IGES records are ASCII"),
                (start + k, start + k + c.len_utf8()),
                "not ASCII",
            ));
        }
        let b = line.as_bytes();
        let end = start + b.len();
        if b.len() < 73 {
            return Err(err(
                format!(
                    "this line has {} columns; an IGES record has 80, with its section letter in column 73",
                    b.len()
                ),
                (start, end),
                "too short for an IGES record",
            )
            .with_hint(Some(
                "a line was cut, or this is not an ASCII IGES file".into(),
            )));
        }
        if b.len() > 80 && b[80..].iter().any(|c| !c.is_ascii_whitespace()) {
            return Err(err(
                format!("this line has {} columns; an IGES record has 80", b.len()),
                (start + 80, end),
                "past column 80",
            ));
        }
        let b = &b[..b.len().min(80)];
        let section = match b[72] {
            b'S' => Section::Start,
            b'G' => Section::Global,
            b'D' => Section::Directory,
            b'P' => Section::Parameter,
            b'T' => Section::Terminate,
            b'B' | b'C' => {
                return Err(err(
                    "binary and compressed IGES files are not read; export the fixed 80-column ASCII form"
                        .into(),
                    (start + 72, start + 73),
                    "binary or compressed form",
                ));
            }
            c => {
                return Err(err(
                    format!(
                        "`{}` in column 73 is not a section letter (S, G, D, P or T)",
                        c as char
                    ),
                    (start + 72, start + 73),
                    "section letter expected",
                ));
            }
        };
        if let Some(prev) = last
            && section < prev
        {
            return Err(err(
                format!(
                    "a {} record after the {} section; the sections come in the order S, G, D, P, T",
                    section.letter(),
                    prev.letter()
                ),
                (start + 72, start + 73),
                "out of order",
            ));
        }
        last = Some(section);
        let list = out.of(section);
        let seq = list.len() + 1;
        let printed = std::str::from_utf8(&b[73..]).unwrap_or("").trim();
        if !printed.is_empty() && printed.parse::<usize>().ok() != Some(seq) {
            return Err(err(
                format!(
                    "this is record {} {seq} by position but it is numbered `{printed}` (a line lost or moved?)",
                    section.letter()
                ),
                (start + 73, start + b.len()),
                "sequence number",
            ));
        }
        list.push(Record {
            section,
            seq,
            start,
            text: b,
        });
    }
    check_terminate(text, &out)?;
    Ok(out)
}

/// The Terminate record counts the records of each section: a file cut short
/// (a failed transfer) is caught here instead of as a missing pointer later.
fn check_terminate(text: &str, s: &Sections) -> Result<(), IgesError> {
    let Some(t) = s.terminate.first() else {
        return Err(err(
            "the file ends without its Terminate (T) record; it may be truncated".into(),
            (text.len(), text.len()),
            "file ends here",
        ));
    };
    if s.global.is_empty() {
        return Err(err(
            "the file has no Global (G) section".into(),
            (t.start, t.start + t.text.len()),
            "reached the end",
        ));
    }
    let counts = [
        ('S', s.start.len()),
        ('G', s.global.len()),
        ('D', s.directory.len()),
        ('P', s.parameter.len()),
    ];
    for (k, (letter, have)) in counts.into_iter().enumerate() {
        let field = t.cols(8 * k + 1, 8 * k + 8);
        let (a, b) = t.span(8 * k + 1, 8 * k + 8);
        if field.first() != Some(&(letter as u8)) {
            return Err(err(
                format!(
                    "the Terminate record should give the {letter} count in columns {}–{}",
                    8 * k + 1,
                    8 * k + 8
                ),
                (a, b),
                "count expected",
            ));
        }
        let n = std::str::from_utf8(&field[1..]).unwrap_or("").trim();
        if n.parse::<usize>().ok() != Some(have) {
            return Err(err(
                format!(
                    "the Terminate record counts `{n}` {letter} records but the file has {have}; it may be truncated or edited"
                ),
                (a, b),
                "count disagrees",
            ));
        }
    }
    Ok(())
}
