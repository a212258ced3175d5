//! Which slots of the Newton matrix's [`Pattern`] the sparse LU
//! ([`super::sparse`]) factorises: those that can hold a non-zero, found at
//! design and at a generic state near it ([`super::tangent::seed_pivots`]),
//! widened when a matrix has a significant entry outside them.

use super::condition::largest;
use super::pattern::{ColumnOrder, Pattern};
use super::pivoting::by_rows;
use super::products::Products;

/// An entry outside a factorisation's slots ([`Live`]) no larger than this
/// fraction of the matrix's largest is left out of it: it is taken for the
/// rounding of an exact zero (four translation entries of two of the car's
/// parts, zero at design and near it, read 7e-15 at the curb), and leaving
/// it out changes the solution by far less than the residual check allows
/// (`satisfies`, 1e-8 of the sizes involved, against this times the number
/// of entries).
pub(super) const DROP: f64 = 1e-14;

/// The slots of a [`Pattern`] the factors are computed on: those that may
/// hold a non-zero. The pattern is structural (whole 6×6 blocks of coupled
/// parts, a joint equation at all six coordinates of its parts), and most of
/// it is zero in every matrix: a joint's equation involves three of a part's
/// six coordinates, and a joint's curvature only its rotations. The seed
/// pivots' slots ([`super::tangent::seed_pivots`]) are 385 of the 828 on one
/// McPherson corner, where a refactorisation on them took 1 736
/// multiply-adds instead of 4 116 on all (on AMD's orders; 1 346 since
/// the seed's columns are ordered with its pivots), and 1 902 of 4 824 on
/// the car (10 401 instead of 33 427; `docs/performance.md`). A matrix with an
/// entry above [`DROP`] outside them (a stop coming into contact) widens
/// them for the solver that met it ([`SparseLu::factor`]).
#[derive(Debug)]
pub(crate) struct Live {
    /// The pattern of the live slots, with its own column order.
    pub(super) pattern: Pattern,
    /// Per slot of `pattern`, the slot of the full pattern it is (read
    /// through [`Self::from`]: `from_need` must stay its bound).
    from: Vec<usize>,
    /// One more than the largest of `from` (0 for none).
    from_need: usize,
    /// Per slot of the full pattern, all bits set if it is not live (the
    /// other slots: at most [`DROP`] of the largest entry in every matrix
    /// factorised), none if it is: a mask `holds` applies to every slot
    /// (the car's 2 922 dead slots lie in hundreds of short runs, whose
    /// loop cost 4 % of a single case).
    outside: Vec<u64>,
    /// The live slots row by row: `(column, slot of the full pattern)`,
    /// row `i`'s at `by_row[row_ptr[i]..row_ptr[i + 1]]` (a product `A x`
    /// as one sum a row, in a register, [`Live::residual`]).
    row_ptr: Vec<usize>,
    by_row: Products,
}

impl Live {
    /// The slots of `full` that `keep` holds, in the column order `order`;
    /// None if AMD fails.
    pub fn ordered(full: &Pattern, keep: &[bool], order: ColumnOrder) -> Option<Live> {
        let pattern = full.restricted(keep, order)?;
        let from: Vec<usize> = (0..full.nnz()).filter(|&k| keep[k]).collect();
        let outside = (0..full.nnz())
            .map(|k| if keep[k] { 0 } else { u64::MAX })
            .collect();
        let (row_ptr, by_row) = rows(&pattern, &from);
        Some(Live {
            pattern,
            from_need: need(&from),
            from,
            outside,
            row_ptr,
            by_row,
        })
    }

    /// Every slot of `full`.
    pub fn all(full: &Pattern) -> Live {
        let from: Vec<usize> = (0..full.nnz()).collect();
        let (row_ptr, by_row) = rows(full, &from);
        Live {
            pattern: full.clone(),
            from_need: need(&from),
            from,
            outside: vec![0; full.nnz()],
            row_ptr,
            by_row,
        }
    }

    /// The largest magnitude of the entries of `A x - b`, for the matrix
    /// `A` of `values` (in the full pattern's slots) on these slots (a NaN
    /// passed over, as by `f64::max`). Row by row: a column-wise product
    /// adds into memory, a chain of dependent loads and stores per row.
    pub fn residual(&self, values: &[f64], x: &[f64], b: &[f64]) -> f64 {
        let mut big = 0.0f64;
        for (i, bi) in b.iter().enumerate() {
            let row = self.row_ptr[i]..self.row_ptr[i + 1];
            let acc = self.by_row.add_to(-bi, row, x, values);
            big = if acc.abs() > big { acc.abs() } else { big };
        }
        big
    }

    /// The slots of `values` (a matrix in a pattern's slots) above [`DROP`]
    /// times its largest entry (and those not a number).
    pub fn significant(values: &[f64]) -> Vec<bool> {
        let tol = DROP * largest(values);
        values.iter().map(|v| v.abs() > tol || v.is_nan()).collect()
    }

