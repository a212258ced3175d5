//! Fitting one candidate to the training steps: Levenberg–Marquardt on its
//! few search variables (`super::candidate::Scale`), the Jacobian by forward
//! differences of whole replays (every kind of parameter alike: geometry
//! that needs a new constraint analysis, path-dependent friction, a stop's
//! contact), then the standard errors from the Jacobian at the optimum.
//!
//! A parameter whose interval is too wide to act on (`choose::determined`)
//! is *undetermined*, said in words and never printed as a number.

use super::Context;
use super::candidate::Candidate;
use super::jacobian::{by_differences, evaluate, residuals};
use super::replay::{Replay, ReplayError, search_simulator};
use crate::model::Model;
use crate::statics::path::Simulator;
use nalgebra::{DMatrix, DVector};

/// A candidate fitted.
#[derive(Debug, Clone)]
pub struct Fitted {
    /// The optimum in search units.
    pub x: Vec<f64>,
    /// Standard errors in search units (scaled by the misfit when it exceeds
    /// the noise); infinite for an undetermined parameter.
    pub sd: Vec<f64>,
    /// Noise-weighted χ² of the training steps at the optimum.
    pub train_chi2: f64,
    pub iterations: usize,
    /// The extended model at the optimum.
    pub model: Model,
    pub replay: Replay,
}

impl Fitted {
    /// The 95 % interval of parameter `i` in search units, if determined.
    pub fn interval(&self, i: usize) -> Option<(f64, f64)> {
        let h = 1.96 * self.sd[i];
        h.is_finite().then(|| (self.x[i] - h, self.x[i] + h))
    }
}

/// Why a fit gave no result.
#[derive(Debug, Clone, PartialEq)]
pub enum FitFailure {
    /// The structural edit was refused (the model's rules).
    Edit(String),
    /// The model did not solve at the start.
    Start(ReplayError),
    /// The search still improved after its last iteration: its point is
    /// not a minimum, so no value or interval of it is a finding.
    NotConverged { iterations: usize },
}

/// Levenberg–Marquardt iterations before a fit that still improves is
/// given up as not converged.
const MAX_ITERATIONS: usize = 30;

fn cost(r: &[f64]) -> f64 {
    r.iter().map(|v| v * v).sum()
}

