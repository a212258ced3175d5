//! `axle emit adm|acf|lcf FILE [--loadcases SET] -o OUT`.

use super::Exit;
use crate::diagnostic::render;
use crate::emit;
use crate::model::Model;
use std::path::{Path, PathBuf};

#[derive(Copy, Clone, PartialEq, Eq, clap::ValueEnum)]
pub enum DeckKind {
    Adm,
    Acf,
    Lcf,
}

/// Checks `file` and returns its model, printing diagnostics.
pub fn load_model(file: &Path) -> Result<Model, Exit> {
    let text = super::read(file).ok_or(Exit::Io)?;
    let (sources, checked) = crate::check::check_str(&file.display().to_string(), &text);
    render::to_stderr(&sources, &checked.problems.list);
    checked.model.ok_or(Exit::Input)
}

pub fn run(kind: DeckKind, file: &Path, loadcases: Option<&str>, out: Option<&PathBuf>) -> Exit {
    let model = match load_model(file) {
        Ok(m) => m,
        Err(e) => return e,
    };
    let stem = |ext: &str| -> String {
        let p = out.map(|p| p.as_path()).unwrap_or(file);
        p.with_extension(ext)
            .file_name()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default()
    };
    let text = match kind {
        DeckKind::Adm => emit::emit_adm(&model).map(|d| {
            for n in &d.notes {
                eprintln!("note: {n}");
            }
            d.text
        }),
        DeckKind::Acf => emit::load_set(&model, loadcases).and_then(|s| {
            let adm = stem("adm");
            let prefix = adm.trim_end_matches(".adm").to_string();
            emit::emit_acf(&model, s, &adm, &prefix)
        }),
        DeckKind::Lcf => emit::load_set(&model, loadcases).and_then(|s| emit::emit_lcf(&model, s)),
    };
    let text = match text {
        Ok(t) => t,
        Err(e) => {
            eprintln!("error: cannot emit {}: {e}", file.display());
            return Exit::Input;
        }
    };
    super::input::emit(out.map(|p| p.as_path()), &text)
}
