//! `axle fmt FILE... [--check]`.

use super::Exit;
use crate::diagnostic::render;
use crate::source::SourceMap;
use std::path::PathBuf;

pub fn run(files: &[PathBuf], check: bool) -> Exit {
    let mut exit = Exit::Ok;
    for path in files {
        let Some(text) = super::read(path) else {
            exit = Exit::Io;
            continue;
        };
        let mut sources = SourceMap::new();
        let id = sources.add(path.display().to_string(), text.clone());
        let formatted = match crate::fmt::format_source(id, &text) {
            Ok(f) => f,
            Err(d) => {
                render::to_stderr(&sources, &[d]);
                if exit == Exit::Ok {
                    exit = Exit::Input;
                }
                continue;
            }
        };
        if formatted == text {
            continue;
        }
        if check {
            eprintln!("{} is not formatted", path.display());
            if exit == Exit::Ok {
                exit = Exit::Input;
            }
        } else if let Err(e) = std::fs::write(path, formatted) {
            eprintln!("error: cannot write {}: {e}", path.display());
            exit = Exit::Io;
        }
    }
    exit
}
