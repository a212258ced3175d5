//! `axle fmt FILE... [--check]`; `axle fmt -` formats stdin to stdout.

use super::Exit;
use super::read::{is_dash, shown};
use super::write::{Target, emit, replace_input};
use crate::diagnostic::render;
use crate::source::SourceMap;
use std::path::PathBuf;

pub fn run(files: &[PathBuf], check: bool) -> Exit {
    let mut exit = Exit::Ok;
    for path in files {
        let text = match super::read(path) {
            Ok(t) => t,
            Err(e) => {
                exit = exit.max(e);
                continue;
            }
        };
        let mut sources = SourceMap::new();
        let id = sources.add(shown(path), text.clone());
        let formatted = match crate::fmt::format_source(id, &text) {
            Ok(f) => f,
            Err(d) => {
                render::to_stderr(&sources, &[d]);
                exit = exit.max(Exit::Input);
                continue;
            }
        };
        if is_dash(path) && !check {
            exit = exit.max(emit(&Target::Stdout, &formatted));
            continue;
        }
        if formatted == text {
            continue;
        }
        if check {
            eprintln!("{} is not formatted", shown(path));
            exit = exit.max(Exit::Input);
        } else if let Err(e) = replace_input(path, &formatted) {
            eprintln!("error: {e}");
            exit = Exit::Io;
        }
    }
    exit
}
