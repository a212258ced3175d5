//! `axle import adm IN.adm -o OUT.axle`.

use super::Exit;
use crate::diagnostic::{Severity, render};
use std::path::{Path, PathBuf};

#[derive(Copy, Clone, PartialEq, Eq, clap::ValueEnum)]
pub enum ImportKind {
    Adm,
}

pub fn run(file: &Path, out: Option<&PathBuf>) -> Exit {
    let text = match super::read(file) {
        Ok(t) => t,
        Err(e) => return e,
    };
    let imported = crate::import::import_adm(&super::read::shown(file), &text);
    render::to_stderr(&imported.sources, &imported.problems);
    match imported.source {
        Some(src)
            if !imported
                .problems
                .iter()
                .any(|d| d.severity == Severity::Error) =>
        {
            super::input::emit(out.map(|p| p.as_path()), &src)
        }
        _ => {
            // The deck was read but the model it describes does not check: keep
            // the source the diagnostics point into, so the user can fix it.
            if let (Some(draft), Some(path)) = (&imported.draft, out)
                && super::input::emit(Some(path), draft) == Exit::Ok
            {
                eprintln!(
                    "note: the axle source read from the deck, with the errors above, was written to {}",
                    path.display()
                );
            }
            Exit::Input
        }
    }
}
