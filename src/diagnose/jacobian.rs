//! The residuals of a candidate at a search point together with their
//! Jacobian, for screening and fitting. For a model without path-dependent
//! elements, one pass of the path simulator with sensitivities
//! ([`Simulator::run_with_sensitivities`]: implicit differentiation with
//! each case's own factorisation) gives every column at the cost of about
//! one replay, whatever the number of parameters; geometry parameters (a
//! joint point) are differentiated the same way, through the constraint
//! residual. With friction in the model (its history depends on the
//! parameters too), the columns are forward differences of whole replays.

use super::Context;
use super::candidate::{CandParam, Candidate, Scale};
use super::channel::{self, Channel};
use super::holdout::Subset;
use super::landmarks::simulated;
use super::replay::{Replay, ReplayError, replay, step_residuals};
use super::rig::RigStep;
use crate::model::{ElementId, Model, PointLoad, WheelId};
use crate::statics::path::Simulator;
use crate::statics::{CaseSensitivity, Parameter, Problem, State};
use nalgebra::{DMatrix, DVector};

impl Parameter for CandParam {
    fn value(&self, model: &Model) -> f64 {
        self.targets.first().map_or(0.0, |a| a.get(model))
    }

    fn set_value(&self, model: &mut Model, value: f64) {
        for a in &self.targets {
            a.set(model, value);
        }
    }

    fn moves_geometry(&self, model: &Model) -> bool {
        self.targets.iter().any(|a| a.moves_geometry(model))
    }

    fn element(&self) -> ElementId {
        self.targets
            .first()
            .map_or(ElementId::Part(crate::model::PartId(0)), |a| a.element)
    }

    fn force_element(&self, model: &Model) -> Option<ElementId> {
        match self.targets.as_slice() {
            [a] => a.force_element(model),
            _ => None,
        }
    }
}

/// What one evaluation gives.
pub struct Evaluation {
    /// Training residuals (noise-weighted).
    pub r: Vec<f64>,
    /// Their Jacobian in search units.
    pub j: DMatrix<f64>,
    pub replay: Replay,
    pub model: Model,
}

/// `d value / d x` of a search variable.
fn dvalue(scale: Scale, x: f64) -> f64 {
    match scale {
        Scale::Log { reference } => reference * x.exp(),
        Scale::Linear { unit, .. } => unit,
    }
}

/// The residuals and Jacobian of `cand` at `x` on its extended model.
pub fn evaluate(
    ctx: &Context,
    cand: &Candidate,
    extended: &Model,
    x: &[f64],
    sim: &mut Simulator,
) -> Result<Evaluation, ReplayError> {
    let m = cand.at(extended, x);
    if !m.frictions.is_empty() {
        let rp = replay(&m, ctx.rig, ctx.designs, sim)?;
        let r = rp.residuals(ctx.rig, ctx.noise, &Subset::Training);
        return Ok(by_differences(ctx, cand, extended, x, (r, rp, m), sim));
    }
    let problem = Problem::new(&m).map_err(|error| ReplayError {
        path: 0,
        step: 0,
        error,
    })?;
    let start = State::design(&m);
    let mut sims = Vec::with_capacity(ctx.rig.len());
    let mut landmarks = Vec::with_capacity(ctx.rig.len());
    let mut rows: Vec<DVector<f64>> = Vec::new();
    let mut r = Vec::new();
    for (p, path) in ctx.rig.iter().enumerate() {
        let cases: Vec<&[PointLoad]> = path.steps.iter().map(|s| s.loads.as_slice()).collect();
        let (run, sens) = sim.run_with_sensitivities(&problem, &cases, &start, &[], &cand.params);
        let fail = |f: crate::statics::path::PathError| ReplayError {
            path: p,
            step: f.case,
            error: f.error,
        };
        if let Some(f) = run.failure {
            return Err(fail(f));
        }
        let sens = sens.map_err(fail)?;
        let d = &ctx.designs[p];
        let mut chans = Vec::with_capacity(run.steps.len());
        let mut marks = Vec::with_capacity(run.steps.len());
        for (k, (eq, s)) in run.steps.iter().zip(&sens).enumerate() {
            let step = &path.steps[k];
            let now = channel::of_state(&m, d, path.wheel, &eq.state);
            let pts = simulated(&m, &eq.state, &step.landmarks);
            if Subset::Training.contains(p, k) {
                step_residuals(ctx.noise, step, &now, &pts, &mut r);
                let dv = value_derivatives(&problem, &m, d, path.wheel, step, &eq.state, s);
                let sigma = |row: usize| match row {
                    c @ 0..5 => ctx.noise[c].sigma,
                    _ => ctx.noise[Channel::Landmarks.index()].sigma,
                };
                for row in 0..dv.nrows() {
                    rows.push(DVector::from_fn(x.len(), |i, _| {
                        dv[(row, i)] * dvalue(cand.params[i].scale, x[i]) / sigma(row)
                    }));
                }
            }
            chans.push(now);
            marks.push(pts);
        }
        sims.push(chans);
        landmarks.push(marks);
    }
    let mut j = DMatrix::zeros(rows.len(), x.len());
    for (k, row) in rows.iter().enumerate() {
        j.set_row(k, &row.transpose());
    }
    Ok(Evaluation {
        r,
        j,
        replay: Replay {
            paths: sims,
            landmarks,
        },
        model: m,
    })
}

