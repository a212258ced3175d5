//! `axle locate FILE --landmarks CSV|IGES... [--reference STEP] [--format table|json] [-o OUT.axle]`,
//! and the landmark loading `correct` shares: CSV files, and IGES files of one
//! measured state each.

use super::Exit;
use crate::diagnostic::{Diagnostic, render};
use crate::locate::plan::{Options, locate_all};
use crate::locate::report::{Report, apply, report};
use crate::measure::poses::{MeasureIssue, Observation};
use crate::model::Model;
use crate::source::SourceMap;
use crate::span::{FileId, Span};
use std::path::{Path, PathBuf};

#[derive(clap::Args)]
pub struct Args {
    /// The axle model.
    pub file: PathBuf,
    /// Landmark CSV (step, part, landmark, x, y, z; global mm) and/or IGES
    /// files (.igs/.iges), one measured state each, numbered on after the CSV steps.
    #[arg(long, required = true, num_args = 1..)]
    pub landmarks: Vec<PathBuf>,
    /// The step whose state is the reference (results are in global coordinates there); default: the first.
    #[arg(long)]
    pub reference: Option<usize>,
    #[arg(long, value_enum, default_value = "table")]
    pub format: super::OutFormat,
    /// Write the model with the located geometry as axle source.
    #[arg(short = 'o', long = "output")]
    pub output: Option<PathBuf>,
    /// Landmark matching tolerance, mm (thesis: 0.5).
    #[arg(long, default_value_t = 0.5)]
    pub tolerance: f64,
    /// Noise of one landmark coordinate, mm.
    #[arg(long, default_value_t = 0.05)]
    pub sigma: f64,
    /// Centres less certain than this (mm) are reported as not observable.
    #[arg(long, default_value_t = 5.0)]
    pub max_uncertainty: f64,
}

pub fn run(a: &Args) -> Exit {
    let mut sources = SourceMap::new();
    let text = match super::read(&a.file) {
        Ok(t) => t,
        Err(e) => return e,
    };
    let id = sources.add(super::read::shown(&a.file), text);
    let checked = crate::check::check_file(&mut sources, id);
    render::to_stderr(&sources, &checked.problems.list);
    let Some(model) = checked.model else {
        return Exit::Input;
    };
    let data = match load_landmarks(&mut sources, &a.landmarks, &model) {
        Ok(d) => d,
        Err(code) => return code,
    };
    let steps = data.fit(&sources, &model, a.tolerance);
    let shown = data.shown();
    if steps.is_empty() {
        eprintln!("error: no step of {shown} gives a part pose");
        return Exit::Input;
    }
    let reference = a.reference.unwrap_or(steps[0].step);
    if !steps.iter().any(|s| s.step == reference) {
        eprintln!("error: step {reference} is not in {shown}");
        return Exit::Input;
    }
    let opt = Options {
        sigma: a.sigma,
        max_uncertainty: a.max_uncertainty,
        ..Options::default()
    };
    let located = locate_all(&model, &steps, &opt);
    let rep = report(&model, &steps, &located, reference);
    if let Some(out) = &a.output {
        let text = crate::fmt::print_model(&apply(&model, &located));
        let code = super::input::emit(Some(out), &text);
        if code != Exit::Ok {
            return code;
        }
    }
    let text = match a.format {
        super::OutFormat::Json => match serde_json::to_string_pretty(&rep) {
            Ok(s) => format!("{s}\n"),
            Err(e) => {
                eprintln!("error: cannot write the results as JSON: {e}");
                return Exit::Io;
            }
        },
        _ => table(&rep),
    };
    super::input::emit(None, &text)
}

