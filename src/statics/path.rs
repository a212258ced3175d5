//! The one load-path simulator (`interfaces.md`, `solve`): solve the cases of a
//! path in order, each from the previous converged [`State`] (poses,
//! multipliers, the loads it balanced, and the history of path-dependent
//! elements), with load sub-stepping inside a case when a full step fails.
//!
//! Every caller goes through it: `solve`, `kc`, identification, `correct`,
//! the `.lcf` heights, trim, the synthetic-data writers, the benches. A
//! [`Simulator`] keeps one solver (buffers and last factorisation) across the
//! cases of a path, so a case starts with the tangent at the previous
//! equilibrium as a linear predictor, and across the paths a caller runs with
//! it (identification iterates), so the buffers are allocated once.
//!
//! A caller may give a *guess* per case (identification warm-starts case `k`
//! from the previous iterate's solution at case `k`): the guess supplies the
//! configuration Newton starts from, while the element history always comes
//! from the path's own previous case, so path-dependent physics is the same
//! as along a cold path.

use super::assembly::Workspace;
use super::newton::Solver;
use super::sensitivity::{self, CaseSensitivity, Parameter};
use super::{Equilibrium, Problem, State, StaticsError, StaticsErrorKind, solve_reusing};
use crate::model::{LoadSetId, Model, PointLoad};
use std::ops::ControlFlow;

/// A failure at one case of a path.
#[derive(Debug, Clone, PartialEq)]
pub struct PathError {
    /// 0-based index of the case that failed.
    pub case: usize,
    pub error: StaticsError,
}

/// What a path produced: the equilibria of the cases that converged, in
/// order, and the failure that stopped it (the cases after it were not tried).
#[derive(Debug, Clone)]
pub struct PathRun {
    pub steps: Vec<Equilibrium>,
    pub failure: Option<PathError>,
}

impl PathRun {
    /// Every case's equilibrium, or the failure (dropping the converged cases).
    pub fn into_result(self) -> Result<Vec<Equilibrium>, PathError> {
        match self.failure {
            None => Ok(self.steps),
            Some(e) => Err(e),
        }
    }
}

/// The loads of every case of a load set, in order.
pub fn set_loads(model: &Model, set: LoadSetId) -> Result<Vec<Vec<PointLoad>>, PathError> {
    let Some(ls) = model.load_sets.get(set.index()) else {
        let error = StaticsError::new(
            StaticsErrorKind::BadInput,
            vec![],
            format!("load set #{} does not exist", set.0),
        );
        return Err(PathError { case: 0, error });
    };
    Ok((0..ls.cases.len())
        .map(|k| model.point_loads(set, k))
        .collect())
}

/// A load-path simulator: one solver kept across the cases of every path it runs.
#[derive(Default)]
pub struct Simulator {
    solver: Option<Solver>,
    /// Load (sub-)step attempts a run may take: `per_case` per case solved
    /// so far plus `extra` ([`Simulator::with_budget`]).
    budget: Option<(usize, usize)>,
}

impl std::fmt::Debug for Simulator {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Simulator").finish_non_exhaustive()
    }
}

impl Simulator {
    pub fn new() -> Simulator {
        Simulator::default()
    }

    /// A simulator whose runs give up (a `NotConverged` failure at the case)
    /// once they have taken more than `per_case` load sub-step attempts per
    /// case so far, plus `extra`. A path that converges in one step per case
    /// takes one attempt per case; one that needs hundreds of sub-steps per
    /// case is near a limit of the model's equilibria, and a caller exploring
    /// parameters (diagnosis) would rather step back than pay for it. The
    /// first case of a run with a fresh solver is not counted.
    pub fn with_budget(per_case: usize, extra: usize) -> Simulator {
        Simulator {
            solver: None,
            budget: Some((per_case, extra)),
        }
    }

    /// Solves `cases` in order from `start`. Case `k` starts from the previous
    /// case's converged state, or, when `guesses` has an entry `k`, from that
    /// guess's configuration with the previous case's history
    /// ([`State::guessed`]). Stops at the first case that fails.
    pub fn run<L: AsRef<[PointLoad]>>(
        &mut self,
        problem: &Problem,
        cases: impl IntoIterator<Item = L>,
        start: &State,
        guesses: &[State],
    ) -> PathRun {
        self.walk(problem, cases, start, guesses, true, |_, _, _| Ok(()))
    }

