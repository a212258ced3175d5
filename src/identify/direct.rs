//! Direct identification (thesis chapter 4): at each measured equilibrium the
//! equations `Q_ext + Q_elast(k) + Φ_qᵀ λ = 0` are linear in the stiffnesses.
//! Projected on the admissible motions (an orthonormal basis L of the null
//! space of the constraint Jacobian) the multipliers drop out:
//! `Lᵀ D k = -Lᵀ Q_ext` (eq. 4.46–4.49). Stacked over the steps and solved by
//! SVD; what the null space of the stacked matrix leaves free is reported.
//!
//! Coordinates are the statics engine's (position and rotation increment per
//! moving part) with rotations scaled by the model's characteristic length, so
//! force and moment equations weigh alike. The constraint rank is numerical
//! (the slider-crank has 18 equations of rank 17, thesis §4.3.2.2).

use super::columns::{column, is_affine, total_force};
use super::combinations::determine;
use super::linalg::{null_space, rank, svd, truncated_solve};
use super::measured::{Measured, unmeasured};
use super::{
    FitNote, Identified, IdentifyError, IdentifyErrorKind, Method, ParamNote, ParamResult, Unknown,
};
use crate::model::address::Address;
use crate::model::schema::FieldId;
use crate::model::{ElementId, Model};
use crate::statics::assembly::col_scale;
use crate::statics::coords::Layout;
use crate::statics::redundancy::scaled_jacobian;
use crate::statics::{Problem, constraint};
use nalgebra::{DMatrix, DVector};

#[derive(Debug, Clone, Copy)]
pub struct DirectOptions {
    /// Singular values of the column-scaled matrix below this fraction of the
    /// largest count as zero.
    pub rank_tol: f64,
}

impl Default for DirectOptions {
    fn default() -> Self {
        DirectOptions { rank_tol: 1e-5 }
    }
}

/// A linear unknown of the stacked system.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Lin {
    /// An unknown the forces are linear in.
    Plain(usize),
    /// A spring's k when its free length is unknown too: the pair (k, k·L0) is
    /// linear (eq. 4.37, 4.38).
    SpringK {
        k: usize,
    },
    SpringKL0 {
        k: usize,
        l0: usize,
    },
}

fn linear_unknowns(unknowns: &[Unknown]) -> Vec<Lin> {
    let mut out = Vec::new();
    for (i, u) in unknowns.iter().enumerate() {
        let a = u.addrs[0];
        match (a.element, a.field) {
            (ElementId::Spring(s), FieldId::SpringK) => {
                match unknowns
                    .iter()
                    .position(|v| v.addrs[0] == Address::spring(s, FieldId::FreeLength))
                {
                    Some(l0) => {
                        out.push(Lin::SpringK { k: i });
                        out.push(Lin::SpringKL0 { k: i, l0 });
                    }
                    None => out.push(Lin::Plain(i)),
                }
            }
            (ElementId::Spring(s), FieldId::FreeLength)
                if unknowns
                    .iter()
                    .any(|v| v.addrs[0] == Address::spring(s, FieldId::SpringK)) => {}
            _ => out.push(Lin::Plain(i)),
        }
    }
    out
}

/// The stacked system `A y = b` (rows: admissible motions of every step).
struct Stacked {
    a: DMatrix<f64>,
    b: DVector<f64>,
}

