//! What `solve` and `kc` share: read and check the model (printing its
//! diagnostics), pick a load set by name, print diagnostics, write results.

use super::Exit;
use crate::diagnostic::suggest::did_you_mean;
use crate::diagnostic::{Diagnostic, render};
use crate::model::{LoadSetId, Model};
use crate::source::SourceMap;
use std::path::Path;

/// A checked model and the sources its diagnostics point into.
pub struct Loaded {
    pub sources: SourceMap,
    pub model: Model,
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
        Some(model) if !checked.problems.has_errors() => Ok(Loaded { sources, model }),
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
    let m = &loaded.model;
    let names = || m.load_sets.iter().map(|s| s.name.as_str());
    let listing = || {
        let all: Vec<&str> = names().collect();
        if all.is_empty() {
            "the model has no load-case sets (write a `loads` block, or `import mcpherson_loads`)"
                .to_string()
        } else {
            format!("the model's load-case sets: {}", all.join(", "))
        }
    };
    match name {
        Some(n) => m.load_set_named(n).ok_or_else(|| {
            let d = Diagnostic::error("E0801", format!("the model has no load-case set `{n}`"))
                .note(listing());
            match did_you_mean(n, names()) {
                Some(h) => d.hint(h),
                None if ["bump", "lateral", "longitudinal"].contains(&n) => {
                    d.hint("the K&C sweeps come with `import mcpherson_loads`")
                }
                None => d,
            }
        }),
        None => m.default_load_set.ok_or_else(|| {
            Diagnostic::error(
                "E0802",
                "no load-case set named and the model has no `default loads`",
            )
            .note(listing())
            .hint("name one with --loadcases SET, or give loads with --loads CSV")
        }),
    }
}

/// Writes results to `path` (`-` or none: stdout) through the one writer.
pub fn emit(path: Option<&Path>, text: &str) -> Exit {
    super::write::emit(&super::write::Target::from_option(path), text)
}

/// Solves a load set in order, each case from the previous state; a failure
/// becomes a diagnostic naming the case, reported, and exit status 1.
pub fn solve_reporting(
    loaded: &Loaded,
    problem: &crate::statics::Problem,
    set: LoadSetId,
) -> Result<Vec<crate::statics::Equilibrium>, Exit> {
    let model = &loaded.model;
    let ls = &model.load_sets[set.index()];
    crate::statics::path::solve_path(problem, set).map_err(|e| {
        let case = ls.cases.get(e.case).map_or("?", |c| c.name.as_str());
        loaded.report(&[e.error.to_diagnostic(model).note(format!(
            "in case `{case}` (step {}) of load set `{}`",
            e.case + 1,
            ls.name
        ))]);
        Exit::Input
    })
}