/// Minimises the training χ² of `cand` from the search point `start`.
/// Every trial point is evaluated with its Jacobian ([`evaluate`]): with the
/// sensitivities that costs about one replay, so an accepted step needs no
/// second pass.
pub fn fit(
    ctx: &Context,
    cand: &Candidate,
    base: &Model,
    start: &[f64],
) -> Result<Fitted, FitFailure> {
    let extended = cand
        .extend(base)
        .map_err(|e| FitFailure::Edit(e.to_string()))?;
    let mut sim = search_simulator();
    if cand.params.len() == 1 && !extended.frictions.is_empty() {
        return fit_line(ctx, cand, &extended, start[0], &mut sim);
    }
    let mut x = start.to_vec();
    let mut ev = evaluate(ctx, cand, &extended, &x, &mut sim).map_err(FitFailure::Start)?;
    let mut c = cost(&ev.r);
    let mut mu = 1e-3;
    let mut iterations = 0;
    let mut converged = false;
    while iterations < MAX_ITERATIONS {
        iterations += 1;
        let rv = DVector::from_column_slice(&ev.r);
        let h = ev.j.transpose() * &ev.j;
        let g = ev.j.transpose() * rv;
        let pinned = pinned(&x, &g, cand);
        if pinned.iter().all(|&p| p) {
            // Every parameter on a bound the data push against: no move left.
            converged = true;
            break;
        }
        let (h, g) = free(&h, &g, &pinned);
        let mut improved = false;
        let mut tried: Option<Vec<f64>> = None;
        while mu < 1e10 {
            let Some(step) = damped_step(&h, &g, mu) else {
                break;
            };
            let xn: Vec<f64> = x
                .iter()
                .zip(step.iter())
                .zip(&cand.params)
                .map(|((xi, s), p)| (xi + s).clamp(p.lo, p.hi))
                .collect();
            // A larger damping that clamps to the same point tries nothing new.
            if xn == x || tried.as_ref() == Some(&xn) {
                mu *= 4.0;
                continue;
            }
            tried = Some(xn.clone());
            // With friction the Jacobian costs a replay per parameter: a
            // trial point gets only its residuals, an accepted one the rest.
            let trial = if extended.frictions.is_empty() {
                evaluate(ctx, cand, &extended, &xn, &mut sim)
            } else {
                match residuals(ctx, cand, &extended, &xn, &mut sim) {
                    Ok(at) if cost(&at.0) < c => {
                        Ok(by_differences(ctx, cand, &extended, &xn, at, &mut sim))
                    }
                    Ok((r, replay, model)) => Ok(super::jacobian::Evaluation {
                        r,
                        j: DMatrix::zeros(0, 0),
                        replay,
                        model,
                    }),
                    Err(e) => Err(e),
                }
            };
            match trial {
                Ok(evn) if cost(&evn.r) < c => {
                    let cn = cost(&evn.r);
                    let moved = xn
                        .iter()
                        .zip(&x)
                        .map(|(a, b)| (a - b).abs())
                        .fold(0.0, f64::max);
                    // Converged for every purpose of the intervals: χ² moved
                    // by less than 0.01 in units of the misfit the intervals
                    // are scaled by (a model far from the data crawls by
                    // steps that change nothing), or the point by 1e-5.
                    let misfit = (c / (ev.r.len() as f64 - x.len() as f64).max(1.0)).max(1.0);
                    let small = c - cn < 0.01 * misfit + 1e-9 * c || moved < 1e-5;
                    x = xn;
                    ev = evn;
                    c = cn;
                    mu = (mu / 3.0).max(1e-9);
                    improved = !small;
                    break;
                }
                _ => mu *= 4.0,
            }
        }
        if !improved {
            converged = true;
            break;
        }
    }
    if !converged {
        return Err(FitFailure::NotConverged { iterations });
    }
    let dof = (ev.r.len() as f64 - x.len() as f64).max(1.0);
    let misfit = (c / dof).max(1.0);
    let sd = standard_errors(&ev.j, misfit);
    Ok(Fitted {
        x,
        sd,
        train_chi2: c,
        iterations,
        model: ev.model,
        replay: ev.replay,
    })
}

/// A one-parameter fit of a model with friction, without derivatives: the
/// χ² of a stick-slip path is continuous in the slip limit but its
/// differences are ragged (a step sticks or slips), and Newton may fail at a
/// point a difference needs. A scan of seven points half a search unit
/// apart around the start, then golden-section search on the best interval;
/// the standard error from the curvature of χ² over ±0.05 at the optimum.
fn fit_line(
    ctx: &Context,
    cand: &Candidate,
    extended: &Model,
    start: f64,
    sim: &mut Simulator,
) -> Result<Fitted, FitFailure> {
    let p = &cand.params[0];
    let mut evals = 0;
    let mut chi = |x: f64, sim: &mut Simulator| -> f64 {
        evals += 1;
        residuals(ctx, cand, extended, &[x.clamp(p.lo, p.hi)], sim)
            .map_or(f64::INFINITY, |(r, _, _)| cost(&r))
    };
    let grid: Vec<f64> = (-3..=3)
        .map(|k| (start + 0.5 * k as f64).clamp(p.lo, p.hi))
        .collect();
    let costs: Vec<f64> = grid.iter().map(|&x| chi(x, sim)).collect();
    let best = (0..grid.len())
        .min_by(|&a, &b| costs[a].total_cmp(&costs[b]))
        .unwrap_or(3);
    if !costs[best].is_finite() {
        let e = residuals(ctx, cand, extended, &[start], sim).err();
        return Err(match e {
            Some(e) => FitFailure::Start(e),
            None => FitFailure::Edit("no point of the scan solved".into()),
        });
    }
    let (mut a, mut b) = (
        grid[best.saturating_sub(1)],
        grid[(best + 1).min(grid.len() - 1)],
    );
    let g = (5f64.sqrt() - 1.0) / 2.0;
    let (mut c, mut d) = (b - g * (b - a), a + g * (b - a));
    let (mut fc, mut fd) = (chi(c, sim), chi(d, sim));
    while b - a > 2e-3 {
        if fc < fd {
            b = d;
            d = c;
            fd = fc;
            c = b - g * (b - a);
            fc = chi(c, sim);
        } else {
            a = c;
            c = d;
            fc = fd;
            d = a + g * (b - a);
            fd = chi(d, sim);
        }
    }
    let x = 0.5 * (a + b);
    let (r, replay, model) =
        residuals(ctx, cand, extended, &[x], sim).map_err(FitFailure::Start)?;
    let c0 = cost(&r);
    let h = 0.05;
    let curv = (chi(x + h, sim) + chi(x - h, sim) - 2.0 * c0) / (h * h);
    let dof = (r.len() as f64 - 1.0).max(1.0);
    let misfit = (c0 / dof).max(1.0);
    // χ² = c0 + (curv / 2) δ², and χ² = Σ r² has Hessian 2 JᵀJ: σ² = 2 / curv.
    let sd = if curv.is_finite() && curv > 0.0 {
        (2.0 / curv * misfit).sqrt()
    } else {
        f64::INFINITY
    };
    Ok(Fitted {
        x: vec![x],
        sd: vec![sd],
        train_chi2: c0,
        iterations: evals,
        model,
        replay,
    })
}