fn stack(
    model: &Model,
    unknowns: &[Unknown],
    lins: &[Lin],
    data: &Measured,
) -> Result<Stacked, IdentifyError> {
    let problem = Problem::new(model).map_err(|e| IdentifyError::statics("", e, model))?;
    let layout = Layout::new(model);
    let n = layout.n();
    let eqs = constraint::equations(model);
    let all: Vec<usize> = (0..eqs.len()).collect();
    let mut work = model.clone();
    for u in unknowns {
        u.set(&mut work, 0.0);
    }
    let mut rows: Vec<DVector<f64>> = Vec::new();
    let mut cols_per_step: Vec<DMatrix<f64>> = Vec::new();
    for k in 0..data.steps.len() {
        let state = data.state(k);
        let sj = scaled_jacobian(model, &layout, &state, &eqs, &all, problem.length);
        let l = null_space(&sj.jac, 1e-9).ok_or_else(|| {
            IdentifyError::of(
                IdentifyErrorKind::Numeric,
                format!(
                    "step {}: the constraint Jacobian is not finite",
                    data.steps[k].step
                ),
                vec![],
            )
        })?;
        let scale = DVector::from_fn(n, |i, _| col_scale(i, problem.length));
        let q0 = total_force(&work, &layout, &state, &data.steps[k].loads)?.component_mul(&scale);
        let mut c = DMatrix::zeros(n, lins.len());
        for (j, lin) in lins.iter().enumerate() {
            let col = match *lin {
                Lin::Plain(i) | Lin::SpringK { k: i } => {
                    column(&mut work, &layout, &state, &unknowns[i], 0.0)?
                }
                Lin::SpringKL0 { k, l0 } => {
                    unknowns[k].set(&mut work, 1.0);
                    let c = column(&mut work, &layout, &state, &unknowns[l0], 0.0);
                    unknowns[k].set(&mut work, 0.0);
                    c?
                }
            };
            c.set_column(j, &col.component_mul(&scale));
        }
        rows.push(-(l.transpose() * q0));
        cols_per_step.push(l.transpose() * c);
    }
    let m: usize = rows.iter().map(|r| r.len()).sum();
    let mut a = DMatrix::zeros(m, lins.len());
    let mut b = DVector::zeros(m);
    let mut at = 0;
    for (r, c) in rows.iter().zip(&cols_per_step) {
        a.view_mut((at, 0), (r.len(), lins.len())).copy_from(c);
        b.rows_mut(at, r.len()).copy_from(r);
        at += r.len();
    }
    Ok(Stacked { a, b })
}

