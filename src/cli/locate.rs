//! `axle locate FILE --landmarks CSV [--reference STEP] [--format table|json] [-o OUT.axle]`.

use super::Exit;
use crate::diagnostic::{Diagnostic, render};
use crate::locate::plan::{Options, locate_all};
use crate::locate::report::{Report, apply, report};
use crate::source::SourceMap;
use crate::span::Span;
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct Args {
    /// The axle model.
    pub file: PathBuf,
    /// Landmark CSV: step, part, landmark, x, y, z (global mm).
    #[arg(long)]
    pub landmarks: PathBuf,
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
    let Some(text) = super::read(&a.file) else {
        return Exit::Io;
    };
    let id = sources.add(a.file.display().to_string(), text);
    let checked = crate::check::check_file(&mut sources, id);
    render::to_stderr(&sources, &checked.problems.list);
    let Some(model) = checked.model else {
        return Exit::Input;
    };
    let Some(data) = super::read(&a.landmarks) else {
        return Exit::Io;
    };
    let data_id = sources.add(a.landmarks.display().to_string(), data.clone());
    let (obs, skipped) = match crate::data::landmarks::read(&data, &model) {
        Ok(x) => x,
        Err(e) => {
            render::to_stderr(&sources, &[e.to_diagnostic(data_id)]);
            return Exit::Input;
        }
    };
    let mut warnings: Vec<Diagnostic> = skipped
        .iter()
        .map(|s| {
            Diagnostic::warning("W0710", s.message.clone())
                .primary(Span::new(data_id, s.start, s.end), "left out")
        })
        .collect();
    let (steps, issues) = crate::measure::poses::fit_poses(&model, &obs, a.tolerance);
    warnings.extend(
        issues
            .iter()
            .map(|i| Diagnostic::warning("W0711", i.message(&model))),
    );
    render::to_stderr(&sources, &warnings);
    if steps.is_empty() {
        eprintln!(
            "error: no step of {} gives a part pose",
            a.landmarks.display()
        );
        return Exit::Input;
    }
    let reference = a.reference.unwrap_or(steps[0].step);
    if !steps.iter().any(|s| s.step == reference) {
        eprintln!(
            "error: step {reference} is not in {}",
            a.landmarks.display()
        );
        return Exit::Input;
    }
    let opt = Options {
        sigma: a.sigma,
        max_uncertainty: a.max_uncertainty,
        ..Options::default()
    };
    let located = locate_all(&model, &steps, &opt);
    let rep = report(&model, &steps, &located, reference);
    match a.format {
        super::OutFormat::Json => match serde_json::to_string_pretty(&rep) {
            Ok(s) => println!("{s}"),
            Err(e) => {
                eprintln!("error: {e}");
                return Exit::Io;
            }
        },
        _ => print!("{}", table(&rep)),
    }
    if let Some(out) = &a.output {
        let text = crate::fmt::print_model(&apply(&model, &located));
        if let Err(e) = std::fs::write(out, text) {
            eprintln!("error: cannot write {}: {e}", out.display());
            return Exit::Io;
        }
    }
    Exit::Ok
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
    s
}
