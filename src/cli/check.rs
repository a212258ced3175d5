//! `axle check FILE...`.

use super::read::{read_text, shown};
use super::write::{Target, emit};
use super::{DiagFormat, Exit};
use crate::diagnostic::render;
use crate::source::SourceMap;
use std::path::PathBuf;

pub fn run(files: &[PathBuf], format: DiagFormat) -> Exit {
    let mut sources = SourceMap::new();
    let mut diags = Vec::new();
    let mut exit = Exit::Ok;
    for path in files {
        let text = match read_text(path) {
            Ok(t) => t,
            Err(e) => {
                // Reported like any other diagnostic, so `--format json` carries it.
                diags.push(e.to_diagnostic(&mut sources, path));
                exit = exit.max(e.exit());
                continue;
            }
        };
        let id = sources.add(shown(path), text);
        let checked = crate::check::check_file(&mut sources, id);
        if checked.problems.has_errors() {
            exit = exit.max(Exit::Input);
        }
        diags.extend(checked.problems.list);
    }
    match format {
        DiagFormat::Human => render::to_stderr(&sources, &diags),
        DiagFormat::Json => {
            let text = format!("{}\n", render::to_json(&sources, &diags));
            let written = emit(&Target::Stdout, &text);
            exit = exit.max(written);
        }
    }
    exit
}
