//! Least-squares identification (beyond the thesis): Levenberg–Marquardt over
//! any unknowns (stiffnesses, spring k and free length, joint coordinates,
//! declared parameters) against every observation at once: the measured
//! landmark positions (through the fitted part poses) and, when given, the K&C
//! channels, each weighted by its noise.
//!
//! Sensitivities are exact: at an equilibrium `R(q, λ, p) = 0`, so
//! `d(q, λ)/dp = -KKT⁻¹ ∂R/∂p` with the statics engine's own Newton matrix;
//! `∂R/∂p` of a stiffness is the element's force column (linear in it), and of
//! a geometric parameter a difference of the residual at the fixed state (no
//! re-solve). Stiffnesses are searched in log space, so they stay positive and
//! their intervals are multiplicative.

use super::columns::{column, is_affine};
use super::linalg::{solve, svd};
use super::measured::Measured;
use super::{Identified, IdentifyError, Method, ParamResult, Unknown};
use crate::geom::{Mat3, Vec3, skew};
use crate::model::{Model, values};
use crate::statics::newton::{assemble, col_scale, kkt};
use crate::statics::{self, Problem, State};
use nalgebra::{DMatrix, DVector};

#[derive(Debug, Clone, Copy)]
pub struct LsqOptions {
    /// Standard deviation of a landmark coordinate, mm.
    pub landmark_sigma: f64,
    /// Standard deviations of the K&C channels: angles (deg) and wheel centre (mm).
    pub angle_sigma: f64,
    pub wc_sigma: f64,
    pub max_iterations: usize,
    /// Stop when an accepted step lowers the cost (half the noise-weighted
    /// χ²) by less than this fraction of it. Below that the fit is the same
    /// within the noise and only sloppy, undetermined directions still drift
    /// (with every McPherson stiffness and the spring unknown, iterations 50
    /// to 100 lower the cost by 2e-5 of it in all).
    pub cost_tolerance: f64,
}

impl Default for LsqOptions {
    fn default() -> Self {
        LsqOptions {
            landmark_sigma: 0.05,
            angle_sigma: 0.01,
            wc_sigma: 0.05,
            max_iterations: 100,
            cost_tolerance: 1e-6,
        }
    }
}

/// How an unknown maps to the search variable.
fn is_log(u: &Unknown) -> bool {
    u.is_stiffness() && u.initial > 0.0
}

fn scale_of(u: &Unknown) -> f64 {
    u.initial.abs().max(1.0)
}

fn to_param(u: &Unknown, x: f64) -> f64 {
    if is_log(u) { x.exp() } else { x * scale_of(u) }
}

/// dp/dx.
fn dparam(u: &Unknown, x: f64) -> f64 {
    if is_log(u) { x.exp() } else { scale_of(u) }
}

/// One observation: a landmark of a part (design position) or a K&C channel.
#[derive(Clone, Copy)]
enum Obs {
    Landmark {
        part: usize,
        design: Vec3,
        target: Vec3,
    },
    Kc {
        channel: usize,
        target: f64,
    },
}

struct Problemset<'a> {
    model: &'a Model,
    unknowns: &'a [Unknown],
    data: &'a Measured,
    obs: Vec<Vec<Obs>>,
    opts: LsqOptions,
}

fn kc_value(model: &Model, st: &State, channel: usize) -> f64 {
    let q = crate::kc::wheel_quantities(model, st, &model.wheels[0]);
    match channel {
        0 => q.toe_deg,
        1 => q.camber_deg,
        c => q.center[c - 2],
    }
}

