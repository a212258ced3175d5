//! The sums of products the sparse LU spends its time in, over index pairs
//! checked once.
//!
//! A refactorisation ([`super::refactor`]) computes each entry of the
//! factors as its matrix entry minus products `L[e] U[f]`; the
//! substitutions ([`super::sparse`]) and the residual check
//! ([`super::live`]) sum a row's entries times a vector's. Each product
//! reads two values through a pair of indices taken from a list, and
//! indexing both checked its bound: two comparisons and branches in a
//! product of five instructions. The pairs are fixed with the factors'
//! structure, so their bounds are found once, when the list is made, and a
//! sum checks the two arrays it reads against them once instead of at every
//! product (6 % of the instructions of a McPherson path,
//! `docs/performance.md`). The refactorisation and the substitutions, which
//! sum every pair once, run after run, check them once a pass ([`Sweep`]).

use std::cell::Cell;
use std::ops::Range;

/// Index pairs `(a, b)` into two arrays, and the least lengths those arrays
/// need (one more than the largest `a` and the largest `b`). The pairs are
/// not changed once made, so the bounds stay theirs.
#[derive(Debug, Clone, Default)]
pub(crate) struct Products {
    pairs: Vec<(u32, u32)>,
    need: (usize, usize),
}

impl Products {
    pub fn new(pairs: Vec<(u32, u32)>) -> Products {
        let need = pairs.iter().fold((0, 0), |(na, nb), &(a, b)| {
            (na.max(a as usize + 1), nb.max(b as usize + 1))
        });
        Products { pairs, need }
    }

    /// The pairs, in order.
    pub fn pairs(&self) -> &[(u32, u32)] {
        &self.pairs
    }

    #[cfg(test)]
    pub fn len(&self) -> usize {
        self.pairs.len()
    }

    /// `acc + Σ x[a] y[b]` over the pairs `range`, added in order (the bits
    /// of the indexed loop it replaces).
    ///
    /// Panics if `range` is outside the pairs or `x` or `y` is shorter
    /// than the pairs need.
    #[inline]
    pub fn add_to(&self, acc: f64, range: Range<usize>, x: &[f64], y: &[f64]) -> f64 {
        self.check(x.len(), y.len());
        let mut acc = acc;
        for &(a, b) in &self.pairs[range] {
            // SAFETY: `check`: `x.len() >= need.0 > a` and
            // `y.len() >= need.1 > b` for every pair (`new`).
            acc += unsafe { x.get_unchecked(a as usize) * y.get_unchecked(b as usize) };
        }
        acc
    }

    /// `acc + Σ (y[b] - z[b]) x[a]` over the pairs `range`, added in
    /// order: the product of a difference of two matrices in the same
    /// slots (`y`, `z`) with a vector (`x`); panics as
    /// [`Self::add_to`] (`y` and `z` each as long as the pairs need).
    #[inline]
    pub fn add_difference_to(
        &self,
        acc: f64,
        range: Range<usize>,
        x: &[f64],
        y: &[f64],
        z: &[f64],
    ) -> f64 {
        self.check(x.len(), y.len().min(z.len()));
        let mut acc = acc;
        for &(a, b) in &self.pairs[range] {
            let (a, b) = (a as usize, b as usize);
            // SAFETY: `check`, as in `add_to`.
            acc += unsafe { (y.get_unchecked(b) - z.get_unchecked(b)) * x.get_unchecked(a) };
        }
        acc
    }

    /// A sweep over every pair, reading `x[a]` and `y[b]`.
    ///
    /// Panics if `x` or `y` is shorter than the pairs need.
    pub fn sweep<'a, X: Values + ?Sized, Y: Values + ?Sized>(
        &'a self,
        x: &'a X,
        y: &'a Y,
    ) -> Sweep<'a, X, Y> {
        self.check(x.len(), y.len());
        Sweep {
            pairs: &self.pairs,
            x,
            y,
        }
    }

    /// Panics unless arrays of these lengths hold every pair's first and
    /// second index: the one check the unchecked reads above rely on (two
    /// comparisons a sum or a sweep, not two a product).
    #[inline(always)]
    fn check(&self, x_len: usize, y_len: usize) {
        assert!(
            x_len >= self.need.0 && y_len >= self.need.1,
            "an array shorter than its products' indices"
        );
    }
}

/// Arrays a [`Sweep`] reads by index: plain ones, and arrays of cells,
/// which a refactorisation writes while its products read them.
///
/// # Safety
/// `at(i)` must be valid for every `i < len()`: a sweep checks the pairs'
/// bounds against `len` once and then reads without a check.
pub(crate) unsafe trait Values {
    fn len(&self) -> usize;
    /// The entry `i`.
    ///
    /// # Safety
    /// `i < self.len()`.
    unsafe fn at(&self, i: usize) -> f64;
}

// SAFETY: `len` is the slice's, and `at` reads within it.
unsafe impl Values for [f64] {
    fn len(&self) -> usize {
        <[f64]>::len(self)
    }
    #[inline(always)]
    unsafe fn at(&self, i: usize) -> f64 {
        // SAFETY: the caller's.
        unsafe { *self.get_unchecked(i) }
    }
}

// SAFETY: `len` is the slice's, and `at` reads within it.
unsafe impl Values for [Cell<f64>] {
    fn len(&self) -> usize {
        <[Cell<f64>]>::len(self)
    }
    #[inline(always)]
    unsafe fn at(&self, i: usize) -> f64 {
        // SAFETY: the caller's.
        unsafe { self.get_unchecked(i).get() }
    }
}

