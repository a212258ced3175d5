//! Newton's method on `Q(q) + Phi_q^T λ = 0, Phi(q) = 0` for one load; called
//! by [`super::solve`], which sub-steps the load when this fails.
//!
//! The system is scaled before it is factorised: rotation increments are
//! multiplied by the characteristic length (so they read as mm at that radius),
//! moment rows divided by it, and constraint rows normalised. Steps are limited
//! (0.5 rad, one characteristic length) and damped by a backtracking line search
//! on the scaled residual norm.

use super::Problem;
use super::constraint::evaluate;
use super::coords::State;
use super::error::{StaticsError, StaticsErrorKind};
use super::forces::{element_wrenches, point_load};
use super::mobility::describe_motion;
use super::redundancy::scaled_jacobian;
use crate::model::{ElementId, PointLoad};
use nalgebra::{DMatrix, DVector};

/// Relative tolerance on the force residual (of the force scale) and on the
/// constraint residual (of the characteristic length).
pub const FORCE_TOL: f64 = 1e-10;
pub const CONSTRAINT_TOL: f64 = 1e-12;
const MAX_ITERATIONS: usize = 40;

/// The scaled residual and its derivative at one state.
pub(crate) struct System {
    /// `S (Q + Phi_q^T λ)`: forces (N) and moments divided by the length (N).
    pub r: DVector<f64>,
    /// `S K S` with `K` the derivative of the residual.
    pub k: DMatrix<f64>,
    /// Scaled Jacobian of the kept equations and their scaled values (mm).
    pub jac: DMatrix<f64>,
    pub phi: DVector<f64>,
    pub row_scale: Vec<f64>,
}

/// `diag(1, 1, 1, 1/L, 1/L, 1/L, ...)`: the scaling of coordinates and rows.
pub(crate) fn col_scale(c: usize, length: f64) -> f64 {
    if c % 6 >= 3 { 1.0 / length } else { 1.0 }
}

pub(crate) fn assemble(
    p: &Problem,
    st: &State,
    loads: &[PointLoad],
) -> Result<System, StaticsError> {
    let n = p.layout.n();
    let mut q = DVector::zeros(n);
    let mut k = DMatrix::zeros(n, n);
    for (_, w) in element_wrenches(&p.model, &p.layout, st)? {
        w.add_force(&mut q);
        w.add_tangent(&mut k);
    }
    for l in loads {
        if let Some(w) = point_load(&p.model, &p.layout, st, l) {
            w.add_force(&mut q);
            w.add_tangent(&mut k);
        }
    }
    for (idx, &e) in p.kept.iter().enumerate() {
        let lam = st.lambda.get(idx).copied().unwrap_or(0.0);
        let (_, w) = evaluate(&p.model, &p.layout, st, &p.equations[e]);
        let w = w.scaled(lam);
        w.add_force(&mut q);
        w.add_tangent(&mut k);
    }
    let sj = scaled_jacobian(&p.model, &p.layout, st, &p.equations, &p.kept, p.length);
    let l = p.length;
    let r = DVector::from_fn(n, |i, _| q[i] * col_scale(i, l));
    let k = DMatrix::from_fn(n, n, |i, j| k[(i, j)] * col_scale(i, l) * col_scale(j, l));
    Ok(System {
        r,
        k,
        jac: sj.jac,
        phi: sj.phi,
        row_scale: sj.row_scale,
    })
}

/// Scaled residual norms: force (of `force`) and constraint (of the length).
pub(crate) fn errors(p: &Problem, sys: &System, force: f64) -> (f64, f64) {
    (
        sys.r.amax() / force,
        if sys.phi.is_empty() {
            0.0
        } else {
            sys.phi.amax() / p.length
        },
    )
}

fn merit(p: &Problem, sys: &System, force: f64) -> f64 {
    (sys.r.norm() / force).powi(2)
        + if sys.phi.is_empty() {
            0.0
        } else {
            (sys.phi.norm() / p.length).powi(2)
        }
}

/// The part of the start state's residual not yet released: `(1 - s)` times the
/// residual (forces and constraints) the start state had under its own loads.
/// Subtracting it makes the start an exact equilibrium at `s = 0`, so sub-steps
/// also release internal preloads (a spring compressed at design), not only the
/// external loads; at `s = 1` it vanishes and the equilibrium is exact.
pub(crate) struct Homotopy {
    pub r0: DVector<f64>,
    pub phi0: DVector<f64>,
    pub remaining: f64,
}

