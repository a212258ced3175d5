//! Diagnosis (`axle diagnose`, `docs/diagnose.md`): what a model gets wrong
//! against rig measurements, the physical cause, the extended model, and the
//! gain on held-out steps.
//!
//! 1. Replay the rig paths on the model in the order measured ([`replay`]);
//!    residuals per channel ([`channel`]) weighted by their noise ([`noise`]).
//! 2. Screen every candidate cause of the library ([`candidate`]) cheaply
//!    ([`screen`]), fit the promising ones to the training steps ([`fit`]),
//!    and judge them on the held-out steps ([`holdout`]) with a penalty per
//!    parameter ([`choose`]).
//! 3. Keep the best if it is significant, extend the model with it, and
//!    diagnose the extended model again, until nothing significant remains.
//!
//! The library is data in, data out: rig paths already read ([`rig`]), a
//! [`Diagnosis`] back; the command line renders it ([`words`] for sentences).

pub mod candidate;
pub mod channel;
pub mod choose;
pub mod fit;
pub mod holdout;
pub mod jacobian;
pub mod kind;
pub mod landmarks;
pub mod noise;
pub mod replay;
pub mod rig;
pub mod screen;
pub mod structure;
pub mod words;

pub use choose::{Diagnosis, Effect, Hypothesis, ParamResult, Summary};
pub use kind::Kind;

use channel::{Channel, Design};
use noise::Noise;
use rig::RigPath;

/// What every stage reads: the rig data, its wheels' design references, and
/// the channel noise.
#[derive(Debug, Clone, Copy)]
pub struct Context<'a> {
    pub rig: &'a [RigPath],
    pub designs: &'a [Design],
    pub noise: &'a Noise,
}

/// What to look for.
#[derive(Debug, Clone, PartialEq)]
pub struct Options {
    /// The kinds of cause in the library (default: all).
    pub kinds: Vec<Kind>,
    /// Channel noise the user gave (others are estimated).
    pub noise: Vec<(Channel, f64)>,
    /// At most this many effects (greedy rounds).
    pub max_effects: usize,
    /// Candidates fully fitted per round, best screened first.
    pub fits: usize,
}

impl Default for Options {
    fn default() -> Options {
        Options {
            kinds: Kind::CAUSES.to_vec(),
            noise: vec![],
            max_effects: 3,
            fits: 6,
        }
    }
}

pub use choose::diagnose;
