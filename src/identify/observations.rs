//! The least-squares observation model: at the equilibria solved with the
//! current unknowns, the noise-weighted residuals of every landmark (moving
//! parts against their registered measurements, the ground's against the
//! registration) and K&C channel, and their exact Jacobian in the search
//! variables.
//!
//! The sensitivities of the equilibria come from the statics service
//! ([`crate::statics::sensitivity`]: implicit differentiation with each
//! step's own factorisation, computed along the path as it is solved); the
//! chain rule to the search variables and the registration's columns
//! (analytic) are here. Force unknowns are set in place in one compiled
//! problem; only geometric unknowns recompile it.

use super::lsq::{LsqOptions, dparam, to_param};
use super::measured::Measured;
use super::{IdentifyError, Unknown};
use crate::geom::{Mat3, Vec3, skew};
use crate::model::{Model, PointLoad, WheelId, values};
use crate::statics::path::Simulator;
use crate::statics::{CaseSensitivity, Parameter, Problem, State, StaticsError};
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
    Ground { design: Vec3, target: Vec3 },
    /// A K&C channel of one wheel: 0 toe, 1 camber, 2-4 the centre's x, y, z.
    Kc {
        wheel: WheelId,
        channel: usize,
        target: f64,
    },
}

/// The simulation at one point of the search: the compiled problem, the
/// equilibrium of every step, the weighted residuals and each step's
/// sensitivity to the unknowns.
pub(super) struct Evaluation {
    pub problem: Problem,
    pub states: Vec<State>,
    pub residuals: DVector<f64>,
    pub sensitivities: Vec<CaseSensitivity>,
}

pub(super) struct Problemset<'a> {
    pub model: &'a Model,
    /// `model` compiled once; the unknowns are set in it in place.
    pub base: Problem,
    pub unknowns: &'a [Unknown],
    pub data: &'a Measured,
    pub obs: Vec<Vec<Obs>>,
    pub opts: LsqOptions,
    /// Nuisance variables after the unknowns: [`REG`] when the measurements
    /// were registered through the ground's landmarks, else 0.
    pub nr: usize,
}

fn kc_value(model: &Model, st: &State, wheel: WheelId, channel: usize) -> f64 {
    let q = crate::kc::wheel_quantities(model, st, &model.wheels[wheel.index()]);
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

    /// The compiled problem at `x`: the base problem with the unknowns set
    /// in place (the constraint analysis is not compiled again), or a
    /// recompiled one when an unknown moves geometry.
    fn problem_at(&self, x: &DVector<f64>) -> Result<Problem, IdentifyError> {
        let err = |m: &Model, e: StaticsError| IdentifyError::statics("", e, m);
        if self.unknowns.iter().any(|u| u.moves_geometry(self.model)) {
            let mut m = self.model.clone();
            for (u, xi) in self.unknowns.iter().zip(x.iter()) {
                u.set(&mut m, to_param(u, *xi));
            }
            return Problem::new(&m).map_err(|e| err(&m, e));
        }
        let mut p = self.base.clone();
        for (u, xi) in self.unknowns.iter().zip(x.iter()) {
            p.set_force_parameter(u, to_param(u, *xi))
                .map_err(|e| err(self.model, e))?;
        }
        Ok(p)
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

    /// Solves every step (warm started) and returns the weighted residuals,
    /// with each step's sensitivity to the unknowns (per internal unit).
    pub fn evaluate(&self, x: &DVector<f64>, warm: &[State]) -> Result<Evaluation, IdentifyError> {
        let (rr, rt) = self.correction(x);
        let problem = self.problem_at(x)?;
        let m = problem.model().clone();
        let loads: Vec<&[PointLoad]> = self.data.steps.iter().map(|s| s.loads.as_slice()).collect();
        // Each step starts from `warm[k]` when given (the previous iterate's
        // solution at that step); the history follows the path.
        let (run, sens) = Simulator::new().run_with_sensitivities(
            &problem,
            &loads,
            &State::design(&m),
            warm,
            self.unknowns,
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
            return Err(IdentifyError::statics(
                format!(
                    "step {}: the model does not solve at the trial values ({})",
                    self.data.steps[e.case].step,
                    names.join(", "),
                ),
                e.error,
                &m,
            ));
        }
        let sens = sens.map_err(|e| {
            IdentifyError::statics(
                format!("step {}", self.data.steps.get(e.case).map_or(0, |s| s.step)),
                e.error,
                &m,
            )
        })?;
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
                    Obs::Kc {
                        wheel,
                        channel,
                        target,
                    } => res.push((kc_value(&m, st, wheel, channel) - target) * w),
                }
            }
        }
        Ok(Evaluation {
            problem,
            states,
            residuals: DVector::from_vec(res),
            sensitivities: sens,
        })
    }

    /// The weighted Jacobian of the residuals in the search variables (the
    /// unknowns, then the registration's) at an evaluation.
    pub fn jacobian(&self, x: &DVector<f64>, ev: &Evaluation) -> DMatrix<f64> {
        let nu = self.unknowns.len();
        let nx = nu + self.nr;
        let model = ev.problem.model();
        let reg_x = &x.as_slice()[nu..nx];
        // d(parameter)/d(search variable) of each unknown.
        let dp: Vec<f64> = self
            .unknowns
            .iter()
            .zip(x.iter())
            .map(|(u, xi)| dparam(u, *xi))
            .collect();
        let mut rows: Vec<DVector<f64>> = Vec::new();
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
        for (k, (st, sens)) in ev.states.iter().zip(&ev.sensitivities).enumerate() {
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
                        let d = sens.point(st, crate::model::PartId(part as u32), &design);
                        for (c, row) in three.iter_mut().enumerate() {
                            for i in 0..nu {
                                row[i] = d[(c, i)] * dp[i] * w;
                            }
                        }
                        rows.extend(three);
                    }
                    Obs::Ground { target, .. } => {
                        let mut three = vec![DVector::zeros(nx); 3];
                        reg_rows(&target, w, &mut three);
                        rows.extend(three);
                    }
                    Obs::Kc { wheel, channel, .. } => {
                        // An explicit function of the state: its derivative along each motion.
                        let d =
                            sens.output(&ev.problem, st, |s| kc_value(model, s, wheel, channel));
                        let mut row = DVector::zeros(nx);
                        for i in 0..nu {
                            row[i] = if d[i].is_finite() {
                                d[i] * dp[i] * w
                            } else {
                                0.0
                            };
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
        j
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
        for kc in &s.kc {
            for (c, v) in [kc.toe_deg, kc.camber_deg, kc.wc.x, kc.wc.y, kc.wc.z]
                .into_iter()
                .enumerate()
            {
                o.push(Obs::Kc {
                    wheel: kc.wheel,
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
            base: Problem::new(&m).expect("compiles"),
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
        let ev = ps.evaluate(&x, &[]).expect("solves");
        let j = ps.jacobian(&x, &ev);
        let st = &ev.states;
        for i in 0..u.len() + REG {
            let h = 1e-5;
            let mut xp = x.clone();
            xp[i] += h;
            let mut xm = x.clone();
            xm[i] -= h;
            let rp = ps.evaluate(&xp, st).expect("solves").residuals;
            let rm = ps.evaluate(&xm, st).expect("solves").residuals;
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
