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
    match (target, write(target, text)) {
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
    match target {
        Target::Stdout => {
            let mut out = std::io::stdout().lock();
            out.write_all(text.as_bytes())
                .and_then(|()| out.flush())
                .map_err(|error| WriteError::Io {
                    target: "to stdout".into(),
                    error,
                })
        }
        Target::File(path) => write_file(path, text.as_bytes()),
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
    write_atomic(path, text.as_bytes())
}

/// The atomic file write: refuse inputs, write a sibling temporary file,
/// sync, rename over the target (a symbolic link's target is replaced, the
/// link kept).
fn write_file(path: &Path, bytes: &[u8]) -> Result<(), WriteError> {
    refuse_input(path)?;
    write_atomic(path, bytes)
}

fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), WriteError> {
    let io = |error| WriteError::Io {
        target: path.display().to_string(),
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
    let result = write_synced(&tmp, bytes, &real).and_then(|()| std::fs::rename(&tmp, &real));
    if result.is_err() {
        // The temporary file is ours alone; the target was never touched.
        let _ = std::fs::remove_file(&tmp);
    }
    result.map_err(io)
}

fn write_synced(tmp: &Path, bytes: &[u8], target: &Path) -> std::io::Result<()> {
    let mut f = std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(tmp)?;
    f.write_all(bytes)?;
    f.flush()?;
    f.sync_all()?;
    // A file replaced keeps its permissions (a read-only deck stays read-only).
    if let Ok(m) = std::fs::metadata(target) {
        f.set_permissions(m.permissions())?;
    }
    Ok(())
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
}
