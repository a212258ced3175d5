//! Mobility at the design configuration, for the checker's diagnostics: counts,
//! redundant equations, and motions that no joint and no force element holds
//! (errors) or holds only very weakly (warnings).
//!
//! Stiffness is compared mass-free and scale-consistently: each moving part's
//! motion is written as the velocity of the centroid of its connection
//! markers (those of joints and force elements, which alone carry stiffness)
//! and its rotation times the size of the mechanism those markers span, so
//! every reduced stiffness is in N/mm and the ratio to the stiffest mode is
//! dimensionless. Neither the global origin nor a marker that connects
//! nothing (a wheel centre written `30 m`) changes a verdict, as they did when
//! rotations were about the origin and scaled by the spread of all markers
//! ([`PartFrames`]).

use super::coords::{Layout, State, connection_markers, marker_centroid, reference_points_of};
use super::forces::element_wrenches;
use super::problem::Equations;
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
        // The motion of the markers' centroid, from the twist of the
        // reference point (the centroid itself in a problem's layout).
        let c = marker_centroid(model, p);
        let vc = x + th.cross(&(c - layout.reference[p.index()]));
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

/// The coordinates the analysis uses, part by part: `(v, φ)` with `v` the
/// velocity of the part's centroid `c` and `φ = l θ` its rotation times the
/// mechanism's size `l`; the solver's coordinates (the velocity `x` of the
/// part's reference point `r`, [`Layout::reference`], and `θ`) are
/// `x = v + (c - r) × φ / l`, `θ = φ / l` (`dq = T dq'`, block-diagonal `T`,
/// applied block by block).
pub struct PartFrames {
    /// Per moving part (layout order): centroid from the reference point
    /// (mm, design) and the length rotations are scaled by (mm, at least 1).
    frames: Vec<(Vec3, f64)>,
}

impl PartFrames {
    /// Each moving part's centroid of connection markers (those the joints
    /// and force elements attach to; all its markers when it has none:
    /// [`super::coords::reference_points`]), from the point `layout`'s coordinates refer
    /// to, and the size of the mechanism: the largest distance of a
    /// connection marker from their common centroid.
    pub fn new(model: &Model, layout: &Layout) -> PartFrames {
        let connected = connection_markers(model);
        let centres = reference_points_of(model, &connected);
        // (From the point `layout`'s coordinates refer to: the frame origin
        // in the checker's analysis, `analyse`; in a problem's centred
        // layout they are these centroids already.)
        let frames = layout
            .moving
            .iter()
            .map(|p| centres[p.index()] - layout.reference[p.index()])
            .collect::<Vec<Vec3>>();
        let pts: Vec<Vec3> = model
            .markers
            .iter()
            .zip(&connected)
            .filter(|(_, c)| **c)
            .map(|(m, _)| m.origin())
            .collect();
        let length = if pts.is_empty() {
            1.0
        } else {
            let c = pts.iter().sum::<Vec3>() / pts.len() as f64;
            pts.iter().map(|q| (q - c).norm()).fold(1.0, f64::max)
        };
        PartFrames {
            frames: frames.into_iter().map(|c| (c, length)).collect(),
        }
    }

    /// `A T`: the columns of `a` (solver coordinates) in the part coordinates.
    pub fn right(&self, a: &DMatrix<f64>) -> DMatrix<f64> {
        let mut out = a.clone();
        for (b, &(c, l)) in self.frames.iter().enumerate() {
            let (x, th) = (6 * b, 6 * b + 3);
            for r in 0..a.nrows() {
                let ax = Vec3::new(a[(r, x)], a[(r, x + 1)], a[(r, x + 2)]);
                // The row times [c]x: a_x^T [c]x = ([c]x^T a_x)^T = (a_x x c)^T.
                let cross = ax.cross(&c);
                for k in 0..3 {
                    out[(r, th + k)] = (cross[k] + a[(r, th + k)]) / l;
                }
            }
        }
        out
    }

    /// `T^T A T` for a square `a`.
    pub fn congruence(&self, a: &DMatrix<f64>) -> DMatrix<f64> {
        self.right(&self.right(a).transpose()).transpose()
    }

    /// `T v`: a motion in part coordinates back in solver coordinates.
    pub fn motion(&self, v: &DVector<f64>) -> DVector<f64> {
        let mut dq = v.clone();
        for (b, &(c, l)) in self.frames.iter().enumerate() {
            let (x, th) = (6 * b, 6 * b + 3);
            let phi = Vec3::new(v[th], v[th + 1], v[th + 2]) / l;
            let cx = c.cross(&phi);
            for k in 0..3 {
                dq[x + k] = v[x + k] + cx[k];
                dq[th + k] = phi[k];
            }
        }
        dq
    }
}