/// The parameters on a bound whose descent direction `−g` points out of it:
/// held there for this step (a projected Levenberg–Marquardt step), so the
/// others still move and a clamped trial is not the same point again.
fn pinned(x: &[f64], g: &DVector<f64>, cand: &Candidate) -> Vec<bool> {
    x.iter()
        .zip(&cand.params)
        .enumerate()
        .map(|(i, (&xi, p))| (xi <= p.lo && g[i] > 0.0) || (xi >= p.hi && g[i] < 0.0))
        .collect()
}

/// `H` and `g` with the pinned parameters' rows and columns decoupled (unit
/// diagonal, zero gradient: their step is zero).
fn free(h: &DMatrix<f64>, g: &DVector<f64>, pinned: &[bool]) -> (DMatrix<f64>, DVector<f64>) {
    let (mut h, mut g) = (h.clone(), g.clone());
    let top = h.diagonal().amax().max(1e-300);
    for (i, _) in pinned.iter().enumerate().filter(|(_, p)| **p) {
        h.row_mut(i).fill(0.0);
        h.column_mut(i).fill(0.0);
        h[(i, i)] = top;
        g[i] = 0.0;
    }
    (h, g)
}

/// The Levenberg–Marquardt step `(H + μ diag H) δ = −g`. A candidate has at
/// most three parameters, all bounded, so every direction is searched
/// (leaving the weak ones out biased the others: a double-wishbone ball
/// joint 3 mm off in x, weakly seen, pulled its z estimate 0.2 mm short and
/// out of its interval).
fn damped_step(h: &DMatrix<f64>, g: &DVector<f64>, mu: f64) -> Option<DVector<f64>> {
    let n = h.nrows();
    let top = h.diagonal().amax();
    if !top.is_finite() || top <= 0.0 {
        return None;
    }
    let mut a = h.clone();
    for i in 0..n {
        a[(i, i)] += mu * h[(i, i)].max(1e-12 * top);
    }
    let step = -a.cholesky()?.solve(g);
    step.iter().all(|v| v.is_finite()).then_some(step)
}

/// Standard errors from `J` (noise-weighted), times `√misfit`, from every
/// direction the data see at all (singular value above 1e-8 of the largest),
/// the weak ones included: a parameter correlated with a direction the fit
/// did not search carries that direction's uncertainty, and the verdict
/// (`choose::determined`) then finds its interval too wide. Infinite for a
/// parameter along a direction the data do not see at all.
fn standard_errors(j: &DMatrix<f64>, misfit: f64) -> Vec<f64> {
    let n = j.ncols();
    let svd = j.clone().svd(false, true);
    let Some(vt) = svd.v_t else {
        return vec![f64::INFINITY; n];
    };
    let top = svd.singular_values.max();
    (0..n)
        .map(|i| {
            let mut var = 0.0;
            for (k, &s) in svd.singular_values.iter().enumerate() {
                let v = vt[(k, i)];
                if s <= 1e-8 * top {
                    if v.abs() > 1e-6 {
                        return f64::INFINITY;
                    }
                    continue;
                }
                var += (v / s).powi(2);
            }
            (var * misfit).sqrt()
        })
        .collect()
}
