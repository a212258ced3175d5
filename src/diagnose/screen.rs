//! Screening: a cheap first look at every candidate, so that only the
//! promising ones are fitted. For each starting point, one replay there (none
//! when the start is the nominal model) and one per parameter a probe step
//! away give a secant Jacobian; the Gauss–Newton step of that linear model
//! predicts how far the candidate could lower the training χ². A secant of a
//! probe-sized step (not a derivative) also sees effects that start at a
//! threshold (friction sticking, a stop touching) where a derivative at the
//! nominal model is zero.

use super::Context;
use super::candidate::Candidate;
use super::holdout::Subset;
use super::replay::replay;
use crate::model::Model;
use crate::statics::path::Simulator;
use nalgebra::{DMatrix, DVector};

/// What screening found for one candidate.
#[derive(Debug, Clone)]
pub struct Screened {
    /// The best starting point for the fit.
    pub start: Vec<f64>,
    /// The predicted training χ² after one linear step from it.
    pub predicted: f64,
    /// Why the candidate could not be screened (its edit refused, or no
    /// start solved).
    pub failed: Option<String>,
}

/// Screens `cand` on `base`, whose training residuals are `r0`.
pub fn screen(ctx: &Context, cand: &Candidate, base: &Model, r0: &[f64]) -> Screened {
    let extended = match cand.extend(base) {
        Ok(m) => m,
        Err(e) => {
            return Screened {
                start: vec![],
                predicted: f64::INFINITY,
                failed: Some(e.to_string()),
            };
        }
    };
    let mut sim = Simulator::new();
    let mut residual = |x: &[f64]| -> Option<Vec<f64>> {
        let m = cand.at(&extended, x);
        replay(&m, ctx.rig, ctx.designs, &mut sim)
            .ok()
            .map(|rp| rp.residuals(ctx.rig, ctx.noise, &Subset::Training))
    };
    let mut best: Option<(Vec<f64>, f64)> = None;
    let mut why = None;
    for start in &cand.starts {
        let rs = if cand.zero_is_nominal && start.iter().all(|v| *v == 0.0) {
            Some(r0.to_vec())
        } else {
            residual(start)
        };
        let Some(rs) = rs else {
            why = Some("the model with it does not solve at its starting point".to_string());
            continue;
        };
        let n = start.len();
        let mut j = DMatrix::zeros(rs.len(), n);
        for i in 0..n {
            let p = &cand.params[i];
            let mut x = start.clone();
            x[i] = (x[i] + p.probe).clamp(p.lo, p.hi);
            let h = x[i] - start[i];
            if h == 0.0 {
                continue;
            }
            if let Some(ri) = residual(&x) {
                if ri.len() == rs.len() {
                    for k in 0..rs.len() {
                        j[(k, i)] = (ri[k] - rs[k]) / h;
                    }
                }
            }
        }
        let predicted = linear_prediction(&j, &rs);
        if best.as_ref().is_none_or(|(_, b)| predicted < *b) {
            best = Some((start.clone(), predicted));
        }
    }
    match best {
        Some((start, predicted)) => Screened {
            start,
            predicted,
            failed: None,
        },
        None => Screened {
            start: vec![],
            predicted: f64::INFINITY,
            failed: why,
        },
    }
}

/// `min |r + J δ|²` over δ (least squares by the SVD, directions of singular
/// value below 1 left out).
fn linear_prediction(j: &DMatrix<f64>, r: &[f64]) -> f64 {
    let rv = DVector::from_column_slice(r);
    let c0 = rv.norm_squared();
    let svd = j.clone().svd(true, false);
    let Some(u) = svd.u else { return c0 };
    let mut gain = 0.0;
    for (k, &s) in svd.singular_values.iter().enumerate() {
        if s >= 1.0 {
            gain += u.column(k).dot(&rv).powi(2);
        }
    }
    (c0 - gain).max(0.0)
}
