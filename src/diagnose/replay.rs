//! Replaying the rig on a model: every measured path simulated in the order
//! measured, each from the design state, state carried from step to step (so
//! loading and unloading differ once the model has friction), through one
//! [`Simulator`] per caller. The result is the simulated channels per step,
//! and from them the noise-weighted residuals of a step subset
//! ([`super::holdout`]).

use super::channel::{self, Design, Measured};
use super::holdout::Subset;
use super::noise::{Noise, weighted};
use super::rig::RigPath;
use crate::model::Model;
use crate::statics::path::Simulator;
use crate::statics::{Problem, State, StaticsError};

/// The simulated channels of every path, step by step.
#[derive(Debug, Clone, PartialEq)]
pub struct Replay {
    pub paths: Vec<Vec<Measured>>,
}

/// Where a replay failed: the path, the step in it, and why.
#[derive(Debug, Clone, PartialEq)]
pub struct ReplayError {
    pub path: usize,
    pub step: usize,
    pub error: StaticsError,
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

impl Replay {
    /// Noise-weighted residuals (simulated − measured) / σ of the steps in
    /// `subset`, channel by channel, in path and step order.
    pub fn residuals(&self, rig: &[RigPath], noise: &Noise, subset: &Subset) -> Vec<f64> {
        let mut out = Vec::new();
        for (p, (sim, path)) in self.paths.iter().zip(rig).enumerate() {
            for (k, (s, step)) in sim.iter().zip(&path.steps).enumerate() {
                if !subset.contains(p, k) {
                    continue;
                }
                let mut r = *s;
                for (c, v) in r.iter_mut().enumerate() {
                    *v -= step.measured[c];
                }
                out.extend_from_slice(&weighted(noise, &r));
            }
        }
        out
    }

    /// Root-mean-square residual per channel (channel units) over `subset`.
    pub fn rms(&self, rig: &[RigPath], subset: &Subset) -> Measured {
        let mut sum = [0.0; 5];
        let mut n = 0usize;
        for (p, (sim, path)) in self.paths.iter().zip(rig).enumerate() {
            for (k, (s, step)) in sim.iter().zip(&path.steps).enumerate() {
                if !subset.contains(p, k) {
                    continue;
                }
                n += 1;
                for c in 0..5 {
                    sum[c] += (s[c] - step.measured[c]).powi(2);
                }
            }
        }
        sum.map(|v| if n == 0 { 0.0 } else { (v / n as f64).sqrt() })
    }
}