    /// As [`Simulator::run`], handing each converged case to `each` as soon
    /// as it is solved (a caller that writes results while the path goes
    /// on), and keeping only the last: the run's `steps` hold the last
    /// converged case, so a path's memory does not grow with its length.
    /// `each` breaking stops the path there (its output is gone, say).
    pub fn run_each<L: AsRef<[PointLoad]>>(
        &mut self,
        problem: &Problem,
        cases: impl IntoIterator<Item = L>,
        start: &State,
        mut each: impl FnMut(usize, &Equilibrium) -> ControlFlow<()>,
    ) -> PathRun {
        self.walk(
            problem,
            cases,
            start,
            &[],
            false,
            |case, _, eq| match each(case, eq) {
                ControlFlow::Continue(()) => Ok(()),
                ControlFlow::Break(()) => Err(()),
            },
        )
    }

    /// As [`Simulator::run`], with the derivative of every converged case
    /// with respect to `params` ([`super::sensitivity`]): by implicit
    /// differentiation with each case's own factorisation, or, for a model
    /// with path-dependent elements (friction), by central differences of
    /// whole paths. The sensitivities stop where the path or their own
    /// computation (a singular equilibrium) failed, with that failure.
    pub fn run_with_sensitivities<L: AsRef<[PointLoad]>, P: Parameter>(
        &mut self,
        problem: &Problem,
        cases: &[L],
        start: &State,
        guesses: &[State],
        params: &[P],
    ) -> (PathRun, Result<Vec<CaseSensitivity>, PathError>) {
        if !problem.model().frictions.is_empty() {
            let run = self.run(problem, cases, start, guesses);
            if let Some(f) = run.failure.clone() {
                return (run, Err(f));
            }
            let s = sensitivity::path_by_differences(problem, cases, start, params)
                .map_err(|error| PathError { case: 0, error });
            return (run, s);
        }
        let values: Vec<f64> = params.iter().map(|p| p.value(problem.model())).collect();
        let mut work = problem.clone();
        let mut ws = Workspace::new(problem);
        let mut out = Vec::with_capacity(cases.len());
        let mut failed = None;
        let run = self.walk(problem, cases, start, guesses, true, |case, sv, eq| {
            let loads = eq.state.loads().to_vec();
            match sensitivity::at_equilibrium(
                problem, &mut work, &mut ws, sv, &eq.state, &loads, params, &values,
            ) {
                Ok(s) => {
                    out.push(s);
                    Ok(())
                }
                Err(error) => {
                    failed = Some(PathError { case, error });
                    Err(())
                }
            }
        });
        let result = match failed.or_else(|| run.failure.clone()) {
            Some(e) => Err(e),
            None => Ok(out),
        };
        (run, result)
    }

    /// The path loop; `after(case, solver, equilibrium)` runs after each
    /// converged case, with the solver holding that equilibrium's matrix, and
    /// stops the path when it fails. `keep`: every converged case is kept
    /// in the run's `steps`, otherwise only the last.
    fn walk<L: AsRef<[PointLoad]>>(
        &mut self,
        problem: &Problem,
        cases: impl IntoIterator<Item = L>,
        start: &State,
        guesses: &[State],
        keep: bool,
        mut after: impl FnMut(usize, &mut Solver, &Equilibrium) -> Result<(), ()>,
    ) -> PathRun {
        // The last factorisation belongs to another path (maybe another
        // problem): no predictor from it, and no condition estimate
        // continued from its estimates (a path's numbers do not depend on
        // what the simulator ran before).
        if let Some(sv) = &mut self.solver {
            sv.ended_at = None;
            sv.direction.forget();
        }
        let mut steps: Vec<Equilibrium> = Vec::new();
        let mut used = 0usize;
        for (case, loads) in cases.into_iter().enumerate() {
            let allowed = self
                .budget
                .map(|(per_case, extra)| (per_case * (case + 1) + extra).saturating_sub(used));
            if let Some(sv) = &mut self.solver {
                sv.attempts_left = allowed;
            }
            let committed = steps.last().map_or(start, |e| &e.state);
            let guessed;
            let from = match guesses.get(case) {
                Some(g) => {
                    guessed = committed.guessed(g);
                    &guessed
                }
                None => committed,
            };
            let solved = solve_reusing(problem, loads.as_ref(), from, &mut self.solver);
            if let Some(sv) = &mut self.solver {
                if let (Some(a), Some(left)) = (allowed, sv.attempts_left) {
                    used += a - left;
                }
                sv.attempts_left = None;
            }
            match solved {
                Ok(eq) => {
                    let stop = match &mut self.solver {
                        Some(sv) => after(case, sv, &eq).is_err(),
                        None => false,
                    };
                    if !keep {
                        steps.clear();
                    }
                    steps.push(eq);
                    if stop {
                        return PathRun {
                            steps,
                            failure: None,
                        };
                    }
                }
                Err(error) => {
                    let failure = Some(PathError { case, error });
                    return PathRun { steps, failure };
                }
            }
        }
        PathRun {
            steps,
            failure: None,
        }
    }
}

