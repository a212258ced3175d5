//! What `solve` and `kc` share: read and check the model (printing its
//! diagnostics), pick a load set by name, print diagnostics, write results.

use super::Exit;
use crate::diagnostic::{Diagnostic, render};
use crate::model::{LoadSetId, Model};
use crate::source::SourceMap;
use std::path::Path;

/// A checked model and the sources its diagnostics point into.
pub struct Loaded {
    pub sources: SourceMap,
    pub model: Model,
    /// The model's file in `sources` (for editing it back).
    pub file: crate::span::FileId,
}

impl Loaded {
    /// Prints diagnostics to stderr.
    pub fn report(&self, diags: &[Diagnostic]) {
        render::to_stderr(&self.sources, diags);
    }
}

/// Reads and checks a model; prints its warnings; `Err` carries the exit status.
pub fn load_model(path: &Path) -> Result<Loaded, Exit> {
    let text = super::read(path)?;
    let mut sources = SourceMap::new();
    let id = sources.add(super::read::shown(path), text);
    let checked = crate::check::check_file(&mut sources, id);
    render::to_stderr(&sources, &checked.problems.list);
    match checked.model {
        Some(model) if !checked.problems.has_errors() => Ok(Loaded {
            sources,
            model,
            file: id,
        }),
        _ => Err(Exit::Input),
    }
}

/// [`pick_set`], reported: a set the command line names that the model lacks
/// (or no set named and no default) is a usage error, exit 2.
pub fn pick_set_reported(loaded: &Loaded, name: Option<&str>) -> Result<LoadSetId, Exit> {
    pick_set(loaded, name).map_err(|d| {
        loaded.report(&[d]);
        Exit::Io
    })
}

/// The set named `name`, or the model's default set. An unknown name gets a
/// did-you-mean and the list of sets.
pub fn pick_set(loaded: &Loaded, name: Option<&str>) -> Result<LoadSetId, Diagnostic> {
    crate::measure::inputs::pick_set(&loaded.model, name)
}

/// Writes results to `path` (`-` or none: stdout) through the one writer.
pub fn emit(path: Option<&Path>, text: &str) -> Exit {
    super::write::emit(&super::write::Target::from_option(path), text)
}

/// A load set solved along its path: the converged cases (only the last
/// when they were handed over one by one, [`solve_reporting_each`]), and the
/// case that failed (its diagnostic already reported).
pub struct Solved {
    pub eqs: Vec<crate::statics::Equilibrium>,
    pub failed: Option<crate::output::report::FailedCase>,
}

/// Solves a load set in order, each case from the previous state; a failure
/// becomes a diagnostic naming the case and the element, reported, and the
/// cases before it are kept for the caller to print (then exit status 1).
pub fn solve_reporting(
    loaded: &Loaded,
    problem: &crate::statics::Problem,
    set: LoadSetId,
) -> Solved {
    let design = crate::statics::State::design(&loaded.model);
    let run = crate::statics::path::run_set(problem, set, &design);
    report_failure(loaded, set, run)
}

/// As [`solve_reporting`], handing each converged case to `each` as it is
/// solved (which may stop the path); the result's `eqs` hold only the last
/// converged case ([`crate::statics::path::run_set_each`]).
pub fn solve_reporting_each(
    loaded: &Loaded,
    problem: &crate::statics::Problem,
    set: LoadSetId,
    each: impl FnMut(usize, &crate::statics::Equilibrium) -> std::ops::ControlFlow<()>,
) -> Solved {
    let design = crate::statics::State::design(&loaded.model);
    let run = crate::statics::path::run_set_each(problem, set, &design, each);
    report_failure(loaded, set, run)
}

/// A path's run with its failure, if any, reported as a diagnostic naming
/// the case.
fn report_failure(loaded: &Loaded, set: LoadSetId, run: crate::statics::path::PathRun) -> Solved {
    let model = &loaded.model;
    let ls = &model.load_sets[set.index()];
    let failed = run.failure.map(|e| {
        let case = ls.cases.get(e.case).map_or("?", |c| c.name.as_str());
        loaded.report(&[e.error.to_diagnostic(model).note(format!(
            "in case `{case}` (step {}) of load set `{}`",
            e.case + 1,
            ls.name
        ))]);
        crate::output::report::FailedCase::new(model, case, e.case + 1, &e.error)
    });
    Solved {
        eqs: run.steps,
        failed,
    }
}