fn table(r: &Report) -> String {
    let mut s = format!("located at step {} (global mm)\n", r.reference_step);
    s += &format!(
        "{:<10} {:<12} {:>30} {:>24} {:>9} {:>11}  method\n",
        "element", "kind", "centre", "axis", "residual", "uncertainty"
    );
    for (name, e) in &r.joints {
        let c = e.center.map_or("not observable".to_string(), |c| {
            format!("({:.2}, {:.2}, {:.2})", c[0], c[1], c[2])
        });
        let a = e.axis.map_or("-".to_string(), |a| {
            format!("({:.3}, {:.3}, {:.3})", a[0], a[1], a[2])
        });
        let u = e
            .uncertainty_mm
            .map_or("-".to_string(), |u| format!("{u:.3}"));
        s += &format!(
            "{name:<10} {:<12} {c:>30} {a:>24} {:>9.3} {u:>11}  {}\n",
            e.kind, e.residual_mm, e.method
        );
        if !e.observable {
            s += &format!("{:<10} {}\n", "", e.note);
        }
    }
    if let Some((step, part, lm, worst)) = r.worst_landmark() {
        let n: usize = r.poses.values().map(|p| p.len()).sum();
        s += &format!(
            "pose fits: {n} (part, step) pairs; worst landmark residual {worst:.3} mm ({part}.{lm} at step {step}); every residual in the JSON output\n"
        );
    }
    s + &relative_table(r)
}

/// Per element, the largest relative rotation and I-marker translation over
/// the steps; every step is in the JSON output.
fn relative_table(r: &Report) -> String {
    if r.relative_motions.is_empty() {
        return String::new();
    }
    let mut s = format!(
        "relative motion of part I in part J since step {} (largest over the steps; every step in the JSON output)\n",
        r.reference_step
    );
    s += &format!(
        "{:<10} {:<28} {:>14} {:>7} {:>13} {:>7}\n",
        "element", "part I in part J", "rotation deg", "step", "I marker mm", "step"
    );
    for (name, m) in &r.relative_motions {
        let Some(((rs, deg), (ts, mm))) = m.largest() else {
            continue;
        };
        let parts = format!("{} in {}", m.parts[0], m.parts[1]);
        s += &format!("{name:<10} {parts:<28} {deg:>14.3} {rs:>7} {mm:>13.3} {ts:>7}\n");
    }
    s
}

/// Landmark observations from every `--landmarks` file, with where each came from.
pub struct Landmarks {
    pub observations: Vec<Observation>,
    /// The file of each observation (parallel to `observations`).
    files: Vec<FileId>,
    names: Vec<String>,
}

fn is_iges(p: &Path) -> bool {
    p.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("igs") || e.eq_ignore_ascii_case("iges"))
}

/// Byte range of 1-based line `n` of `text`.
fn line_span(text: &str, n: usize) -> (usize, usize) {
    let start: usize = text
        .split_inclusive('\n')
        .take(n.saturating_sub(1))
        .map(str::len)
        .sum();
    let len = text[start..].find('\n').unwrap_or(text.len() - start);
    (start, start + len)
}

/// Reads landmark files: CSV files keep their `step` column; IGES files are one
/// measured state each, numbered in the order given after the last CSV step.
/// Prints warnings, and notes about the lines and planes IGES files carry.
/// `Err` once an error was printed (a missing file is an I/O error, exit 2).
pub fn load_landmarks(
    sources: &mut SourceMap,
    paths: &[PathBuf],
    model: &Model,
) -> Result<Landmarks, Exit> {
    let mut out = Landmarks {
        observations: Vec::new(),
        files: Vec::new(),
        names: paths.iter().map(|p| p.display().to_string()).collect(),
    };
    let mut warnings: Vec<Diagnostic> = Vec::new();
    let skipped_warning = |id: FileId, s: &crate::data::landmarks::Skipped| {
        Diagnostic::warning("W0710", s.message.clone())
            .primary(Span::new(id, s.start, s.end), "left out")
    };
    let (csv, iges): (Vec<&PathBuf>, Vec<&PathBuf>) = paths.iter().partition(|p| !is_iges(p));
    for path in csv {
        let text = super::read(path)?;
        let id = sources.add(super::read::shown(path), text);
        match crate::data::landmarks::read(sources.text(id), model) {
            Ok((obs, skipped)) => {
                warnings.extend(skipped.iter().map(|s| skipped_warning(id, s)));
                out.files.extend(obs.iter().map(|_| id));
                out.observations.extend(obs);
            }
            Err(e) => {
                render::to_stderr(sources, &[e.to_diagnostic(id)]);
                return Err(Exit::Input);
            }
        }
    }
    let first = out.observations.iter().map(|o| o.step).max().unwrap_or(0) + 1;
    for (k, path) in iges.into_iter().enumerate() {
        let bytes = super::read::read_bytes(path).map_err(|e| {
            let mut s = SourceMap::new();
            let d = e.to_diagnostic(&mut s, path);
            render::to_stderr(&s, &[d]);
            e.exit()
        })?;
        let text = crate::data::iges::ascii_columns(&bytes);
        let id = sources.add(path.display().to_string(), text);
        let text = sources.text(id);
        let file = match crate::data::iges::parse(text) {
            Ok(f) => f,
            Err(e) => {
                render::to_stderr(sources, &[e.to_diagnostic(id)]);
                return Err(Exit::Input);
            }
        };
        warnings.extend(file.warnings.iter().map(|w| {
            let mut d = w.to_diagnostic(id);
            d.severity = crate::diagnostic::Severity::Warning;
            d
        }));
        let step = first + k;
        let (obs, skipped) = crate::data::landmarks::from_iges(&file, step, text, model);
        warnings.extend(skipped.iter().map(|s| skipped_warning(id, s)));
        eprintln!(
            "note: {} is step {step}: {} landmark points",
            path.display(),
            obs.len()
        );
        for line in geometry_notes(&file) {
            eprintln!("  {line}");
        }
        out.files.extend(obs.iter().map(|_| id));
        out.observations.extend(obs);
    }
    render::to_stderr(sources, &warnings);
    Ok(out)
}