/// The K&C channels and the landmark coordinates of one step, in the order
/// of [`step_residuals`].
fn values(
    model: &Model,
    d: &channel::Design,
    wheel: WheelId,
    step: &RigStep,
    state: &State,
) -> Vec<f64> {
    let mut v = channel::of_state(model, d, wheel, state).to_vec();
    for x in simulated(model, state, &step.landmarks) {
        v.extend(x.iter());
    }
    v
}

/// `d value / d parameter` at a solved state ((5 + 3 landmarks) ×
/// parameters): central differences of the values along each parameter's
/// state derivative (no solve: the state moves along its tangent).
fn value_derivatives(
    problem: &Problem,
    model: &Model,
    d: &channel::Design,
    wheel: WheelId,
    step: &RigStep,
    state: &State,
    s: &CaseSensitivity,
) -> DMatrix<f64> {
    let n = s.params();
    let mut out = DMatrix::zeros(5 + 3 * step.landmarks.len(), n);
    for j in 0..n {
        let col = s.dq.column(j);
        let amax = col.amax();
        if amax == 0.0 {
            continue;
        }
        let h = 1e-6 / amax;
        let dq = DVector::from_fn(col.len(), |r, _| col[r] * h);
        let (mut sp, mut sm) = (state.clone(), state.clone());
        sp.apply(&problem.layout, &dq);
        sm.apply(&problem.layout, &(-dq));
        let (a, b) = (
            values(model, d, wheel, step, &sp),
            values(model, d, wheel, step, &sm),
        );
        for (row, (a, b)) in a.iter().zip(&b).enumerate() {
            out[(row, j)] = (a - b) / (2.0 * h);
        }
    }
    out
}

/// The Jacobian by forward differences of whole replays (friction in the
/// model), around the point `x` whose residuals, replay and model are `at`
/// (already computed by the caller: a trial point the search accepts).
pub fn by_differences(
    ctx: &Context,
    cand: &Candidate,
    extended: &Model,
    x: &[f64],
    at: (Vec<f64>, Replay, Model),
    sim: &mut Simulator,
) -> Evaluation {
    let (r, rp, m) = at;
    let mut j = DMatrix::zeros(r.len(), x.len());
    for i in 0..x.len() {
        let p = &cand.params[i];
        // Forward, or backward where forward leaves the bounds or does not
        // solve (a stick-slip path Newton fails on at that point).
        let h = if x[i] + 1e-3 > p.hi { -1e-3 } else { 1e-3 };
        for h in [h, -h] {
            let mut xp = x.to_vec();
            xp[i] += h;
            let mi = cand.at(extended, &xp);
            let Ok(rpi) = replay(&mi, ctx.rig, ctx.designs, sim) else {
                continue;
            };
            let ri = rpi.residuals(ctx.rig, ctx.noise, &Subset::Training);
            if ri.len() == r.len() {
                for k in 0..r.len() {
                    j[(k, i)] = (ri[k] - r[k]) / h;
                }
                break;
            }
        }
    }
    Evaluation {
        r,
        j,
        replay: rp,
        model: m,
    }
}

/// Only the residuals and replay (a trial step), without the Jacobian.
pub fn residuals(
    ctx: &Context,
    cand: &Candidate,
    extended: &Model,
    x: &[f64],
    sim: &mut Simulator,
) -> Result<(Vec<f64>, Replay, Model), ReplayError> {
    let m = cand.at(extended, x);
    let rp = replay(&m, ctx.rig, ctx.designs, sim)?;
    let r = rp.residuals(ctx.rig, ctx.noise, &Subset::Training);
    Ok((r, rp, m))
}