impl Homotopy {
    fn apply(&self, mut sys: System) -> System {
        if self.remaining > 0.0 && self.r0.len() == sys.r.len() && self.phi0.len() == sys.phi.len()
        {
            sys.r -= &self.r0 * self.remaining;
            sys.phi -= &self.phi0 * self.remaining;
        }
        sys
    }
}

pub(crate) enum Failure {
    /// No point in sub-stepping: the model itself is at fault.
    Fatal(StaticsError),
    /// Newton stalled or ran out of iterations; a smaller load step may succeed.
    Stalled(State),
}

/// Newton from `st` to equilibrium under `loads`; returns the iterations used.
pub(crate) fn newton(
    p: &Problem,
    loads: &[PointLoad],
    st: &mut State,
    force: f64,
    homotopy: &Homotopy,
) -> Result<usize, Failure> {
    let n = p.layout.n();
    let m = p.kept.len();
    if st.lambda.len() != m {
        st.lambda = vec![0.0; m];
    }
    let fatal = Failure::Fatal;
    let mut sys = homotopy.apply(assemble(p, st, loads).map_err(fatal)?);
    for it in 0..MAX_ITERATIONS {
        let (ef, ec) = errors(p, &sys, force);
        if ef < FORCE_TOL && ec < CONSTRAINT_TOL {
            return Ok(it);
        }
        let a = kkt(&sys);
        let mut b = DVector::zeros(n + m);
        b.rows_mut(0, n).copy_from(&(-&sys.r));
        b.rows_mut(n, m).copy_from(&(-&sys.phi));
        let x = solve_dense(&a, &b);
        let suspicious = match &x {
            Some(x) => x.rows(0, n).amax() > 1e3 * p.length,
            None => true,
        };
        if suspicious {
            if let Some(e) = singular_direction(p, &a) {
                return Err(fatal(e));
            }
        }
        let Some(mut x) = x else {
            return Err(Failure::Stalled(st.clone()));
        };
        // Limit the step: 0.5 rad of rotation, one characteristic length of travel
        // (both are length-scaled here).
        let biggest = x.rows(0, n).amax();
        if biggest > 0.5 * p.length {
            x *= 0.5 * p.length / biggest;
        }
        let m0 = merit(p, &sys, force);
        let mut alpha = 1.0;
        let mut accepted = None;
        for _ in 0..12 {
            let mut trial = st.clone();
            let dq = DVector::from_fn(n, |i, _| alpha * x[i] * col_scale(i, p.length));
            trial.apply(&p.layout, &dq);
            for k in 0..m {
                trial.lambda[k] += alpha * x[n + k] / sys.row_scale[k];
            }
            if let Ok(ts) = assemble(p, &trial, loads).map(|t| homotopy.apply(t)) {
                let m1 = merit(p, &ts, force);
                if m1.is_finite() && m1 < (1.0 - 1e-4 * alpha) * m0 {
                    accepted = Some((trial, ts));
                    break;
                }
            }
            alpha *= 0.5;
        }
        match accepted {
            Some((t, s)) => {
                *st = t;
                sys = s;
            }
            None => {
                // Rounding floor: no decrease possible, but already nearly converged.
                if ef < 1e3 * FORCE_TOL && ec < 1e3 * CONSTRAINT_TOL {
                    return Ok(it);
                }
                return Err(Failure::Stalled(st.clone()));
            }
        }
    }
    Err(Failure::Stalled(st.clone()))
}

/// The scaled Newton matrix `[S K S, J^T; J, 0]`.
pub(crate) fn kkt(sys: &System) -> DMatrix<f64> {
    let (n, m) = (sys.k.nrows(), sys.jac.nrows());
    let mut a = DMatrix::zeros(n + m, n + m);
    a.view_mut((0, 0), (n, n)).copy_from(&sys.k);
    a.view_mut((0, n), (n, m)).copy_from(&sys.jac.transpose());
    a.view_mut((n, 0), (m, n)).copy_from(&sys.jac);
    a
}

/// Solves a dense square system by faer's LU; None if the result is not finite
/// or does not satisfy the system (faer does not report singular matrices).
pub(crate) fn solve_dense(a: &DMatrix<f64>, b: &DVector<f64>) -> Option<DVector<f64>> {
    let nn = a.nrows();
    let fa = faer::MatRef::from_column_major_slice(a.as_slice(), nn, nn);
    let fb = faer::MatRef::from_column_major_slice(b.as_slice(), nn, 1);
    let lu = fa.partial_piv_lu();
    let sol = faer::linalg::solvers::Solve::solve(&lu, fb);
    let x = DVector::from_fn(nn, |i, _| sol[(i, 0)]);
    if !x.iter().all(|v| v.is_finite()) {
        return None;
    }
    let res = (a * &x - b).amax();
    if res > 1e-8 * (b.amax() + a.amax() * x.amax()) {
        return None;
    }
    Some(x)
}

