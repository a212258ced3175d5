//! `axle diagnose FILE --kc CSV... [--landmarks CSV|IGES...] [--noise CHANNEL=SIGMA...] [--candidates KIND,...]
//! [--format table|json] [-o EXTENDED.axle] [--report DIR]` (`docs/diagnose.md`).

use super::Exit;
use crate::diagnose::channel::Channel;
use crate::diagnose::choose::DiagnoseError;
use crate::diagnose::{Diagnosis, Kind, Options, diagnose, landmarks, rig};
use crate::diagnostic::{Diagnostic, render};
use crate::model::{ElementId, Model};
use std::path::PathBuf;

#[derive(Copy, Clone, PartialEq, Eq, clap::ValueEnum)]
pub enum Format {
    Table,
    Json,
}

#[derive(clap::Args)]
pub struct Args {
    /// The axle model to diagnose.
    pub file: PathBuf,
    /// K&C rig data, one file per measured load path, rows in the order
    /// measured (step, fx, fy, fz, wc_x, wc_y, wc_z, toe_deg, camber_deg).
    #[arg(long, required = true, num_args = 1..)]
    pub kc: Vec<PathBuf>,
    /// Landmark data measured on the same run (step, part, landmark, x, y, z;
    /// or IGES, one state per file): one CSV per --kc file, in the same order,
    /// or any number with a single --kc file.
    #[arg(long, num_args = 1..)]
    pub landmarks: Vec<PathBuf>,
    /// The noise of a channel, e.g. `toe_deg=0.005` (channel units); the
    /// others are estimated from the data.
    #[arg(long, value_name = "CHANNEL=SIGMA")]
    pub noise: Vec<String>,
    /// The kinds of cause to consider (default: all).
    #[arg(long, value_name = "KIND,...", value_delimiter = ',')]
    pub candidates: Vec<String>,
    #[arg(long, value_enum, default_value = "table")]
    pub format: Format,
    /// Write the model with the causes found added here (your file, comments kept).
    #[arg(short = 'o', long = "output")]
    pub output: Option<PathBuf>,
    /// Write an HTML report (K&C curves measured, nominal and extended) into this folder.
    #[arg(long, value_name = "DIR")]
    pub report: Option<PathBuf>,
}

fn usage(message: String) -> Exit {
    eprintln!("error: {message}");
    Exit::Io
}

/// The options from the command line, or a usage error.
fn options(a: &Args) -> Result<Options, Exit> {
    let mut o = Options::default();
    let names: Vec<&str> = Channel::ALL.iter().map(|c| c.name()).collect();
    for n in &a.noise {
        let Some((ch, v)) = n.split_once('=') else {
            return Err(usage(format!(
                "--noise {n}: expected CHANNEL=SIGMA, channels: {}",
                names.join(", ")
            )));
        };
        let Some(c) = Channel::parse(ch.trim()) else {
            return Err(usage(format!(
                "--noise: no channel `{ch}`; channels: {}",
                names.join(", ")
            )));
        };
        match v.trim().parse::<f64>() {
            Ok(s) if s.is_finite() && s > 0.0 => o.noise.push((c, s)),
            _ => {
                return Err(usage(format!(
                    "--noise {n}: the deviation must be a positive number"
                )));
            }
        }
    }
    if !a.candidates.is_empty() {
        o.kinds.clear();
        for k in &a.candidates {
            match Kind::parse(k.trim()) {
                Some(kind) => o.kinds.push(kind),
                None => {
                    let all: Vec<&str> = Kind::CAUSES.iter().map(|k| k.name()).collect();
                    return Err(usage(format!(
                        "--candidates: no kind `{k}`; kinds: {}",
                        all.join(", ")
                    )));
                }
            }
        }
    }
    Ok(o)
}

/// A K&C file of some of the model's wheels: the others are replayed
/// unloaded, which is right only if the rig left them so (W1307).
fn unloaded_wheels(
    model: &crate::model::Model,
    paths: &[rig::RigPath],
    file: crate::span::FileId,
) -> Option<crate::diagnostic::Diagnostic> {
    let missing: Vec<&str> = model
        .wheels
        .iter()
        .enumerate()
        .filter(|(k, _)| paths.iter().all(|p| p.wheel.index() != *k))
        .map(|(_, w)| w.name.as_str())
        .collect();
    if missing.is_empty() {
        return None;
    }
    Some(
        crate::diagnostic::Diagnostic::warning(
            "W1307",
            format!(
                "the K&C file has no rows of wheel{} {}: replayed unloaded",
                if missing.len() > 1 { "s" } else { "" },
                missing.iter().map(|n| format!("`{n}`")).collect::<Vec<_>>().join(", ")
            ),
        )
        .primary(crate::span::Span::new(file, 0, 0), "this K&C file")
        .note("on an axle rig both wheels are usually loaded; a wheel left out of the file is taken as carrying no load, and the diagnosis then explains a difference the rig did not have")
        .hint("give the rows of every wheel the rig loaded (`wheel` column), one row per wheel and step"),
    )
}

