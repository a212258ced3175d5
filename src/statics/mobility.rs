//! Mobility at the design configuration, for the checker's diagnostics: counts,
//! redundant equations, and motions that no joint and no force element holds
//! (errors) or holds only very weakly (warnings).
//!
//! Stiffness is compared mass-free and scale-consistently: rotations are
//! multiplied by the model's characteristic length, so every reduced stiffness
//! is in N/mm and the ratio to the stiffest mode is dimensionless.

use super::Problem;
use super::coords::{Layout, State};
use super::forces::element_wrenches;
use super::redundancy::{RedundantEquation, rank_and_null_space, scaled_jacobian};
use crate::geom::Vec3;
use crate::model::{Model, PartId};
use nalgebra::{DMatrix, DVector};
use serde::Serialize;

/// Reduced stiffness below this fraction of the stiffest mode: unrestrained.
pub const UNRESTRAINED: f64 = 1e-10;
/// Below this fraction: nearly unrestrained (a warning).
pub const NEARLY_UNRESTRAINED: f64 = 1e-6;

/// A motion of the mechanism described for a reader.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Motion {
    /// The part that moves most.
    pub part: PartId,
    /// A rotation (about `axis` through `point`) rather than a translation (along `axis`).
    pub rotation: bool,
    /// Unit direction, global.
    pub axis: [f64; 3],
    /// A point on the rotation axis (mm, global at design); the part's marker centroid for a translation.
    pub point: [f64; 3],
    /// "rotation of `tie_rod` about axis (0.17, -0.98, 0.06) through (104.5, 524.0, 217.9)".
    pub words: String,
    /// Stiffness of the mode relative to the stiffest mode (0 when none is stiff).
    pub ratio: f64,
}

#[derive(Debug, Clone, PartialEq, Default, Serialize)]
pub struct Mobility {
    /// 6 per moving part.
    pub coordinates: usize,
    /// Scalar constraint equations of all joints.
    pub equations: usize,
    /// Grübler count: coordinates minus equations.
    pub grubler: i64,
    /// Numerical rank of the constraint Jacobian at design.
    pub rank: usize,
    /// Degrees of freedom: coordinates minus rank.
    pub dof: usize,
    pub redundant: Vec<RedundantEquation>,
    /// Motions with no stiffness at all (errors).
    pub unrestrained: Vec<Motion>,
    /// Motions much softer than the stiffest mode (warnings).
    pub nearly_unrestrained: Vec<Motion>,
    /// Motions with clearly negative stiffness at design: preloaded elements
    /// (a compressed spring) push the mechanism away from the design state.
    pub unstable: Vec<Motion>,
}

fn round(v: f64, digits: i32) -> f64 {
    let s = 10f64.powi(digits);
    // `+ 0.0` turns -0 into 0, which reads better in messages.
    (v * s).round() / s + 0.0
}

/// Describes a coordinate increment (mm, rad) by the part that moves most.
pub fn describe_motion(model: &Model, layout: &Layout, dq: &DVector<f64>, length: f64) -> Motion {
    let mut best = (
        f64::NEG_INFINITY,
        0usize,
        Vec3::zeros(),
        Vec3::zeros(),
        Vec3::zeros(),
    );
    for (b, &p) in layout.moving.iter().enumerate() {
        let x = Vec3::new(dq[6 * b], dq[6 * b + 1], dq[6 * b + 2]);
        let th = Vec3::new(dq[6 * b + 3], dq[6 * b + 4], dq[6 * b + 5]);
        let pts: Vec<Vec3> = model
            .markers
            .iter()
            .filter(|m| m.part == p)
            .map(|m| m.origin())
            .collect();
        let c = if pts.is_empty() {
            Vec3::zeros()
        } else {
            pts.iter().sum::<Vec3>() / pts.len() as f64
        };
        let vc = x + th.cross(&c);
        let size = vc.norm() + th.norm() * length;
        if size > best.0 {
            best = (size, b, th, vc, c);
        }
    }
    let (_, b, th, vc, c) = best;
    let part = layout.moving.get(b).copied().unwrap_or(PartId(0));
    let name = &model.part(part).name;
    let rotation = th.norm() * length >= vc.norm();
    let (mut axis, point) = if rotation {
        (th.normalize(), c + th.cross(&vc) / th.norm_squared())
    } else if vc.norm() > 0.0 {
        (vc.normalize(), c)
    } else {
        (Vec3::x(), c)
    };
    // Deterministic sign: the largest component positive.
    if axis[axis.iamax()] < 0.0 {
        axis = -axis;
    }
    let f = |v: &Vec3, d: i32| format!("({}, {}, {})", round(v.x, d), round(v.y, d), round(v.z, d));
    let words = if rotation {
        format!(
            "rotation of `{name}` about axis {} through {} mm",
            f(&axis, 3),
            f(&point, 1)
        )
    } else {
        format!("translation of `{name}` along {}", f(&axis, 3))
    };
    Motion {
        part,
        rotation,
        axis: axis.into(),
        point: point.into(),
        words,
        ratio: 0.0,
    }
}

/// Mobility of a problem at design: counts, redundancy, unrestrained motions.
pub fn analyse(p: &Problem) -> Mobility {
    let (model, layout) = (&p.model, &p.layout);
    let design = State::design(model);
    let all: Vec<usize> = (0..p.equations.len()).collect();
    let sj = scaled_jacobian(model, layout, &design, &p.equations, &all, p.length);
    let n = layout.n();
    let mut mob = Mobility {
        coordinates: n,
        equations: p.equations.len(),
        grubler: n as i64 - p.equations.len() as i64,
        redundant: p.redundant.clone(),
        ..Mobility::default()
    };
    let Some((rank, null)) = rank_and_null_space(&sj.jac) else {
        // No SVD: fall back on the greedy count, which needs no iteration.
        mob.rank = p.kept.len();
        mob.dof = n - mob.rank;
        return mob;
    };
    mob.rank = rank;
    mob.dof = n - rank;
    if mob.dof == 0 {
        return mob;
    }
    // Tangent stiffness of the force elements at design, no load, length-scaled.
    let mut k = DMatrix::zeros(n, n);
    let Ok(ws) = element_wrenches(model, layout, &design) else {
        return mob;
    };
    for (_, w) in ws {
        w.add_tangent(&mut k);
    }
    let s = |i: usize| if i % 6 >= 3 { 1.0 / p.length } else { 1.0 };
    let k = DMatrix::from_fn(n, n, |i, j| -k[(i, j)] * s(i) * s(j));
    let kr = null.transpose() * (&k + k.transpose()) * 0.5 * &null;
    let eig = kr.symmetric_eigen();
    let kmax = eig.eigenvalues.iter().cloned().fold(0.0, f64::max);
    for (i, &ev) in eig.eigenvalues.iter().enumerate() {
        let ratio = if kmax > 0.0 { ev / kmax } else { 0.0 };
        if ratio >= NEARLY_UNRESTRAINED {
            continue;
        }
        let v = &null * eig.eigenvectors.column(i);
        let dq = DVector::from_fn(n, |r, _| v[r] * s(r));
        let mut motion = describe_motion(model, layout, &dq, p.length);
        motion.ratio = ratio;
        if ratio < -NEARLY_UNRESTRAINED {
            mob.unstable.push(motion);
        } else if ratio < UNRESTRAINED {
            mob.unrestrained.push(motion);
        } else {
            mob.nearly_unrestrained.push(motion);
        }
    }
    mob
}
