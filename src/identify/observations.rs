//! The least-squares observation model: at the equilibria solved with the
//! current unknowns, the noise-weighted residuals of every landmark (moving
//! parts against their registered measurements, the ground's against the
//! registration) and K&C channel, and their exact Jacobian in the search
//! variables.
//!
//! Sensitivities are exact: at an equilibrium `R(q, λ, p) = 0`, so
//! `d(q, λ)/dp = -KKT⁻¹ ∂R/∂p` with the statics engine's own Newton matrix;
//! `∂R/∂p` of a stiffness is the element's force column (linear in it), and of
//! a geometric parameter a difference of the residual at the fixed state (no
//! re-solve). The registration's columns are analytic.

use super::columns::{column, is_affine};
use super::linalg::solve;
use super::lsq::{LsqOptions, dparam, scale_of, to_param};
use super::measured::Measured;
use super::{IdentifyError, Unknown};
use crate::geom::{Mat3, Vec3, skew};
use crate::model::{Model, values};
use crate::statics::newton::{assemble, col_scale, kkt};
use crate::statics::path::Simulator;
use crate::statics::{Problem, State};
use nalgebra::{DMatrix, DVector};

/// The registration's search variables: a rotation vector in mrad and a
/// translation in mm, a correction applied to the registered measurements
/// (`R(ω) y + τ`). Milliradians keep its columns on the scale of the others
/// (a milliradian moves a point 1 m away by 1 mm).
pub(super) const REG: usize = 6;
const MRAD: f64 = 1e-3;

fn registration(x: &[f64]) -> (Mat3, Vec3) {
    let w = Vec3::new(x[0], x[1], x[2]) * MRAD;
    (
        nalgebra::Rotation3::new(w).into_inner(),
        Vec3::new(x[3], x[4], x[5]),
    )
}

/// d(R(ω) y + τ) / d(registration variables), 3 × 6: the rotation through
/// the left Jacobian of SO(3), exp(ω + dω) = exp(J_l(ω) dω) exp(ω).
fn registration_jacobian(x: &[f64], y: &Vec3) -> nalgebra::SMatrix<f64, 3, 6> {
    let w = Vec3::new(x[0], x[1], x[2]) * MRAD;
    let (r, _) = registration(x);
    let th = w.norm();
    let k = skew(&w);
    let jl = if th < 1e-8 {
        Mat3::identity() + 0.5 * k
    } else {
        Mat3::identity()
            + k * ((1.0 - th.cos()) / (th * th))
            + k * k * ((th - th.sin()) / (th * th * th))
    };
    let dw = -skew(&(r * y)) * jl * MRAD;
    let mut j = nalgebra::SMatrix::<f64, 3, 6>::zeros();
    j.fixed_view_mut::<3, 3>(0, 0).copy_from(&dw);
    j.fixed_view_mut::<3, 3>(0, 3).copy_from(&Mat3::identity());
    j
}

/// One observation: a landmark of a moving part or of the ground (design
/// position against its registered measurement), or a K&C channel.
#[derive(Clone, Copy)]
pub(super) enum Obs {
    Landmark {
        part: usize,
        design: Vec3,
        target: Vec3,
    },
    /// A ground landmark: it does not move, so it observes only the registration.
    Ground {
        design: Vec3,
        target: Vec3,
    },
    Kc {
        channel: usize,
        target: f64,
    },
}