/// Mobility of a model at design, from its compiled equations: counts,
/// redundancy, unrestrained motions.
pub(crate) fn analyse(model: &Model, p: &Equations) -> Mobility {
    // In the frame origins' coordinates (recentred by `PartFrames`), not the
    // problem's: where the design carries a preload (a compressed spring, a
    // bushing written twisted) the stiffness there is not a true second
    // derivative, and it depends on the point the rotations are taken about;
    // the verdicts keep the coordinates they were measured in.
    let layout = &Layout::new(model);
    let design = State::design(model);
    let all: Vec<usize> = (0..p.equations.len()).collect();
    let frames = PartFrames::new(model, layout);
    // The constraint Jacobian in part coordinates, rows normalised again.
    let mut jac =
        frames.right(&scaled_jacobian(model, layout, &design, &p.equations, &all, 1.0).jac);
    for mut row in jac.row_iter_mut() {
        let norm = row.norm();
        if norm > 0.0 {
            row /= norm;
        }
    }
    let n = layout.n();
    let mut mob = Mobility {
        coordinates: n,
        equations: p.equations.len(),
        grubler: n as i64 - p.equations.len() as i64,
        redundant: p.redundant.clone(),
        ..Mobility::default()
    };
    let Some((rank, null)) = rank_and_null_space(&jac) else {
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
    let k = frames.congruence(&-k);
    let kr = null.transpose() * (&k + k.transpose()) * 0.5 * &null;
    let eig = kr.symmetric_eigen();
    let kmax = eig.eigenvalues.iter().cloned().fold(0.0, f64::max);
    let describe = |v: DVector<f64>, ratio: f64| {
        let dq = frames.motion(&v);
        let mut motion = describe_motion(model, layout, &dq, p.length);
        motion.ratio = ratio;
        motion
    };
    let mut free = Vec::new();
    for (i, &ev) in eig.eigenvalues.iter().enumerate() {
        let ratio = if kmax > 0.0 { ev / kmax } else { 0.0 };
        if ratio >= NEARLY_UNRESTRAINED {
            continue;
        }
        let v = &null * eig.eigenvectors.column(i);
        if ratio < -NEARLY_UNRESTRAINED {
            mob.unstable.push(describe(v, ratio));
        } else if ratio < UNRESTRAINED {
            free.push(v);
        } else {
            mob.nearly_unrestrained.push(describe(v, ratio));
        }
    }
    // The free motions share one eigenvalue (zero), so the eigen solver may
    // return any mixture of them: two parts free at once could be described as
    // one motion of both. Separate them before naming a part.
    if !free.is_empty() {
        let separated = separate(&DMatrix::from_columns(&free));
        for v in separated.column_iter() {
            mob.unrestrained.push(describe(v.into_owned(), 0.0));
        }
    }
    mob
}

/// The sparsest basis of the span of `basis`'s columns that Gauss-Jordan
/// elimination with full pivoting finds (the reduced row-echelon form of its
/// transpose), each vector normalised. Motions that involve disjoint sets of
/// coordinates (two independently free parts) come out apart, whatever
/// mixture of them the columns were.
fn separate(basis: &DMatrix<f64>) -> DMatrix<f64> {
    let mut a = basis.transpose();
    let (m, n) = a.shape();
    let scale = a.amax();
    let mut used = vec![false; n];
    for i in 0..m {
        let mut best = (0.0, i, 0);
        for r in i..m {
            for j in (0..n).filter(|&j| !used[j]) {
                if a[(r, j)].abs() > best.0 {
                    best = (a[(r, j)].abs(), r, j);
                }
            }
        }
        let (size, r, j) = best;
        if size <= 1e-12 * scale {
            break;
        }
        used[j] = true;
        a.swap_rows(i, r);
        let pivot = a[(i, j)];
        a.row_mut(i).scale_mut(1.0 / pivot);
        let row = a.row(i).into_owned();
        for k in (0..m).filter(|&k| k != i) {
            let f = a[(k, j)];
            if f != 0.0 {
                for c in 0..n {
                    a[(k, c)] -= f * row[c];
                }
            }
        }
    }
    for mut row in a.row_iter_mut() {
        let norm = row.norm();
        if norm > 0.0 {
            row /= norm;
        }
    }
    a.transpose()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two motions on disjoint coordinates (a part turning, another sliding),
    /// handed over as two different mixtures of both, come back apart.
    #[test]
    fn separate_recovers_motions_of_disjoint_parts_from_a_mixture() {
        let mut turn = DVector::zeros(12);
        turn[5] = 1.0; // part 0 about z
        let mut slide = DVector::zeros(12);
        slide[6] = 0.6; // part 1 along (0.6, 0.8, 0)
        slide[7] = 0.8;
        let mixed =
            DMatrix::from_columns(&[&turn * 0.8 + &slide * 0.6, &turn * 0.6 - &slide * 0.8]);
        let out = separate(&mixed);
        assert_eq!(out.ncols(), 2);
        for expected in [&turn, &slide] {
            let hit = out
                .column_iter()
                .any(|c| (c - expected).norm() < 1e-12 || (c + expected).norm() < 1e-12);
            assert!(hit, "{expected} not among {out}");
        }
    }

    /// A motion of two coupled parts is not split: the span is kept.
    #[test]
    fn separate_keeps_the_span() {
        let v = DVector::from_fn(12, |i, _| (i as f64 + 1.0).sin());
        let w = DVector::from_fn(12, |i, _| (i as f64 * 0.7).cos());
        let basis = DMatrix::from_columns(&[v, w]);
        let out = separate(&basis);
        // Each output column lies in the input span: its residual after
        // projection onto the span is zero.
        let q = basis.clone().qr().q();
        for c in out.column_iter() {
            let r = c - &q * (q.transpose() * c);
            assert!(r.norm() < 1e-12, "{r}");
            assert!((c.norm() - 1.0).abs() < 1e-12);
        }
    }
}
