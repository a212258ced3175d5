//! `axle import adm IN.adm -o OUT.axle`.

use super::Exit;
use crate::diagnostic::{Severity, render};
use std::path::{Path, PathBuf};

#[derive(Copy, Clone, PartialEq, Eq, clap::ValueEnum)]
pub enum ImportKind {
    Adm,
}

pub fn run(file: &Path, out: Option<&PathBuf>) -> Exit {
    let Some(text) = super::read(file) else {
        return Exit::Io;
    };
    let imported = crate::import::import_adm(&file.display().to_string(), &text);
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
        _ => Exit::Input,
    }
}
