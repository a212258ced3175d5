//! The dense LU factorisation of the scaled Newton matrix, with buffers kept
//! across Newton iterations so that an iteration allocates nothing, a check of
//! each solution against the matrix, and a cheap estimate of how close the
//! matrix is to singular.
//!
//! The factorisation is a plain right-looking LU with partial pivoting (the
//! LAPACK `getf2` order) that skips the updates of a zero multiplier or a zero
//! entry of `U`: the Newton matrix of a mechanism is mostly zeros (the 47×47
//! McPherson matrix has a fifth of its entries set), and at this size faer's
//! blocked LU and triangular solves cost several times more than the
//! arithmetic (issue 12). Skipping a zero update is exact; against faer's
//! blocked order only the rounding of the factors differs.
//!
//! The estimate decides when the exact (and, at this size, far more costly)
//! SVD test of [`super::system::singular_direction`] must run: it is a lower
//! bound on `‖A⁻¹‖` from two steps of inverse iteration, the method of LAPACK's
//! condition estimators. A singular matrix amplifies every start vector with a
//! component along its null direction by `1/σ_min`, so the estimate flags it
//! (by many orders of magnitude beyond the threshold) unless the start vector
//! is orthogonal to that direction to rounding, which the fixed irregular start
//! vector below makes practically impossible.

use super::condition::{BlockSizes, DifferenceLanes, Direction, Scale, SizeLanes, largest};
use faer::Mat;
use std::cell::Cell;

/// The residual a solution may leave, of the sizes involved (`‖b‖ + ‖A‖
/// ‖x‖`, largest entries): the residual check of both factorisations
/// ([`Lu::satisfies`], [`super::sparse::SparseLu::solution_holds`]).
pub(crate) const SOLVED_WITHIN: f64 = 1e-8;

/// One independent block of a block-diagonal matrix ([`super::blocks`]):
/// its indices, its own dense factorisation, and buffers to gather into.
struct Block {
    idx: Vec<usize>,
    lu: Lu,
    a: Mat<f64>,
    x: Vec<f64>,
    b: Vec<f64>,
}

pub(crate) struct Lu {
    /// Independent blocks, each factorised on its own; empty: one dense matrix.
    blocks: Vec<Block>,
    /// The matrix factorised, and its factors in place (by columns,
    /// contiguous: the elimination's row swaps and column loops then index
    /// one slice).
    a: Mat<f64>,
    lu: Vec<f64>,
    /// Row `k` was swapped with row `piv[k] >= k` at step `k`.
    piv: Vec<usize>,
    /// The multipliers of the current step (a copy of a column of `L`).
    col: Vec<f64>,
    dim: usize,
    /// The first `coords` rows and columns are the coordinates', the rest
    /// the multipliers' ([`super::condition`]).
    coords: usize,
    /// Largest absolute entry of the matrix factorised.
    a_max: f64,
    /// Its scaling for the condition estimates, computed when first asked
    /// for (at most once a case, not once a factorisation).
    scale: Cell<Option<Scale>>,
    /// Whether `lu` holds a factorisation.
    valid: bool,
    res: Vec<f64>,
}

impl Lu {
    /// For `dim`×`dim` matrices whose first `coords` unknowns are
    /// coordinates.
    pub fn new(dim: usize, coords: usize) -> Lu {
        Lu {
            blocks: Vec::new(),
            a: Mat::zeros(dim, dim),
            lu: vec![0.0; dim * dim],
            piv: vec![0; dim],
            col: vec![0.0; dim],
            dim,
            coords,
            a_max: 0.0,
            scale: Cell::new(None),
            valid: false,
            res: vec![0.0; dim],
        }
    }