impl Problemset<'_> {
    fn sigma(&self, o: &Obs) -> f64 {
        match o {
            Obs::Landmark { .. } => self.opts.landmark_sigma,
            Obs::Kc { channel, .. } => {
                if *channel < 2 {
                    self.opts.angle_sigma
                } else {
                    self.opts.wc_sigma
                }
            }
        }
    }

    fn model_at(&self, x: &DVector<f64>) -> Model {
        let mut m = self.model.clone();
        for (u, xi) in self.unknowns.iter().zip(x.iter()) {
            u.set(&mut m, to_param(u, *xi));
        }
        m
    }

    /// Solves every step (warm started) and returns the weighted residuals.
    fn evaluate(
        &self,
        x: &DVector<f64>,
        warm: &[State],
    ) -> Result<(Problem, Vec<State>, DVector<f64>), IdentifyError> {
        let m = self.model_at(x);
        let problem =
            Problem::new(&m).map_err(|e| IdentifyError::new(e.message(&m), e.elements.clone()))?;
        let mut states = Vec::with_capacity(self.data.steps.len());
        let mut res = Vec::new();
        let mut prev = State::design(&m);
        for (k, s) in self.data.steps.iter().enumerate() {
            let start = warm.get(k).cloned().unwrap_or_else(|| prev.clone());
            let eq = statics::solve(&problem, &s.loads, &start).map_err(|e| {
                let names: Vec<String> = self
                    .unknowns
                    .iter()
                    .zip(x.iter())
                    .map(|(u, xi)| {
                        format!(
                            "{} = {:.4e}",
                            u.label(),
                            crate::units::to_boundary(to_param(u, *xi), u.dim)
                        )
                    })
                    .collect();
                IdentifyError::new(
                    format!(
                        "step {}: the model does not solve at the trial values ({}): {}",
                        s.step,
                        names.join(", "),
                        e.message(&m)
                    ),
                    e.elements.clone(),
                )
            })?;
            for o in &self.obs[k] {
                let w = 1.0 / self.sigma(o);
                match *o {
                    Obs::Landmark {
                        part,
                        design,
                        target,
                    } => {
                        let (t, r) = eq.state.part_pose(crate::model::PartId(part as u32));
                        let p = t + r * design;
                        for c in 0..3 {
                            res.push((p[c] - target[c]) * w);
                        }
                    }
                    Obs::Kc { channel, target } => {
                        res.push((kc_value(&m, &eq.state, channel) - target) * w)
                    }
                }
            }
            prev = eq.state.clone();
            states.push(eq.state);
        }
        Ok((problem, states, DVector::from_vec(res)))
    }

    /// The weighted Jacobian of the residuals in the search variables.
    fn jacobian(
        &self,
        x: &DVector<f64>,
        problem: &Problem,
        states: &[State],
    ) -> Result<DMatrix<f64>, IdentifyError> {
        let nu = self.unknowns.len();
        let n = problem.layout.n();
        let length = problem.length;
        let mut work = problem.model.clone();
        let mut rows: Vec<DVector<f64>> = Vec::new();
        let fail = |what: &str, step: usize| {
            IdentifyError::new(
                format!(
                    "step {step}: the equilibrium is singular, so its sensitivity to the unknowns is undefined ({what})"
                ),
                vec![],
            )
        };
        for (k, st) in states.iter().enumerate() {
            let step = self.data.steps[k].step;
            let loads = &self.data.steps[k].loads;
            let sys = assemble(problem, st, loads)
                .map_err(|e| IdentifyError::new(e.message(&work), e.elements.clone()))?;
            let a = kkt(&sys);
            let m = sys.jac.nrows();
            let mut b = DMatrix::zeros(n + m, nu);
            for (i, u) in self.unknowns.iter().enumerate() {
                let dp = dparam(u, x[i]);
                if is_affine(&work, u) {
                    let p = to_param(u, x[i]);
                    let c = column(&mut work, &problem.layout, st, u, p)?;
                    for r in 0..n {
                        b[(r, i)] = -c[r] * col_scale(r, length) * dp;
                    }
                } else {
                    // Geometry moves: central difference of the residual at this state.
                    let h = 1e-4 * scale_of(u).max(1.0);
                    let p = to_param(u, x[i]);
                    let at = |v: f64| -> Result<(DVector<f64>, DVector<f64>), IdentifyError> {
                        let mut mm = problem.model.clone();
                        u.set(&mut mm, v);
                        let pr = Problem::new(&mm)
                            .map_err(|e| IdentifyError::new(e.message(&mm), e.elements.clone()))?;
                        if pr.kept != problem.kept {
                            return Err(fail(
                                "the redundant constraints change with the parameter",
                                step,
                            ));
                        }
                        let s = assemble(&pr, st, loads)
                            .map_err(|e| IdentifyError::new(e.message(&mm), e.elements.clone()))?;
                        Ok((s.r, s.phi))
                    };
                    let (rp, pp) = at(p + h)?;
                    let (rm, pm) = at(p - h)?;
                    for r in 0..n {
                        b[(r, i)] = -(rp[r] - rm[r]) / (2.0 * h) * dp;
                    }
                    for r in 0..m {
                        b[(n + r, i)] = -(pp[r] - pm[r]) / (2.0 * h) * dp;
                    }
                }
            }
            let sol = solve(&a, &b).ok_or_else(|| fail("singular Newton matrix", step))?;
            // dq for each unknown, unscaled.
            let dq = DMatrix::from_fn(n, nu, |r, c| sol[(r, c)] * col_scale(r, length));
            for o in &self.obs[k] {
                let w = 1.0 / self.sigma(o);
                match *o {
                    Obs::Landmark { part, design, .. } => {
                        let Some(blk) = problem.layout.block_of_part[part] else {
                            for _ in 0..3 {
                                rows.push(DVector::zeros(nu));
                            }
                            continue;
                        };
                        let (_, rot) = st.part_pose(crate::model::PartId(part as u32));
                        let arm = rot * design;
                        let g: Mat3 = -skew(&arm);
                        for c in 0..3 {
                            let mut row = DVector::zeros(nu);
                            for i in 0..nu {
                                let mut v = dq[(6 * blk + c, i)];
                                for a in 0..3 {
                                    v += g[(c, a)] * dq[(6 * blk + 3 + a, i)];
                                }
                                row[i] = v * w;
                            }
                            rows.push(row);
                        }
                    }
                    Obs::Kc { channel, .. } => {
                        // Explicit function of the state: difference along each motion.
                        let mut row = DVector::zeros(nu);
                        for i in 0..nu {
                            let h = 1e-6 / dq.column(i).amax().max(1e-300);
                            let mut sp = st.clone();
                            let mut sm = st.clone();
                            let d = DVector::from_fn(n, |r, _| dq[(r, i)] * h);
                            sp.apply(&problem.layout, &d);
                            sm.apply(&problem.layout, &(-d));
                            let v = (kc_value(&work, &sp, channel) - kc_value(&work, &sm, channel))
                                / (2.0 * h);
                            row[i] = if v.is_finite() { v * w } else { 0.0 };
                        }
                        rows.push(row);
                    }
                }
            }
        }
        let mut j = DMatrix::zeros(rows.len(), nu);
        for (r, row) in rows.iter().enumerate() {
            j.set_row(r, &row.transpose());
        }
        Ok(j)
    }
}

