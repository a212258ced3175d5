//! Linearised compliance at an equilibrium: how a marker moves under a small
//! extra wrench, from the same Newton matrix (constraints included).

use super::assembly::col_scale;
use super::coords::marker_kin;
use super::error::{StaticsError, StaticsErrorKind};
use super::forces::point_load;
use super::newton::{CONSTRAINT_TOL, FORCE_TOL};
use super::system::{DenseLu, assemble, kkt};
use super::{Equilibrium, Problem};
use crate::geom::Vec3;
use crate::model::{ElementId, MarkerId, PartId, PointLoad};
use nalgebra::DVector;

/// A marker's 6×6 compliance ([`compliance`]).
pub type Compliance = [[f64; 6]; 6];

/// The 6×6 compliance of a marker at an equilibrium: column `c` is the marker's
/// displacement (mm) and rotation (rad), global, under a unit global force
/// (`c < 3`, N) or torque (`c >= 3`, N·mm) at its origin. Rows
/// `[dx, dy, dz, rx, ry, rz]`. A marker on ground has zero compliance.
pub fn compliance(
    problem: &Problem,
    eq: &Equilibrium,
    marker: MarkerId,
) -> Result<Compliance, StaticsError> {
    compliances(problem, eq, &[marker])?
        .pop()
        .unwrap_or_else(|| Err(unknown_marker()))
}

/// The compliances ([`compliance`]) of several markers at one equilibrium,
/// in their order: the Newton matrix is assembled and factorised once for
/// all of them (it was factorised once per column, 24 times for a car's
/// four wheels, half of `axle kc` on the car). `Err` when the matrix cannot
/// be assembled; a marker whose columns the factorisation does not solve
/// has its own error.
pub fn compliances(
    problem: &Problem,
    eq: &Equilibrium,
    markers: &[MarkerId],
) -> Result<Vec<Result<Compliance, StaticsError>>, StaticsError> {
    let p = problem;
    let st = &eq.state;
    let sys = assemble(p, st, &st.loads)?;
    let a = kkt(&sys);
    let lu = DenseLu::new(&a);
    let one = |marker: MarkerId| {
        if marker.index() >= p.model.markers.len() {
            return Err(unknown_marker());
        }
        marker_compliance(p, eq, &sys, &lu, marker)
    };
    Ok(markers.iter().map(|&m| one(m)).collect())
}

fn unknown_marker() -> StaticsError {
    StaticsError::new(
        StaticsErrorKind::BadInput,
        vec![],
        "compliance of a marker the model does not have",
    )
}

