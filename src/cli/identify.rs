//! `axle identify FILE --landmarks CSV|IGES... [--kc CSV] [--loads CSV] [--loadcases SET]
//! --method direct|iterative|lsq [--unknown NAME...] [--format table|json]
//! [-o OUT.axle] [--report DIR]`: reads the model and the data, runs one identification
//! method, prints the parameters (boundary units) and optionally writes the
//! identified model and the plots comparing measured, initial and identified
//! K&C curves.

use super::Exit;
use crate::diagnostic::{Diagnostic, render};
use crate::identify::measured::Measured;
use crate::identify::{self, BoundIssue, FitNote, Identified, ParamNote};
use crate::measure::inputs;
use crate::source::SourceMap;
use crate::units::{from_boundary, to_boundary};
use serde_json::{Value, json};
use std::path::{Path, PathBuf};

#[derive(Copy, Clone, PartialEq, Eq, clap::ValueEnum)]
pub enum IdentifyMethod {
    Direct,
    Iterative,
    Lsq,
}

#[derive(Copy, Clone, PartialEq, Eq, clap::ValueEnum)]
pub enum IdentifyFormat {
    Table,
    Json,
}

/// The options of `identify`, as parsed by clap.
#[derive(clap::Args)]
pub struct IdentifyArgs {
    pub file: PathBuf,
    /// Landmark files: CSV (step, part, landmark, x, y, z) and/or IGES (one
    /// measured state per file, numbered after the CSV steps).
    #[arg(long, num_args = 1.., required = true)]
    pub landmarks: Vec<PathBuf>,
    /// Landmark matching tolerance, mm (thesis: 0.5).
    #[arg(long, default_value_t = 0.5)]
    pub match_tolerance: f64,
    /// K&C CSV: its fx, fy, fz (and mx, my, mz) are the loads; lsq also fits its channels.
    #[arg(long, conflicts_with_all = ["loads", "loadcases"])]
    pub kc: Option<PathBuf>,
    /// Loads CSV: step, fx, fy, fz [, mx, my, mz].
    #[arg(long, conflicts_with = "loadcases")]
    pub loads: Option<PathBuf>,
    /// A load-case set of the model, matched to the landmark steps in order.
    #[arg(long)]
    pub loadcases: Option<String>,
    #[arg(long, value_enum)]
    pub method: IdentifyMethod,
    /// Parameters to identify (`A.k_x`, `spring.free_length`, `L7.z`, a declared parameter).
    #[arg(long, num_args = 1..)]
    pub unknown: Vec<String>,
    #[arg(long, value_enum, default_value = "table")]
    pub format: IdentifyFormat,
    /// Write the identified model (axle source) here.
    #[arg(short = 'o', long = "output")]
    pub output: Option<PathBuf>,
    /// Start every unknown stiffness at this value (N/mm or N*mm/deg), as the thesis does.
    #[arg(long)]
    pub initial: Option<f64>,
    /// Iterative: smallest correlation for a stiffness to count as identified.
    #[arg(long, default_value_t = 0.75)]
    pub threshold: f64,
    /// Iterative: relative change at convergence.
    #[arg(long, default_value_t = 0.01)]
    pub tolerance: f64,
    /// Least squares: landmark noise, mm (standard deviation per coordinate).
    #[arg(long, default_value_t = 0.05)]
    pub sigma: f64,
    /// Write SVG plots of measured, initial and identified toe and camber
    /// under each load direction the data sweep into this directory.
    #[arg(long)]
    pub report: Option<PathBuf>,
}

/// Why identification stopped: the diagnostics and the exit status.
struct Failure(Vec<Diagnostic>, Exit);

impl Failure {
    fn input(d: Diagnostic) -> Failure {
        Failure(vec![d], Exit::Input)
    }

    /// A bad option value (exit 2, like clap's own usage errors).
    fn option(message: &str) -> Failure {
        Failure(vec![Diagnostic::error("E1102", message)], Exit::Io)
    }
}

