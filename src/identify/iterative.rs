//! Iterative identification (thesis chapter 5): simulate the model with the
//! current stiffnesses, regress each bushing's measured deformation against
//! the force the simulation puts through it, per axis with an offset term
//! (eq. 5.10: slope K and assembly offset E⁰), accept a slope only when the
//! correlation exceeds a threshold (eq. 5.12, 0.75), average the radial axes of
//! axisymmetric bushings weighted by their force spread (eq. 5.13), and repeat
//! until no stiffness changes by more than the relative tolerance (eq. 5.14).
//!
//! Only the parts around each identified bushing need measured poses; the
//! model keeps its full kinematics. Each step's equilibrium starts from its own
//! previous one, so after the first pass a solve is a few Newton iterations.

use super::measured::Measured;
use super::notes::{AxisFit, AxisRegression};
use super::{
    FitNote, HistoryEntry, Identified, IdentifyError, IdentifyErrorKind, Method, ParamNote,
    ParamResult, Unknown,
};
use crate::model::address::Address;
use crate::model::{BushingId, ElementId, Model};
use crate::statics::coords::Layout;
use crate::statics::path::Simulator;
use crate::statics::{Problem, State, forces};

#[derive(Debug, Clone, Copy)]
pub struct IterativeOptions {
    /// Smallest correlation for a slope to be accepted (thesis: 0.75).
    pub threshold: f64,
    /// Relative change below which a stiffness has converged (thesis: 0.01).
    pub tolerance: f64,
    pub max_iterations: usize,
}

impl Default for IterativeOptions {
    fn default() -> Self {
        IterativeOptions {
            threshold: 0.75,
            tolerance: 0.01,
            max_iterations: 200,
        }
    }
}

/// The stiffnesses set in place in the compiled problem (the constraint
/// analysis is not compiled again).
fn set_values(
    problem: &mut Problem,
    unknowns: &[Unknown],
    values: &[f64],
) -> Result<(), IdentifyError> {
    for (u, v) in unknowns.iter().zip(values) {
        problem
            .set_force_parameter(u, *v)
            .map_err(|e| IdentifyError::statics("", e, problem.model()))?;
    }
    Ok(())
}

/// The bushing axis an address names: (bushing, axis 0..6 with 3.. rotational).
fn axis(a: Address) -> Option<(BushingId, usize)> {
    a.bushing_stiffness()
        .map(|(b, rot, n)| (b, if rot { 3 + n } else { n }))
}

/// Keeps the unknowns this method can identify (stiffnesses of bushings whose
/// two parts are measured at every step), with a note on what was left out.
pub fn restrict(
    model: &Model,
    unknowns: &[Unknown],
    data: &Measured,
) -> (Vec<Unknown>, Vec<FitNote>) {
    let mut kept = Vec::new();
    let mut left = Vec::new();
    for u in unknowns {
        let ok = u.addrs.iter().all(|a| {
            axis(*a).is_some_and(|(b, _)| {
                let bu = &model.bushings[b.index()];
                data.has_part(model.marker(bu.i).part) && data.has_part(model.marker(bu.j).part)
            })
        });
        if ok {
            kept.push(u.clone());
        } else {
            left.push(u.label());
        }
    }
    let notes = if left.is_empty() {
        vec![]
    } else {
        vec![FitNote::NotIterative { unknowns: left }]
    };
    (kept, notes)
}

/// Regression of `y` on `x` with an offset: (slope, correlation, intercept on x, spread of y).
fn regress(x: &[f64], y: &[f64]) -> (f64, f64, f64, f64) {
    let n = x.len() as f64;
    let mx = x.iter().sum::<f64>() / n;
    let my = y.iter().sum::<f64>() / n;
    let (mut sxy, mut sxx, mut syy) = (0.0, 0.0, 0.0);
    for (a, b) in x.iter().zip(y) {
        sxy += (a - mx) * (b - my);
        sxx += (a - mx) * (a - mx);
        syy += (b - my) * (b - my);
    }
    let k = sxy / sxx;
    let r = sxy / (sxx * syy).sqrt();
    (k, r, mx - my / k, syy)
}

