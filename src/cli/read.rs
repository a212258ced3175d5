//! Reading the command's input files: `-` is stdin, a byte that is not UTF-8
//! is a diagnostic at its line and column, and every file read is remembered so
//! the writer ([`super::write`]) can refuse to write onto it.

use super::Exit;
use crate::diagnostic::{Diagnostic, render};
use crate::source::SourceMap;
use crate::span::Span;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// One file the command read, as the writer compares it: the path with links
/// resolved, and on Unix the device and inode (a hard link has its own path).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Identity {
    pub canonical: Option<PathBuf>,
    pub device_inode: Option<(u64, u64)>,
}

impl Identity {
    /// The identity of an existing file; `None` when it does not exist.
    pub fn of(path: &Path) -> Option<Identity> {
        let meta = std::fs::metadata(path).ok()?;
        Some(Identity {
            canonical: std::fs::canonicalize(path).ok(),
            device_inode: device_inode(&meta),
        })
    }

    pub fn same_file(&self, other: &Identity) -> bool {
        let same_path = self.canonical.is_some() && self.canonical == other.canonical;
        let same_inode = self.device_inode.is_some() && self.device_inode == other.device_inode;
        same_path || same_inode
    }
}

#[cfg(unix)]
fn device_inode(meta: &std::fs::Metadata) -> Option<(u64, u64)> {
    use std::os::unix::fs::MetadataExt;
    Some((meta.dev(), meta.ino()))
}

#[cfg(not(unix))]
fn device_inode(_: &std::fs::Metadata) -> Option<(u64, u64)> {
    None
}

/// The files read so far by this process (the command line runs one command).
static INPUTS: Mutex<Vec<(PathBuf, Identity)>> = Mutex::new(Vec::new());

fn remember(path: &Path) {
    if let Some(id) = Identity::of(path)
        && let Ok(mut list) = INPUTS.lock()
    {
        list.push((path.to_path_buf(), id));
    }
}

/// The input that is the same file as `target`, if any (by its given path).
/// Only while its path still leads to that file: an input deleted or
/// replaced since it was read leaves its device and inode numbers free for
/// another file (seen in the tests, which share this process: a file read
/// and deleted by one test, its inode reused by another test's output,
/// which was refused as that input).
pub fn input_at(target: &Identity) -> Option<PathBuf> {
    let list = INPUTS.lock().ok()?;
    list.iter()
        .find(|(p, id)| {
            id.same_file(target) && Identity::of(p).is_some_and(|now| now.same_file(target))
        })
        .map(|(p, _)| p.clone())
}

/// True for the path `-`, which names stdin (input) or stdout (output).
pub fn is_dash(path: &Path) -> bool {
    path.as_os_str() == "-"
}

/// The name diagnostics give a file: `<stdin>` for `-`.
pub fn shown(path: &Path) -> String {
    if is_dash(path) {
        "<stdin>".to_string()
    } else {
        path.display().to_string()
    }
}

/// Why a file gave no text.
#[derive(Debug)]
pub enum ReadError {
    /// The file could not be read (missing, a folder, no permission).
    Io(std::io::Error),
    /// The bytes are not UTF-8: the text with the bad bytes replaced, and the
    /// byte offset and value of the first bad one.
    NotUtf8 { lossy: String, at: usize, byte: u8 },
}

impl ReadError {
    /// The exit status this failure means: an unreadable file is an I/O
    /// error (2), bad bytes in a readable file are wrong input (1).
    pub fn exit(&self) -> Exit {
        match self {
            ReadError::Io(_) => Exit::Io,
            ReadError::NotUtf8 { .. } => Exit::Input,
        }
    }

    /// A diagnostic with the file's name (I/O: at its start; bad bytes: at
    /// their line and column), the file added to `sources` to quote it.
    pub fn to_diagnostic(&self, sources: &mut SourceMap, path: &Path) -> Diagnostic {
        match self {
            ReadError::Io(e) => {
                let file = sources.add(shown(path), String::new());
                Diagnostic::error("E0003", format!("cannot read {}: {e}", shown(path)))
                    .primary(Span::new(file, 0, 0), "this file")
            }
            ReadError::NotUtf8 { lossy, at, byte } => {
                // Offsets in the lossy text: each bad sequence became U+FFFD.
                let start = lossy.find('\u{FFFD}').unwrap_or(0);
                let file = sources.add(shown(path), lossy.clone());
                Diagnostic::error(
                    "E0002",
                    format!("byte 0x{byte:02X} (file offset {at}) is not UTF-8 text"),
                )
                .primary(
                    Span::new(file, start, start + '\u{FFFD}'.len_utf8()),
                    "not UTF-8",
                )
                .hint("save the file as UTF-8 (axle files and CSV data are UTF-8 text)")
            }
        }
    }
}

/// The bytes of `path` (stdin for `-`), remembered as an input.
pub fn read_bytes(path: &Path) -> Result<Vec<u8>, ReadError> {
    use std::io::Read;
    if is_dash(path) {
        let mut buf = Vec::new();
        std::io::stdin()
            .lock()
            .read_to_end(&mut buf)
            .map_err(ReadError::Io)?;
        return Ok(buf);
    }
    let bytes = std::fs::read(path).map_err(ReadError::Io)?;
    remember(path);
    Ok(bytes)
}

/// The UTF-8 text of `path` (stdin for `-`), remembered as an input.
pub fn read_text(path: &Path) -> Result<String, ReadError> {
    let bytes = read_bytes(path)?;
    String::from_utf8(bytes).map_err(|e| {
        let at = e.utf8_error().valid_up_to();
        let bytes = e.into_bytes();
        ReadError::NotUtf8 {
            lossy: String::from_utf8_lossy(&bytes).into_owned(),
            at,
            byte: bytes.get(at).copied().unwrap_or(0),
        }
    })
}

/// Reads a text file, printing the failure as a diagnostic; `Err` is the exit status.
pub fn read(path: &Path) -> Result<String, Exit> {
    read_text(path).map_err(|e| {
        let mut sources = SourceMap::new();
        let d = e.to_diagnostic(&mut sources, path);
        render::to_stderr(&sources, &[d]);
        e.exit()
    })
}