pub fn run(a: &IdentifyArgs) -> Exit {
    let mut sources = SourceMap::new();
    let text = match super::read(&a.file) {
        Ok(t) => t,
        Err(e) => return e,
    };
    let file = sources.add(super::read::shown(&a.file), text);
    let checked = crate::check::check_file(&mut sources, file);
    let errors = checked.problems.has_errors();
    render::to_stderr(&sources, &checked.problems.list);
    let (Some(model), false) = (checked.model, errors) else {
        return Exit::Input;
    };
    let result = identify(a, &mut sources, file, &model);
    let out = match result {
        Ok(out) => out,
        Err(Failure(diags, code)) => {
            // `--format json` carries the failure as its diagnostics on stdout.
            match a.format {
                IdentifyFormat::Json => {
                    let text = format!("{}\n", render::to_json(&sources, &diags));
                    let _ = super::input::emit(None, &text);
                }
                IdentifyFormat::Table => render::to_stderr(&sources, &diags),
            }
            return code;
        }
    };
    let text = match a.format {
        IdentifyFormat::Json => format!(
            "{}\n",
            serde_json::to_string_pretty(&to_json(&out)).unwrap_or_default()
        ),
        IdentifyFormat::Table => to_table(&out),
    };
    super::input::emit(None, &text)
}

/// Reads the data, identifies, writes `-o` and `--report`; the result to print.
fn identify(
    a: &IdentifyArgs,
    sources: &mut SourceMap,
    file: crate::span::FileId,
    checked: &crate::model::Model,
) -> Result<Identified, Failure> {
    // As read: `--initial` changes the starting values, not the file's.
    let mut model = checked.clone();
    if !(a.sigma > 0.0 && a.sigma.is_finite())
        || !(a.tolerance > 0.0)
        || !(a.match_tolerance > 0.0)
        || !a.threshold.is_finite()
    {
        return Err(Failure::option(
            "--sigma, --tolerance and --match-tolerance must be positive numbers",
        ));
    }

    // Landmarks → part poses (warnings point at the data line left out).
    let files = super::locate::landmark_files(sources, &a.landmarks)
        .map_err(|(d, code)| Failure(vec![*d], code))?;
    let mut remarks = inputs::Remarks::default();
    let landmarks = inputs::read_landmarks(sources, &files, &model, &mut remarks);
    let poses = landmarks.map(|l| {
        let steps = l.fit(sources, &model, a.match_tolerance, &mut remarks);
        (l, steps)
    });
    super::locate::render_remarks(sources, &remarks);
    let (landmarks, poses) = poses.map_err(Failure::input)?;
    // Too few states, or a measured part missing: one error, not a table of
    // unidentified parameters.
    let purpose = crate::locate::preflight::Purpose::Identify;
    if let Some(d) = super::locate::preflight(&landmarks, &model, &poses, purpose) {
        return Err(Failure::input(d));
    }

    // Loads per step.
    let read = |sources: &mut SourceMap, path: &Path| {
        let text = super::read::read_text(path);
        let text = text.map_err(|e| Failure(vec![e.to_diagnostic(sources, path)], e.exit()))?;
        Ok::<_, Failure>(sources.add(super::read::shown(path), text))
    };
    let source = match (&a.kc, &a.loads) {
        (Some(path), _) => inputs::LoadSource::Kc(read(sources, path)?),
        (None, Some(path)) => inputs::LoadSource::Loads(read(sources, path)?),
        (None, None) => inputs::LoadSource::Set(a.loadcases.as_deref()),
    };
    let data = inputs::assemble(sources, &model, &poses, source).map_err(|d| {
        // A set the command line names that the model lacks is a usage error.
        let usage = matches!(d.code, "E0801" | "E0802");
        Failure(vec![d], if usage { Exit::Io } else { Exit::Input })
    })?;
    let failed =
        |e: identify::IdentifyError, m: &crate::model::Model| Failure::input(e.to_diagnostic(m));

    // Unknowns, optionally all stiffnesses started at one value.
    let unknowns = identify::select_unknowns(&model, &a.unknown).map_err(|e| failed(e, &model))?;
    if let Some(v) = a.initial {
        if !(v > 0.0 && v.is_finite()) {
            return Err(Failure::option("--initial must be a positive stiffness"));
        }
        for u in unknowns.iter().filter(|u| u.is_stiffness()) {
            u.set(&mut model, from_boundary(v, u.dim));
        }
    }
    let mut unknowns = identify::select_unknowns(&model, &a.unknown).unwrap_or(unknowns);
    let mut notes = Vec::new();
    let result = match a.method {
        IdentifyMethod::Direct => {
            identify::direct::identify(&model, &unknowns, &data, Default::default())
        }
        IdentifyMethod::Iterative => {
            if a.unknown.is_empty() {
                let (k, n) = identify::iterative::restrict(&model, &unknowns, &data);
                unknowns = k;
                notes = n;
            }
            if unknowns.is_empty() {
                return Err(Failure::input(
                    identify::IdentifyError::of(
                        identify::IdentifyErrorKind::Unknowns,
                        "no bushing has both of its parts measured, so the iterative method has nothing to identify",
                        vec![],
                    )
                    .to_diagnostic(&model),
                ));
            }
            let opts = identify::iterative::IterativeOptions {
                threshold: a.threshold,
                tolerance: a.tolerance,
                ..Default::default()
            };
            identify::iterative::identify(&model, &unknowns, &data, opts)
        }
        IdentifyMethod::Lsq => {
            let opts = identify::lsq::LsqOptions {
                landmark_sigma: a.sigma,
                ..Default::default()
            };
            identify::lsq::identify(&model, &unknowns, &data, opts)
        }
    };
    let mut r = result.map_err(|e| failed(e, &model))?;
    r.notes.extend(notes);
    if let Some(out) = &a.output {
        let new = r.apply(&model);
        let text = super::model_out::edited(sources, file, checked, &new, "identify", &[])
            .map_err(|code| Failure(vec![], code))?;
        let code = super::input::emit(Some(out), &text);
        if code != Exit::Ok {
            return Err(Failure(vec![], code));
        }
    }
    if let Some(dir) = &a.report {
        let n = write_report(dir, &model, &r, &data)?;
        r.notes.extend(n);
    }
    Ok(r)
}

