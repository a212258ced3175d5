//! Solving a load set along its cases in order, each case from the previous
//! equilibrium (`interfaces.md`, `solve`): the common loop of `solve`, `kc`
//! and the benchmarks.

use super::{Equilibrium, Problem, State, StaticsError, StaticsErrorKind, solve};
use crate::model::LoadSetId;

/// A failure at one case of a path.
#[derive(Debug, Clone, PartialEq)]
pub struct PathError {
    /// 0-based index of the case that failed.
    pub case: usize,
    pub error: StaticsError,
}

/// The equilibria of every case of `set`, the first from the design configuration.
pub fn solve_path(problem: &Problem, set: LoadSetId) -> Result<Vec<Equilibrium>, PathError> {
    solve_path_from(problem, set, &State::design(problem.model()))
}

/// As [`solve_path`], starting from `start` (a warm start).
pub fn solve_path_from(
    problem: &Problem,
    set: LoadSetId,
    start: &State,
) -> Result<Vec<Equilibrium>, PathError> {
    let model = problem.model();
    let Some(ls) = model.load_sets.get(set.index()) else {
        let error = StaticsError::new(
            StaticsErrorKind::BadInput,
            vec![],
            format!("load set #{} does not exist", set.0),
        );
        return Err(PathError { case: 0, error });
    };
    let mut out: Vec<Equilibrium> = Vec::with_capacity(ls.cases.len());
    for case in 0..ls.cases.len() {
        let from = out.last().map_or(start, |e| &e.state);
        let eq = solve(problem, &model.point_loads(set, case), from)
            .map_err(|error| PathError { case, error })?;
        out.push(eq);
    }
    Ok(out)
}
