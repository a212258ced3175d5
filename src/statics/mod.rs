//! Static equilibrium of a checked model (`conventions.md`, "Static equilibrium"):
//! Newton on `Q(q) + Phi_q^T λ = 0, Phi(q) = 0` from the design configuration or
//! from the previous state of a load path, with automatic load sub-stepping.
//!
//! Layout: `problem` (the model compiled once, [`Problem`]), [`coords`] (6
//! coordinates per moving part, rotation increments by Rodrigues), [`wrench`]
//! (the one generalised-force shape every element reduces to), [`constraint`]
//! (joint primitives), [`forces`] (bushings, springs, stops, loads),
//! [`redundancy`], [`newton`], `isolation` (whether an equilibrium is
//! isolated), `failure` (what a solve that failed names), [`mobility`],
//! [`compliance`], [`path`] (the one load-path simulator), [`sensitivity`]
//! (derivatives of equilibria).

pub mod assembly;
pub mod batch;
pub mod blocks;
#[cfg(all(target_arch = "x86_64", unix))]
mod compiled;
pub mod compliance;
mod condition;
pub mod constraint;
pub mod coords;
pub mod error;
mod extrapolation;
mod failure;
pub mod forces;
pub mod friction;
mod isolation;
mod linear;
mod live;
pub mod mobility;
pub mod newton;
pub mod path;
mod pattern;
mod pivoting;
mod problem;
mod products;
pub mod redundancy;
mod refactor;
pub mod sensitivity;
mod sparse;
mod system;
mod tangent;
#[cfg(test)]
pub(crate) mod testkit;
pub mod wrench;
#[cfg(all(target_arch = "x86_64", unix))]
mod x86;

pub use compliance::{StoppingError, compliance, compliances, stopping_error};
pub use coords::State;
pub use error::{StaticsError, StaticsErrorKind};
pub use mobility::{Mobility, Motion};
pub use problem::Problem;
pub use redundancy::RedundantEquation;
pub use sensitivity::{CaseSensitivity, Parameter};

use crate::geom::Vec3;
use crate::model::{ElementId, JointId, LoadSetId, Model, PointLoad};
use isolation::CHECK_SINGULAR_BELOW;
use newton::{Failure, Homotopy, Solver, newton};
use redundancy::scaled_jacobian;

/// The reaction of a joint on its I part: a force at the I marker origin and a
/// torque, global (N, N·mm).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Reaction {
    pub joint: JointId,
    pub force: Vec3,
    pub torque: Vec3,
}

/// A converged static equilibrium.
#[derive(Debug, Clone)]
pub struct Equilibrium {
    pub state: State,
    /// Newton iterations (steps) over all sub-steps.
    pub iterations: usize,
    /// LU factorisations of the Newton matrix these took: a step may reuse the
    /// previous factorisation (see [`newton`]), and the end of a solve may
    /// factorise the equilibrium's matrix for the singularity check.
    pub factorizations: usize,
    /// Extra load steps taken because a full step failed (0: one step sufficed).
    pub substeps: usize,
    /// Final residual: the larger of the force residual relative to the force
    /// scale at the equilibrium (its largest element force or applied load) and the constraint residual relative to the characteristic length.
    pub residual: f64,
    /// The force (N) `residual` is relative to: the largest element force
    /// or applied load at the equilibrium. With the characteristic length
    /// [`Problem::length`] it says how far from the exact equilibrium the
    /// solve may have stopped: a force residual of `FORCE_TOL` times this
    /// along the model's softest direction.
    pub force_scale: f64,
    pub reactions: Vec<Reaction>,
}

/// Loads between `from` (at 0) and `to` (at 1), marker by marker.
fn interpolate(from: &[PointLoad], to: &[PointLoad], s: f64) -> Vec<PointLoad> {
    if s >= 1.0 {
        return to.to_vec();
    }
    let mut out: Vec<PointLoad> = Vec::new();
    for (w, set) in [(1.0 - s, from), (s, to)] {
        for l in set {
            let k = match out.iter().position(|o| o.marker == l.marker) {
                Some(k) => k,
                None => {
                    out.push(PointLoad {
                        marker: l.marker,
                        force: Vec3::zeros(),
                        torque: Vec3::zeros(),
                    });
                    out.len() - 1
                }
            };
            out[k].force += l.force * w;
            out[k].torque += l.torque * w;
        }
    }
    out
}

/// The force scale of a solve: applied loads and the element forces at the
/// start (`element_scale`, N).
fn force_scale(p: &Problem, loads: &[PointLoad], start: &State, element_scale: f64) -> f64 {
    let mut f = 1.0f64.max(element_scale);
    for l in loads.iter().chain(start.loads.iter()) {
        f = f.max(l.force.norm() + l.torque.norm() / p.length);
    }
    f
}