    /// Whether every entry of `values` (in the full pattern's slots) outside
    /// these slots is at most [`DROP`] times `largest` (the matrix's largest
    /// entry), and a number.
    // (`!(x <= tol)` on purpose: a NaN must fail it.)
    #[allow(clippy::neg_cmp_op_on_partial_ord)]
    pub fn holds(&self, values: &[f64], largest: f64) -> bool {
        // One pass over every slot, the live ones masked to zero, without a
        // branch: an entry past the tolerance or not a number fails `<=`
        // (one comparison, which vectorises; `>` and `is_nan` apart, it
        // took 50 000 instructions a factorisation of eight coupled
        // corners, whose outside entries are not all exact zeros, after a
        // pass OR-ing their bits that found so). A tolerance that is not a
        // number (a matrix's largest entry never is) lets only NaNs fail.
        let tol = DROP * largest;
        let tol = if tol.is_nan() { f64::INFINITY } else { tol };
        let mut out = 0u64;
        for (v, m) in values.iter().zip(&self.outside) {
            let x = f64::from_bits(v.to_bits() & m).abs();
            out |= u64::from(!(x <= tol));
        }
        out == 0
    }

    /// The bits of every entry of `values` (in the full pattern's slots)
    /// outside these slots OR-ed together: zero when all of them are exact
    /// zeros (`+0.0`), as in every McPherson matrix met so far (eight
    /// coupled corners' hold roundings there).
    pub fn outside_bits(&self, values: &[f64]) -> u64 {
        values
            .iter()
            .zip(&self.outside)
            .fold(0u64, |acc, (v, m)| acc | (v.to_bits() & m))
    }

    /// The entries of `values` outside these slots set to zero.
    pub fn clear_outside(&self, values: &mut [f64]) {
        for (v, m) in values.iter_mut().zip(&self.outside) {
            *v = f64::from_bits(v.to_bits() & !m);
        }
    }

    /// These slots and the [`significant`](Self::significant) ones of
    /// `values`, in these slots' column order.
    pub fn widened(&self, full: &Pattern, values: &[f64]) -> Option<Live> {
        let mut keep = Live::significant(values);
        self.from.iter().for_each(|&k| keep[k] = true);
        Live::ordered(full, &keep, ColumnOrder::Given(&self.pattern.order))
    }

    /// Per live slot, the slot of the full pattern it is.
    pub fn from(&self) -> &[usize] {
        &self.from
    }

    /// One more than the largest slot of [`Self::from`] (0 for none): the
    /// least length of a matrix in the full pattern's slots that holds them.
    pub fn matrix_need(&self) -> usize {
        self.from_need
    }

    /// `values` (in the full pattern's slots) at the live slots copied
    /// into `a` (the other slots of `a` left as they are), and their
    /// largest magnitude (NaNs passed over). By index, unchecked, in eight
    /// lanes of the maximum: the copy was one load and two stores an entry
    /// (into `a` and a vector of the live entries, for the maximum's pass
    /// after), each index checked against both arrays.
    ///
    /// Panics if `values` or `a` is shorter than the full pattern's slots
    /// that are live.
    pub fn copy_into(&self, values: &[f64], a: &mut [f64]) -> f64 {
        assert!(
            self.from_need <= values.len() && self.from_need <= a.len(),
            "a matrix shorter than its live slots"
        );
        let mut mx = [0.0f64; 8];
        let mut copy = |lane: usize, k: usize| {
            // SAFETY: `k < from_need` (its definition), asserted above to
            // be within both arrays.
            let x = unsafe { *values.get_unchecked(k) };
            unsafe { *a.get_unchecked_mut(k) = x };
            let v = x.abs();
            mx[lane] = if v > mx[lane] { v } else { mx[lane] };
        };
        let mut chunks = self.from.chunks_exact(8);
        for c in &mut chunks {
            for (lane, &k) in c.iter().enumerate() {
                copy(lane, k);
            }
        }
        for (lane, &k) in chunks.remainder().iter().enumerate() {
            copy(lane, k);
        }
        mx.iter().fold(0.0f64, |m, v| m.max(*v))
    }

    /// The slots kept, of how many.
    #[cfg(test)]
    pub fn count(&self) -> (usize, usize) {
        let dead = self.outside.iter().filter(|m| **m != 0).count();
        (self.from.len(), self.from.len() + dead)
    }
}

/// One more than the largest slot of `from`, 0 for none.
fn need(from: &[usize]) -> usize {
    from.iter().max().map_or(0, |k| k + 1)
}

/// The slots of `pattern` (the full pattern's `from`) row by row, as
/// [`Live::by_row`] holds them, with the rows' starts: the pattern's
/// entries by rows ([`by_rows`], as the factors'), each then named by its
/// slot of the full pattern. (The full pattern's slots, and so its
/// dimension, fit in 32 bits: [`Pattern::new`].)
pub(super) fn rows(pattern: &Pattern, from: &[usize]) -> (Vec<usize>, Products) {
    let n = pattern.dim();
    let columns = (0..n).map(|j| (j, pattern.col_ptr[j]..pattern.col_ptr[j + 1]));
    // (`None` only past 32 bits, which the pattern excludes.)
    let (row_ptr, mut by_row) = by_rows(n, columns, &pattern.row_idx).unwrap_or_default();
    for (_, k) in &mut by_row {
        *k = from[*k as usize] as u32;
    }
    (row_ptr, Products::new(by_row))
}
