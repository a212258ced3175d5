//! Screening: a cheap first look at every candidate, so that only the
//! promising ones are fitted. The residuals and their Jacobian at a
//! candidate's starting point predict, by one Gauss–Newton step of that
//! linear model, how far the candidate could lower the training χ². Every
//! candidate that starts at the nominal model (a stiffness, a joint point, a
//! cubic term, an offset, a free length) is screened by one pass with the
//! sensitivities to all their parameters at once; the others (a stop, a split
//! part, friction) start away from it, at each of their starting points.

use super::Context;
use super::candidate::Candidate;
use super::jacobian::{Evaluation, evaluate};
use super::replay::search_simulator;
use crate::model::Model;
use nalgebra::{DMatrix, DVector};
use rayon::prelude::*;

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

/// Screens the candidates whose search point 0 is the nominal model all at
/// once: one evaluation of `base` with every one of their parameters gives
/// each its Jacobian columns. Returns one result per candidate of `cands`
/// (in order), `None` for those it does not handle.
pub fn screen_at_nominal(
    ctx: &Context,
    cands: &[Candidate],
    base: &Model,
) -> Result<Vec<Option<Screened>>, String> {
    let at0: Vec<usize> = (0..cands.len())
        .filter(|&i| cands[i].zero_is_nominal && cands[i].edits.is_empty())
        .collect();
    let mut params = Vec::new();
    let mut cols = Vec::new();
    for &i in &at0 {
        cols.push(params.len());
        params.extend(cands[i].params.iter().cloned());
    }
    let all = Candidate {
        params,
        starts: vec![],
        edits: vec![],
        ..cands[at0.first().copied().unwrap_or(0)].clone()
    };
    let mut out = vec![None; cands.len()];
    if at0.is_empty() {
        return Ok(out);
    }
    let x0 = vec![0.0; all.params.len()];
    // The sensitivities of one path are independent of the others': one
    // job per path on all cores.
    let parts: Vec<Result<Evaluation, String>> = (0..ctx.rig.len())
        .into_par_iter()
        .map(|p| {
            let one = Context {
                rig: &ctx.rig[p..p + 1],
                designs: &ctx.designs[p..p + 1],
                noise: ctx.noise,
            };
            evaluate(&one, &all, base, &x0, &mut search_simulator()).map_err(|e| {
                format!(
                    "the nominal model's sensitivities failed at step {}: {}",
                    e.step + 1,
                    e.error.detail
                )
            })
        })
        .collect();
    let mut r = Vec::new();
    let mut rows: Vec<DMatrix<f64>> = Vec::new();
    for part in parts {
        let ev = part?;
        r.extend(ev.r);
        rows.push(ev.j);
    }
    let n: usize = rows.iter().map(|j| j.nrows()).sum();
    let mut j = DMatrix::zeros(n, all.params.len());
    let mut at = 0;
    for b in &rows {
        j.view_mut((at, 0), (b.nrows(), b.ncols())).copy_from(b);
        at += b.nrows();
    }
    for (k, &i) in at0.iter().enumerate() {
        let np = cands[i].params.len();
        let jc = j.columns(cols[k], np).into_owned();
        out[i] = Some(Screened {
            start: vec![0.0; np],
            predicted: linear_prediction(&jc, &r),
            failed: None,
        });
    }
    Ok(out)
}

/// Screens one candidate from each of its starting points (one evaluation
/// with its Jacobian per start).
pub fn screen(ctx: &Context, cand: &Candidate, base: &Model) -> Screened {
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
    let mut sim = search_simulator();
    let mut best: Option<(Vec<f64>, f64)> = None;
    let mut why = None;
    for start in &cand.starts {
        match evaluate(ctx, cand, &extended, start, &mut sim) {
            Ok(ev) => {
                let predicted = linear_prediction(&ev.j, &ev.r);
                if best.as_ref().is_none_or(|(_, b)| predicted < *b) {
                    best = Some((start.clone(), predicted));
                }
            }
            Err(e) => {
                why = Some(format!(
                    "the model with it does not solve at its starting point (step {} of path {}: {})",
                    e.step + 1,
                    e.path + 1,
                    e.error.detail
                ));
            }
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