/// A load beyond any suspension (`check`'s E0214 limits: 10 MN, 10 MN·m) as
/// an error naming its marker and value: such a load (a slip of exponent,
/// `1e200 N`) swamps every tolerance and overflows the force norms, so it is
/// refused rather than solved. Every caller of the statics (a loads file, an
/// API user, a sweep) meets the same limit.
fn implausible_load(loads: &[PointLoad]) -> Option<StaticsError> {
    use crate::units::Dim;
    for l in loads {
        for (v, dim, unit) in [(l.force, Dim::FORCE, "N"), (l.torque, Dim::TORQUE, "N*mm")] {
            let Some((limit, shown)) = crate::check::plausible_limit(dim) else {
                continue;
            };
            // The largest component: its magnitude cannot overflow.
            let big = v.iter().fold(0.0f64, |a, x| a.max(x.abs()));
            if big > limit {
                return Some(StaticsError::new(
                    StaticsErrorKind::BadInput,
                    vec![ElementId::Marker(l.marker)],
                    format!(
                        "a load of {big:e} {unit} is beyond any suspension (more than {shown}): check the unit and the exponent"
                    ),
                ));
            }
        }
    }
    None
}

/// The smallest load step (of the whole change of load) before giving up.
const MIN_STEP: f64 = 1.0 / 4096.0;

/// Static equilibrium under `loads`, starting from `start` (the load is applied in
/// sub-steps from the loads `start` was in equilibrium with when a full step fails).
pub fn solve(
    problem: &Problem,
    loads: &[PointLoad],
    start: &State,
) -> Result<Equilibrium, StaticsError> {
    solve_reusing(problem, loads, start, &mut None)
}

/// As [`solve`], keeping the solver's buffers in `buffers` for the next case
/// of a path. When this solve starts where the previous one with the same
/// buffers ended, its first step uses that solve's last factorisation (the
/// tangent at the previous equilibrium: a linear predictor for the new load)
/// instead of factorising again.
pub(crate) fn solve_reusing(
    problem: &Problem,
    loads: &[PointLoad],
    start: &State,
    buffers: &mut Option<Solver>,
) -> Result<Equilibrium, StaticsError> {
    let model = &problem.model;
    if let Some(l) = loads
        .iter()
        .find(|l| l.marker.index() >= model.markers.len())
    {
        return Err(StaticsError::new(
            StaticsErrorKind::BadInput,
            vec![],
            format!(
                "a load refers to marker #{} that the model does not have",
                l.marker.0
            ),
        ));
    }
    if start.poses.len() != model.parts.len() {
        return Err(StaticsError::new(
            StaticsErrorKind::BadInput,
            vec![],
            "the start state belongs to another model",
        ));
    }
    if let Some(l) = loads
        .iter()
        .find(|l| !(l.force.iter().chain(l.torque.iter()).all(|v| v.is_finite())))
    {
        return Err(StaticsError::new(
            StaticsErrorKind::BadInput,
            vec![ElementId::Marker(l.marker)],
            "a load component is not a finite number",
        ));
    }
    if let Some(e) = implausible_load(loads) {
        return Err(e);
    }
    let m = problem.kept.len();
    let dim = problem.layout.n() + m;
    let sv = match buffers {
        Some(sv) if sv.lu.dim() == dim => sv,
        _ => buffers.insert(Solver::new(problem, start)),
    };
    sv.factorizations = 0;
    let ended_at = sv.ended_at.take();
    sv.predict = ended_at
        .as_ref()
        .is_some_and(|e| e.poses == start.poses && e.lambda == start.lambda);
    // Not across a friction's stick/slip kink: the correction of a case
    // that slipped is no guide to one that sticks.
    let smooth = problem.model.frictions.is_empty();
    sv.extrapolation
        .begin(&start.loads, loads, sv.predict && smooth);
    let mut state = start.clone();
    if state.lambda.len() != m {
        state.lambda = vec![0.0; m];
    }
    // The first full step starts from this evaluation, which also gives the
    // element forces of the force scale. A predicted first step does not use
    // the Newton matrix at the start (Newton evaluates it if the prediction
    // fails).
    // The workspace holds the evaluation at the last solve's end, under its
    // loads: at the same state, only the loads change (a friction's history,
    // committed since, may change its force: evaluated afresh).
    match &ended_at {
        Some(e) if sv.predict && smooth => sv.ws.exchange_loads(problem, &state, &e.loads, loads),
        _ => sv.ws.eval(problem, &state, loads, !sv.predict)?,
    }
    let force = force_scale(problem, loads, start, sv.ws.element_scale);
    let from = &start.loads;
    // The start's own residual, needed only once a sub-step is taken.
    let mut start_residual: Option<(Vec<f64>, Vec<f64>)> = None;
    let mut evaluated = true;
    let (mut s, mut ds, mut steps, mut iterations) = (0.0f64, 1.0f64, 0usize, 0usize);
    while s < 1.0 {
        if let Some(left) = &mut sv.attempts_left {
            if *left == 0 {
                return Err(failure::over_budget());
            }
            *left -= 1;
        }
        let target = if s + ds >= 1.0 - 1e-12 { 1.0 } else { s + ds };
        let l = interpolate(from, loads, target);
        let (r0, phi0) = if target < 1.0 {
            if start_residual.is_none() {
                let mut w0 = assembly::Workspace::new(problem);
                w0.eval(problem, start, from, false)?;
                start_residual = Some((w0.r, w0.phi));
            }
            start_residual.clone().unwrap_or_default()
        } else {
            (Vec::new(), Vec::new())
        };
        let h = Homotopy {
            r0,
            phi0,
            remaining: 1.0 - target,
        };
        let mut trial = std::mem::take(&mut sv.spare);
        trial.clone_from(&state);
        match newton(problem, &l, &mut trial, force, &h, sv, evaluated) {
            Ok(it) => {
                iterations += it;
                steps += 1;
                std::mem::swap(&mut state, &mut trial);
                state.loads = l;
                // An accepted (sub-)step: its friction slip becomes history.
                friction::commit(model, &problem.layout, &mut state);
                s = target;
                ds *= 2.0;
            }
            Err(Failure::Fatal(e)) => return Err(e),
            Err(Failure::Stalled(at)) => {
                iterations += 1;
                sv.predict = false;
                sv.extrapolation.abandon();
                ds /= 2.0;
                if ds < MIN_STEP {
                    return Err(failure::not_converged(problem, &at, &l, force));
                }
            }
        }
        sv.spare = trial;
        evaluated = false;
    }
    if steps != 1 {
        sv.extrapolation.abandon();
    }
    sv.extrapolation.end();
    let eq = finish(problem, state, iterations, steps.saturating_sub(1), sv)?;
    // (Into the last end's allocations.)
    let mut end = ended_at.unwrap_or_else(|| std::mem::take(&mut sv.spare));
    end.clone_from(&eq.state);
    sv.ended_at = Some(end);
    Ok(eq)
}