/// The pairs of a [`Products`] taken a run at a time, from the front or
/// from the back, over two arrays checked against them once: a
/// refactorisation and a substitution sum every pair once, run after run
/// (an entry of the factors, a row), and checking the arrays and the run's
/// range at each run cost about as much as its two or three products
/// (`docs/performance.md`).
pub(crate) struct Sweep<'a, X: ?Sized, Y: ?Sized> {
    pairs: &'a [(u32, u32)],
    x: &'a X,
    y: &'a Y,
}

impl<X: Values + ?Sized, Y: Values + ?Sized> Sweep<'_, X, Y> {
    /// `acc - Σ x[a] y[b]` over the next `count` pairs from the front,
    /// subtracted in order (the bits of the indexed loop it replaces).
    ///
    /// Panics if fewer than `count` pairs remain.
    #[inline]
    pub fn subtract_next(&mut self, acc: f64, count: usize) -> f64 {
        assert!(count <= self.pairs.len(), "fewer pairs left than asked for");
        // SAFETY: checked above.
        unsafe { self.subtract_next_unchecked(acc, count) }
    }

    /// [`Self::subtract_next`] without checking that `count` pairs remain
    /// (a refactorisation's entries take every pair once, by counts fixed
    /// with its plan: two instructions an entry saved); the checked one is
    /// this after its check.
    ///
    /// # Safety
    /// At least `count` pairs remain.
    #[inline]
    pub unsafe fn subtract_next_unchecked(&mut self, acc: f64, count: usize) -> f64 {
        // SAFETY: the caller's.
        let (now, rest) = unsafe { self.pairs.split_at_unchecked(count) };
        self.pairs = rest;
        self.subtract(acc, now)
    }

    /// `acc - Σ x[a] y[b]` over the last `count` pairs that remain, in
    /// their order; panics as [`Self::subtract_next`].
    #[inline]
    pub fn subtract_last(&mut self, acc: f64, count: usize) -> f64 {
        let Some(at) = self.pairs.len().checked_sub(count) else {
            panic!("fewer pairs left than asked for");
        };
        let (rest, now) = self.pairs.split_at(at);
        self.pairs = rest;
        self.subtract(acc, now)
    }

    #[inline(always)]
    fn subtract(&self, acc: f64, pairs: &[(u32, u32)]) -> f64 {
        let mut acc = acc;
        for &(a, b) in pairs {
            // SAFETY: every pair of the products is within `need`, which
            // `x` and `y` were checked against (`Products::sweep`, `check`).
            acc -= unsafe { self.x.at(a as usize) * self.y.at(b as usize) };
        }
        acc
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The sums are the indexed loops' to the bit, and an array too short
    /// for any pair (not only those summed) is refused.
    #[test]
    fn sums_are_the_indexed_loops_and_short_arrays_are_refused() {
        let pairs = vec![(3, 0), (0, 2), (1, 1), (3, 2)];
        let p = Products::new(pairs.clone());
        let x = [0.1, -2.5, 7.0, 1.0 / 3.0];
        let y = [1e-3, 9.0, -0.7];
        let (mut minus, mut plus) = (5.0, -5.0);
        for &(a, b) in &pairs[1..4] {
            minus -= x[a as usize] * y[b as usize];
            plus += x[a as usize] * y[b as usize];
        }
        assert_eq!(p.add_to(-5.0, 1..4, &x, &y).to_bits(), plus.to_bits());
        assert_eq!(p.add_to(5.0, 2..2, &x, &y), 5.0);
        // A sweep: the first pair alone, then three, then none left.
        let mut sweep = p.sweep(&x[..], &y[..]);
        let first = 1.5 - x[3] * y[0];
        assert_eq!(sweep.subtract_next(1.5, 1).to_bits(), first.to_bits());
        assert_eq!(sweep.subtract_next(5.0, 3).to_bits(), minus.to_bits());
        assert_eq!(sweep.subtract_next(2.0, 0), 2.0);
        // From the back, over cells: the last three, then the first.
        let cells = Cell::from_mut(&mut [0.1, -2.5, 7.0, 1.0 / 3.0][..])
            .as_slice_of_cells()
            .to_vec();
        let mut sweep = p.sweep(&cells[..], &y[..]);
        assert_eq!(sweep.subtract_last(5.0, 3).to_bits(), minus.to_bits());
        assert_eq!(sweep.subtract_last(1.5, 1).to_bits(), first.to_bits());
        // The pair (3, 0), outside the range summed, still needs x[3].
        let short = std::panic::catch_unwind(|| p.add_to(0.0, 1..2, &x[..3], &y));
        assert!(short.is_err());
        assert!(std::panic::catch_unwind(|| p.sweep(&x[..], &y[..2])).is_err());
        assert!(std::panic::catch_unwind(|| p.sweep(&x[..3], &y[..])).is_err());
        assert!(std::panic::catch_unwind(|| p.add_to(0.0, 3..5, &x, &y)).is_err());
        // More pairs than remain, from either end.
        let more = |back: bool| {
            std::panic::catch_unwind(|| {
                let mut sweep = p.sweep(&x[..], &y[..]);
                sweep.subtract_next(0.0, 2);
                if back {
                    sweep.subtract_last(0.0, 3)
                } else {
                    sweep.subtract_next(0.0, 3)
                }
            })
        };
        assert!(more(false).is_err() && more(true).is_err());
    }
}