pub fn identify(
    model: &Model,
    unknowns: &[Unknown],
    data: &Measured,
    opts: LsqOptions,
) -> Result<Identified, IdentifyError> {
    let ground = model.ground();
    let mut obs: Vec<Vec<Obs>> = Vec::new();
    let mut n_eff = 0usize;
    for s in &data.steps {
        let mut o = Vec::new();
        for (p, pose) in s.poses.iter().enumerate() {
            let Some((t, r)) = pose else { continue };
            if Some(crate::model::PartId(p as u32)) == ground {
                continue;
            }
            let mut any = false;
            for l in model.landmarks.iter().filter(|l| l.part.index() == p) {
                let design = values(&l.position);
                o.push(Obs::Landmark {
                    part: p,
                    design,
                    target: t + r * design,
                });
                any = true;
            }
            if any {
                n_eff += 6;
            }
        }
        if let (Some(kc), false) = (s.kc, model.wheels.is_empty()) {
            for (c, v) in [kc.toe_deg, kc.camber_deg, kc.wc.x, kc.wc.y, kc.wc.z]
                .into_iter()
                .enumerate()
            {
                o.push(Obs::Kc {
                    channel: c,
                    target: v,
                });
                n_eff += 1;
            }
        }
        obs.push(o);
    }
    let nu = unknowns.len();
    if n_eff <= nu {
        return Err(IdentifyError::new(
            format!("{n_eff} independent observations cannot determine {nu} unknowns"),
            vec![],
        ));
    }
    let ps = Problemset {
        model,
        unknowns,
        data,
        obs,
        opts,
    };
    let x0 = DVector::from_fn(nu, |i, _| {
        let u = &unknowns[i];
        if is_log(u) {
            u.initial.ln()
        } else {
            u.initial / scale_of(u)
        }
    });
    let (mut problem, mut states, mut r) = ps.evaluate(&x0, &[])?;
    let mut x = x0.clone();
    let mut cost = 0.5 * r.norm_squared();
    let mut mu = 1e-3;
    let mut iterations = 0;
    let mut jac = ps.jacobian(&x, &problem, &states)?;
    for it in 1..=opts.max_iterations {
        iterations = it;
        let g = jac.transpose() * &r;
        let h = jac.transpose() * &jac;
        let mut accepted = false;
        let mut small_step = false;
        for _ in 0..12 {
            let mut a = h.clone();
            for i in 0..nu {
                a[(i, i)] += mu * h[(i, i)].max(1e-12 * h.diagonal().amax()).max(1e-300);
            }
            let Some(step) = solve(&a, &DMatrix::from_column_slice(nu, 1, (-&g).as_slice())) else {
                mu *= 10.0;
                continue;
            };
            let mut step = step.column(0).into_owned();
            // A box trust region of a factor e per stiffness (one unit in the
            // scaled variables): nearly free directions would otherwise take
            // steps the statics cannot follow.
            for v in step.iter_mut() {
                *v = v.clamp(-1.0, 1.0);
            }
            // Keep stiffnesses within six decades of where they started.
            let xt = DVector::from_fn(nu, |i, _| {
                let v = x[i] + step[i];
                if is_log(&unknowns[i]) {
                    v.clamp(x0[i] - 14.0, x0[i] + 14.0)
                } else {
                    v
                }
            });
            if (&xt - &x).amax() < 1e-10 {
                small_step = true;
                break;
            }
            match ps.evaluate(&xt, &states) {
                Ok((p2, s2, r2))
                    if r2.iter().all(|v| v.is_finite()) && 0.5 * r2.norm_squared() < cost =>
                {
                    let c2 = 0.5 * r2.norm_squared();
                    let rel_drop = (cost - c2) / cost.max(1e-300);
                    x = xt;
                    problem = p2;
                    states = s2;
                    r = r2;
                    cost = c2;
                    mu = (mu / 10.0).max(1e-12);
                    accepted = true;
                    small_step = rel_drop < opts.cost_tolerance;
                    break;
                }
                _ => mu *= 10.0,
            }
        }
        if !accepted || small_step {
            break;
        }
        jac = ps.jacobian(&x, &problem, &states)?;
    }
    // Statistics at the solution.
    let dof = n_eff - nu;
    let s0 = (2.0 * cost / dof as f64).sqrt();
    let d = svd(&jac, nu > jac.nrows())
        .ok_or_else(|| IdentifyError::new("the Jacobian is not finite", vec![]))?;
    let smax = d.s.first().copied().unwrap_or(0.0);
    let rnk = d.s.iter().filter(|&&s| s > 1e-10 * smax).count();
    let factor = s0.max(1.0).powi(2);
    let mut cov = DMatrix::zeros(nu, nu);
    for k in 0..rnk {
        let v = d.v.column(k);
        cov += v * v.transpose() * (factor / (d.s[k] * d.s[k]));
    }
    let null = d.v.columns(rnk, d.v.ncols() - rnk).into_owned();
    let mut params = Vec::with_capacity(nu);
    for (i, u) in unknowns.iter().enumerate() {
        let p = to_param(u, x[i]);
        let in_null = null.nrows() > 0 && null.ncols() > 0 && null.row(i).norm() > 1e-3;
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
            note: if identifiable {
                None
            } else if in_null {
                Some("not identifiable: it does not affect the observations".into())
            } else {
                Some(format!(
                    "not identifiable from these data: its 95 % interval spans a factor {:.2} (fitted {:.4e})",
                    (1.0 + relw.min(1e12)),
                    crate::units::to_boundary(p, u.dim)
                ))
            },
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
    Ok(Identified {
        method: Method::Lsq,
        unknowns: unknowns.to_vec(),
        params,
        combinations: Vec::new(),
        rank: rnk,
        singular_values: d.s.clone(),
        iterations,
        history: Vec::new(),
        correlation: Some(correlation),
        sigma0: Some(s0),
        notes: vec![format!(
            "{n_eff} independent observations (6 per fitted pose, 1 per K&C channel), {nu} unknowns; a posteriori sigma factor {s0:.3}"
        )],
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The implicit-function Jacobian equals a central difference of the
    /// whole simulation (landmark residuals), for stiffnesses, the spring and
    /// a joint coordinate.
    #[test]
    fn sensitivities_match_finite_differences_of_the_simulation() {
        let (_, c) =
            crate::check::check_str("m.axle", include_str!("../../examples/mcpherson.axle"));
        let m = c.model.expect("checks");
        let set = m.load_set_named("thesis_table_5_1").expect("set");
        let eqs = statics::solve_set(&m, set).expect("solves");
        let steps: Vec<(State, Vec<_>)> = eqs
            .into_iter()
            .enumerate()
            .take(7)
            .map(|(k, e)| (e.state, m.point_loads(set, k)))
            .collect();
        let data = Measured::from_states(&m, &steps);
        let names: Vec<String> = [
            "A.k_x",
            "B.k_x",
            "B.kt_z",
            "spring.k",
            "spring.free_length",
            "L7.z",
        ]
        .map(String::from)
        .to_vec();
        let u = super::super::select_unknowns(&m, &names).expect("unknowns");
        let ps = Problemset {
            model: &m,
            unknowns: &u,
            data: &data,
            obs: data
                .steps
                .iter()
                .map(|s| {
                    m.landmarks
                        .iter()
                        .filter(|l| !m.part(l.part).ground)
                        .map(|l| {
                            let (t, r) = s.poses[l.part.index()].expect("pose");
                            let d = values(&l.position);
                            Obs::Landmark {
                                part: l.part.index(),
                                design: d,
                                target: t + r * d,
                            }
                        })
                        .collect()
                })
                .collect(),
            opts: LsqOptions::default(),
        };
        let x = DVector::from_fn(u.len(), |i, _| {
            if is_log(&u[i]) {
                u[i].initial.ln()
            } else {
                u[i].initial / scale_of(&u[i])
            }
        });
        let (p, st, _) = ps.evaluate(&x, &[]).expect("solves");
        let j = ps.jacobian(&x, &p, &st).expect("jacobian");
        for i in 0..u.len() {
            let h = 1e-5;
            let mut xp = x.clone();
            xp[i] += h;
            let mut xm = x.clone();
            xm[i] -= h;
            let (_, _, rp) = ps.evaluate(&xp, &st).expect("solves");
            let (_, _, rm) = ps.evaluate(&xm, &st).expect("solves");
            let fd = (rp - rm) / (2.0 * h);
            let err = (&fd - j.column(i)).amax();
            assert!(
                err < 1e-4 * (1.0 + fd.amax()),
                "{}: err {err}, scale {}",
                u[i].label(),
                fd.amax()
            );
        }
    }
}
