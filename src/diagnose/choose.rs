//! The diagnosis loop and its verdict: screen, fit the promising candidates,
//! judge each on the held-out steps, keep the best if it is significant, and
//! go again on the extended model (greedy), until nothing significant is left.
//!
//! Judging: a candidate's *score* is the fall of the held-out χ² it brings,
//! less a penalty of `2 ln(n)` per parameter (`n` held-out residuals; the
//! Bayesian information criterion's price of a parameter, doubled because
//! the candidates are many and the best of many noise fits looks better than
//! one). It is *significant* when the score exceeds 10 and the fall is at least
//! 5 % of what the held-out χ² exceeds its noise expectation by: a residual
//! within the noise is not a finding. Candidates are independent, so they are
//! screened and fitted on all cores (rayon); the order of the results is the
//! library's, so a run is the same on any number of cores.

use super::candidate::{CandParam, Candidate, Ranges, Scale, library};
use super::channel::Channel;
use super::channel::PerChannel;
use super::fit::{FitFailure, Fitted, fit};
use super::holdout::{Subset, count};
use super::kind::Kind;
use super::noise::{self, Noise};
use super::replay::{Replay, ReplayError, channels_of, designs, replay_states, residual_count};
use super::rig::RigPath;
use super::screen::{Screened, screen, screen_at_nominal};
use super::{Context, Options};
use crate::model::{ElementId, Model};
use crate::statics::State;
use crate::statics::path::Simulator;
use crate::units::to_boundary;
use rayon::prelude::*;

/// Residual summary of one model on the rig.
#[derive(Debug, Clone, PartialEq)]
pub struct Summary {
    /// RMS per channel over every step, and over the held-out steps.
    pub rms: PerChannel,
    pub rms_held_out: PerChannel,
    /// Noise-weighted χ² of the training and of the held-out steps.
    pub train_chi2: f64,
    pub held_out_chi2: f64,
}

/// One fitted parameter, in boundary units (N/mm, N·mm/deg, mm, deg).
#[derive(Debug, Clone, PartialEq)]
pub struct ParamResult {
    pub name: String,
    pub unit: String,
    /// `None` when the data do not determine it (then nothing is printed).
    pub value: Option<f64>,
    pub interval: Option<(f64, f64)>,
    /// The model's value before the extension, for "against".
    pub nominal: Option<f64>,
    /// The value the fit ended at, determined or not (kept in the extended
    /// model, which needs a number; never printed as a finding).
    pub fitted: f64,
    /// The fit ended on a bound of the search (a stiffness 10 times the
    /// model's): the data want more than the candidate allows, so the value
    /// is not an estimate (and is not printed as one).
    pub at_bound: bool,
}

/// A candidate fitted and judged.
#[derive(Debug, Clone)]
pub struct Hypothesis {
    pub kind: Kind,
    pub element: ElementId,
    /// The element of the extended model that carries the change.
    pub changed: ElementId,
    pub element_name: String,
    pub detail: String,
    pub params: Vec<ParamResult>,
    pub summary: Summary,
    /// Held-out χ² fall less the parameter penalty.
    pub score: f64,
    pub significant: bool,
    pub model: Model,
    pub replay: Replay,
}

/// A cause found: the hypothesis and its gain per channel on the held-out
/// steps (fraction of the RMS error it removed), against the model before it.
#[derive(Debug, Clone)]
pub struct Effect {
    pub hypothesis: Hypothesis,
    pub gain: PerChannel,
    pub before: Summary,
}

/// A candidate that could not be judged, and why (reported, then skipped).
#[derive(Debug, Clone, PartialEq)]
pub struct Skipped {
    pub kind: Kind,
    pub element_name: String,
    pub detail: String,
    pub why: String,
}

/// Everything a diagnosis found.
#[derive(Debug, Clone)]
pub struct Diagnosis {
    pub noise: Noise,
    pub baseline: Summary,
    pub nominal: Replay,
    /// The first round's hypotheses, best first.
    pub hypotheses: Vec<Hypothesis>,
    /// The causes found, in the order found (by impact).
    pub effects: Vec<Effect>,
    pub skipped: Vec<Skipped>,
    /// The model with every effect added, and its replay.
    pub model: Model,
    pub replay: Replay,
    /// Held-out and training residual counts (channels × steps, and three
    /// per landmark).
    pub held_out: usize,
    pub training: usize,
    /// Candidates screened and fitted over all rounds.
    pub screened: usize,
    pub fitted: usize,
    /// Wall time spent screening and fitting, over all rounds.
    pub screen_time: std::time::Duration,
    pub fit_time: std::time::Duration,
}

