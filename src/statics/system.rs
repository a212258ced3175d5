//! The scaled residual, stiffness and constraint Jacobian at one state as
//! dense matrices ([`assemble`]): what the analyses around the Newton loop
//! read (a failure's diagnosis, the compliance, the tests), evaluated by the
//! loop's own [`Workspace`].

use super::Problem;
use super::assembly::Workspace;
use super::coords::State;
use super::error::StaticsError;
use crate::model::PointLoad;
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
