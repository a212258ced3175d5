//! Replaying the rig on a model: every measured path simulated in the order
//! measured, each from the design state, state carried from step to step (so
//! loading and unloading differ once the model has friction), through one
//! [`Simulator`] per caller. The result is the simulated channels per step,
//! and from them the noise-weighted residuals of a step subset
//! ([`super::holdout`]).

use super::channel::{self, Channel, Design, Measured, PerChannel};
use super::holdout::Subset;
use super::landmarks::{misfit, simulated};
use super::noise::{Noise, weighted};
use super::rig::{RigPath, RigStep};
use crate::geom::Vec3;
use crate::model::Model;
use crate::statics::path::Simulator;
use crate::statics::{Problem, State, StaticsError};

/// The simulated channels of every path, step by step.
#[derive(Debug, Clone, PartialEq)]
pub struct Replay {
    pub paths: Vec<Vec<Measured>>,
    /// The simulated positions of the landmarks measured at each step (in
    /// the order of [`super::rig::RigStep::landmarks`]).
    pub landmarks: Vec<Vec<Vec<Vec3>>>,
}

/// Where a replay failed: the path, the step in it, and why.
#[derive(Debug, Clone, PartialEq)]
pub struct ReplayError {
    pub path: usize,
    pub step: usize,
    pub error: StaticsError,
}

/// The simulator of a search (screening, fitting): a replay that needs more
/// than three load sub-step attempts per step on average (a nominal replay
/// takes one) is near a limit of the candidate model's equilibria and fails
/// instead, so the search steps back at the cost of a few ordinary replays
/// (a part split with a very soft bending joint once took 40 000 Newton
/// iterations on one path, seconds per trial).
pub fn search_simulator() -> Simulator {
    Simulator::with_budget(3, 30)
}

/// The rig's design references, one per path (its wheel).
pub fn designs(model: &Model, rig: &[RigPath]) -> Vec<Design> {
    rig.iter()
        .map(|p| channel::design(model, p.wheel))
        .collect()
}

/// Simulates `model` along every path of `rig`; `designs` from [`designs`] of
/// the nominal model, so that every model is measured against the same
/// reference as the rig data.
pub fn replay(
    model: &Model,
    rig: &[RigPath],
    designs: &[Design],
    sim: &mut Simulator,
) -> Result<Replay, ReplayError> {
    Ok(channels_of(
        model,
        rig,
        designs,
        &replay_states(model, rig, sim)?,
    ))
}

/// The channels of solved states (one list per path).
pub fn channels_of(
    model: &Model,
    rig: &[RigPath],
    designs: &[Design],
    states: &[Vec<State>],
) -> Replay {
    Replay {
        paths: states
            .iter()
            .zip(rig)
            .zip(designs)
            .map(|((st, p), d)| {
                st.iter()
                    .map(|s| channel::of_state(model, d, p.wheel, s))
                    .collect()
            })
            .collect(),
        landmarks: states
            .iter()
            .zip(rig)
            .map(|(st, p)| {
                st.iter()
                    .zip(&p.steps)
                    .map(|(s, step)| simulated(model, s, &step.landmarks))
                    .collect()
            })
            .collect(),
    }
}

/// The solved states of every step of every path.
pub fn replay_states(
    model: &Model,
    rig: &[RigPath],
    sim: &mut Simulator,
) -> Result<Vec<Vec<State>>, ReplayError> {
    let problem = Problem::new(model).map_err(|error| ReplayError {
        path: 0,
        step: 0,
        error,
    })?;
    let start = State::design(model);
    let mut out = Vec::with_capacity(rig.len());
    for (k, p) in rig.iter().enumerate() {
        let cases: Vec<&[crate::model::PointLoad]> =
            p.steps.iter().map(|s| s.loads.as_slice()).collect();
        let run = sim.run(&problem, &cases, &start, &[]);
        if let Some(f) = run.failure {
            return Err(ReplayError {
                path: k,
                step: f.case,
                error: f.error,
            });
        }
        out.push(run.steps.into_iter().map(|e| e.state).collect());
    }
    Ok(out)
}

/// Appends the noise-weighted residuals of one step: its K&C channels
/// `sim`, then the coordinates of its landmarks at `points`.
pub fn step_residuals(
    noise: &Noise,
    step: &RigStep,
    sim: &Measured,
    points: &[Vec3],
    out: &mut Vec<f64>,
) {
    let mut r = *sim;
    for (c, v) in r.iter_mut().enumerate() {
        *v -= step.measured[c];
    }
    out.extend_from_slice(&weighted(noise, &r));
    let sigma = noise[Channel::Landmarks.index()].sigma;
    for (x, (_, m)) in points.iter().zip(&step.landmarks) {
        out.extend((x - m).iter().map(|d| d / sigma));
    }
}

/// The number of residuals of `rig` in `subset` (channels × steps, and three
/// per landmark).
pub fn residual_count(rig: &[RigPath], subset: Subset) -> usize {
    rig.iter()
        .enumerate()
        .map(|(p, path)| {
            path.steps
                .iter()
                .enumerate()
                .filter(|(k, _)| subset.contains(p, *k))
                .map(|(_, s)| 5 + 3 * s.landmarks.len())
                .sum::<usize>()
        })
        .sum()
}

impl Replay {
    /// Noise-weighted residuals (simulated − measured) / σ of the steps in
    /// `subset`, in path and step order: per step the K&C channels, then
    /// each landmark's three coordinates ([`step_residuals`]).
    pub fn residuals(&self, rig: &[RigPath], noise: &Noise, subset: &Subset) -> Vec<f64> {
        let mut out = Vec::new();
        for (p, (sim, path)) in self.paths.iter().zip(rig).enumerate() {
            for (k, (s, step)) in sim.iter().zip(&path.steps).enumerate() {
                if subset.contains(p, k) {
                    step_residuals(noise, step, s, &self.landmarks[p][k], &mut out);
                }
            }
        }
        out
    }

    /// Root-mean-square residual per channel (channel units) over `subset`;
    /// for the landmarks, per coordinate.
    pub fn rms(&self, rig: &[RigPath], subset: &Subset) -> PerChannel {
        let mut sum = [0.0; 6];
        let (mut n, mut coords) = (0usize, 0usize);
        for (p, (sim, path)) in self.paths.iter().zip(rig).enumerate() {
            for (k, (s, step)) in sim.iter().zip(&path.steps).enumerate() {
                if !subset.contains(p, k) {
                    continue;
                }
                n += 1;
                for c in 0..5 {
                    sum[c] += (s[c] - step.measured[c]).powi(2);
                }
                sum[5] += misfit(&self.landmarks[p][k], &step.landmarks);
                coords += 3 * step.landmarks.len();
            }
        }
        let mean = |v: f64, n: usize| if n == 0 { 0.0 } else { (v / n as f64).sqrt() };
        let mut out = [0.0; 6];
        for c in 0..5 {
            out[c] = mean(sum[c], n);
        }
        out[5] = mean(sum[5], coords);
        out
    }
}