/// What an IGES file holds besides points: lines and planes are listed (the
/// thesis measures joint axes and faces with them; `locate` finds axes from
/// motion instead), other entity types counted.
fn geometry_notes(file: &crate::data::iges::Iges) -> Vec<String> {
    use crate::data::iges::Geometry;
    let f = |v: crate::geom::Vec3| format!("({:.3}, {:.3}, {:.3})", v.x, v.y, v.z);
    let mut notes = Vec::new();
    let mut other: std::collections::BTreeMap<i64, usize> = Default::default();
    for e in &file.entities {
        let name = e.name().unwrap_or("(unnamed)");
        match &e.geometry {
            Some(Geometry::Line { from, to }) => notes.push(format!(
                "line `{name}` (D {}) from {} to {}: read, not used by locate",
                e.de,
                f(*from),
                f(*to)
            )),
            Some(Geometry::Plane { normal, offset }) => notes.push(format!(
                "plane `{name}` (D {}) normal {} at {offset:.3} mm: read, not used by locate",
                e.de,
                f(*normal)
            )),
            Some(Geometry::Point(_)) => {}
            None if matches!(e.kind, 124 | 406) => {}
            None => *other.entry(e.kind).or_default() += 1,
        }
    }
    for (kind, n) in other {
        notes.push(format!(
            "{n} entit{} of IGES type {kind} ignored",
            if n == 1 { "y" } else { "ies" }
        ));
    }
    notes
}

impl Landmarks {
    /// The files, for messages.
    pub fn shown(&self) -> String {
        self.names.join(", ")
    }

    /// Fits every part's pose at every step and prints what was left out,
    /// pointing at the line of the data file it came from.
    pub fn fit(
        &self,
        sources: &SourceMap,
        model: &Model,
        tolerance: f64,
    ) -> Vec<crate::measure::poses::StepPoses> {
        let (steps, issues) =
            crate::measure::poses::fit_poses(model, &self.observations, tolerance);
        let at = |step: usize, line: usize| {
            self.observations
                .iter()
                .zip(&self.files)
                .find(|(o, _)| o.step == step && o.line == line)
                .map(|(_, id)| {
                    let (a, b) = line_span(sources.text(*id), line);
                    Span::new(*id, a, b)
                })
        };
        let warnings: Vec<Diagnostic> = issues
            .iter()
            .map(|i| {
                let d = Diagnostic::warning("W0711", i.message(model));
                let (span, label) = match i {
                    MeasureIssue::LeftOut { step, line, .. } => (at(*step, *line), "left out"),
                    MeasureIssue::NoPose { step, lines, .. } => {
                        (lines.first().and_then(|l| at(*step, *l)), "no pose")
                    }
                };
                match span {
                    Some(s) => d.primary(s, label),
                    None => d,
                }
            })
            .collect();
        render::to_stderr(sources, &warnings);
        steps
    }
}
