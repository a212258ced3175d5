//! Redundant constraint equations: found by a rank-revealing factorisation of
//! the scaled constraint Jacobian at design, reported once with the joints
//! involved, and left out of the Newton system so that it stays regular.
//!
//! Rows are scaled to unit norm after the rotation columns are multiplied by the
//! model's characteristic length, so lengths and cosines weigh alike.

use super::constraint::{Equation, evaluate, is_length};
use super::coords::{Layout, State};
use crate::model::{JointId, Model, Primitive};
use nalgebra::{DMatrix, DVector};
use serde::Serialize;

/// A constraint equation implied by earlier ones (in declaration order).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RedundantEquation {
    pub joint: JointId,
    #[serde(skip)]
    pub primitive: Primitive,
    /// The primitive in words: `d·x`, `z_I·x_J`.
    pub equation: String,
    /// The joints whose equations combine to this one (including its own joint
    /// when it takes part).
    pub with: Vec<JointId>,
}

/// The constraint values and the scaled Jacobian (rows: equations).
pub struct ScaledJacobian {
    /// Values divided by their row scale (mm-equivalent).
    pub phi: DVector<f64>,
    /// Rows with rotation columns times `length`, each row divided by its norm.
    pub jac: DMatrix<f64>,
    /// The factor each row was divided by (after column scaling).
    pub row_scale: Vec<f64>,
}

pub fn scaled_jacobian(
    model: &Model,
    layout: &Layout,
    state: &State,
    eqs: &[Equation],
    rows: &[usize],
    length: f64,
) -> ScaledJacobian {
    let n = layout.n();
    let mut jac = DMatrix::zeros(rows.len(), n);
    let mut phi = DVector::zeros(rows.len());
    let mut row_scale = Vec::with_capacity(rows.len());
    for (r, &e) in rows.iter().enumerate() {
        let (v, w) = evaluate(model, layout, state, &eqs[e]);
        let mut g = DVector::zeros(n);
        w.add_force(&mut g);
        for c in 0..n {
            jac[(r, c)] = if c % 6 >= 3 { g[c] / length } else { g[c] };
        }
        let norm = jac.row(r).norm();
        // A row that vanishes at design (e.g. a joint between two ground markers)
        // gets its natural scale, so it counts as dependent below.
        let s = if norm > 0.0 {
            norm
        } else if is_length(eqs[e].primitive) {
            1.0
        } else {
            1.0 / length
        };
        row_scale.push(s);
        for c in 0..n {
            jac[(r, c)] /= s;
        }
        phi[r] = v / s;
    }
    ScaledJacobian {
        phi,
        jac,
        row_scale,
    }
}

/// Which equations are independent, in declaration order.
pub struct Independence {
    pub kept: Vec<usize>,
    pub redundant: Vec<RedundantEquation>,
}

/// Below this residual (rows have unit norm) a row lies in the span of earlier rows.
const DEPENDENT: f64 = 1e-9;

/// Greedy in declaration order: a row is kept if it is independent of the rows
/// kept so far (modified Gram–Schmidt, twice for stability), so the later of two
/// conflicting joints is the one named.
pub fn independence(eqs: &[Equation], jac: &DMatrix<f64>) -> Independence {
    let mut basis: Vec<DVector<f64>> = Vec::new();
    let mut kept = Vec::new();
    let mut redundant = Vec::new();
    for r in 0..jac.nrows() {
        let row: DVector<f64> = jac.row(r).transpose();
        let mut v = row.clone();
        for _ in 0..2 {
            for b in &basis {
                // In place: `v -= b * c` made a vector per step, which cost
                // more than the arithmetic (the same products and sums).
                let c = b.dot(&v);
                let (v, b) = (v.as_mut_slice(), b.as_slice());
                v.iter_mut().zip(b).for_each(|(x, y)| *x -= y * c);
            }
        }
        let res = v.norm();
        if res > DEPENDENT && row.norm() > 0.0 {
            basis.push(v / res);
            kept.push(r);
        } else {
            redundant.push(RedundantEquation {
                joint: eqs[r].joint,
                primitive: eqs[r].primitive,
                equation: eqs[r].primitive.describe(),
                with: involved(eqs, jac, &kept, r),
            });
        }
    }
    Independence { kept, redundant }
}

/// The joints of the kept rows that combine to row `r` (least squares), with `r`'s own.
fn involved(eqs: &[Equation], jac: &DMatrix<f64>, kept: &[usize], r: usize) -> Vec<JointId> {
    let mut joints = vec![eqs[r].joint];
    if kept.is_empty() {
        return joints;
    }
    let a = DMatrix::from_fn(jac.ncols(), kept.len(), |i, k| jac[(kept[k], i)]);
    let b: DVector<f64> = jac.row(r).transpose();
    let svd = a.svd(true, true);
    if let Ok(x) = svd.solve(&b, 1e-10) {
        for (k, &row) in kept.iter().enumerate() {
            if x[k].abs() > 1e-8 && !joints.contains(&eqs[row].joint) {
                joints.push(eqs[row].joint);
            }
        }
    }
    joints.sort();
    joints
}

/// Numerical rank of a scaled Jacobian by faer's SVD (singular values above
/// `1e-9` of the largest), with the right singular vectors of the null space.
pub fn rank_and_null_space(jac: &DMatrix<f64>) -> Option<(usize, DMatrix<f64>)> {
    let (m, n) = (jac.nrows(), jac.ncols());
    if n == 0 {
        return Some((0, DMatrix::zeros(0, 0)));
    }
    if m == 0 {
        return Some((0, DMatrix::identity(n, n)));
    }
    let a = faer::MatRef::from_column_major_slice(jac.as_slice(), m, n);
    let svd = a.svd().ok()?;
    let s = svd.S().column_vector();
    let smax = (0..m.min(n)).map(|i| s[i]).fold(0.0, f64::max);
    let rank = (0..m.min(n))
        .filter(|&i| s[i] > 1e-9 * smax.max(1e-300))
        .count();
    let v = svd.V();
    let null = DMatrix::from_fn(n, n - rank, |i, k| v[(i, rank + k)]);
    Some((rank, null))
}