/// Why there is no diagnosis.
#[derive(Debug, Clone, PartialEq)]
pub enum DiagnoseError {
    /// The nominal model does not solve along a path.
    Nominal(ReplayError),
    /// Too few steps to hold any out and still fit.
    TooFewSteps { steps: usize, needed: usize },
}

/// The penalty of one parameter, in held-out χ².
fn penalty(n: usize) -> f64 {
    2.0 * (n.max(2) as f64).ln()
}

fn summary(ctx: &Context, rp: &Replay) -> Summary {
    let chi = |s: &Subset| {
        rp.residuals(ctx.rig, ctx.noise, s)
            .iter()
            .map(|v| v * v)
            .sum()
    };
    Summary {
        rms: rp.rms(ctx.rig, &Subset::All),
        rms_held_out: rp.rms(ctx.rig, &Subset::HeldOut),
        train_chi2: chi(&Subset::Training),
        held_out_chi2: chi(&Subset::HeldOut),
    }
}

/// The range of each spring's length along the replayed states.
fn ranges(model: &Model, states: &[Vec<State>]) -> Ranges {
    let spring_length = model
        .springs
        .iter()
        .map(|s| {
            let (mi, mj) = (model.marker(s.i), model.marker(s.j));
            let mut r = (f64::INFINITY, f64::NEG_INFINITY);
            for st in states.iter().flatten() {
                let (xi, ri) = st.part_pose(mi.part);
                let (xj, rj) = st.part_pose(mj.part);
                let l = ((xi + ri * mi.origin()) - (xj + rj * mj.origin())).norm();
                r = (r.0.min(l), r.1.max(l));
            }
            r
        })
        .collect();
    Ranges { spring_length }
}

fn results(cand: &Candidate, f: &Fitted) -> Vec<ParamResult> {
    cand.params
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let shown = |x: f64| to_boundary(p.scale.value(x), p.dim);
            let search = f.interval(i);
            let at_bound = (f.x[i] - p.lo).abs() < 1e-6 || (f.x[i] - p.hi).abs() < 1e-6;
            let determined = !at_bound && search.is_some_and(|(a, b)| determined(p, f.x[i], a, b));
            let interval = search.map(|(a, b)| {
                let (a, b) = (shown(a.max(p.lo)), shown(b.min(p.hi)));
                (a.min(b), a.max(b))
            });
            ParamResult {
                name: p.name.clone(),
                unit: p.dim.boundary_unit(),
                value: determined.then(|| shown(f.x[i])),
                interval: if determined { interval } else { None },
                nominal: p.nominal.map(|v| to_boundary(v, p.dim)),
                fitted: shown(f.x[i]),
                at_bound,
            }
        })
        .collect()
}

/// A parameter is determined when its 95 % interval is within a factor 1.5
/// either way (a ratio), or when its half-width is below half the change
/// fitted or one probe step (a length: a joint point, a free length).
fn determined(p: &CandParam, x: f64, lo: f64, hi: f64) -> bool {
    match p.scale {
        Scale::Log { .. } => (hi - lo) / 2.0 < 1.5f64.ln(),
        Scale::Linear { .. } => (hi - lo) / 2.0 < (0.5 * x.abs()).max(p.probe.abs()),
    }
}

/// The fitted point with each model value rounded to a tenth of its
/// standard error (at least six significant digits kept; four for an
/// undetermined one), so the extended file reads `775.3`, not `775.2817…`.
fn rounded(c: &Candidate, f: &Fitted) -> Vec<f64> {
    c.params
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let v = p.scale.value(f.x[i]);
            let d = (p.scale.value(f.x[i] + 1e-6) - v).abs() / 1e-6;
            let sd = d * f.sd[i];
            let mag = v.abs().max(1e-300).log10().floor();
            let step = if sd.is_finite() && sd > 0.0 {
                10f64
                    .powf((sd / 10.0).log10().floor())
                    .max(10f64.powf(mag - 5.0))
            } else {
                10f64.powf(mag - 3.0)
            };
            let r = (v / step).round() * step;
            // Printing a multiple of `step` exactly: round the decimal digits.
            let digits = (-step.log10().floor()).clamp(0.0, 12.0) as i32;
            let r = (r * 10f64.powi(digits)).round() / 10f64.powi(digits);
            p.scale.search(r)
        })
        .collect()
}