/// One marker's compliance from the factorised Newton matrix of `sys`.
fn marker_compliance(
    p: &Problem,
    eq: &Equilibrium,
    sys: &super::system::System,
    lu: &DenseLu,
    marker: MarkerId,
) -> Result<Compliance, StaticsError> {
    let st = &eq.state;
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
        let Some(x) = lu.solve(&b) else {
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

/// How far from the exact equilibrium a solve may have stopped, for one
/// moving part, to first order.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StoppingError {
    pub part: PartId,
    /// Bound on the distance of the part's reference point from its exact
    /// place (mm): the point the solver's coordinates refer to, the
    /// centroid of its connection markers at design
    /// ([`super::coords::reference_points`]).
    pub distance: f64,
    /// Bound on the angle of the part's rotation from its exact one (rad).
    pub angle: f64,
}

/// How far from the exact equilibrium a solve may have stopped, part by
/// part (see [`StoppingError`]).
///
/// Newton stops once every scaled force residual is below
/// [`FORCE_TOL`] of [`Equilibrium::force_scale`] and every constraint
/// residual below [`CONSTRAINT_TOL`] of the length; a residual `r` leaves
/// the coordinates `A⁻¹ r` from the exact equilibrium (`A` the Newton
/// matrix), so coordinate `i` is within `Σ_j |A⁻¹_ij| tol_j`. Two solves of
/// the same mechanism (along other paths, or as part of a larger model) can
/// stop at iterates as far apart as the sum of their bounds, which is what a
/// comparison of their poses must allow and no more.
///
/// It inverts the dense Newton matrix (cubic in the unknowns: a few
/// milliseconds for the 255 of the car), so it is meant for checks and
/// reports on chosen cases, not for every case of a path.
pub fn stopping_error(
    problem: &Problem,
    eq: &Equilibrium,
) -> Result<Vec<StoppingError>, StaticsError> {
    let p = problem;
    let st = &eq.state;
    let sys = assemble(p, st, &st.loads)?;
    let a = kkt(&sys);
    let (n, m) = (sys.k.nrows(), sys.jac.nrows());
    let nn = n + m;
    let fa = faer::MatRef::from_column_major_slice(a.as_slice(), nn, nn);
    let inverse = faer::linalg::solvers::DenseSolveCore::inverse(&fa.partial_piv_lu());
    let tol = |j: usize| {
        if j < n {
            FORCE_TOL * eq.force_scale
        } else {
            CONSTRAINT_TOL * p.length
        }
    };
    let mut bound = vec![0.0; n];
    for (i, b) in bound.iter_mut().enumerate() {
        *b = (0..nn).map(|j| inverse[(i, j)].abs() * tol(j)).sum::<f64>();
    }
    if !bound.iter().all(|b| b.is_finite()) {
        return Err(StaticsError::new(
            StaticsErrorKind::Unrestrained,
            vec![],
            "the linearised system is singular at this equilibrium, so the distance to the exact equilibrium is unbounded",
        ));
    }
    // Each component within its bound: the vector within their norm. The
    // rotation coordinates are scaled by the length (see `col_scale`).
    let norm = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
    Ok(p.layout
        .moving
        .iter()
        .zip(bound.chunks(6))
        .map(|(&part, c)| StoppingError {
            part,
            distance: norm(&c[..3]),
            angle: norm(&c[3..]) * col_scale(3, p.length),
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One part on one bushing at its origin: translations and rotations
    /// decouple, and each coordinate's error is its residual's tolerance
    /// over its stiffness: `FORCE_TOL F / k` (mm) and, the torque rows
    /// being scaled by the length, `FORCE_TOL F L / k_t` (rad); three
    /// components each make `√3` of that.
    #[test]
    fn a_part_on_one_bushing_stops_within_its_tolerance_over_its_stiffness() {
        let model = block();
        let problem = Problem::new(&model).expect("compiles");
        let set = model.load_set_named("push").expect("set");
        let eq = &crate::statics::solve_set(&model, set).expect("solves")[0];
        let f = eq.force_scale;
        // The load's magnitude, which the bushing's force balances.
        let load = (300.0f64 * 300.0 + 100.0 * 100.0).sqrt();
        assert!((f - load).abs() < 1e-6 * load, "{f}");
        let e = stopping_error(&problem, eq).expect("regular");
        assert_eq!(e.len(), 1);
        let k_t = 5000.0_f64.to_degrees();
        let distance = 3f64.sqrt() * FORCE_TOL * f / 2000.0;
        let angle = 3f64.sqrt() * FORCE_TOL * f * problem.length / k_t;
        assert!(
            (e[0].distance - distance).abs() < 1e-3 * distance,
            "{e:?} {distance}"
        );
        assert!((e[0].angle - angle).abs() < 1e-3 * angle, "{e:?} {angle}");
    }

    /// One part on one bushing at its origin (2000 N/mm, 5000 N·mm/deg in
    /// every direction), pushed at that point.
    fn block() -> crate::model::Model {
        let (_, c) = crate::check::check_str(
            "block.axle",
            "model block
ground frame {
    marker B at (0, 0, 0) mm
    marker far at (0, 0, 400) mm
}
part block {
    marker B at (0, 0, 0) mm
}
bushing B {
    i block.B
    j frame.B
    k_radial 2000 N/mm
    k_axial 2000 N/mm
    kt_radial 5000 N*mm/deg
    kt_axial 5000 N*mm/deg
}
loads push table (block.B.fz N, block.B.fx N) {
    c1 300 -100
}
",
        );
        c.model.expect("checks clean")
    }

    /// The compliances of several markers from one factorisation are each
    /// marker's own, to the bit; the block's at its bushing point is the
    /// bushing's inverse stiffness (the load at that point adds no
    /// stiffness about it); a ground marker's is zero, an unknown marker an
    /// error of its own.
    #[test]
    fn compliances_of_several_markers_are_each_markers_own() {
        let model = block();
        let problem = Problem::new(&model).expect("compiles");
        let set = model.load_set_named("push").expect("set");
        let eq = &crate::statics::solve_set(&model, set).expect("solves")[0];
        let part = model.part_named("block").expect("part");
        let frame = model.part_named("frame").expect("ground");
        let b = model.marker_named(part, "B").expect("marker");
        let far = model.marker_named(frame, "far").expect("marker");
        let unknown = MarkerId(model.markers.len() as u32);
        let all = compliances(&problem, eq, &[b, far, unknown]).expect("assembles");
        assert_eq!(all.len(), 3);
        let own = compliance(&problem, eq, b).expect("regular");
        assert_eq!(all[0].as_ref().expect("regular"), &own);
        assert_eq!(all[1].as_ref().expect("ground"), &[[0.0; 6]; 6]);
        assert!(all[2].is_err());
        let rad = 1.0 / 5000.0_f64.to_degrees();
        for i in 0..6 {
            let want = if i < 3 { 1.0 / 2000.0 } else { rad };
            assert!((own[i][i] - want).abs() < 1e-3 * want, "{i}: {own:?}");
        }
    }
}
