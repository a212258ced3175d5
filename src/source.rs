//! The set of source files of one run: user files and the stdlib modules they import.

use crate::span::FileId;
use codespan_reporting::files::{Error as FilesError, Files, SimpleFile};

/// Files by [`FileId`]; implements codespan's `Files` so diagnostics can be rendered.
#[derive(Default, Clone)]
pub struct SourceMap {
    files: Vec<SimpleFile<String, String>>,
}

impl SourceMap {
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds a file and returns its id; the same name may be added twice (ids differ).
    pub fn add(&mut self, name: impl Into<String>, text: impl Into<String>) -> FileId {
        self.files.push(SimpleFile::new(name.into(), text.into()));
        FileId((self.files.len() - 1) as u32)
    }

    pub fn text(&self, id: FileId) -> &str {
        self.files[id.0 as usize].source()
    }

    pub fn name(&self, id: FileId) -> &str {
        self.files[id.0 as usize].name()
    }

    /// Finds a file already added under this name.
    pub fn find(&self, name: &str) -> Option<FileId> {
        self.files
            .iter()
            .position(|f| f.name() == name)
            .map(|i| FileId(i as u32))
    }

    /// 0-based line and UTF-16 column of a byte offset, as the Language Server
    /// Protocol counts positions (a `é` is one unit, a `𝑥` two).
    pub fn utf16_position(&self, id: FileId, byte: usize) -> (u32, u32) {
        let text = self.text(id);
        let byte = floor_char_boundary(text, byte.min(text.len()));
        let line = self.line_index(id, byte).unwrap_or(0);
        let start = self.line_range(id, line).map_or(0, |r| r.start).min(byte);
        let col = text[start..byte].encode_utf16().count();
        (line as u32, col as u32)
    }

    /// The byte offset of a 0-based line and UTF-16 column; a position past the
    /// end of its line is the line's end (before its line break), past the last
    /// line the end of the text.
    pub fn utf16_offset(&self, id: FileId, line: u32, col: u32) -> usize {
        let text = self.text(id);
        let Ok(range) = self.line_range(id, line as usize) else {
            return text.len();
        };
        let line_text = text[range.clone()].trim_end_matches(['\n', '\r']);
        let mut units = 0u32;
        for (i, c) in line_text.char_indices() {
            if units >= col {
                return range.start + i;
            }
            units += c.len_utf16() as u32;
        }
        range.start + line_text.len()
    }

    /// 1-based line and column (in characters) of a byte offset.
    pub fn line_col(&self, id: FileId, byte: usize) -> (usize, usize) {
        match self.location(id, byte) {
            Ok(loc) => (loc.line_number, loc.column_number),
            Err(_) => (1, 1),
        }
    }
}

/// The largest char boundary at or before `i` (a label may end inside a
/// multi-byte character only through a bug; positions must not panic on it).
fn floor_char_boundary(text: &str, mut i: usize) -> usize {
    while !text.is_char_boundary(i) {
        i -= 1;
    }
    i
}

impl<'a> Files<'a> for SourceMap {
    type FileId = FileId;
    type Name = &'a str;
    type Source = &'a str;

    fn name(&'a self, id: FileId) -> Result<&'a str, FilesError> {
        self.files
            .get(id.0 as usize)
            .map(|f| f.name().as_str())
            .ok_or(FilesError::FileMissing)
    }

    fn source(&'a self, id: FileId) -> Result<&'a str, FilesError> {
        self.files
            .get(id.0 as usize)
            .map(|f| f.source().as_str())
            .ok_or(FilesError::FileMissing)
    }

    fn line_index(&'a self, id: FileId, byte_index: usize) -> Result<usize, FilesError> {
        self.files
            .get(id.0 as usize)
            .ok_or(FilesError::FileMissing)?
            .line_index((), byte_index)
    }

    fn line_range(
        &'a self,
        id: FileId,
        line_index: usize,
    ) -> Result<std::ops::Range<usize>, FilesError> {
        self.files
            .get(id.0 as usize)
            .ok_or(FilesError::FileMissing)?
            .line_range((), line_index)
    }
}

#[cfg(test)]
mod tests {
    use super::SourceMap;

    #[test]
    fn utf16_positions_count_code_units() {
        // `é` is 2 bytes and 1 UTF-16 unit; `𝑥` (U+1D465) is 4 bytes and 2 units:
        // `// é𝑥 ` is 3 + 1 + 2 + 1 = 7 units.
        let mut s = SourceMap::new();
        let id = s.add("t", "ab\n// é𝑥 z\r\nq");
        let z = "ab\n// é𝑥 ".len();
        assert_eq!(s.utf16_position(id, z), (1, 7));
        assert_eq!(s.utf16_offset(id, 1, 7), z);
        assert_eq!(s.utf16_position(id, 0), (0, 0));
        assert_eq!(s.utf16_offset(id, 2, 0), "ab\n// é𝑥 z\r\n".len());
        // Past the end of a line: its end, before `\r\n`; past the text: its end.
        assert_eq!(s.utf16_offset(id, 1, 99), z + 1);
        assert_eq!(s.utf16_offset(id, 9, 0), s.text(id).len());
        // Inside a multi-byte character: the character's start.
        assert_eq!(s.utf16_position(id, "ab\n// é".len() + 1), (1, 4));
    }
}
