//! `axle solve FILE [--loadcases SET | --loads CSV] [--format …] [-o OUT] [--trim …]`.

use super::input::{Loaded, emit, load_model, pick_set_reported};
use super::{Exit, OutFormat};
use crate::diagnostic::Diagnostic;
use crate::kc::kc_rows;
use crate::model::LoadSetId;
use crate::output::report::{CaseReport, Reporter};
use crate::output::warning;
use crate::output::{kc_table, parts_csv, solve_json, solve_table};
use crate::statics::Problem;
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
    // The cases after a failed one, never tried (no stale pose is printed).
    let not_solved: Vec<(String, usize)> = match failed {
        Some(f) => names
            .iter()
            .enumerate()
            .skip(f.step)
            .map(|(k, n)| (n.clone(), k + 1))
            .collect(),
        None => Vec::new(),
    };
    loaded.report(&warning::of_path(model, &names, eqs));

    let text = match args.format {
        OutFormat::Json => solve_json::solve(
            &model.name,
            &ls.name,
            &reports,
            failed,
            failed.map(|_| not_solved.as_slice()),
            trim.as_ref().map(|t| &t.json),
        ),
        OutFormat::Table => {
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
