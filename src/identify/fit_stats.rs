//! Statistics of a least-squares fit at its solution: parameter covariance,
//! 95 % intervals, the correlation matrix and the identifiability verdict
//! from the singular values of the noise-weighted Jacobian.
//!
//! Nuisance parameters (the registration of the measuring frame to the model
//! frame) are fitted with the unknowns but not reported. Their uncertainty
//! must still widen the unknowns' intervals: the covariance of the unknowns is
//! the unknowns' block of the full covariance, which equals the inverse of
//! `J_eff^T J_eff` with `J_eff` the unknowns' columns with the nuisance columns
//! projected out (`(I - J_n J_n^+) J_u`, the Schur complement). The verdict and
//! the rank are then taken from `J_eff`'s singular values, so a parameter whose
//! effect the nuisance can imitate is not called identified.
//!
//! An unknown that ended at one of its declared bounds with the data pulling it
//! beyond is held there: its column is left out (the others' covariance is
//! conditional on it) and it is reported "at bound" with no interval.

use super::linalg::{solve, svd};
use super::lsq::{is_log, scale_of};
use super::{BoundIssue, IdentifyError, IdentifyErrorKind, ParamNote, ParamResult, Unknown};
use nalgebra::DMatrix;

/// The fit at its solution.
pub struct Fit<'a> {
    pub unknowns: &'a [Unknown],
    /// Fitted values, internal units, one per unknown.
    pub values: Vec<f64>,
    /// Noise-weighted Jacobian in the search variables: the unknowns' columns
    /// first, then `nuisance` columns.
    pub jac: &'a DMatrix<f64>,
    pub nuisance: usize,
    /// Half the noise-weighted χ².
    pub cost: f64,
    /// Independent observations.
    pub n_eff: usize,
    /// Per unknown: held at a bound by the data.
    pub at_bound: Vec<Option<BoundIssue>>,
}

pub struct Stats {
    pub params: Vec<ParamResult>,
    pub correlation: Vec<Vec<f64>>,
    pub rank: usize,
    pub singular_values: Vec<f64>,
    /// A posteriori σ factor.
    pub sigma0: f64,
    pub dof: usize,
}

pub fn statistics(fit: &Fit) -> Result<Stats, IdentifyError> {
    let nu = fit.unknowns.len();
    let free: Vec<usize> = (0..nu).filter(|&i| fit.at_bound[i].is_none()).collect();
    let nf = free.len();
    let rows = fit.jac.nrows();
    let dof = fit.n_eff.saturating_sub(nf + fit.nuisance).max(1);
    let s0 = (2.0 * fit.cost / dof as f64).sqrt();
    let mut ju = DMatrix::from_fn(rows, nf, |r, c| fit.jac[(r, free[c])]);
    if fit.nuisance > 0 {
        let jn = fit.jac.columns(nu, fit.nuisance).into_owned();
        let ntn = jn.transpose() * &jn;
        let coef = solve(&ntn, &(jn.transpose() * &ju)).ok_or_else(|| {
            IdentifyError::of(
                IdentifyErrorKind::Undetermined,
                "the registration of the measured frame to the model frame is not determined by the ground's landmarks",
                vec![],
            )
        })?;
        ju -= &jn * coef;
    }
    let d = svd(&ju, nf > rows).ok_or_else(|| {
        IdentifyError::of(
            IdentifyErrorKind::Numeric,
            "the Jacobian is not finite",
            vec![],
        )
    })?;
    let smax = d.s.first().copied().unwrap_or(0.0);
    let rnk = d.s.iter().filter(|&&s| s > 1e-10 * smax).count();
    let factor = s0.max(1.0).powi(2);
    // Covariance of the free unknowns (search variables), then placed in the
    // full nu × nu matrix (zero rows for unknowns held at a bound).
    let mut cf = DMatrix::zeros(nf, nf);
    for k in 0..rnk {
        let v = d.v.column(k);
        cf += v * v.transpose() * (factor / (d.s[k] * d.s[k]));
    }
    let mut cov = DMatrix::zeros(nu, nu);
    for (a, &i) in free.iter().enumerate() {
        for (b, &j) in free.iter().enumerate() {
            cov[(i, j)] = cf[(a, b)];
        }
    }
    let null = d.v.columns(rnk, d.v.ncols() - rnk).into_owned();
    let mut params = Vec::with_capacity(nu);
    for (i, u) in fit.unknowns.iter().enumerate() {
        let p = fit.values[i];
        if let Some(side) = fit.at_bound[i] {
            params.push(ParamResult {
                initial: u.initial,
                value: Some(p),
                interval: None,
                identifiable: false,
                notes: vec![ParamNote::HeldAtBound {
                    upper: side == BoundIssue::AtUpper,
                    value: crate::units::to_boundary(p, u.dim),
                    unit: u.dim.boundary_unit(),
                }],
                bound: Some(side),
            });
            continue;
        }
        #[allow(clippy::expect_used)] // `i` is not held, so it is in `free`
        let a = free.iter().position(|&f| f == i).expect("free unknown");
        let in_null = null.nrows() > 0 && null.ncols() > 0 && null.row(a).norm() > 1e-3;
        let sd = cov[(i, i)].max(0.0).sqrt();
        let (lo, hi, relw) = if is_log(u) {
            (
                p * (-1.96 * sd).exp(),
                p * (1.96 * sd).exp(),
                (1.96 * sd).exp() - 1.0,
            )
        } else {
            let w = 1.96 * sd * scale_of(u);
            (
                p - w,
                p + w,
                if p != 0.0 { w / p.abs() } else { f64::INFINITY },
            )
        };
        let identifiable =
            !in_null && relw.is_finite() && (relw < 0.5 || !u.is_stiffness()) && p.is_finite();
        params.push(ParamResult {
            initial: u.initial,
            value: if identifiable { Some(p) } else { None },
            interval: if identifiable { Some((lo, hi)) } else { None },
            identifiable,
            notes: if identifiable {
                Vec::new()
            } else if in_null {
                vec![ParamNote::NotObserved]
            } else {
                vec![ParamNote::WideInterval {
                    relative_half_width: relw,
                    fitted: crate::units::to_boundary(p, u.dim),
                }]
            },
            bound: None,
        });
    }
    let correlation = (0..nu)
        .map(|i| {
            (0..nu)
                .map(|j| {
                    let den = (cov[(i, i)] * cov[(j, j)]).sqrt();
                    if den > 0.0 { cov[(i, j)] / den } else { 0.0 }
                })
                .collect()
        })
        .collect();
    Ok(Stats {
        params,
        correlation,
        rank: rnk,
        singular_values: d.s.clone(),
        sigma0: s0,
        dof,
    })
}
