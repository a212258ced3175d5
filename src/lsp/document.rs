//! One open file: its text, its analysis (the partial model and the name
//! table), and conversions between LSP positions and byte offsets.

use crate::check::{Analysis, Passes};
use crate::source::SourceMap;
use crate::span::{FileId, Span};
use lsp_types::{Position, Range, Uri};

/// Files larger than this are not checked as they are typed (a generated sweep
/// of several megabytes would make every keystroke wait); `axle check` still
/// checks them.
pub const LIVE_LIMIT: usize = 2 << 20;

pub struct Document {
    pub uri: Uri,
    pub sources: SourceMap,
    pub file: FileId,
    /// `None` for a file over [`LIVE_LIMIT`].
    pub analysis: Option<Analysis>,
}

impl Document {
    pub fn new(uri: Uri, text: String, passes: Passes) -> Document {
        let mut sources = SourceMap::new();
        let name = file_name(&uri);
        let big = text.len() > LIVE_LIMIT;
        let file = sources.add(name, text);
        let analysis = (!big).then(|| crate::check::analyse(&mut sources, file, passes));
        Document {
            uri,
            sources,
            file,
            analysis,
        }
    }

    pub fn text(&self) -> &str {
        self.sources.text(self.file)
    }

    pub fn offset(&self, p: Position) -> usize {
        self.sources.utf16_offset(self.file, p.line, p.character)
    }

    pub fn range(&self, span: Span) -> Range {
        crate::diagnostic::render::lsp_range(&self.sources, span)
    }

    /// The span of this file covering `offset`, for symbol look-up.
    pub fn file_span(&self) -> Span {
        Span::new(self.file, 0, self.text().len())
    }

    /// Whether the file parsed without a syntax error.
    pub fn parsed(&self) -> bool {
        self.analysis.as_ref().is_some_and(|a| a.parsed)
    }
}

/// The file name the checker sees (its stem names the model, as on the command line).
fn file_name(uri: &Uri) -> String {
    let path = uri
        .path()
        .as_estr()
        .decode()
        .into_string_lossy()
        .into_owned();
    match path.rsplit('/').next() {
        Some(n) if !n.is_empty() => n.to_string(),
        _ => "untitled.axle".into(),
    }
}
