//! `axle identify FILE --landmarks CSV|IGES... [--kc CSV] [--loads CSV] [--loadcases SET]
//! --method direct|iterative|lsq [--unknown NAME...] [--format table|json]
//! [-o OUT.axle] [--report DIR]`: reads the model and the data, runs one identification
//! method, prints the parameters (boundary units) and optionally writes the
//! identified model and the plots comparing measured, initial and identified
//! K&C curves.

use super::Exit;
use crate::diagnostic::render;
use crate::identify::measured::{self, Measured};
use crate::identify::{self, BoundIssue, Identified};
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

fn fail(sources: &SourceMap, d: crate::diagnostic::Diagnostic) -> Exit {
    render::to_stderr(sources, &[d]);
    Exit::Input
}

/// Reads a data file into the source map (so diagnostics can quote it).
fn data(sources: &mut SourceMap, path: &Path) -> Option<crate::span::FileId> {
    let text = super::read(path).ok()?;
    Some(sources.add(super::read::shown(path), text))
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
    let (Some(mut model), false) = (checked.model, errors) else {
        return Exit::Input;
    };
    if !(a.sigma > 0.0 && a.sigma.is_finite())
        || !(a.tolerance > 0.0)
        || !(a.match_tolerance > 0.0)
        || !a.threshold.is_finite()
    {
        eprintln!("error: --sigma, --tolerance and --match-tolerance must be positive numbers");
        return Exit::Io;
    }

    // Landmarks → part poses (warnings point at the data line left out).
    let landmarks = match super::locate::load_landmarks(&mut sources, &a.landmarks, &model) {
        Ok(d) => d,
        Err(code) => return code,
    };
    let poses = landmarks.fit(&sources, &model, a.match_tolerance);
    let steps: Vec<usize> = poses.iter().map(|p| p.step).collect();

    // Loads per step.
    let mut kc = Vec::new();
    let loads = if let Some(path) = a.kc.as_ref().or(a.loads.as_ref()) {
        let Some(id) = data(&mut sources, path) else {
            return Exit::Io;
        };
        let text = sources.text(id).to_string();
        let (l, _) = match measured::loads_of_file(&model, &text) {
            Ok(x) => x,
            Err(e) => return fail(&sources, e.to_diagnostic(id)),
        };
        if a.kc.as_deref() == Some(path.as_path()) {
            kc = match measured::kc_channels(&text) {
                Ok(k) => k,
                Err(e) => return fail(&sources, e.to_diagnostic(id)),
            };
            let measured_steps: Vec<usize> =
                landmarks.observations.iter().map(|o| o.step).collect();
            if let Err(e) = measured::same_steps(&kc, &measured_steps) {
                eprintln!("error: {}: {e}", path.display());
                return Exit::Input;
            }
        }
        l
    } else {
        let set = match &a.loadcases {
            Some(name) => match model.load_set_named(name) {
                Some(s) => s,
                None => {
                    let names: Vec<&str> =
                        model.load_sets.iter().map(|s| s.name.as_str()).collect();
                    eprintln!(
                        "error: the model has no load-case set `{name}` (it has {})",
                        names.join(", ")
                    );
                    // A wrong name on the command line is a usage error.
                    return Exit::Io;
                }
            },
            None => match model.default_load_set {
                Some(s) => s,
                None => {
                    eprintln!(
                        "error: no loads: give --kc, --loads or --loadcases (the model has no default load set)"
                    );
                    return Exit::Io;
                }
            },
        };
        match measured::match_in_order(measured::loads_of_set(&model, set), &steps) {
            Ok(l) => l,
            Err(e) => {
                eprintln!("error: {e}");
                return Exit::Input;
            }
        }
    };
    let mut data = match Measured::from_poses(&model, &poses, &loads) {
        Ok(d) => d,
        Err(e) => {
            eprintln!("error: {e}");
            return Exit::Input;
        }
    };
    measured::attach_kc(&mut data, &kc);

    // Unknowns, optionally all stiffnesses started at one value.
    let unknowns = match identify::select_unknowns(&model, &a.unknown) {
        Ok(u) => u,
        Err(e) => {
            eprintln!("error: {e}");
            return Exit::Input;
        }
    };
    if let Some(v) = a.initial {
        if !(v > 0.0 && v.is_finite()) {
            eprintln!("error: --initial must be a positive stiffness");
            return Exit::Io;
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
                eprintln!(
                    "error: no bushing has both of its parts measured, so the iterative method has nothing to identify"
                );
                return Exit::Input;
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
    let mut r = match result {
        Ok(r) => r,
        Err(e) => {
            let named: Vec<String> = e.elements.iter().map(|x| model.describe(*x)).collect();
            if named.is_empty() {
                eprintln!("error: {}", e.message);
            } else {
                eprintln!("error: {} [{}]", e.message, named.join(", "));
            }
            return Exit::Input;
        }
    };
    r.notes.extend(notes);
    if let Some(out) = &a.output {
        let text = crate::fmt::print_model(&r.apply(&model));
        let code = super::input::emit(Some(out), &text);
        if code != Exit::Ok {
            return code;
        }
    }
    if let Some(dir) = &a.report {
        match write_report(dir, &model, &r, &data) {
            Ok(n) => r.notes.extend(n),
            Err(e) => return e,
        }
    }
    let text = match a.format {
        IdentifyFormat::Json => match serde_json::to_string_pretty(&to_json(&r)) {
            Ok(s) => format!("{s}\n"),
            Err(e) => {
                eprintln!("error: cannot write the results as JSON: {e}");
                return Exit::Io;
            }
        },
        IdentifyFormat::Table => to_table(&r),
    };
    super::input::emit(None, &text)
}

/// Writes `toe_camber_<direction>.svg` per swept load direction into `dir`;
/// returns one note per file with the toe and camber RMS against the measured
/// curve of the initial and the identified model.
fn write_report(
    dir: &Path,
    initial: &crate::model::Model,
    r: &Identified,
    data: &Measured,
) -> Result<Vec<String>, Exit> {
    let curves = identify::report::curves(initial, &r.apply(initial), data).map_err(|e| {
        let named: Vec<String> = e.elements.iter().map(|x| initial.describe(*x)).collect();
        if named.is_empty() {
            eprintln!("error: {}", e.message);
        } else {
            eprintln!("error: {} [{}]", e.message, named.join(", "));
        }
        Exit::Input
    })?;
    if let Err(e) = std::fs::create_dir_all(dir) {
        eprintln!("error: cannot create {}: {e}", dir.display());
        return Err(Exit::Io);
    }
    let mut notes = Vec::new();
    for c in &curves {
        let text = identify::report::svg(c, &initial.name, r.method).map_err(|e| {
            eprintln!("error: cannot draw the report plots: {e}");
            Exit::Io
        })?;
        let path = dir.join(format!("toe_camber_{}.svg", c.name));
        if super::input::emit(Some(&path), &text) != Exit::Ok {
            return Err(Exit::Io);
        }
        notes.push(format!(
            "report {}: {} measured steps; RMS toe / camber against measured: initial {:.4} / {:.4} deg, identified {:.4} / {:.4} deg",
            path.display(),
            c.measured.len(),
            c.rms(&c.initial, false),
            c.rms(&c.initial, true),
            c.rms(&c.identified, false),
            c.rms(&c.identified, true),
        ));
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
                    "note": p.note,
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
        "notes": r.notes,
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
        if let Some(n) = &p.note {
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