/// Writes `toe_camber_<direction>.svg` per swept load direction into `dir`
/// (`toe_camber_<wheel>_<direction>.svg` per wheel of a model of several);
/// returns one note per file with the toe and camber RMS against the measured
/// curve of the initial and the identified model.
fn write_report(
    dir: &Path,
    initial: &crate::model::Model,
    r: &Identified,
    data: &Measured,
) -> Result<Vec<identify::FitNote>, Failure> {
    let curves = identify::report::curves(initial, &r.apply(initial), data)
        .map_err(|e| Failure::input(e.to_diagnostic(initial)))?;
    let report_error = |what: String| Failure(vec![Diagnostic::error("E1109", what)], Exit::Io);
    std::fs::create_dir_all(dir)
        .map_err(|e| report_error(format!("cannot create {}: {e}", dir.display())))?;
    let mut notes = Vec::new();
    for c in &curves {
        let text = identify::report::svg(c, &initial.name, r.method)
            .map_err(|e| report_error(format!("cannot draw the report plots: {e}")))?;
        let path = dir.join(format!("{}.svg", c.file));
        let code = super::input::emit(Some(&path), &text);
        if code != Exit::Ok {
            return Err(Failure(vec![], code));
        }
        let note = identify::FitNote::Report {
            path: path.display().to_string(),
            steps: c.measured.len(),
            initial: [c.rms(&c.initial, false), c.rms(&c.initial, true)],
            identified: [c.rms(&c.identified, false), c.rms(&c.identified, true)],
        };
        notes.push(note);
    }
    Ok(notes)
}

/// A finite number as JSON, anything else as null (JSON has no NaN).
fn num(v: f64) -> Value {
    if v.is_finite() { json!(v) } else { Value::Null }
}

/// The result in `interfaces.md`'s JSON shape (boundary units), with extra fields.
pub fn to_json(r: &Identified) -> Value {
    let mut params = serde_json::Map::new();
    for (u, p) in r.unknowns.iter().zip(&r.params) {
        let b = |v: f64| to_boundary(v, u.dim);
        for name in &u.names {
            let mut entry = json!({
                    "initial": num(b(p.initial)),
                    "value": p.value.map_or(Value::Null, |v| num(b(v))),
                    "unit": u.dim.boundary_unit(),
                    "interval": p.interval.map_or(Value::Null, |(lo, hi)| json!([num(b(lo)), num(b(hi))])),
                    "identifiable": p.identifiable,
                    "note": ParamNote::join(&p.notes),
            });
            // Only present when the value is at or beyond its declared bounds.
            if let Some(issue) = p.bound {
                entry["bound"] = json!(bound_word(issue));
            }
            params.insert(name.clone(), entry);
        }
    }
    let labels: Vec<String> = r.unknowns.iter().map(|u| u.label()).collect();
    json!({
        "method": r.method.name(),
        "parameters": params,
        "determined_combinations": r.combinations.iter().map(|c| c.expression()).collect::<Vec<_>>(),
        "combinations": r.combinations.iter().map(|c| json!({
            "expression": c.expression(), "value": num(c.value), "unit": c.unit,
        })).collect::<Vec<_>>(),
        "rank": r.rank,
        "singular_values": r.singular_values.iter().map(|s| num(*s)).collect::<Vec<_>>(),
        "iterations": r.iterations,
        "history": r.history.iter().map(|h| json!({
            "iteration": h.iteration,
            "values": r.unknowns.iter().zip(&h.values).map(|(u, v)| (u.label(), num(to_boundary(*v, u.dim)))).collect::<serde_json::Map<_, _>>(),
        })).collect::<Vec<_>>(),
        "sigma0": r.sigma0.map(num),
        "correlation": r.correlation.as_ref().map(|c| json!({
            "parameters": labels,
            "matrix": c.iter().map(|row| row.iter().map(|v| num(*v)).collect::<Vec<_>>()).collect::<Vec<_>>(),
        })),
        "notes": r.notes.iter().map(FitNote::text).collect::<Vec<_>>(),
    })
}

