//! Linearised compliance at an equilibrium: how a marker moves under a small
//! extra wrench, from the same Newton matrix (constraints included).

use super::assembly::{assemble, col_scale};
use super::coords::marker_kin;
use super::error::{StaticsError, StaticsErrorKind};
use super::forces::point_load;
use super::newton::{kkt, solve_dense};
use super::{Equilibrium, Problem};
use crate::geom::Vec3;
use crate::model::{ElementId, MarkerId, PointLoad};
use nalgebra::DVector;

/// The 6×6 compliance of a marker at an equilibrium: column `c` is the marker's
/// displacement (mm) and rotation (rad), global, under a unit global force
/// (`c < 3`, N) or torque (`c >= 3`, N·mm) at its origin. Rows
/// `[dx, dy, dz, rx, ry, rz]`. A marker on ground has zero compliance.
pub fn compliance(
    problem: &Problem,
    eq: &Equilibrium,
    marker: MarkerId,
) -> Result<[[f64; 6]; 6], StaticsError> {
    let p = problem;
    if marker.index() >= p.model.markers.len() {
        return Err(StaticsError::new(
            StaticsErrorKind::BadInput,
            vec![],
            "compliance of a marker the model does not have",
        ));
    }
    let st = &eq.state;
    let sys = assemble(p, st, &st.loads)?;
    let a = kkt(&sys);
    let (n, m) = (sys.k.nrows(), sys.jac.nrows());
    let mk = marker_kin(&p.model, &p.layout, st, marker);
    let mut out = [[0.0; 6]; 6];
    let Some(block) = mk.block else {
        return Ok(out);
    };
    for c in 0..6 {
        let mut unit = PointLoad {
            marker,
            force: Vec3::zeros(),
            torque: Vec3::zeros(),
        };
        if c < 3 {
            unit.force[c] = 1.0;
        } else {
            unit.torque[c - 3] = 1.0;
        }
        let mut dq_ext = DVector::zeros(n);
        if let Some(w) = point_load(&p.model, &p.layout, st, &unit) {
            w.add_force(&mut dq_ext);
        }
        let mut b = DVector::zeros(n + m);
        for i in 0..n {
            b[i] = -dq_ext[i] * col_scale(i, p.length);
        }
        let Some(x) = solve_dense(&a, &b) else {
            return Err(StaticsError::new(
                StaticsErrorKind::Unrestrained,
                vec![ElementId::Marker(marker)],
                "the linearised system is singular at this equilibrium, so the compliance is unbounded",
            ));
        };
        let o = 6 * block;
        let dx = Vec3::new(x[o], x[o + 1], x[o + 2]);
        let th = Vec3::new(x[o + 3], x[o + 4], x[o + 5]) * col_scale(3, p.length);
        let dp = dx + th.cross(&mk.r);
        for r in 0..3 {
            out[r][c] = dp[r];
            out[r + 3][c] = th[r];
        }
    }
    Ok(out)
}
