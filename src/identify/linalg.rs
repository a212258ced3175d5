//! Dense linear algebra for identification on nalgebra matrices, through faer
//! (SVD, LU), with every result checked for finiteness: faer reports neither
//! singular matrices nor NaN inputs.

use nalgebra::{DMatrix, DVector};

fn as_faer(m: &DMatrix<f64>) -> faer::MatRef<'_, f64> {
    faer::MatRef::from_column_major_slice(m.as_slice(), m.nrows(), m.ncols())
}

fn to_na(m: faer::MatRef<'_, f64>) -> DMatrix<f64> {
    DMatrix::from_fn(m.nrows(), m.ncols(), |i, j| m[(i, j)])
}

/// A singular value decomposition `A = U diag(s) Vᵀ`, `s` descending.
pub struct Svd {
    pub u: DMatrix<f64>,
    pub s: Vec<f64>,
    /// Right singular vectors as columns (all `ncols` of them when `full`).
    pub v: DMatrix<f64>,
}

/// SVD; `full` gives the whole V (the null space of a wide matrix needs it).
/// None when the input or output is not finite or the iteration fails.
pub fn svd(a: &DMatrix<f64>, full: bool) -> Option<Svd> {
    if a.nrows() == 0 || a.ncols() == 0 || !a.iter().all(|x| x.is_finite()) {
        return None;
    }
    let f = as_faer(a);
    let (u, s, v) = if full {
        let d = f.svd().ok()?;
        let s: Vec<f64> = d.S().column_vector().iter().copied().collect();
        (to_na(d.U()), s, to_na(d.V()))
    } else {
        let d = f.thin_svd().ok()?;
        let s: Vec<f64> = d.S().column_vector().iter().copied().collect();
        (to_na(d.U()), s, to_na(d.V()))
    };
    if !s.iter().chain(v.iter()).all(|x| x.is_finite()) {
        return None;
    }
    Some(Svd { u, s, v })
}

/// Numerical rank: singular values above `rel` times the largest.
pub fn rank(s: &[f64], rel: f64) -> usize {
    let top = s.first().copied().unwrap_or(0.0);
    if !(top > 0.0) {
        return 0;
    }
    s.iter().filter(|&&x| x > rel * top).count()
}

/// Orthonormal basis of the null space of `a` (columns), with relative rank tolerance.
pub fn null_space(a: &DMatrix<f64>, rel: f64) -> Option<DMatrix<f64>> {
    let n = a.ncols();
    if a.nrows() == 0 {
        return Some(DMatrix::identity(n, n));
    }
    let d = svd(a, true)?;
    let r = rank(&d.s, rel);
    Some(d.v.columns(r, n - r).into_owned())
}

/// Solves `A X = B` by LU; None when the result is not finite or does not
/// satisfy the system (a singular matrix).
pub fn solve(a: &DMatrix<f64>, b: &DMatrix<f64>) -> Option<DMatrix<f64>> {
    use faer::linalg::solvers::Solve;
    let n = a.nrows();
    if n == 0 || a.ncols() != n || b.nrows() != n {
        return None;
    }
    let lu = as_faer(a).partial_piv_lu();
    let x = to_na(lu.solve(as_faer(b)).as_ref());
    if !x.iter().all(|v| v.is_finite()) {
        return None;
    }
    let res = (a * &x - b).amax();
    if res > 1e-8 * (b.amax() + a.amax() * x.amax()).max(1e-300) {
        return None;
    }
    Some(x)
}

/// Minimum-norm least-squares solution of `A x ≈ b` truncated to rank `r` of
/// the given SVD of A.
pub fn truncated_solve(d: &Svd, b: &DVector<f64>, r: usize) -> DVector<f64> {
    let mut x = DVector::zeros(d.v.nrows());
    for k in 0..r.min(d.s.len()) {
        let c = d.u.column(k).dot(b) / d.s[k];
        x += d.v.column(k) * c;
    }
    x
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn null_space_and_truncated_solve() {
        // Rank 2 in 3 unknowns: x0 + x1 and x2 determined, x0 - x1 not.
        let a = DMatrix::from_row_slice(3, 3, &[1.0, 1.0, 0.0, 0.0, 0.0, 2.0, 2.0, 2.0, 1.0]);
        let n = null_space(&a, 1e-10).expect("svd");
        assert_eq!(n.ncols(), 1);
        assert!((n[(0, 0)] + n[(1, 0)]).abs() < 1e-12 && n[(2, 0)].abs() < 1e-12);
        let d = svd(&a, false).expect("svd");
        assert_eq!(rank(&d.s, 1e-10), 2);
        let b = a.clone() * DVector::from_vec(vec![3.0, 1.0, 5.0]);
        let x = truncated_solve(&d, &b, 2);
        assert!((x[0] - 2.0).abs() < 1e-12 && (x[1] - 2.0).abs() < 1e-12);
        assert!((x[2] - 5.0).abs() < 1e-12);
        assert!(solve(&a, &DMatrix::identity(3, 3)).is_none(), "singular");
        let nan = DMatrix::from_element(2, 2, f64::NAN);
        assert!(svd(&nan, true).is_none());
    }
}