pub(super) struct Problemset<'a> {
    pub model: &'a Model,
    pub unknowns: &'a [Unknown],
    pub data: &'a Measured,
    pub obs: Vec<Vec<Obs>>,
    pub opts: LsqOptions,
    /// Nuisance variables after the unknowns: [`REG`] when the measurements
    /// were registered through the ground's landmarks, else 0.
    pub nr: usize,
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
            Obs::Landmark { .. } | Obs::Ground { .. } => self.opts.landmark_sigma,
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

    /// The registration correction at `x` (identity without registration).
    pub fn correction(&self, x: &DVector<f64>) -> (Mat3, Vec3) {
        let nu = self.unknowns.len();
        if self.nr == REG {
            registration(&x.as_slice()[nu..nu + REG])
        } else {
            (Mat3::identity(), Vec3::zeros())
        }
    }

    /// Solves every step (warm started) and returns the weighted residuals.
    pub fn evaluate(
        &self,
        x: &DVector<f64>,
        warm: &[State],
    ) -> Result<(Problem, Vec<State>, DVector<f64>), IdentifyError> {
        let m = self.model_at(x);
        let (rr, rt) = self.correction(x);
        let problem =
            Problem::new(&m).map_err(|e| IdentifyError::new(e.message(&m), e.elements.clone()))?;
        // Each step starts from `warm[k]` when given (the previous iterate's
        // solution at that step); the history follows the path.
        let run = Simulator::new().run(
            &problem,
            self.data.steps.iter().map(|s| &s.loads),
            &State::design(&m),
            warm,
        );
        if let Some(e) = run.failure {
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
            return Err(IdentifyError::new(
                format!(
                    "step {}: the model does not solve at the trial values ({}): {}",
                    self.data.steps[e.case].step,
                    names.join(", "),
                    e.error.message(&m)
                ),
                e.error.elements.clone(),
            ));
        }
        let mut res = Vec::new();
        let states: Vec<State> = run.steps.into_iter().map(|e| e.state).collect();
        for (k, st) in states.iter().enumerate() {
            for o in &self.obs[k] {
                let w = 1.0 / self.sigma(o);
                match *o {
                    Obs::Landmark {
                        part,
                        design,
                        target,
                    } => {
                        let (t, r) = st.part_pose(crate::model::PartId(part as u32));
                        let p = t + r * design;
                        let y = rr * target + rt;
                        for c in 0..3 {
                            res.push((p[c] - y[c]) * w);
                        }
                    }
                    Obs::Ground { design, target } => {
                        let y = rr * target + rt;
                        for c in 0..3 {
                            res.push((design[c] - y[c]) * w);
                        }
                    }
                    Obs::Kc { channel, target } => {
                        res.push((kc_value(&m, st, channel) - target) * w)
                    }
                }
            }
        }
        Ok((problem, states, DVector::from_vec(res)))
    }

    /// The weighted Jacobian of the residuals in the search variables (the
    /// unknowns, then the registration's).
    pub fn jacobian(
        &self,
        x: &DVector<f64>,
        problem: &Problem,
        states: &[State],
    ) -> Result<DMatrix<f64>, IdentifyError> {
        let nu = self.unknowns.len();
        let nx = nu + self.nr;
        let n = problem.layout.n();
        let length = problem.length;
        let mut work = problem.model.clone();
        let mut rows: Vec<DVector<f64>> = Vec::new();
        let reg_x = &x.as_slice()[nu..nx];
        // The registration's three columns of one registered target.
        let reg_rows = |target: &Vec3, w: f64, rows: &mut [DVector<f64>]| {
            if self.nr == REG {
                let j = registration_jacobian(reg_x, target);
                for (c, row) in rows.iter_mut().enumerate() {
                    for a in 0..REG {
                        row[nu + a] = -j[(c, a)] * w;
                    }
                }
            }
        };
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
                    Obs::Landmark {
                        part,
                        design,
                        target,
                    } => {
                        let mut three = vec![DVector::zeros(nx); 3];
                        reg_rows(&target, w, &mut three);
                        if let Some(blk) = problem.layout.block_of_part[part] {
                            let (_, rot) = st.part_pose(crate::model::PartId(part as u32));
                            let arm = rot * design;
                            let g: Mat3 = -skew(&arm);
                            for (c, row) in three.iter_mut().enumerate() {
                                for i in 0..nu {
                                    let mut v = dq[(6 * blk + c, i)];
                                    for a in 0..3 {
                                        v += g[(c, a)] * dq[(6 * blk + 3 + a, i)];
                                    }
                                    row[i] = v * w;
                                }
                            }
                        }
                        rows.extend(three);
                    }
                    Obs::Ground { target, .. } => {
                        let mut three = vec![DVector::zeros(nx); 3];
                        reg_rows(&target, w, &mut three);
                        rows.extend(three);
                    }
                    Obs::Kc { channel, .. } => {
                        // Explicit function of the state: difference along each motion.
                        let mut row = DVector::zeros(nx);
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
        let mut j = DMatrix::zeros(rows.len(), nx);
        for (r, row) in rows.iter().enumerate() {
            j.set_row(r, &row.transpose());
        }
        Ok(j)
    }
}

/// The observations of every step, the number of independent ones (6 per
/// fitted pose, 1 per K&C channel) and whether the ground was measured (the
/// registration is then estimated with the unknowns).
pub(super) fn observations(model: &Model, data: &Measured) -> (Vec<Vec<Obs>>, usize, bool) {
    let ground = model.ground();
    let mut obs: Vec<Vec<Obs>> = Vec::new();
    let mut n_eff = 0usize;
    let mut registered = false;
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
        if let (Some(g), Some((t, r))) = (ground, s.ground) {
            let mut any = false;
            for l in model.landmarks.iter().filter(|l| l.part == g) {
                let design = values(&l.position);
                o.push(Obs::Ground {
                    design,
                    target: t + r * design,
                });
                any = true;
            }
            if any {
                n_eff += 6;
                registered = true;
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
    (obs, n_eff, registered)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::identify::lsq::to_search;

    /// The implicit-function Jacobian equals a central difference of the
    /// whole simulation (landmark residuals), for stiffnesses, the spring, a
    /// joint coordinate and the six registration variables.
    #[test]
    fn sensitivities_match_finite_differences_of_the_simulation() {
        let (_, c) =
            crate::check::check_str("m.axle", include_str!("../../examples/mcpherson.axle"));
        let m = c.model.expect("checks");
        let set = m.load_set_named("thesis_table_5_1").expect("set");
        let eqs = crate::statics::solve_set(&m, set).expect("solves");
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
        // Every landmark, the ground's too, with the registration estimated
        // (at a non-zero correction, so the rotation's Jacobian is tested away
        // from the identity).
        let g = m.ground().expect("ground");
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
                        .map(|l| {
                            let (t, r) = s.poses[l.part.index()].expect("pose");
                            let d = values(&l.position);
                            if l.part == g {
                                Obs::Ground {
                                    design: d,
                                    target: t + r * d + Vec3::new(0.01, -0.02, 0.005),
                                }
                            } else {
                                Obs::Landmark {
                                    part: l.part.index(),
                                    design: d,
                                    target: t + r * d,
                                }
                            }
                        })
                        .collect()
                })
                .collect(),
            opts: LsqOptions::default(),
            nr: REG,
        };
        let reg = [0.3, -0.2, 0.1, 0.05, -0.1, 0.02];
        let x = DVector::from_fn(u.len() + REG, |i, _| match u.get(i) {
            Some(ui) => to_search(ui, ui.initial),
            None => reg[i - u.len()],
        });
        let (p, st, _) = ps.evaluate(&x, &[]).expect("solves");
        let j = ps.jacobian(&x, &p, &st).expect("jacobian");
        for i in 0..u.len() + REG {
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
                u.get(i)
                    .map_or(format!("registration {}", i - u.len()), |x| x.label()),
                fd.amax()
            );
        }
    }
}
