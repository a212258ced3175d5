//! `axle locate FILE --landmarks CSV|IGES... [--reference STEP] [--format table|json] [-o OUT.axle]`,
//! and the landmark file reading `identify` and `correct` share (the files are
//! read here; `measure::inputs` turns their text into observations and poses).

use super::Exit;
use crate::diagnostic::{Diagnostic, render};
use crate::locate::plan::{Options, locate_all};
use crate::locate::preflight::{self, Purpose};
use crate::locate::report::{Report, apply, report};
use crate::measure::inputs::{self, LandmarkFile, LandmarkFormat, Landmarks, Remarks};
use crate::model::Model;
use crate::source::SourceMap;
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
    /// Axes whose direction is less certain than this (degrees, one standard
    /// deviation) are not reported; today only a strut's axis has its own
    /// uncertainty.
    #[arg(long, default_value_t = 2.0)]
    pub max_axis_uncertainty: f64,
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
    let (data, steps) = match landmarks(&mut sources, &a.landmarks, &model, a.tolerance) {
        Ok(x) => x,
        Err(code) => return code,
    };
    if let Some(d) = preflight(&data, &model, &steps, Purpose::Locate) {
        render::to_stderr(&sources, &[d]);
        return Exit::Input;
    }
    let reference = match data.step(&steps, a.reference) {
        Ok(s) => s.step,
        Err(d) => {
            render::to_stderr(&sources, &[d]);
            return Exit::Input;
        }
    };
    let opt = Options {
        sigma: a.sigma,
        max_uncertainty: a.max_uncertainty,
        max_axis_uncertainty: a.max_axis_uncertainty,
        ..Options::default()
    };
    let located = locate_all(&model, &steps, &opt);
    let rep = report(&model, &steps, &located, reference);
    if let Some(out) = &a.output {
        let new = apply(&model, &located);
        let text = match super::model_out::edited(&sources, id, &model, &new, "locate", &[]) {
            Ok(t) => t,
            Err(code) => return code,
        };
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
        "{:<10} {:<12} {:>30} {:>32} {:>9} {:>11}  method\n",
        "element", "kind", "centre", "axis", "residual", "uncertainty"
    );
    for (name, e) in &r.joints {
        let c = e.center.map_or("not observable".to_string(), |c| {
            format!("({:.2}, {:.2}, {:.2})", c[0], c[1], c[2])
        });
        let a = e.axis.map_or("-".to_string(), |a| {
            let within = e
                .axis_uncertainty_deg
                .map_or(String::new(), |u| format!(" ±{u:.2}°"));
            format!("({:.3}, {:.3}, {:.3}){within}", a[0], a[1], a[2])
        });
        let u = e
            .uncertainty_mm
            .map_or("-".to_string(), |u| format!("{u:.3}"));
        let res = e.residual_mm.map_or("-".to_string(), |r| format!("{r:.3}"));
        s += &format!(
            "{name:<10} {:<12} {c:>30} {a:>32} {res:>9} {u:>11}  {}\n",
            e.kind, e.method
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

/// What the landmark data lacks for `purpose` (`locate::preflight`), as one
/// error naming the data files; `correct` passes the one step it uses.
pub fn preflight(
    data: &Landmarks,
    model: &Model,
    steps: &[crate::measure::poses::StepPoses],
    purpose: Purpose,
) -> Option<Diagnostic> {
    preflight::check_for(model, steps, purpose)
        .map(|d| d.note(format!("the landmark data: {}", data.shown())))
}

fn is_iges(p: &Path) -> bool {
    p.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("igs") || e.eq_ignore_ascii_case("iges"))
}

/// Reads the `--landmarks` files into the source map (IGES as its 80-column
/// text). `Err` with the diagnostic and exit status of an unreadable file.
pub fn landmark_files(
    sources: &mut SourceMap,
    paths: &[PathBuf],
) -> Result<Vec<LandmarkFile>, (Box<Diagnostic>, Exit)> {
    let mut files = Vec::new();
    for path in paths {
        let (text, format) = if is_iges(path) {
            let bytes = super::read::read_bytes(path);
            let bytes = bytes.map_err(|e| (Box::new(e.to_diagnostic(sources, path)), e.exit()))?;
            (
                crate::data::iges::ascii_columns(&bytes),
                LandmarkFormat::Iges,
            )
        } else {
            let text = super::read::read_text(path);
            (
                text.map_err(|e| (Box::new(e.to_diagnostic(sources, path)), e.exit()))?,
                LandmarkFormat::Csv,
            )
        };
        let id = sources.add(super::read::shown(path), text);
        files.push(LandmarkFile { id, format });
    }
    Ok(files)
}

/// Reads the landmark files and fits the part poses; prints the warnings and
/// notes; `Err` once an error was printed.
pub fn landmarks(
    sources: &mut SourceMap,
    paths: &[PathBuf],
    model: &Model,
    tolerance: f64,
) -> Result<(Landmarks, Vec<crate::measure::poses::StepPoses>), Exit> {
    let files = landmark_files(sources, paths).map_err(|(d, code)| {
        render::to_stderr(sources, &[*d]);
        code
    })?;
    let mut remarks = Remarks::default();
    let data = inputs::read_landmarks(sources, &files, model, &mut remarks);
    let result = data.map(|d| {
        let steps = d.fit(sources, model, tolerance, &mut remarks);
        (d, steps)
    });
    render_remarks(sources, &remarks);
    result.map_err(|d| {
        render::to_stderr(sources, &[d]);
        Exit::Input
    })
}

/// Warnings as diagnostics, notes as `note:` lines, on stderr.
pub fn render_remarks(sources: &SourceMap, remarks: &Remarks) {
    render::to_stderr(sources, &remarks.warnings);
    for n in &remarks.notes {
        match n.strip_prefix("  ") {
            Some(detail) => eprintln!("  {detail}"),
            None => eprintln!("note: {n}"),
        }
    }
}
