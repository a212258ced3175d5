//! Fitting one candidate to the training steps: Levenberg–Marquardt on its
//! few search variables (`super::candidate::Scale`), the Jacobian by forward
//! differences of whole replays (every kind of parameter alike: geometry
//! that needs a new constraint analysis, path-dependent friction, a stop's
//! contact), then the standard errors from the Jacobian at the optimum.
//!
//! A direction the data hardly see (a singular value of the noise-weighted
//! Jacobian below 1: moving along it by one search unit changes χ² by less
//! than 1) is not searched, and a parameter along it has no interval: it is
//! *undetermined*, said in words and never printed as a number.

use super::Context;
use super::candidate::Candidate;
use super::holdout::Subset;
use super::replay::{Replay, ReplayError, replay};
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
}

/// Replays `cand` at `x` on `extended`: training residuals and the replay.
fn evaluate(
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

fn cost(r: &[f64]) -> f64 {
    r.iter().map(|v| v * v).sum()
}

/// Forward-difference Jacobian of the training residuals at `x` (columns
/// that fail to solve are zero: that direction is then not searched).
fn jacobian(
    ctx: &Context,
    cand: &Candidate,
    extended: &Model,
    x: &[f64],
    r: &[f64],
    sim: &mut Simulator,
) -> DMatrix<f64> {
    let mut j = DMatrix::zeros(r.len(), x.len());
    for i in 0..x.len() {
        let p = &cand.params[i];
        let mut h = 1e-3;
        if x[i] + h > p.hi {
            h = -h;
        }
        let mut xp = x.to_vec();
        xp[i] += h;
        if let Ok((rp, _, _)) = evaluate(ctx, cand, extended, &xp, sim) {
            if rp.len() == r.len() {
                for k in 0..r.len() {
                    j[(k, i)] = (rp[k] - r[k]) / h;
                }
            }
        }
    }
    j
}

/// Minimises the training χ² of `cand` from the search point `start`.
pub fn fit(
    ctx: &Context,
    cand: &Candidate,
    base: &Model,
    start: &[f64],
) -> Result<Fitted, FitFailure> {
    let extended = cand
        .extend(base)
        .map_err(|e| FitFailure::Edit(e.to_string()))?;
    let mut sim = Simulator::new();
    let mut x = start.to_vec();
    let (mut r, mut rp, mut m) =
        evaluate(ctx, cand, &extended, &x, &mut sim).map_err(FitFailure::Start)?;
    let mut c = cost(&r);
    let mut mu = 1e-3;
    let mut iterations = 0;
    let mut jac = jacobian(ctx, cand, &extended, &x, &r, &mut sim);
    while iterations < 30 {
        iterations += 1;
        let rv = DVector::from_column_slice(&r);
        let h = jac.transpose() * &jac;
        let g = jac.transpose() * rv;
        let mut improved = false;
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
            match evaluate(ctx, cand, &extended, &xn, &mut sim) {
                Ok((rn, rpn, mn)) if cost(&rn) < c => {
                    let cn = cost(&rn);
                    let moved = xn
                        .iter()
                        .zip(&x)
                        .map(|(a, b)| (a - b).abs())
                        .fold(0.0, f64::max);
                    let small = c - cn < 1e-7 * c + 1e-9 || moved < 1e-5;
                    x = xn;
                    r = rn;
                    rp = rpn;
                    m = mn;
                    c = cn;
                    mu = (mu / 3.0).max(1e-9);
                    improved = !small;
                    break;
                }
                _ => mu *= 4.0,
            }
        }
        if !improved {
            break;
        }
        jac = jacobian(ctx, cand, &extended, &x, &r, &mut sim);
    }
    let dof = (r.len() as f64 - x.len() as f64).max(1.0);
    let misfit = (c / dof).max(1.0);
    let sd = standard_errors(&jac, misfit);
    Ok(Fitted {
        x,
        sd,
        train_chi2: c,
        iterations,
        model: m,
        replay: rp,
    })
}

/// The Levenberg–Marquardt step `(H + μ diag H) δ = −g`, leaving out the
/// directions the data do not see (singular values of `J` below 1).
fn damped_step(h: &DMatrix<f64>, g: &DVector<f64>, mu: f64) -> Option<DVector<f64>> {
    let n = h.nrows();
    let e = h.clone().symmetric_eigen();
    let mut step = DVector::zeros(n);
    let top = e.eigenvalues.amax();
    if !top.is_finite() {
        return None;
    }
    let mut a = h.clone();
    for i in 0..n {
        a[(i, i)] += mu * h[(i, i)].max(1e-12 * top).max(1e-300);
    }
    // Project out the unseen directions of H (eigenvalue of H = σ² < 1).
    let mut p = DMatrix::<f64>::identity(n, n);
    for k in 0..n {
        if e.eigenvalues[k] < 1.0 {
            let v = e.eigenvectors.column(k);
            p -= v * v.transpose();
        }
    }
    let ap = &p * a * &p + (DMatrix::identity(n, n) - &p);
    let gp = &p * g;
    if let Some(ch) = ap.cholesky() {
        step = -ch.solve(&gp);
    }
    step.iter().all(|v| v.is_finite()).then_some(step)
}

/// Standard errors from `J` (noise-weighted), times `√misfit`; infinite for
/// a parameter with a component along a direction the data do not see.
fn standard_errors(j: &DMatrix<f64>, misfit: f64) -> Vec<f64> {
    let n = j.ncols();
    let svd = j.clone().svd(false, true);
    let Some(vt) = svd.v_t else {
        return vec![f64::INFINITY; n];
    };
    (0..n)
        .map(|i| {
            let mut var = 0.0;
            for (k, &s) in svd.singular_values.iter().enumerate() {
                let v = vt[(k, i)];
                if s < 1.0 {
                    if v.abs() > 0.1 {
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
