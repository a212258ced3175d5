//! The one way the command line writes results: never onto one of the
//! command's inputs, atomically to files, and with stdout failures reported.
//!
//! A file is written to a temporary file in the target's folder, flushed to
//! disk, then renamed over the target, so a full disk or a kill during the
//! write leaves the old file whole. `-` as the target is stdout.

use super::Exit;
use super::read::{Identity, input_at, is_dash};
use std::io::Write;
use std::path::{Path, PathBuf};

/// Where results go.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Target {
    Stdout,
    File(PathBuf),
}

impl Target {
    /// `-o FILE`: absent or `-` is stdout.
    pub fn from_option(path: Option<&Path>) -> Target {
        match path {
            Some(p) if !is_dash(p) => Target::File(p.to_path_buf()),
            _ => Target::Stdout,
        }
    }
}

/// Why a write did not happen.
#[derive(Debug)]
pub enum WriteError {
    /// The target is one of the command's inputs (`input` as the user named it).
    WouldOverwriteInput { target: PathBuf, input: PathBuf },
    Io {
        target: String,
        error: std::io::Error,
    },
}

impl std::fmt::Display for WriteError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            WriteError::WouldOverwriteInput { target, input } if target == input => write!(
                f,
                "refusing to write {}: it is an input of this command; name another output file",
                target.display()
            ),
            WriteError::WouldOverwriteInput { target, input } => write!(
                f,
                "refusing to write {}: it is the same file as the input {}; name another output file",
                target.display(),
                input.display()
            ),
            WriteError::Io { target, error } => write!(f, "cannot write {target}: {error}"),
        }
    }
}

/// Writes `text` to `target`; prints a failure and returns its exit status
/// (2). A closed stdout pipe (`axle … | head`) exits 2 without a message.
pub fn emit(target: &Target, text: &str) -> Exit {
    reported(target, write(target, text))
}

/// The exit status of a write's outcome, its failure printed as [`emit`]
/// prints it.
pub fn reported(target: &Target, written: Result<(), WriteError>) -> Exit {
    match (target, written) {
        (_, Ok(())) => Exit::Ok,
        (Target::Stdout, Err(WriteError::Io { error, .. }))
            if error.kind() == std::io::ErrorKind::BrokenPipe =>
        {
            Exit::Io
        }
        (_, Err(e)) => {
            eprintln!("error: {e}");
            Exit::Io
        }
    }
}

/// Writes `text` to `target` (see the module doc).
pub fn write(target: &Target, text: &str) -> Result<(), WriteError> {
    let mut out = Stream::open(target)?;
    out.write(text.as_bytes())?;
    out.commit()
}

/// Results written piece by piece as they are made (`solve --format json`
/// of a long load path), with the guarantees of [`write`]: a file target is
/// refused when it is an input, written to a sibling temporary file and
/// renamed over the target only by [`Stream::commit`]; a stream dropped
/// uncommitted (an error on the way) removes its temporary file and leaves
/// the target as it was. Stdout is written as the pieces come.
pub struct Stream {
    sink: Sink,
    /// The target as messages name it.
    shown: String,
}

enum Sink {
    Stdout(std::io::StdoutLock<'static>),
    File {
        file: std::fs::File,
        tmp: PathBuf,
        real: PathBuf,
        committed: bool,
    },
}

impl Stream {
    /// Opens `target` for writing (see [`Stream`]).
    pub fn open(target: &Target) -> Result<Stream, WriteError> {
        match target {
            Target::Stdout => Ok(Stream {
                sink: Sink::Stdout(std::io::stdout().lock()),
                shown: "to stdout".into(),
            }),
            Target::File(path) => {
                refuse_input(path)?;
                Stream::open_atomic(path)
            }
        }
    }

    fn open_atomic(path: &Path) -> Result<Stream, WriteError> {
        let shown = path.display().to_string();
        let io = |error| WriteError::Io {
            target: shown.clone(),
            error,
        };
        let real = match std::fs::symlink_metadata(path) {
            Ok(m) if m.file_type().is_symlink() => std::fs::canonicalize(path).map_err(io)?,
            _ => path.to_path_buf(),
        };
        if real.is_dir() {
            return Err(io(std::io::Error::new(
                std::io::ErrorKind::IsADirectory,
                "it is a folder",
            )));
        }
        // Renaming would replace a read-only file that a plain write may not touch.
        if std::fs::metadata(&real).is_ok_and(|m| m.permissions().readonly()) {
            return Err(io(std::io::Error::new(
                std::io::ErrorKind::PermissionDenied,
                "the file is read-only",
            )));
        }
        let dir = match real.parent() {
            Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
            _ => PathBuf::from("."),
        };
        let name = real
            .file_name()
            .map_or_else(|| "out".into(), |n| n.to_string_lossy().into_owned());
        let tmp = dir.join(format!(".{name}.{}.axle-tmp", std::process::id()));
        let file = std::fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&tmp)
            .map_err(io)?;
        Ok(Stream {
            sink: Sink::File {
                file,
                tmp,
                real,
                committed: false,
            },
            shown,
        })
    }