/// Checks the equilibrium is isolated and the left-out redundant equations
/// hold, and collects the reactions. `sv.ws` holds the residual and Newton
/// matrix at `state`; `sv.lu` factorises the matrix of the last Newton
/// iteration when `sv.factored`.
fn finish(
    p: &Problem,
    state: State,
    iterations: usize,
    substeps: usize,
    sv: &mut Solver,
) -> Result<Equilibrium, StaticsError> {
    let (ef, ec) = sv.ws.errors(p);
    // A free motion at equilibrium is an error, not a result (`isolation`).
    let rcond = isolation::equilibrium_condition(p, sv);
    if rcond < CHECK_SINGULAR_BELOW
        && let Some(e) = system::singular_direction(p, &sv.ws.matrix())
    {
        return Err(e);
    }
    if p.kept.len() < p.equations.len() {
        let left_out: Vec<usize> = (0..p.equations.len())
            .filter(|k| !p.kept.contains(k))
            .collect();
        let sj = scaled_jacobian(
            &p.model,
            &p.layout,
            &state,
            &p.equations,
            &left_out,
            p.length,
        );
        for (&k, v) in left_out.iter().zip(sj.phi.iter()) {
            // Redundant equations hold only as well as the geometry's consistency.
            if v.abs() > 1e-6 * p.length {
                return Err(StaticsError::new(
                    StaticsErrorKind::InconsistentRedundancy,
                    vec![ElementId::Joint(p.equations[k].joint)],
                    format!(
                        "the redundant equation {} is violated by {:.3e} at equilibrium: the joints of the loop disagree",
                        p.equations[k].primitive.describe(),
                        v
                    ),
                ));
            }
        }
    }
    let mut reactions: Vec<Reaction> = Vec::with_capacity(p.model.joints.len());
    // `sv.ws` was evaluated at `state`: its unit reactions are the wrenches'.
    for (idx, &e) in p.kept.iter().enumerate() {
        let eq = &p.equations[e];
        let (g, m) = sv.ws.unit_reaction[idx];
        let lam = state.lambda.get(idx).copied().unwrap_or(0.0);
        // Searched from the last: a joint's equations come together, so
        // its reaction is found at once (from the first, the search grew
        // with the joints times their equations: 45 % of `finish` on
        // eight coupled corners).
        match reactions.iter_mut().rev().find(|r| r.joint == eq.joint) {
            Some(r) => {
                r.force += g * lam;
                r.torque += m * lam;
            }
            None => reactions.push(Reaction {
                joint: eq.joint,
                force: g * lam,
                torque: m * lam,
            }),
        }
    }
    Ok(Equilibrium {
        state,
        iterations,
        factorizations: sv.factorizations,
        substeps,
        residual: ef.max(ec),
        force_scale: sv.ws.force_scale(),
        reactions,
    })
}

/// Solves every case of a load set in order, each from the previous state
/// (the [`path`] simulator on a freshly compiled problem).
pub fn solve_set(model: &Model, set: LoadSetId) -> Result<Vec<Equilibrium>, StaticsError> {
    let cases = path::set_loads(model, set).map_err(|e| e.error)?;
    let problem = Problem::new(model)?;
    path::simulate(&problem, &cases, &State::design(model))
        .into_result()
        .map_err(|e| e.error)
}

/// Mobility of the model at the design configuration (for the checker).
pub fn mobility(model: &Model) -> Mobility {
    mobility::analyse(model, &problem::Equations::of(model))
}