struct Round {
    /// The summary of the model the round started from.
    before: Summary,
    hypotheses: Vec<Hypothesis>,
    skipped: Vec<Skipped>,
    screened: usize,
    fitted: usize,
    screen_time: std::time::Duration,
    fit_time: std::time::Duration,
}

/// One round: every candidate on `model` (whose replay is `rp`, states
/// `states`), except the causes already found.
fn round(
    ctx: &Context,
    model: &Model,
    states: &[Vec<State>],
    rp: &Replay,
    found: &[(Kind, ElementId)],
    opts: &Options,
    held: usize,
) -> Round {
    let before = summary(ctx, rp);
    let cands: Vec<Candidate> = library(model, &opts.kinds, &ranges(model, states))
        .into_iter()
        .filter(|c| !found.contains(&(c.kind, c.element)))
        .collect();
    let t0 = std::time::Instant::now();
    let mut skipped = Vec::new();
    let at_nominal = match screen_at_nominal(ctx, &cands, model) {
        Ok(s) => s,
        Err(why) => {
            skipped.push(Skipped {
                kind: Kind::None,
                element_name: String::new(),
                detail: "screening at the nominal model".into(),
                why,
            });
            vec![None; cands.len()]
        }
    };
    let screened: Vec<Screened> = cands
        .par_iter()
        .zip(at_nominal)
        .map(|(c, s)| s.unwrap_or_else(|| screen(ctx, c, model)))
        .collect();
    let mut order: Vec<usize> = Vec::new();
    for (i, s) in screened.iter().enumerate() {
        match &s.failed {
            Some(why) => skipped.push(Skipped {
                kind: cands[i].kind,
                element_name: cands[i].element_name(model),
                detail: cands[i].detail.clone(),
                why: why.clone(),
            }),
            None => order.push(i),
        }
    }
    order.sort_by(|&a, &b| screened[a].predicted.total_cmp(&screened[b].predicted));
    order.truncate(opts.fits);
    let t1 = std::time::Instant::now();
    let fits: Vec<(usize, Result<Fitted, FitFailure>)> = order
        .par_iter()
        .map(|&i| (i, fit(ctx, &cands[i], model, &screened[i].start)))
        .collect();
    let t2 = std::time::Instant::now();
    let excess = (before.held_out_chi2 - held as f64).max(0.0);
    let mut hypotheses = Vec::new();
    for (i, f) in fits {
        let c = &cands[i];
        match f {
            Ok(mut f) => {
                if let Ok(ext) = c.extend(model) {
                    f.model = c.at(&ext, &rounded(c, &f));
                }
                let s = summary(ctx, &f.replay);
                let fall = before.held_out_chi2 - s.held_out_chi2;
                let score = fall - penalty(held) * c.params.len() as f64;
                let seen = visible(ctx, &before, &s);
                hypotheses.push(Hypothesis {
                    kind: c.kind,
                    element: c.element,
                    changed: c.changed(model),
                    element_name: c.element_name(model),
                    detail: c.detail.clone(),
                    params: results(c, &f),
                    summary: s,
                    score,
                    significant: score > 10.0 && fall >= 0.05 * excess && seen,
                    model: f.model,
                    replay: f.replay,
                });
            }
            Err(e) => skipped.push(Skipped {
                kind: c.kind,
                element_name: c.element_name(model),
                detail: c.detail.clone(),
                why: match e {
                    FitFailure::Edit(w) => w,
                    FitFailure::NotConverged { iterations } => format!(
                        "the fit did not converge in {iterations} iterations (no value is given for it)"
                    ),
                    FitFailure::Start(r) => format!(
                        "did not solve at step {} of path {}: {}",
                        r.step + 1,
                        r.path + 1,
                        r.error.detail
                    ),
                },
            }),
        }
    }
    hypotheses.sort_by(|a, b| b.score.total_cmp(&a.score));
    Round {
        before,
        hypotheses,
        skipped,
        screened: cands.len(),
        fitted: order.len(),
        screen_time: t1 - t0,
        fit_time: t2 - t1,
    }
}