/// [`Simulator::run`] with a fresh simulator and no guesses.
pub fn simulate<L: AsRef<[PointLoad]>>(
    problem: &Problem,
    cases: impl IntoIterator<Item = L>,
    start: &State,
) -> PathRun {
    Simulator::new().run(problem, cases, start, &[])
}

/// A path of the one case `loads` from `start` (trim, correction passes):
/// its equilibrium or the case's error.
pub fn solve_case(
    problem: &Problem,
    loads: &[PointLoad],
    start: &State,
) -> Result<Equilibrium, StaticsError> {
    let mut run = simulate(problem, [loads], start);
    match (run.failure, run.steps.pop()) {
        (Some(e), _) => Err(e.error),
        (None, Some(eq)) => Ok(eq),
        (None, None) => Err(StaticsError::new(
            StaticsErrorKind::BadInput,
            vec![],
            "a path of one case gave no equilibrium",
        )),
    }
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
    run_set(problem, set, start).into_result()
}

/// Every case of `set` from `start`, keeping the converged cases on failure.
pub fn run_set(problem: &Problem, set: LoadSetId, start: &State) -> PathRun {
    on_set_loads(problem, set, |cases| simulate(problem, cases, start))
}

/// As [`run_set`], handing each converged case to `each` as it is solved
/// and keeping only the last ([`Simulator::run_each`]).
pub fn run_set_each(
    problem: &Problem,
    set: LoadSetId,
    start: &State,
    each: impl FnMut(usize, &Equilibrium) -> ControlFlow<()>,
) -> PathRun {
    on_set_loads(problem, set, |cases| {
        Simulator::new().run_each(problem, cases, start, each)
    })
}

/// `run` on the loads of every case of `set`, or the failure to find them.
fn on_set_loads(
    problem: &Problem,
    set: LoadSetId,
    run: impl FnOnce(&[Vec<PointLoad>]) -> PathRun,
) -> PathRun {
    match set_loads(problem.model(), set) {
        Ok(cases) => run(&cases),
        Err(e) => PathRun {
            steps: Vec::new(),
            failure: Some(e),
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::statics::testkit::{mcpherson, random_walk};

    /// A path starts without the condition direction the simulator's last
    /// path ended on, as it starts without its predictor: a path's numbers
    /// do not depend on what the simulator ran before.
    #[test]
    fn a_path_starts_without_the_last_paths_condition_direction() {
        let m = mcpherson();
        let p = Problem::new(&m).expect("problem");
        let design = State::design(&m);
        let loads = random_walk(&m);
        let mut sim = Simulator::new();
        let run = sim.run(&p, &loads[..3], &design, &[]);
        assert!(run.failure.is_none());
        let sv = sim.solver.as_ref().expect("a solver");
        assert!(!sv.direction.is_cold() && sv.ended_at.is_some());
        let run = sim.run(&p, Vec::<Vec<PointLoad>>::new(), &design, &[]);
        assert!(run.steps.is_empty() && run.failure.is_none());
        let sv = sim.solver.as_ref().expect("a solver");
        assert!(sv.direction.is_cold() && sv.ended_at.is_none());
    }
}