    fn error(&self, error: std::io::Error) -> WriteError {
        WriteError::Io {
            target: self.shown.clone(),
            error,
        }
    }

    /// Writes the next piece.
    pub fn write(&mut self, bytes: &[u8]) -> Result<(), WriteError> {
        let written = match &mut self.sink {
            Sink::Stdout(out) => out.write_all(bytes),
            Sink::File { file, .. } => file.write_all(bytes),
        };
        written.map_err(|e| self.error(e))
    }

    /// Ends the output: stdout flushed; a file synced, given the
    /// permissions of the file it replaces, and renamed over it.
    pub fn commit(mut self) -> Result<(), WriteError> {
        let done = match &mut self.sink {
            Sink::Stdout(out) => out.flush(),
            Sink::File {
                file,
                tmp,
                real,
                committed,
            } => file
                .flush()
                .and_then(|()| file.sync_all())
                .and_then(|()| match std::fs::metadata(&*real) {
                    // A file replaced keeps its permissions (a read-only deck
                    // stays read-only).
                    Ok(m) => file.set_permissions(m.permissions()),
                    Err(_) => Ok(()),
                })
                .and_then(|()| std::fs::rename(&*tmp, &*real))
                .map(|()| *committed = true),
        };
        done.map_err(|e| self.error(e))
    }
}

impl Drop for Stream {
    fn drop(&mut self) {
        if let Sink::File {
            tmp,
            committed: false,
            ..
        } = &self.sink
        {
            // The temporary file is ours alone; the target was never touched.
            let _ = std::fs::remove_file(tmp);
        }
    }
}

/// Refuses a target that is one of the command's inputs (same path, a link
/// to it, or a hard link); a target that does not exist yet is no input.
pub fn refuse_input(path: &Path) -> Result<(), WriteError> {
    match Identity::of(path).and_then(|id| input_at(&id)) {
        Some(input) => Err(WriteError::WouldOverwriteInput {
            target: path.to_path_buf(),
            input,
        }),
        None => Ok(()),
    }
}

/// Refuses, before any work, an output that is the same file as an input
/// named on the command line (the check at write time covers the rest).
pub fn refuse_overlap(inputs: &[&Path], outputs: &[&Path]) -> Result<(), WriteError> {
    for out in outputs.iter().filter(|p| !is_dash(p)) {
        let Some(target) = Identity::of(out) else {
            continue;
        };
        if let Some(input) = inputs
            .iter()
            .find(|i| Identity::of(i).is_some_and(|id| id.same_file(&target)))
        {
            return Err(WriteError::WouldOverwriteInput {
                target: out.to_path_buf(),
                input: input.to_path_buf(),
            });
        }
    }
    Ok(())
}

/// Replaces an input file with new text (`fmt` in place): the same atomic
/// write, the one case where writing onto an input is the point.
pub fn replace_input(path: &Path, text: &str) -> Result<(), WriteError> {
    let mut out = Stream::open_atomic(path)?;
    out.write(text.as_bytes())?;
    out.commit()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The write-time check knows every file read, also those the command
    /// line does not name (a module imported by the model, say).
    #[test]
    fn a_file_once_read_is_refused_as_a_target_and_others_are_written() {
        let dir = std::env::temp_dir().join(format!("axle-write-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("temp dir");
        let input = dir.join("read.axle");
        std::fs::write(&input, "ground g {}\n").expect("write");
        super::super::read::read_text(&input).expect("reads");
        let target = Target::File(dir.join(".").join("read.axle"));
        assert!(matches!(
            write(&target, "lost"),
            Err(WriteError::WouldOverwriteInput { .. })
        ));
        assert_eq!(
            std::fs::read_to_string(&input).expect("kept"),
            "ground g {}\n"
        );
        let other = dir.join("other.txt");
        write(&Target::File(other.clone()), "new").expect("written");
        assert_eq!(std::fs::read_to_string(&other).expect("read"), "new");
        std::fs::remove_dir_all(&dir).ok();
    }

    /// A stream dropped before its commit (an error on the way) leaves the
    /// target as it was and no temporary file; committed, it replaces it.
    #[test]
    fn a_stream_replaces_its_target_only_when_committed() {
        let dir = std::env::temp_dir().join(format!("axle-stream-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("temp dir");
        let target = dir.join("out.json");
        std::fs::write(&target, "old\n").expect("write");
        let files = || std::fs::read_dir(&dir).expect("dir").count();
        let mut out = Stream::open(&Target::File(target.clone())).expect("opens");
        out.write(b"half of a ").expect("written");
        assert_eq!(files(), 2);
        drop(out);
        assert_eq!(std::fs::read_to_string(&target).expect("read"), "old\n");
        assert_eq!(files(), 1);
        let mut out = Stream::open(&Target::File(target.clone())).expect("opens");
        for piece in ["new ", "text\n"] {
            out.write(piece.as_bytes()).expect("written");
        }
        out.commit().expect("committed");
        assert_eq!(
            std::fs::read_to_string(&target).expect("read"),
            "new text\n"
        );
        assert_eq!(files(), 1);
        std::fs::remove_dir_all(&dir).ok();
    }
}
