//! `axle check FILE...`.

use super::{DiagFormat, Exit};
use crate::diagnostic::render;
use crate::source::SourceMap;
use std::path::PathBuf;

pub fn run(files: &[PathBuf], format: DiagFormat) -> Exit {
    let mut sources = SourceMap::new();
    let mut diags = Vec::new();
    let mut exit = Exit::Ok;
    for path in files {
        let Some(text) = super::read(path) else {
            exit = Exit::Io;
            continue;
        };
        let id = sources.add(path.display().to_string(), text);
        let checked = crate::check::check_file(&mut sources, id);
        if checked.problems.has_errors() && exit == Exit::Ok {
            exit = Exit::Input;
        }
        diags.extend(checked.problems.list);
    }
    match format {
        DiagFormat::Human => render::to_stderr(&sources, &diags),
        DiagFormat::Json => println!("{}", render::to_json(&sources, &diags)),
    }
    exit
}
