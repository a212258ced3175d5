//! The dense LU factorisation of the scaled Newton matrix, with buffers kept
//! across Newton iterations so that an iteration allocates nothing, a check of
//! each solution against the matrix (faer does not report singular matrices),
//! and a cheap estimate of how close the matrix is to singular.
//!
//! The estimate decides when the exact (and, at this size, far more costly)
//! SVD test of [`super::newton::singular_direction`] must run: it is a lower
//! bound on `‖A⁻¹‖` from two steps of inverse iteration, the method of LAPACK's
//! condition estimators. A singular matrix amplifies every start vector with a
//! component along its null direction by `1/σ_min`, so the estimate flags it
//! (by many orders of magnitude beyond the threshold) unless the start vector
//! is orthogonal to that direction to rounding, which the fixed irregular start
//! vector below makes practically impossible.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::lu::partial_pivoting::{factor, solve};
use faer::perm::PermRef;
use faer::{Conj, Mat, Par};

pub(crate) struct Lu {
    /// The matrix factorised, and its factors in place.
    a: Mat<f64>,
    lu: Mat<f64>,
    fwd: Vec<usize>,
    bwd: Vec<usize>,
    mem: MemBuffer,
    /// Largest absolute entry and Frobenius norm of the matrix factorised.
    a_max: f64,
    a_fro: f64,
    /// Whether `lu` holds a factorisation.
    valid: bool,
    res: Vec<f64>,
}

impl Lu {
    pub fn new(dim: usize) -> Lu {
        let par = Par::Seq;
        let req = factor::lu_in_place_scratch::<usize, f64>(dim, dim, par, Default::default())
            .or(solve::solve_in_place_scratch::<usize, f64>(dim, 1, par));
        Lu {
            a: Mat::zeros(dim, dim),
            lu: Mat::zeros(dim, dim),
            fwd: vec![0; dim],
            bwd: vec![0; dim],
            mem: MemBuffer::new(req),
            a_max: 0.0,
            a_fro: 0.0,
            valid: false,
            res: vec![0.0; dim],
        }
    }

    pub fn dim(&self) -> usize {
        self.lu.nrows()
    }

    /// Factorises `a`; false if a pivot is zero or not finite.
    pub fn factor(&mut self, a: &Mat<f64>) -> bool {
        // Column slices: plain `memcpy`s, cheaper here than faer's generic copy.
        for j in 0..a.ncols() {
            self.a
                .col_as_slice_mut(j)
                .copy_from_slice(a.col_as_slice(j));
            self.lu
                .col_as_slice_mut(j)
                .copy_from_slice(a.col_as_slice(j));
        }
        // Eight independent lanes: a single running max and sum is a chain of
        // dependent scalar operations that cost as much as a fifth of the
        // whole solve; lanes let the compiler use vector instructions.
        let (mut mx, mut sq) = ([0.0f64; 8], [0.0f64; 8]);
        for j in 0..a.ncols() {
            let col = a.col_as_slice(j);
            let mut chunks = col.chunks_exact(8);
            for c in &mut chunks {
                for k in 0..8 {
                    let v = c[k].abs();
                    // Like `f64::max`, a NaN entry does not replace the maximum.
                    mx[k] = if v > mx[k] { v } else { mx[k] };
                    sq[k] += v * v;
                }
            }
            for (k, v) in chunks.remainder().iter().enumerate() {
                let v = v.abs();
                mx[k] = if v > mx[k] { v } else { mx[k] };
                sq[k] += v * v;
            }
        }
        self.a_max = mx.iter().fold(0.0f64, |m, v| m.max(*v));
        self.a_fro = sq.iter().sum::<f64>().sqrt();
        factor::lu_in_place(
            self.lu.as_mut(),
            &mut self.fwd,
            &mut self.bwd,
            Par::Seq,
            MemStack::new(&mut self.mem),
            Default::default(),
        );
        let n = self.dim();
        self.valid = (0..n).all(|i| {
            let d = self.lu[(i, i)];
            d.is_finite() && d != 0.0
        });
        self.valid
    }

    /// Solves `A x = b` in place (`b` becomes `x`); false if there is no
    /// factorisation or the result is not finite.
    pub fn solve(&mut self, b: &mut [f64]) -> bool {
        if !self.valid {
            return false;
        }
        let n = self.dim();
        let rhs = faer::MatMut::from_column_major_slice_mut(b, n, 1);
        // SAFETY: `fwd` and `bwd` are the inverse permutations written by `lu_in_place`.
        let perm = unsafe { PermRef::new_unchecked(&self.fwd, &self.bwd, n) };
        solve::solve_in_place_with_conj(
            self.lu.as_ref(),
            self.lu.as_ref(),
            perm,
            Conj::No,
            rhs,
            Par::Seq,
            MemStack::new(&mut self.mem),
        );
        b.iter().all(|v| v.is_finite())
    }