/// If the scaled Newton matrix is numerically singular, the unrestrained motion
/// as an error naming the part that moves most.
pub(crate) fn singular_direction(p: &Problem, a: &DMatrix<f64>) -> Option<StaticsError> {
    let (ratio, motion) = softest_motion(p, a)?;
    if ratio > 1e-12 {
        return None;
    }
    Some(StaticsError::new(
        StaticsErrorKind::Unrestrained,
        vec![ElementId::Part(motion.part)],
        format!(
            "the equilibrium equations are singular: nothing restrains the {}",
            motion.words
        ),
    ))
}

/// The softest motion of the scaled Newton matrix: its smallest singular value
/// relative to the largest, and the motion of its singular vector.
pub(crate) fn softest_motion(
    p: &Problem,
    a: &DMatrix<f64>,
) -> Option<(f64, super::mobility::Motion)> {
    let nn = a.nrows();
    let n = p.layout.n();
    let fa = faer::MatRef::from_column_major_slice(a.as_slice(), nn, nn);
    let svd = fa.svd().ok()?;
    let s = svd.S().column_vector();
    let smax = s[0];
    let smin = s[nn - 1];
    let v = svd.V();
    let dq = DVector::from_fn(n, |i, _| v[(i, nn - 1)] * col_scale(i, p.length));
    if !(smax > 0.0) || dq.iter().all(|x| *x == 0.0) {
        return None;
    }
    Some((
        smin / smax,
        describe_motion(&p.model, &p.layout, &dq, p.length),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::Vec3;
    use crate::statics::{State, solve};

    fn mcpherson() -> crate::model::Model {
        let (_, c) = crate::check::check_str(
            "mcpherson.axle",
            include_str!("../../examples/mcpherson.axle"),
        );
        c.model.expect("the example checks")
    }

    fn wheel_load(m: &crate::model::Model, fx: f64, fy: f64, fz: f64) -> Vec<PointLoad> {
        vec![PointLoad {
            marker: m.wheels[0].contact,
            force: Vec3::new(fx, fy, fz),
            torque: Vec3::zeros(),
        }]
    }

    /// The whole Newton matrix (elements, the moving load, the λ-weighted
    /// constraint curvature, the constraint Jacobian), scaled as Newton uses it,
    /// equals a central difference of the scaled residual, at a loaded McPherson
    /// state away from equilibrium (nonzero multipliers, bushings deflected).
    #[test]
    fn newton_matrix_equals_a_finite_difference_jacobian() {
        let m = mcpherson();
        let p = Problem::new(&m).expect("problem");
        let st = solve(&p, &wheel_load(&m, 0.0, 0.0, 1500.0), &State::design(&m))
            .expect("c1")
            .state;
        let loads = wheel_load(&m, 2000.0, -3000.0, 4500.0);
        let sys = assemble(&p, &st, &loads).expect("assembles");
        assert!(sys.r.amax() > 100.0, "away from equilibrium");
        let (n, nm) = (p.layout.n(), p.kept.len());
        let h = 1e-6;
        let (mut worst_k, mut worst_j) = (0.0f64, 0.0f64);
        for c in 0..n {
            let at = |s: f64| {
                let mut t = st.clone();
                let mut dq = DVector::zeros(n);
                dq[c] = s * col_scale(c, p.length);
                t.apply(&p.layout, &dq);
                let sy = assemble(&p, &t, &loads).expect("assembles");
                (sy.r, sy.phi)
            };
            let ((rp, pp), (rm, pm)) = (at(h), at(-h));
            let scale = 1.0 + sys.k.column(c).amax();
            for r in 0..n {
                let fd = (rp[r] - rm[r]) / (2.0 * h);
                worst_k = worst_k.max((fd - sys.k[(r, c)]).abs() / scale);
            }
            for r in 0..nm {
                // Rows have unit norm, so this error is relative.
                let fd = (pp[r] - pm[r]) / (2.0 * h);
                worst_j = worst_j.max((fd - sys.jac[(r, c)]).abs());
            }
        }
        eprintln!("Newton matrix vs central differences: K {worst_k:.1e}, J {worst_j:.1e}");
        assert!(worst_k < 1e-6 && worst_j < 1e-6, "{worst_k} {worst_j}");
    }
}