/// Whether some channel whose held-out error exceeded twice its noise lost
/// at least a tenth of it: a fall of χ² spread thinly over channels already
/// within their noise is not a finding.
fn visible(ctx: &Context, before: &Summary, after: &Summary) -> bool {
    let g = gain(before, after);
    (0..6).any(|c| {
        ctx.noise[c].present() && before.rms_held_out[c] > 2.0 * ctx.noise[c].sigma && g[c] >= 0.1
    })
}

fn gain(before: &Summary, after: &Summary) -> PerChannel {
    let mut g = [0.0; 6];
    for ((g, b), a) in g
        .iter_mut()
        .zip(&before.rms_held_out)
        .zip(&after.rms_held_out)
    {
        *g = if *b > 0.0 { 1.0 - a / b } else { 0.0 };
    }
    g
}

/// Diagnoses `model` against the rig paths.
pub fn diagnose(
    model: &Model,
    rig: &[RigPath],
    opts: &Options,
) -> Result<Diagnosis, DiagnoseError> {
    let steps: usize = rig.iter().map(|p| p.steps.len()).sum();
    let held = residual_count(rig, Subset::HeldOut);
    let training = residual_count(rig, Subset::Training);
    let training_steps: usize = rig
        .iter()
        .map(|p| count(Subset::Training, p.steps.len()))
        .sum();
    if held == 0 || training_steps < 4 {
        return Err(DiagnoseError::TooFewSteps { steps, needed: 6 });
    }
    let noise = noise::noise(rig, &opts.noise);
    let designs = designs(model, rig);
    let ctx = Context {
        rig,
        designs: &designs,
        noise: &noise,
    };
    let mut sim = Simulator::new();
    let states = replay_states(model, rig, &mut sim).map_err(DiagnoseError::Nominal)?;
    let nominal = channels_of(model, rig, &designs, &states);
    let baseline = summary(&ctx, &nominal);

    let mut current = model.clone();
    let mut cur_states = states;
    let mut cur_replay = nominal.clone();
    let mut found: Vec<(Kind, ElementId)> = Vec::new();
    let mut effects: Vec<Effect> = Vec::new();
    let mut first: Option<Vec<Hypothesis>> = None;
    let mut skipped = Vec::new();
    let (mut screened, mut fitted) = (0, 0);
    let (mut screen_time, mut fit_time) = Default::default();
    for _ in 0..opts.max_effects {
        let r = round(&ctx, &current, &cur_states, &cur_replay, &found, opts, held);
        screened += r.screened;
        fitted += r.fitted;
        screen_time += r.screen_time;
        fit_time += r.fit_time;
        skipped.extend(r.skipped);
        let best = r.hypotheses.first().filter(|h| h.significant).cloned();
        if first.is_none() {
            first = Some(r.hypotheses);
        }
        let Some(best) = best else { break };
        let before = r.before;
        let Ok(st) = replay_states(&best.model, rig, &mut sim) else {
            break;
        };
        found.push((best.kind, best.element));
        current = best.model.clone();
        cur_states = st;
        cur_replay = best.replay.clone();
        effects.push(Effect {
            gain: gain(&before, &best.summary),
            before,
            hypothesis: best,
        });
    }
    Ok(Diagnosis {
        noise,
        baseline,
        nominal,
        hypotheses: first.unwrap_or_default(),
        effects,
        skipped,
        model: current,
        replay: cur_replay,
        held_out: held,
        training,
        screened,
        fitted,
        screen_time,
        fit_time,
    })
}

impl Diagnosis {
    /// The gain of every effect together, per channel, on the held-out
    /// steps, against the nominal model.
    pub fn total_gain(&self) -> PerChannel {
        match self.effects.last() {
            Some(e) => gain(&self.baseline, &e.hypothesis.summary),
            None => [0.0; 6],
        }
    }

    /// The channels measured (the landmarks only when given).
    pub fn channels(&self) -> Vec<Channel> {
        Channel::ALL
            .into_iter()
            .filter(|c| self.noise[c.index()].present())
            .collect()
    }
}
