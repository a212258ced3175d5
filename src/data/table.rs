//! The shared layout of axle's data files: a header row, comma-separated
//! fields, `#` comment lines and blank lines skipped, fields trimmed. The files
//! carry numbers and names only, so there is no quoting beyond stripping one
//! pair of surrounding double quotes; splitting by hand keeps the exact byte
//! span of every field for diagnostics.

use super::CsvError;

/// One field: its trimmed text and byte range in the file.
#[derive(Debug, Clone, PartialEq)]
pub struct Field<'a> {
    pub text: &'a str,
    pub start: usize,
    pub end: usize,
}

/// A data row: its 1-based line number, byte range, and fields.
#[derive(Debug, Clone, PartialEq)]
pub struct Row<'a> {
    pub line: usize,
    pub start: usize,
    pub end: usize,
    pub fields: Vec<Field<'a>>,
}

/// A table: header fields (lower-cased names) and rows.
#[derive(Debug, Clone, PartialEq)]
pub struct Table<'a> {
    pub header: Row<'a>,
    pub names: Vec<String>,
    pub rows: Vec<Row<'a>>,
}

impl Table<'_> {
    /// Index of a column by name.
    pub fn column(&self, name: &str) -> Option<usize> {
        self.names.iter().position(|n| n == name)
    }
}

fn split_line(text: &str, line: usize, start: usize) -> Row<'_> {
    let mut fields = Vec::new();
    let mut at = 0;
    for raw in text.split(',') {
        let lead = raw.len() - raw.trim_start().len();
        let mut t = raw.trim();
        let mut s = start + at + lead;
        if t.len() >= 2 && t.starts_with('"') && t.ends_with('"') {
            t = &t[1..t.len() - 1];
            s += 1;
        }
        fields.push(Field {
            text: t,
            start: s,
            end: s + t.len(),
        });
        at += raw.len() + 1;
    }
    Row {
        line,
        start,
        end: start + text.len(),
        fields,
    }
}

/// Splits `text` into a header and rows. An empty file (nothing but comments)
/// and a header with an empty or repeated column name are errors.
pub fn parse(text: &str) -> Result<Table<'_>, CsvError> {
    let mut rows = Vec::new();
    let mut offset = 0;
    for (n, raw) in text.split_inclusive('\n').enumerate() {
        let line = raw.trim_end_matches(['\n', '\r']);
        let start = offset;
        offset += raw.len();
        let t = line.trim();
        if t.is_empty() || t.starts_with('#') {
            continue;
        }
        rows.push(split_line(line, n + 1, start));
    }
    if rows.is_empty() {
        return Err(CsvError::new(
            "E0701",
            "the file has no header row and no data",
            (text.len(), text.len()),
            "nothing but comments before here",
        ));
    }
    let header = rows.remove(0);
    let mut names: Vec<String> = Vec::new();
    for f in &header.fields {
        let name = f.text.to_ascii_lowercase();
        if name.is_empty() {
            return Err(CsvError::new(
                "E0702",
                "a column of the header row has no name",
                (f.start, f.end),
                "empty column name",
            ));
        }
        if names.contains(&name) {
            return Err(CsvError::new(
                "E0702",
                format!("column `{name}` appears twice in the header"),
                (f.start, f.end),
                "repeated here",
            ));
        }
        names.push(name);
    }
    Ok(Table {
        header,
        names,
        rows,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fields_keep_their_byte_spans() {
        let text = "# c\nstep, fx\n 1 ,\"2.5\"\n";
        let t = parse(text).expect("table");
        assert_eq!(t.names, ["step", "fx"]);
        let r = &t.rows[0];
        assert_eq!(r.line, 3);
        assert_eq!(r.fields[0].text, "1");
        assert_eq!(&text[r.fields[0].start..r.fields[0].end], "1");
        assert_eq!(&text[r.fields[1].start..r.fields[1].end], "2.5");
    }

    #[test]
    fn empty_and_comment_only_files_are_errors() {
        assert_eq!(parse("").map(|_| ()).unwrap_err().code, "E0701");
        assert_eq!(parse("# only\n\n").map(|_| ()).unwrap_err().code, "E0701");
        assert_eq!(parse("a,,b\n").map(|_| ()).unwrap_err().code, "E0702");
    }
}