    /// A factorisation of matrices that are block diagonal over `groups`
    /// (disjoint index sets covering `0..dim`): dense when there is one.
    pub fn with_blocks(dim: usize, coords: usize, groups: Vec<Vec<usize>>) -> Lu {
        if groups.len() <= 1 {
            return Lu::new(dim, coords);
        }
        let mut lu = Lu::new(0, 0);
        (lu.dim, lu.coords) = (dim, coords);
        lu.res = vec![0.0; dim];
        lu.blocks = groups
            .into_iter()
            .map(|idx| {
                let k = idx.len();
                // A block's coordinates come first, as in the whole matrix.
                let own = idx.iter().filter(|&&i| i < coords).count();
                Block {
                    idx,
                    lu: Lu::new(k, own),
                    a: Mat::zeros(k, k),
                    x: vec![0.0; k],
                    b: vec![0.0; k],
                }
            })
            .collect();
        lu
    }

    pub fn dim(&self) -> usize {
        self.dim
    }

    /// [`Self::factor`] block by block: only the blocks' entries are read.
    fn factor_blocks(&mut self, a: &Mat<f64>) -> bool {
        let (mut valid, mut a_max) = (true, 0.0f64);
        for blk in &mut self.blocks {
            for (c, &j) in blk.idx.iter().enumerate() {
                let src = a.col_as_slice(j);
                let dst = blk.a.col_as_slice_mut(c);
                for (d, &i) in dst.iter_mut().zip(&blk.idx) {
                    *d = src[i];
                }
            }
            valid &= blk.lu.factor(&blk.a);
            a_max = a_max.max(blk.lu.a_max);
        }
        self.a_max = a_max;
        self.scale.set(None);
        self.valid = valid;
        valid
    }