/// Identifies the unknowns from measured equilibria (every moving part measured).
pub fn identify(
    model: &Model,
    unknowns: &[Unknown],
    data: &Measured,
    opts: DirectOptions,
) -> Result<Identified, IdentifyError> {
    if let Some(p) = data.missing_part(model) {
        return Err(unmeasured(model, p, "direct"));
    }
    if let Some(u) = unknowns.iter().find(|u| !is_affine(model, u)) {
        return Err(IdentifyError::of(
            IdentifyErrorKind::Method,
            format!(
                "the direct method needs equilibrium equations linear in the unknowns, and `{}` moves the geometry; use --method lsq",
                u.label()
            ),
            vec![u.element()],
        ));
    }
    let lins = linear_unknowns(unknowns);
    let st = stack(model, unknowns, &lins, data)?;
    let (m, nl) = (st.a.nrows(), st.a.ncols());
    if m == 0 {
        return Err(IdentifyError::of(
            IdentifyErrorKind::Undetermined,
            "the mechanism has no admissible motion, so its equilibria say nothing about the stiffnesses",
            vec![],
        ));
    }
    // Column scaling by the initial values: a column then measures how much a
    // relative change of its unknown changes the equations, so an axis the data
    // hardly deform (1e-12 mm of rounding) stays negligible instead of being
    // blown up to unit norm. Unknowns without a usable initial value fall back
    // to unit column norm.
    let init = |l: &Lin| match *l {
        Lin::Plain(i) | Lin::SpringK { k: i } => unknowns[i].initial,
        Lin::SpringKL0 { k, l0 } => unknowns[k].initial * unknowns[l0].initial,
    };
    let cn: Vec<f64> = lins
        .iter()
        .enumerate()
        .map(|(j, l)| {
            let v0 = init(l).abs();
            let norm = st.a.column(j).norm();
            if v0.is_finite() && v0 > 0.0 {
                1.0 / v0
            } else if norm > 0.0 {
                norm
            } else {
                1.0
            }
        })
        .collect();
    let a_s = DMatrix::from_fn(m, nl, |i, j| st.a[(i, j)] / cn[j]);
    let d = svd(&a_s, m < nl).ok_or_else(|| {
        IdentifyError::of(
            IdentifyErrorKind::Numeric,
            "the identification matrix is not finite (bad measured poses?)",
            vec![],
        )
    })?;
    let r = rank(&d.s, opts.rank_tol);
    let z = truncated_solve(&d, &st.b, r);
    let y: Vec<f64> = (0..nl).map(|j| z[j] / cn[j]).collect();
    let null = d.v.columns(r, d.v.ncols() - r).into_owned();
    // Covariance from the residual (zero for exact synthetic data).
    let res = &a_s * &z - &st.b;
    let dof = m.saturating_sub(r);
    let s2 = if dof > 0 {
        res.norm_squared() / dof as f64
    } else {
        0.0
    };
    let mut cov_z = DMatrix::zeros(nl, nl);
    for k in 0..r {
        let v = d.v.column(k);
        cov_z += v * v.transpose() * (s2 / (d.s[k] * d.s[k]));
    }
    let cov = |i: usize, j: usize| cov_z[(i, j)] / (cn[i] * cn[j]);

    // Names, boundary factors and units of the linear unknowns.
    let lin_name = |l: &Lin| match *l {
        Lin::Plain(i) | Lin::SpringK { k: i } => unknowns[i].label(),
        Lin::SpringKL0 { k, l0 } => format!("{}*{}", unknowns[k].label(), unknowns[l0].label()),
    };
    let factor = |l: &Lin| match *l {
        Lin::Plain(i) | Lin::SpringK { k: i } => unknowns[i].dim.boundary_factor(),
        Lin::SpringKL0 { .. } => 1.0,
    };
    let unit = |l: &Lin| match *l {
        Lin::Plain(i) | Lin::SpringK { k: i } => unknowns[i].dim.boundary_unit(),
        Lin::SpringKL0 { .. } => "N".to_string(),
    };
    let names: Vec<String> = lins.iter().map(lin_name).collect();
    let units: Vec<String> = lins.iter().map(unit).collect();
    let scale: Vec<f64> = lins
        .iter()
        .enumerate()
        .map(|(j, l)| cn[j] * factor(l))
        .collect();
    let yb: Vec<f64> = lins
        .iter()
        .enumerate()
        .map(|(j, l)| y[j] / factor(l))
        .collect();
    let det = determine(&null, &scale, &yb, &names, &units);

    let mut params: Vec<ParamResult> = unknowns
        .iter()
        .map(|u| ParamResult {
            initial: u.initial,
            value: None,
            interval: None,
            identifiable: false,
            notes: Vec::new(),
            bound: None,
        })
        .collect();
    let why_not = |j: usize| -> ParamNote {
        match det.groups.iter().find(|g| g.contains(&j)) {
            Some(g) if g.len() > 1 => ParamNote::OnlyCombined {
                with: g
                    .iter()
                    .filter(|&&o| o != j)
                    .map(|&o| names[o].clone())
                    .collect(),
            },
            _ if st.a.column(j).norm() == 0.0 => ParamNote::NotDeformed,
            _ => ParamNote::NoEffect,
        }
    };
    for (j, lin) in lins.iter().enumerate() {
        let (i, v, var) = match *lin {
            Lin::Plain(i) | Lin::SpringK { k: i } => (i, y[j], cov(j, j)),
            Lin::SpringKL0 { k, l0 } => {
                // L0 = (k·L0) / k, by the delta method; needs k determined too.
                let jk = lins
                    .iter()
                    .position(|l| *l == Lin::SpringK { k })
                    .unwrap_or(j);
                if !det.determined[jk] {
                    params[l0].notes = vec![why_not(jk)];
                    continue;
                }
                let (kv, kl) = (y[jk], y[j]);
                let l = kl / kv;
                let var = (cov(j, j) - 2.0 * l * cov(j, jk) + l * l * cov(jk, jk)) / (kv * kv);
                (l0, l, var)
            }
        };
        let p = &mut params[i];
        if !det.determined[j] {
            p.notes = vec![why_not(j)];
            continue;
        }
        if !v.is_finite() {
            p.notes = vec![ParamNote::NotFinite];
            continue;
        }
        let half = 1.96 * var.max(0.0).sqrt();
        if unknowns[i].is_stiffness() && v <= 0.0 {
            p.notes = vec![ParamNote::NotPositive {
                value: crate::units::to_boundary(v, unknowns[i].dim),
            }];
            continue;
        }
        if half > 0.5 * v.abs() && unknowns[i].is_stiffness() {
            p.notes = vec![ParamNote::Imprecise {
                half_width_percent: 100.0 * half / v.abs(),
            }];
            continue;
        }
        p.value = Some(v);
        p.identifiable = true;
        p.interval = Some((v - half, v + half));
    }
    let notes = vec![FitNote::DirectSize {
        steps: data.steps.len(),
        equations: m,
        per_step: m / data.steps.len().max(1),
        unknowns: nl,
        rank: r,
    }];
    let mut out = Identified {
        method: Method::Direct,
        unknowns: unknowns.to_vec(),
        params,
        combinations: det.combinations,
        rank: r,
        singular_values: d.s.clone(),
        iterations: 1,
        history: Vec::new(),
        correlation: None,
        sigma0: if dof > 0 { Some(s2.sqrt()) } else { None },
        notes,
    };
    super::flag_outside_bounds(&mut out);
    Ok(out)
}