pub fn identify(
    model: &Model,
    unknowns: &[Unknown],
    data: &Measured,
    opts: IterativeOptions,
) -> Result<Identified, IdentifyError> {
    for u in unknowns {
        let Some((b, _)) = u
            .addrs
            .iter()
            .find_map(|a| axis(*a))
            .filter(|_| u.addrs.iter().all(|a| axis(*a).is_some()))
        else {
            return Err(IdentifyError::of(
                IdentifyErrorKind::Method,
                format!(
                    "the iterative method identifies bushing stiffnesses only, not `{}`; use --method lsq or direct",
                    u.label()
                ),
                vec![u.element()],
            ));
        };
        let bu = &model.bushings[b.index()];
        for m in [bu.i, bu.j] {
            let part = model.marker(m).part;
            if !data.has_part(part) {
                return Err(IdentifyError::of(
                    IdentifyErrorKind::Method,
                    format!(
                        "bushing `{}` cannot be identified iteratively: part `{}` has no measured pose at every step",
                        bu.name,
                        model.part(part).name
                    ),
                    vec![ElementId::Bushing(b), ElementId::Part(part)],
                ));
            }
        }
    }
    if data.steps.len() < 2 {
        return Err(IdentifyError::of(
            IdentifyErrorKind::Undetermined,
            "the iterative method regresses over steps and needs at least 2",
            vec![],
        ));
    }
    let layout = Layout::new(model);
    // Measured deformation of every bushing axis the unknowns touch, per step.
    let measured_def = |b: BushingId, ax: usize| -> Vec<f64> {
        (0..data.steps.len())
            .map(|k| {
                let ev = forces::bushing_state(
                    model,
                    &layout,
                    &data.state(k),
                    &model.bushings[b.index()],
                );
                if ax < 3 { ev.t[ax] } else { ev.angles[ax - 3] }
            })
            .collect()
    };
    let defs: Vec<Vec<Vec<f64>>> = unknowns
        .iter()
        .map(|u| {
            u.addrs
                .iter()
                .map(|a| {
                    #[allow(clippy::expect_used)]
                    // every address was checked to be a bushing axis above
                    let (b, ax) = axis(*a).expect("checked above");
                    measured_def(b, ax)
                })
                .collect()
        })
        .collect();
    let mut problem = Problem::new(model).map_err(|e| IdentifyError::statics("", e, model))?;
    let mut values: Vec<f64> = unknowns.iter().map(|u| u.initial).collect();
    set_values(&mut problem, unknowns, &values)?;
    let mut history = vec![HistoryEntry {
        iteration: 0,
        values: values.clone(),
    }];
    // Each iteration's path starts every step from the previous iterate's
    // solution at that step (a guess; the history follows the path).
    let mut states: Vec<State> = Vec::new();
    let mut simulator = Simulator::new();
    let mut accepted = vec![false; unknowns.len()];
    let mut detail: Vec<Vec<AxisRegression>> = vec![Vec::new(); unknowns.len()];
    for it in 1..=opts.max_iterations {
        // Simulate every step with the current stiffnesses.
        let run = simulator.run(
            &problem,
            data.steps.iter().map(|s| &s.loads),
            &State::design(model),
            &states,
        );
        if let Some(e) = run.failure {
            return Err(IdentifyError::statics(
                format!(
                    "iteration {it}, step {}: the model with the current stiffnesses does not solve",
                    data.steps[e.case].step,
                ),
                e.error,
                model,
            ));
        }
        states = run.steps.into_iter().map(|e| e.state).collect();
        let mut next = values.clone();
        for (i, u) in unknowns.iter().enumerate() {
            let mut per_axis: Vec<(f64, f64)> = Vec::new(); // (new K, weight)
            let mut ok_any = false;
            let mut axes = Vec::new();
            for (a, addr) in u.addrs.iter().enumerate() {
                #[allow(clippy::expect_used)]
                // every address was checked to be a bushing axis above
                let (b, ax) = axis(*addr).expect("checked above");
                let force: Vec<f64> = states
                    .iter()
                    .map(|st| {
                        let ev = forces::bushing_state(
                            problem.model(),
                            &layout,
                            st,
                            &problem.model().bushings[b.index()],
                        );
                        // The force on I opposes the deformation: regress -F.
                        -(if ax < 3 {
                            ev.force[ax]
                        } else {
                            ev.torque[ax - 3]
                        })
                    })
                    .collect();
                let (k, r, e0, spread) = regress(&defs[i][a], &force);
                let ok = r.is_finite() && k.is_finite() && r > opts.threshold && k > 0.0;
                ok_any |= ok;
                per_axis.push((if ok { k } else { values[i] }, spread));
                let unit = if ax < 3 { "mm" } else { "deg" };
                axes.push(AxisRegression {
                    name: u.names[a].clone(),
                    fit: r.is_finite().then(|| AxisFit {
                        r,
                        offset: if ax < 3 { e0 } else { e0.to_degrees() },
                        unit,
                    }),
                });
            }
            // Axisymmetric pair: weighted by the spread of the loads (eq. 5.13).
            let w: f64 = per_axis.iter().map(|p| p.1).sum();
            next[i] = if per_axis.len() > 1 && w > 0.0 && w.is_finite() {
                per_axis.iter().map(|p| p.0 * p.1).sum::<f64>() / w
            } else {
                per_axis[0].0
            };
            accepted[i] = ok_any;
            detail[i] = axes;
        }
        let changed: Vec<usize> = (0..values.len())
            .filter(|&i| (next[i] - values[i]).abs() > opts.tolerance * values[i].abs())
            .collect();
        values = next;
        set_values(&mut problem, unknowns, &values)?;
        history.push(HistoryEntry {
            iteration: it,
            values: values.clone(),
        });
        if changed.is_empty() {
            let params = unknowns
                .iter()
                .enumerate()
                .map(|(i, u)| ParamResult {
                    initial: u.initial,
                    value: Some(values[i]),
                    interval: None,
                    identifiable: accepted[i],
                    notes: vec![ParamNote::Regression {
                        axes: detail[i].clone(),
                        kept_below: (!accepted[i]).then_some(opts.threshold),
                    }],
                    bound: None,
                })
                .collect();
            let mut out = Identified {
                method: Method::Iterative,
                unknowns: unknowns.to_vec(),
                params,
                combinations: Vec::new(),
                rank: accepted.iter().filter(|a| **a).count(),
                singular_values: Vec::new(),
                iterations: it,
                history,
                correlation: None,
                sigma0: None,
                notes: vec![FitNote::Converged {
                    tolerance: opts.tolerance,
                    iterations: it,
                }],
            };
            super::flag_outside_bounds(&mut out);
            return Ok(out);
        }
        if it == opts.max_iterations {
            return Err(IdentifyError::of(
                IdentifyErrorKind::NotConverged,
                format!(
                    "no convergence in {it} iterations: {} still change by more than {} (relative)",
                    changed
                        .iter()
                        .map(|&i| format!("`{}`", unknowns[i].label()))
                        .collect::<Vec<_>>()
                        .join(", "),
                    opts.tolerance
                ),
                changed.iter().map(|&i| unknowns[i].element()).collect(),
            ));
        }
    }
    Err(IdentifyError::of(
        IdentifyErrorKind::Options,
        "no iteration was allowed (max_iterations is 0)",
        vec![],
    ))
}

#[cfg(test)]
mod tests {
    use super::regress;

    #[test]
    fn regression_recovers_slope_and_offset() {
        let x = [1.0, 2.0, 3.0, 4.0];
        let y: Vec<f64> = x.iter().map(|t| 5.0 * (t - 0.5)).collect();
        let (k, r, e0, _) = regress(&x, &y);
        assert!((k - 5.0).abs() < 1e-12 && (r - 1.0).abs() < 1e-12 && (e0 - 0.5).abs() < 1e-12);
    }
}