    /// Factorises `a`; false if a pivot is zero or not finite.
    pub fn factor(&mut self, a: &Mat<f64>) -> bool {
        if !self.blocks.is_empty() {
            return self.factor_blocks(a);
        }
        // Column slices: plain `memcpy`s, cheaper here than faer's generic copy.
        for j in 0..a.ncols() {
            self.a
                .col_as_slice_mut(j)
                .copy_from_slice(a.col_as_slice(j));
        }
        let n = self.dim();
        for (j, dst) in self.lu.chunks_exact_mut(n.max(1)).enumerate() {
            dst.copy_from_slice(a.col_as_slice(j));
        }
        self.a_max = largest(&self.lu);
        self.scale.set(None);
        self.eliminate();
        let n = self.dim();
        self.valid = (0..n).all(|i| {
            let d = self.lu[i * n + i];
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
        if !self.blocks.is_empty() {
            let mut ok = b.len() == self.dim;
            for blk in &mut self.blocks {
                if !ok {
                    break;
                }
                for (v, &i) in blk.x.iter_mut().zip(&blk.idx) {
                    *v = b[i];
                }
                ok &= blk.lu.solve(&mut blk.x);
                for (v, &i) in blk.x.iter().zip(&blk.idx) {
                    b[i] = *v;
                }
            }
            return ok;
        }
        let n = self.dim();
        if b.len() != n {
            return false;
        }
        substitute(&self.lu, &self.piv, b);
        b.iter().all(|v| v.is_finite())
    }

    /// LU with partial pivoting of `self.lu` in place (`P A = L U`, the unit
    /// lower factor below the diagonal), right-looking: at step `k` the
    /// largest entry of column `k` on or below the diagonal is the pivot, the
    /// column is divided by it, and each later column with a non-zero entry
    /// in row `k` is updated. A zero pivot leaves its column as it is (the
    /// caller finds it on the diagonal).
    fn eliminate(&mut self) {
        let Lu { lu, piv, col, .. } = self;
        eliminate(lu, piv, col);
    }

    /// Whether `x` solves `A x = b` to a residual of [`SOLVED_WITHIN`] of
    /// the sizes involved, `a` being the matrix last factorised.
    pub fn satisfies(&mut self, a: &Mat<f64>, x: &[f64], b: &[f64]) -> bool {
        let x_max = x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let b_max = b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        if !self.blocks.is_empty() {
            // Entries outside the blocks are zero by structure.
            let mut r = 0.0f64;
            for blk in &mut self.blocks {
                for (k, &i) in blk.idx.iter().enumerate() {
                    (blk.x[k], blk.b[k]) = (x[i], b[i]);
                }
                let res = &mut blk.lu.res;
                res.iter_mut().zip(&blk.b).for_each(|(r, v)| *r = -v);
                for (j, xj) in blk.x.iter().enumerate() {
                    for (ri, aij) in res.iter_mut().zip(blk.a.col_as_slice(j)) {
                        *ri += aij * xj;
                    }
                }
                r = res.iter().fold(r, |m, v| m.max(v.abs()));
            }
            return r <= SOLVED_WITHIN * (b_max + self.a_max * x_max);
        }
        let res = &mut self.res;
        res.iter_mut().zip(b).for_each(|(r, v)| *r = -v);
        for (j, xj) in x.iter().enumerate() {
            for (ri, aij) in res.iter_mut().zip(a.col_as_slice(j)) {
                *ri += aij * xj;
            }
        }
        let r = res.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        r <= SOLVED_WITHIN * (b_max + self.a_max * x_max)
    }

    /// The unknowns that are coordinates (the first).
    pub fn coords(&self) -> usize {
        self.coords
    }

    /// The scaling of [`super::condition`] for the matrix last factorised.
    pub fn scale(&self) -> Scale {
        if let Some(s) = self.scale.get() {
            return s;
        }
        let s = self.sizes().scale(self.coords);
        self.scale.set(Some(s));
        s
    }

    /// The sizes of the matrix factorised, by block.
    fn sizes(&self) -> BlockSizes {
        let mut sizes = BlockSizes::default();
        if !self.blocks.is_empty() {
            for blk in &self.blocks {
                sizes.merge(&blk.lu.sizes());
            }
            return sizes;
        }
        let c = self.coords.min(self.dim());
        let mut lanes = SizeLanes::default();
        for j in 0..self.dim() {
            let (top, bottom) = self.a.col_as_slice(j).split_at(c);
            lanes.add_column(j < c, top, bottom);
        }
        lanes.sizes()
    }

    /// `‖D (b - A) D‖_F / ‖D A D‖_F` for the matrix `A` last factorised and
    /// its scaling `D`: how far a reciprocal condition of `A` can be from
    /// that of `b`.
    pub fn distance_to(&self, b: &Mat<f64>) -> f64 {
        if !self.valid || b.nrows() != self.dim() || b.ncols() != self.dim() {
            return f64::INFINITY;
        }
        let s = self.scale();
        if !self.blocks.is_empty() {
            let mut d = 0.0f64;
            for blk in &self.blocks {
                for (c, &j) in blk.idx.iter().enumerate() {
                    let (x, y) = (blk.a.col_as_slice(c), b.col_as_slice(j));
                    for (xi, &i) in x.iter().zip(&blk.idx) {
                        let w = s.weight(i) * s.weight(j);
                        d += (xi - y[i]) * (xi - y[i]) * w * w;
                    }
                }
            }
            return d.sqrt() / s.fro;
        }
        let c = s.coords.min(self.dim());
        let mut d = DifferenceLanes::default();
        for j in 0..self.dim() {
            let (x, y) = (self.a.col_as_slice(j), b.col_as_slice(j));
            let ((xt, xb), (yt, yb)) = (x.split_at(c), y.split_at(c));
            d.add_column(j < c, (xt, yt), (xb, yb));
        }
        d.total(&s).sqrt() / s.fro
    }

    /// Adds `(b - A) y` to `out`, `A` the matrix last factorised (within its
    /// blocks: entries outside them are zero by structure in both).
    pub fn add_difference_times(&self, b: &Mat<f64>, y: &[f64], out: &mut [f64]) {
        if !self.blocks.is_empty() {
            for blk in &self.blocks {
                for (c, &j) in blk.idx.iter().enumerate() {
                    let (x, col) = (blk.a.col_as_slice(c), b.col_as_slice(j));
                    for (xi, &i) in x.iter().zip(&blk.idx) {
                        out[i] += (col[i] - xi) * y[j];
                    }
                }
            }
            return;
        }
        for (j, yj) in y.iter().enumerate() {
            let (x, col) = (self.a.col_as_slice(j), b.col_as_slice(j));
            for (o, (xi, bi)) in out.iter_mut().zip(x.iter().zip(col)) {
                *o += (bi - xi) * yj;
            }
        }
    }

    /// [`Self::reciprocal_condition_along`] from the cold start.
    #[cfg(test)]
    pub fn reciprocal_condition(&mut self) -> f64 {
        self.reciprocal_condition_along(&mut Direction::default())
    }

    /// An estimate of `σ_min / σ_max` of the factorised matrix `A` scaled
    /// as `D A D` ([`super::condition`]), from above (it may overstate the
    /// ratio, by a small factor for any matrix met in practice):
    /// `1 / (‖D A D‖_F · ‖(D A D)⁻¹ y‖)` after two inverse iterations from
    /// the irregular start, or one from where the last estimate of
    /// `direction` ended ([`super::condition::Direction`]).
    pub fn reciprocal_condition_along(&mut self, direction: &mut Direction) -> f64 {
        let n = self.dim();
        if !self.valid || n == 0 {
            return 0.0;
        }
        let s = self.scale();
        s.reciprocal_condition_along(n, direction, |y| self.solve(y))
    }
}

// The factorisation and substitutions as free functions. (A build with AVX2
// chosen at run time was worth 1-3 %: not worth `unsafe` in the solver.)

/// LU with partial pivoting of `lu` (`n × n` by columns, `n = piv.len()`)
/// in place.
fn eliminate(lu: &mut [f64], piv: &mut [usize], col: &mut [f64]) {
    let n = piv.len();
    for k in 0..n {
        let c = &lu[k * n + k..k * n + n];
        let mut p = 0;
        let mut best = c[0].abs();
        for (i, v) in c.iter().enumerate().skip(1) {
            if v.abs() > best {
                (p, best) = (i, v.abs());
            }
        }
        let p = k + p;
        piv[k] = p;
        if p != k {
            for cj in lu.chunks_exact_mut(n) {
                cj.swap(k, p);
            }
        }
        let d = lu[k * n + k];
        if d == 0.0 || !d.is_finite() {
            continue;
        }
        let ck = &mut lu[k * n + k + 1..k * n + n];
        ck.iter_mut().for_each(|v| *v /= d);
        // Only the rows from the first to the last non-zero multiplier change.
        let Some(first) = ck.iter().position(|v| *v != 0.0) else {
            continue;
        };
        let last = ck.iter().rposition(|v| *v != 0.0).unwrap_or(first);
        let (lo, hi) = (k + 1 + first, k + 2 + last);
        let l = &mut col[lo..hi];
        l.copy_from_slice(&ck[first..=last]);
        for cj in lu[(k + 1) * n..].chunks_exact_mut(n) {
            let u = cj[k];
            if u != 0.0 {
                for (x, li) in cj[lo..hi].iter_mut().zip(l.iter()) {
                    *x -= li * u;
                }
            }
        }
    }
}

/// `b` becomes `A⁻¹ b` for the factors of [`eliminate`].
fn substitute(lu: &[f64], piv: &[usize], b: &mut [f64]) {
    let n = piv.len();
    for (k, &p) in piv.iter().enumerate() {
        b.swap(k, p);
    }
    // L y = P b (unit diagonal), column by column, skipping zero entries of y.
    for k in 0..n {
        let bk = b[k];
        if bk != 0.0 {
            let l = &lu[k * n + k + 1..k * n + n];
            for (bi, li) in b[k + 1..n].iter_mut().zip(l) {
                *bi -= li * bk;
            }
        }
    }
    // U x = y, column by column from the last.
    for k in (0..n).rev() {
        let u = &lu[k * n..k * n + k + 1];
        b[k] /= u[k];
        let bk = b[k];
        if bk != 0.0 {
            for (bi, ui) in b[..k].iter_mut().zip(&u[..k]) {
                *bi -= ui * bk;
            }
        }
    }
}

#[cfg(test)]
#[path = "linear_tests.rs"]
mod tests;
