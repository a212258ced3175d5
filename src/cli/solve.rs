//! `axle solve FILE [--loadcases SET | --loads CSV] [--format …] [-o OUT] [--trim …]`.

use super::input::{Loaded, emit, load_model, pick_set_reported};
use super::write::{Stream, Target, reported};
use super::{Exit, OutFormat};
use crate::diagnostic::Diagnostic;
use crate::kc::kc_rows;
use crate::model::LoadSetId;
use crate::output::report::{CaseReport, FailedCase, Reporter};
use crate::output::solve_json::SolveDocument;
use crate::output::warning;
use crate::output::{kc_table, parts_csv, solve_table};
use crate::statics::Problem;
use std::ops::ControlFlow;
use std::path::PathBuf;

pub struct TrimArgs {
    pub param: String,
    pub case: Option<String>,
    pub marker: Option<String>,
}

pub struct Args {
    pub file: PathBuf,
    pub loadcases: Option<String>,
    pub loads: Option<PathBuf>,
    pub format: OutFormat,
    pub output: Option<PathBuf>,
    pub trim: Option<TrimArgs>,
}

/// The set to solve: from `--loads` (added to the model) or by name.
fn load_set(loaded: &mut Loaded, args: &Args) -> Result<LoadSetId, Exit> {
    let Some(path) = &args.loads else {
        return pick_set_reported(loaded, args.loadcases.as_deref());
    };
    let text = super::read(path)?;
    let name = path
        .file_stem()
        .map_or("loads".into(), |s| s.to_string_lossy().into_owned());
    let file = loaded.sources.add(super::read::shown(path), text.clone());
    match crate::data::loads::read(&text, &name, &loaded.model) {
        Ok(set) => {
            loaded.model.load_sets.push(set);
            Ok(LoadSetId(loaded.model.load_sets.len() as u32 - 1))
        }
        Err(e) => {
            loaded.report(&[e.to_diagnostic(file)]);
            Err(Exit::Input)
        }
    }
}

pub fn run(args: &Args) -> Exit {
    match solve(args) {
        Ok(e) | Err(e) => e,
    }
}

fn solve(args: &Args) -> Result<Exit, Exit> {
    let mut loaded = load_model(&args.file)?;
    let set = load_set(&mut loaded, args)?;
    let trim = match &args.trim {
        Some(t) => Some(super::trim::run(&mut loaded, set, t)?),
        None => None,
    };
    let model = &loaded.model;
    let fail = |d: Diagnostic| {
        loaded.report(&[d]);
        Exit::Input
    };
    let problem = Problem::new(model).map_err(|e| fail(e.to_diagnostic(model)))?;
    if args.format == OutFormat::Json {
        return Ok(stream_json(&loaded, &problem, set, args, trim.as_ref()));
    }
    let ls = &model.load_sets[set.index()];
    let solved = super::input::solve_reporting(&loaded, &problem, set);
    let (eqs, failed) = (&solved.eqs, solved.failed.as_ref());
    let reporter = Reporter::new(model);
    let reports: Vec<CaseReport> = eqs
        .iter()
        .zip(&ls.cases)
        .enumerate()
        .map(|(k, (eq, c))| reporter.case(&c.name, k + 1, eq))
        .collect();
    let names: Vec<String> = ls.cases.iter().map(|c| c.name.clone()).collect();
    let not_solved = failed.map_or(Vec::new(), |f| not_solved(&names, f));
    loaded.report(&warning::of_path(model, &names, eqs));

    let text = match args.format {
        // (JSON was written as it was solved, `stream_json`.)
        OutFormat::Table | OutFormat::Json => {
            let head = trim
                .as_ref()
                .map_or(String::new(), |t| format!("{}\n", t.line));
            format!(
                "{head}{}",
                solve_table::cases(&model.name, &ls.name, &reports, failed, &not_solved)
            )
        }
        OutFormat::Csv if model.wheels.is_empty() => parts_csv::csv(&reports),
        OutFormat::Csv => {
            let states: Vec<_> = eqs.iter().map(|e| &e.state).collect();
            kc_table::csv(&kc_rows(model, set, &states))
        }
    };
    match emit(args.output.as_deref(), &text) {
        // The converged cases are written; the failing one was reported.
        Exit::Ok if failed.is_some() => Ok(Exit::Input),
        e => Ok(e),
    }
}

/// The cases after a failed one, never tried (no stale pose is printed):
/// name and step.
fn not_solved(names: &[String], failed: &FailedCase) -> Vec<(String, usize)> {
    let rest = names.iter().enumerate().skip(failed.step);
    rest.map(|(k, n)| (n.clone(), k + 1)).collect()
}

/// How much of the JSON document is made before it is written out.
const JSON_PIECE: usize = 1 << 16;

/// `solve --format json`: each case written as it is solved (a long load
/// path holds neither its states, nor its reports, nor the whole text:
/// 20 000 McPherson cases take 19 MB instead of 223 MB), then the failing
/// case, the cases not solved and the trim. The output is opened before the
/// solve, so a target that cannot be written costs no solve.
fn stream_json(
    loaded: &super::input::Loaded,
    problem: &Problem,
    set: LoadSetId,
    args: &Args,
    trim: Option<&super::trim::TrimReport>,
) -> Exit {
    let (model, target) = (&loaded.model, Target::from_option(args.output.as_deref()));
    let mut out = match Stream::open(&target) {
        Ok(out) => out,
        Err(e) => return reported(&target, Err(e)),
    };
    let ls = &model.load_sets[set.index()];
    let reporter = Reporter::new(model);
    // Room for a piece and the case that fills it (a McPherson case is 7
    // kB). Grown from empty, the text was copied at each doubling up to 128
    // KiB, the larger copies into pages not touched before: 35-40 of the
    // 500-case run's 390 page faults, at about 2 µs each on a virtual
    // machine (`docs/performance.md`).
    let mut doc = SolveDocument::with_capacity(JSON_PIECE + JSON_PIECE / 4);
    let mut warnings = warning::PathWarnings::new(model);
    // The first write error, which stops the path (`axle solve … | head`
    // solves no more than it writes).
    let mut written = Ok(());
    // (The path keeps no states: each case is reported and forgotten.)
    let solved = super::input::solve_reporting_each(loaded, problem, set, |k, eq| {
        let report = reporter.case(&ls.cases[k].name, k + 1, eq);
        warnings.add_reported(&eq.state, &report);
        doc.case(&report);
        if doc.pending() >= JSON_PIECE {
            written = doc.drain(|b| out.write(b));
        }
        match written {
            Ok(()) => ControlFlow::Continue(()),
            Err(_) => ControlFlow::Break(()),
        }
    });
    let names: Vec<String> = ls.cases.iter().map(|c| c.name.clone()).collect();
    let failed = solved.failed.as_ref();
    let not_solved = failed.map(|f| not_solved(&names, f));
    loaded.report(&warnings.finish(&names));
    let tail = doc.end(
        &ls.name,
        &model.name,
        failed,
        not_solved.as_deref(),
        trim.map(|t| &t.json),
    );
    let written = written
        .and_then(|()| out.write(tail.as_bytes()))
        .and_then(|()| out.commit());
    match reported(&target, written) {
        // The converged cases are written; the failing one was reported.
        Exit::Ok if failed.is_some() => Exit::Input,
        e => e,
    }
}
