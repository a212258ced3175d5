//! The scaled residual, stiffness and constraint Jacobian at one state as
//! dense matrices ([`assemble`]): what the analyses around the Newton loop
//! read (a failure's diagnosis, the compliance, the tests), evaluated by the
//! loop's own [`Workspace`]; the dense Newton matrix ([`kkt`]), its LU
//! ([`DenseLu`]) and its singular-value test ([`singular_direction`]).

use super::Problem;
use super::assembly::{Workspace, col_scale};
use super::coords::State;
use super::error::{StaticsError, StaticsErrorKind};
use super::mobility::describe_motion;
use crate::model::{ElementId, PointLoad};
use nalgebra::{DMatrix, DVector};

/// The scaled residual and its derivative at one state.
pub(crate) struct System {
    /// `S (Q + Phi_q^T λ)`: forces (N) and moments divided by the length (N).
    pub r: DVector<f64>,
    /// `S K S` with `K` the derivative of the residual.
    pub k: DMatrix<f64>,
    /// Scaled Jacobian of the kept equations and their scaled values (mm).
    pub jac: DMatrix<f64>,
    pub phi: DVector<f64>,
}

pub(crate) fn assemble(
    p: &Problem,
    st: &State,
    loads: &[PointLoad],
) -> Result<System, StaticsError> {
    let mut ws = Workspace::new(p);
    ws.eval(p, st, loads, true)?;
    let (n, m) = (p.layout.n(), p.kept.len());
    let a = ws.matrix();
    Ok(System {
        r: DVector::from_column_slice(&ws.r),
        k: a.view((0, 0), (n, n)).into_owned(),
        jac: a.view((n, 0), (m, n)).into_owned(),
        phi: DVector::from_column_slice(&ws.phi),
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

/// The scaled Newton matrix `[S K S, J^T; J, 0]`.
pub(crate) fn kkt(sys: &System) -> DMatrix<f64> {
    let (n, m) = (sys.k.nrows(), sys.jac.nrows());
    let mut a = DMatrix::zeros(n + m, n + m);
    a.view_mut((0, 0), (n, n)).copy_from(&sys.k);
    a.view_mut((0, n), (n, m)).copy_from(&sys.jac.transpose());
    a.view_mut((n, 0), (m, n)).copy_from(&sys.jac);
    a
}

/// A dense square matrix with faer's LU of it and its largest entry (found
/// once for every right-hand side [`DenseLu::solve`] checks).
pub(crate) struct DenseLu<'a> {
    a: &'a DMatrix<f64>,
    lu: faer::linalg::solvers::PartialPivLu<f64>,
    a_max: f64,
}

impl<'a> DenseLu<'a> {
    /// faer's LU of the dense square matrix `a`.
    pub fn new(a: &'a DMatrix<f64>) -> DenseLu<'a> {
        let nn = a.nrows();
        DenseLu {
            a,
            lu: faer::MatRef::from_column_major_slice(a.as_slice(), nn, nn).partial_piv_lu(),
            a_max: a.amax(),
        }
    }

    /// Solves `a x = b`; None if the result is not finite or does not
    /// satisfy the system (faer does not report singular matrices).
    pub fn solve(&self, b: &DVector<f64>) -> Option<DVector<f64>> {
        let nn = self.a.nrows();
        let fb = faer::MatRef::from_column_major_slice(b.as_slice(), nn, 1);
        let sol = faer::linalg::solvers::Solve::solve(&self.lu, fb);
        let x = DVector::from_fn(nn, |i, _| sol[(i, 0)]);
        if !x.iter().all(|v| v.is_finite()) {
            return None;
        }
        let res = (self.a * &x - b).amax();
        if res > 1e-8 * (b.amax() + self.a_max * x.amax()) {
            return None;
        }
        Some(x)
    }
}

/// If the scaled Newton matrix is numerically singular, the unrestrained motion
/// as an error naming the part that moves most. Judged on the matrix with its
/// multipliers weighed as the condition estimate weighs them
/// ([`super::condition`]), the estimate that decides when this test runs.
pub(crate) fn singular_direction(p: &Problem, a: &DMatrix<f64>) -> Option<StaticsError> {
    let (ratio, motion) = softest_motion(p, &super::condition::scaled(a, p.layout.n()))?;
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