pub fn run(a: &Args) -> Exit {
    let opts = match options(a) {
        Ok(o) => o,
        Err(e) => return e,
    };
    let super::input::Loaded {
        mut sources,
        model,
        file: id,
    } = match super::input::load_model(&a.file) {
        Ok(l) => l,
        Err(e) => return e,
    };
    let mut paths = Vec::new();
    // The first path of each file: landmark files pair with K&C files.
    let mut firsts = Vec::new();
    for p in &a.kc {
        let text = match super::read(p) {
            Ok(t) => t,
            Err(e) => return e,
        };
        let name = p.file_stem().map_or_else(
            || super::read::shown(p),
            |s| s.to_string_lossy().into_owned(),
        );
        let file = sources.add(super::read::shown(p), text);
        match rig::read(&model, file, &name, sources.text(file)) {
            Ok(r) => {
                if let Some(w) = unloaded_wheels(&model, &r, file) {
                    render::to_stderr(&sources, &[w]);
                }
                firsts.push(paths.len());
                paths.extend(r);
            }
            Err(d) => {
                render::to_stderr(&sources, &[d]);
                return Exit::Input;
            }
        }
    }
    let files = match super::locate::landmark_files(&mut sources, &a.landmarks) {
        Ok(f) => f,
        Err((d, code)) => {
            render::to_stderr(&sources, &[*d]);
            return code;
        }
    };
    let mut remarks = crate::measure::inputs::Remarks::default();
    // A file of two wheels gives two paths of the same run: its landmarks
    // go with the first (the parts' poses, counted once).
    let mut heads: Vec<rig::RigPath> = firsts.iter().map(|&i| paths[i].clone()).collect();
    let joined = landmarks::attach(&sources, &model, &mut heads, &files, &mut remarks);
    for (&i, h) in firsts.iter().zip(heads) {
        paths[i] = h;
    }
    super::locate::render_remarks(&sources, &remarks);
    if let Err(d) = joined {
        render::to_stderr(&sources, &[d]);
        return Exit::Input;
    }
    let d = match diagnose(&model, &paths, &opts) {
        Ok(d) => d,
        Err(e) => {
            render::to_stderr(&sources, &[failure(&model, &paths, &e)]);
            return Exit::Input;
        }
    };
    if let Some(out) = &a.output {
        let reasons = reasons(&model, &d);
        let text =
            match super::model_out::edited(&sources, id, &model, &d.model, "diagnose", &reasons) {
                Ok(t) => t,
                Err(code) => return code,
            };
        let code = super::input::emit(Some(out), &text);
        if code != Exit::Ok {
            return code;
        }
    }
    if let Some(dir) = &a.report {
        let html = crate::output::diagnose_html::page(&model, &paths, &d);
        if let Err(e) = std::fs::create_dir_all(dir) {
            eprintln!("error: cannot create {}: {e}", dir.display());
            return Exit::Io;
        }
        let code = super::input::emit(Some(&dir.join("diagnose.html")), &html);
        if code != Exit::Ok {
            return code;
        }
    }
    let text = match a.format {
        Format::Table => crate::output::diagnose_table::table(&d, &paths, &model.name),
        Format::Json => {
            let v = crate::output::diagnose_json::to_json(&d, &paths);
            serde_json::to_string_pretty(&v).unwrap_or_default() + "\n"
        }
    };
    super::input::emit(None, &text)
}

/// The diagnostic of a diagnosis that could not run.
fn failure(model: &Model, paths: &[rig::RigPath], e: &DiagnoseError) -> Diagnostic {
    match e {
        DiagnoseError::Nominal(r) => {
            let path = &paths[r.path.min(paths.len().saturating_sub(1))];
            let step = path.steps.get(r.step).map_or(0, |s| s.step);
            r.error
                .to_diagnostic(model)
                .note(format!(
                    "the model itself does not solve along `{}` at step {step}: diagnose replays the rig on the model as it is first",
                    path.name
                ))
        }
        DiagnoseError::TooFewSteps { steps, needed } => Diagnostic::error(
            "E1304",
            format!(
                "the K&C files hold {steps} steps; a diagnosis holds every third step out and needs at least {needed}"
            ),
        )
        .hint("measure more steps along each path"),
    }
}

/// The comment on each element the diagnosis changed or added.
fn reasons(model: &Model, d: &Diagnosis) -> Vec<(ElementId, String)> {
    let _ = model;
    d.effects
        .iter()
        .map(|e| {
            (
                e.hypothesis.changed,
                crate::diagnose::words::sentence(e, &d.noise),
            )
        })
        .collect()
}