    /// Whether `x` solves `A x = b` to a residual of `1e-8` of the sizes
    /// involved, `a` being the matrix last factorised.
    pub fn satisfies(&mut self, a: &Mat<f64>, x: &[f64], b: &[f64]) -> bool {
        let x_max = x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let b_max = b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let res = &mut self.res;
        res.iter_mut().zip(b).for_each(|(r, v)| *r = -v);
        for (j, xj) in x.iter().enumerate() {
            for (ri, aij) in res.iter_mut().zip(a.col_as_slice(j)) {
                *ri += aij * xj;
            }
        }
        let r = res.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        r <= 1e-8 * (b_max + self.a_max * x_max)
    }

    /// `‖b - A‖_F / ‖A‖_F` for the matrix `A` last factorised: how far a
    /// reciprocal condition of `A` can be from that of `b`.
    pub fn distance_to(&self, b: &Mat<f64>) -> f64 {
        if !self.valid || b.nrows() != self.dim() || b.ncols() != self.dim() {
            return f64::INFINITY;
        }
        // Lanes for vector instructions, as in `factor`.
        let mut d = [0.0f64; 8];
        for j in 0..self.dim() {
            let (x, y) = (self.a.col_as_slice(j), b.col_as_slice(j));
            for (k, (x, y)) in x.iter().zip(y).enumerate() {
                d[k % 8] += (x - y) * (x - y);
            }
        }
        d.iter().sum::<f64>().sqrt() / self.a_fro
    }

    /// An estimate of `σ_min / σ_max` of the factorised matrix from above (it
    /// may overstate the ratio, by a small factor for any matrix met in
    /// practice): `1 / (‖A‖_F · ‖A⁻¹ y‖)` after two inverse iterations.
    pub fn reciprocal_condition(&mut self) -> f64 {
        let n = self.dim();
        if !self.valid || n == 0 {
            return 0.0;
        }
        let a_fro = self.a_fro;
        // Irregular signs and sizes: no structure of a mechanism lines up with it.
        let mut y: Vec<f64> = (0..n)
            .map(|i| {
                let t = (i as f64 + 1.0) * 0.618_033_988_749_895;
                (t - t.floor()) - 0.5
            })
            .collect();
        let mut growth = 0.0f64;
        for _ in 0..2 {
            let norm = y.iter().map(|v| v * v).sum::<f64>().sqrt();
            if norm.is_nan() || norm <= 0.0 {
                return 0.0;
            }
            y.iter_mut().for_each(|v| *v /= norm);
            if !self.solve(&mut y) {
                return 0.0;
            }
            growth = growth.max(y.iter().map(|v| v * v).sum::<f64>().sqrt());
        }
        if growth.is_nan() || growth <= 0.0 || a_fro <= 0.0 {
            return 0.0;
        }
        1.0 / (a_fro * growth)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn matrix(n: usize, seed: u64) -> Mat<f64> {
        let mut s = seed;
        Mat::from_fn(n, n, |_, _| {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        })
    }

    /// Solutions satisfy the system; the condition estimate is within a small
    /// factor of the SVD's ratio for a regular matrix and flags a singular one.
    #[test]
    fn solves_and_estimates_the_condition() {
        let n = 47;
        let a = matrix(n, 3);
        let mut lu = Lu::new(n);
        assert!(lu.factor(&a));
        let b: Vec<f64> = (0..n).map(|i| (i as f64).sin()).collect();
        let mut x = b.clone();
        assert!(lu.solve(&mut x));
        assert!(lu.satisfies(&a, &x, &b));
        let s = a.singular_values().expect("svd");
        let ratio = s[n - 1] / s[0];
        let est = lu.reciprocal_condition();
        assert!(est > 0.1 * ratio && est < 50.0 * ratio, "{est} vs {ratio}");
        // Rank n - 1: the last column repeats a combination of two others.
        let mut sing = a.clone();
        for i in 0..n {
            sing[(i, n - 1)] = 2.0 * a[(i, 0)] - 0.5 * a[(i, 7)];
        }
        let ok = lu.factor(&sing);
        assert!(!ok || lu.reciprocal_condition() < 1e-12);
    }
}
