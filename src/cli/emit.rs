//! `axle emit adm|acf|lcf FILE [--loadcases SET] [--vertical force|height] [--axle WHEEL] -o OUT`.

use super::Exit;
use super::input::{Loaded, load_model, pick_set_reported};
use crate::emit;
use std::path::{Path, PathBuf};

#[derive(Copy, Clone, PartialEq, Eq, clap::ValueEnum)]
pub enum DeckKind {
    Adm,
    Acf,
    Lcf,
}

/// What the `.lcf` vertical columns hold.
#[derive(Copy, Clone, PartialEq, Eq, clap::ValueEnum)]
pub enum VerticalMode {
    /// `wheel_vertical_force`: the wheels' fz.
    Force,
    /// `wheel_center_height`: the wheel-centre z at axle's equilibrium.
    Height,
}

/// The set to write: the named one (an unknown name gets the did-you-mean of
/// `solve`), else the default set, else the first.
fn set(loaded: &Loaded, name: Option<&str>) -> Result<crate::model::LoadSetId, Exit> {
    match name {
        Some(_) => pick_set_reported(loaded, name),
        None => emit::load_set(&loaded.model, None).map_err(|e| {
            loaded.report(&[e.to_diagnostic(&loaded.model)]);
            Exit::Input
        }),
    }
}

pub fn run(
    kind: DeckKind,
    file: &Path,
    loadcases: Option<&str>,
    vertical: VerticalMode,
    axle: Option<&str>,
    out: Option<&PathBuf>,
) -> Exit {
    let loaded = match load_model(file) {
        Ok(l) => l,
        Err(e) => return e,
    };
    let model = &loaded.model;
    let stem = |ext: &str| -> String {
        let p = out.map(|p| p.as_path()).unwrap_or(file);
        p.with_extension(ext)
            .file_name()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default()
    };
    let text = match kind {
        DeckKind::Adm => emit::emit_adm(model).map(|d| {
            for n in &d.notes {
                eprintln!("note: {n}");
            }
            d.text
        }),
        DeckKind::Acf | DeckKind::Lcf => {
            let s = match set(&loaded, loadcases) {
                Ok(s) => s,
                Err(e) => return e,
            };
            if kind == DeckKind::Acf {
                let adm = stem("adm");
                let prefix = adm.trim_end_matches(".adm").to_string();
                emit::emit_acf(model, s, &adm, &prefix)
            } else if vertical == VerticalMode::Height {
                crate::kc::heights::centre_heights(model, s).and_then(|h| {
                    emit::emit_lcf_axle(model, s, &emit::Vertical::CentreHeight(h), axle)
                })
            } else {
                emit::emit_lcf_axle(model, s, &emit::Vertical::Force, axle)
            }
        }
    };
    match text {
        Ok(t) => super::input::emit(out.map(|p| p.as_path()), &t),
        Err(e) => {
            // Labelled at the responsible element's line in the axle file.
            loaded.report(&[e.to_diagnostic(model)]);
            Exit::Input
        }
    }
}