fn fmt_num(v: f64) -> String {
    let v = identify::round_sig(v, 6);
    format!("{v}")
}

/// How a value relates to its declared bounds, in the words of the table and JSON.
fn bound_word(issue: BoundIssue) -> &'static str {
    match issue {
        BoundIssue::AtLower => "AT lower BOUND",
        BoundIssue::AtUpper => "AT upper BOUND",
        BoundIssue::BelowLower => "OUTSIDE bounds (below)",
        BoundIssue::AboveUpper => "OUTSIDE bounds (above)",
    }
}

pub fn to_table(r: &Identified) -> String {
    use std::fmt::Write;
    let mut o = String::new();
    let _ = writeln!(o, "method: {}", r.method.name());
    let _ = writeln!(
        o,
        "{:<28} {:>12} {:>12} {:>27}  {:<10} verdict",
        "parameter", "initial", "identified", "95 % interval", "unit"
    );
    for (u, p) in r.unknowns.iter().zip(&r.params) {
        let b = |v: f64| to_boundary(v, u.dim);
        let value = match (p.value, p.identifiable) {
            (Some(v), true) => fmt_num(b(v)),
            (Some(v), false) => format!("({})", fmt_num(b(v))),
            (None, _) => "-".into(),
        };
        let interval = p.interval.map_or("-".to_string(), |(lo, hi)| {
            format!("[{}, {}]", fmt_num(b(lo)), fmt_num(b(hi)))
        });
        let verdict = match (p.bound, p.identifiable) {
            (Some(issue), _) => bound_word(issue).to_string(),
            (None, true) => "identified".to_string(),
            (None, false) => "NOT identified".to_string(),
        };
        let _ = writeln!(
            o,
            "{:<28} {:>12} {:>12} {:>27}  {:<10} {verdict}",
            u.label(),
            fmt_num(b(p.initial)),
            value,
            interval,
            u.dim.boundary_unit()
        );
        if let Some(n) = ParamNote::join(&p.notes) {
            let _ = writeln!(o, "    {n}");
        }
    }
    if !r.combinations.is_empty() {
        let _ = writeln!(
            o,
            "determined combinations (their terms are not determined one by one):"
        );
        for c in &r.combinations {
            let _ = writeln!(
                o,
                "    {} = {} {}",
                c.expression(),
                fmt_num(c.value),
                c.unit
            );
        }
    }
    if r.history.len() > 1 {
        let _ = writeln!(o, "iteration history (boundary units):");
        let w: Vec<usize> = r.unknowns.iter().map(|u| u.names[0].len().max(9)).collect();
        let _ = write!(o, "{:>4}", "it");
        for (u, w) in r.unknowns.iter().zip(&w) {
            let _ = write!(o, " {:>w$}", u.names[0]);
        }
        let _ = writeln!(o);
        for h in &r.history {
            let _ = write!(o, "{:>4}", h.iteration);
            for ((u, v), w) in r.unknowns.iter().zip(&h.values).zip(&w) {
                let _ = write!(
                    o,
                    " {:>w$}",
                    fmt_num(identify::round_sig(to_boundary(*v, u.dim), 5))
                );
            }
            let _ = writeln!(o);
        }
    }
    let _ = writeln!(o, "rank {}, iterations {}", r.rank, r.iterations);
    if !r.singular_values.is_empty() {
        let s: Vec<String> = r
            .singular_values
            .iter()
            .map(|s| format!("{s:.3e}"))
            .collect();
        let _ = writeln!(o, "singular values: {}", s.join(" "));
    }
    if let Some(s) = r.sigma0 {
        let _ = writeln!(o, "a posteriori sigma factor: {s:.3}");
    }
    for n in &r.notes {
        let _ = writeln!(o, "note: {n}");
    }
    o
}

#[cfg(test)]
#[path = "identify_tests.rs"]
mod tests;
