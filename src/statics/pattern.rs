//! The sparsity pattern of the scaled Newton matrix `[S K S, J^T; J, 0]`,
//! read once per [`super::Problem`] from which parts each element, load and
//! constraint wrench acts on (as [`super::blocks`] reads it), and the slots of
//! its value array that [`super::assembly`] scatters into.
//!
//! `K` is stored in 6×6 blocks of coupled parts (every part couples to
//! itself), and each multiplier in the rows and columns of the parts its
//! joint acts on. A wrench's parts do not depend on the state (a stop out of
//! contact still names its two parts, with zero stiffness), so the pattern
//! holds at every state. It is stored by columns (CSC), every column's rows
//! ascending: the 6 rows of each coupled part, then the multipliers; the six
//! columns of a part share one row structure, so a 3×3 block lands in three
//! contiguous runs of the value array found by one look-up in a table of
//! coupled parts.

use super::Problem;
use super::condition::{SizeDifferenceLanes, Slots};
use super::constraint::evaluate;
use super::coords::State;
use super::forces::for_each_element;
use super::products::Products;
use faer::sparse::SymbolicSparseColMatRef;
use std::ops::Range;

/// The slots of one equation's entries at one part's coordinates (see
/// [`Pattern::constraint_block`]).
#[derive(Debug, Clone, Copy)]
pub(crate) struct ConstraintBlock {
    row: usize,
    stride: usize,
    column: usize,
}

impl ConstraintBlock {
    /// The slots of `(n + k, 6 q + a)` and `(6 q + a, n + k)`.
    #[cfg(test)]
    pub fn slots(&self, a: usize) -> (usize, usize) {
        (self.row + a * self.stride, self.column + a)
    }

    /// Adds `g[a] * inv` to both entries of each coordinate `a` of the
    /// part: the equation's row (slots a column length apart) and its
    /// column (six contiguous slots); each range's bounds checked once.
    #[inline]
    pub fn add(&self, vals: &mut [f64], g: &[f64], inv: f64) {
        let row = &mut vals[self.row..=self.row + 5 * self.stride];
        for (x, g) in row.iter_mut().step_by(self.stride).zip(g) {
            *x += g * inv;
        }
        for (x, g) in vals[self.column..self.column + 6].iter_mut().zip(g) {
            *x += g * inv;
        }
    }
}

/// The slots of every 3×3 block of `K` a wrench between two given parts
/// can write ([`Pattern::wrench_slots`]): a wrench's parts do not change
/// from one evaluation to the next, so the assembly finds its blocks'
/// slots once and reads them by the blocks' local places
/// ([`super::wrench::Wrench::each_tangent`]), not by a search of the
/// pattern per block (44 instructions a block: 2 % of a McPherson case's
/// instructions).
#[derive(Debug, Clone, Copy)]
pub(crate) struct WrenchSlots {
    /// The wrench's coordinate offsets the slots are for.
    offsets: [Option<usize>; 2],
    /// Per local block `4 * row block + column block`, its three columns'
    /// first slots; [`NOT_COUPLED`] first where the pattern lacks it.
    at: [[u32; 3]; 16],
}

impl WrenchSlots {
    /// Whether these are the slots of a wrench with `offsets`.
    #[inline]
    pub fn are_for(&self, offsets: [Option<usize>; 2]) -> bool {
        self.offsets == offsets
    }

    /// The three columns' first slots of local block `k`, None if the
    /// pattern lacks the block.
    #[inline]
    pub fn block(&self, k: usize) -> Option<[usize; 3]> {
        let at = self.at[k];
        (at[0] != NOT_COUPLED).then(|| at.map(|a| a as usize))
    }
}

/// The column order of a [`Pattern::restricted`] pattern: AMD's of its own
/// slots, or one given (the whole pattern's, or the one a factorisation
/// chose, which widened slots keep).
#[derive(Debug, Clone, Copy)]
pub(crate) enum ColumnOrder<'a> {
    Amd,
    Given(&'a [usize]),
}

/// The inverse of the permutation `p`: `inverse(p)[p[k]] = k`.
pub(crate) fn inverse(p: &[usize]) -> Vec<usize> {
    let mut inv = vec![0; p.len()];
    for (k, &c) in p.iter().enumerate() {
        inv[c] = k;
    }
    inv
}

/// A pair of parts not coupled, in [`Pattern`]'s `block_at`.
const NOT_COUPLED: u32 = u32::MAX;

/// The most parts for which [`Pattern`] tabulates every pair (8 MB of
/// table; a whole vehicle has tens of parts).
const BLOCK_TABLE_PARTS: usize = 1024;

#[derive(Debug, Clone)]
pub(crate) struct Pattern {
    /// Coordinates (6 per moving part) and multipliers.
    n: usize,
    m: usize,
    /// Per part, the parts coupled to it (itself included), ascending.
    parts: Vec<Vec<usize>>,
    /// Per pair of parts `(c, r)` at `c * parts + r`: the slot of `r`'s
    /// first row in `c`'s first column ([`NOT_COUPLED`] if absent) and the
    /// length of `c`'s columns (the six hold the same rows, so a row's
    /// slots in them are a length apart). [`Pattern::block_slots`]'s
    /// search done once: one load instead of a binary search and three
    /// columns' starts per 3×3 block scattered. Empty beyond
    /// [`BLOCK_TABLE_PARTS`] parts and in a [`Pattern::restricted`] one,
    /// where the search is kept.
    block_at: Vec<(u32, u32)>,
    /// Per multiplier, the parts its equation acts on, ascending.
    of_mult: Vec<Vec<usize>>,
    /// Per multiplier `k` and each of its parts `q` (as in `of_mult`), where
    /// its equation's entries lie ([`Pattern::constraint_block`]), found
    /// once instead of at every evaluation. Empty in a
    /// [`Pattern::restricted`] one, which no assembly scatters into.
    mult_blocks: Vec<Vec<ConstraintBlock>>,
    pub col_ptr: Vec<usize>,
    pub row_idx: Vec<usize>,
    /// Per column, the end of its coordinate rows (they come first, the
    /// multipliers' after; a multiplier's column has only coordinate rows).
    pub coord_end: Vec<usize>,
    /// The slots of the blocks `K`, `C` and `Cᵀ`, `Z` of `[K Cᵀ; C Z]`
    /// (the condition estimates' weights, [`super::condition`]).
    kkt_blocks: [Slots; 3],
    /// A fill-reducing column order (AMD, or the one a factorisation chose,
    /// [`Pattern::set_order`]) and its inverse, for the sparse LU.
    pub order: Vec<usize>,
    pub order_inv: Vec<usize>,
    /// Every slot row by row (`(column, slot)`, each row's at
    /// `rows.1[rows.0[i]..rows.0[i + 1]]`), made when first asked for
    /// ([`Pattern::rows`]).
    rows: std::sync::OnceLock<(Vec<usize>, Products)>,
    /// The pivots every sparse LU of the problem starts from (those of the
    /// matrix at design, [`super::tangent::seed_pivots`], set by the first
    /// solver; None: the design matrix could not be factorised).
    pub pivots: std::sync::OnceLock<Option<super::sparse::Pivots>>,
}

impl Pattern {
    /// The pattern of `p`'s Newton matrix; None when a wrench's parts cannot
    /// be read at design, an equation acts on no moving part, or its slots
    /// do not fit the 32-bit indices of [`super::live::Live`]'s rows (four
    /// billion entries: far beyond any mechanism).
    pub fn new(p: &Problem) -> Option<Pattern> {
        let (n, m) = (p.layout.n(), p.kept.len());
        let np = n / 6;
        let st = State::design(&p.model);
        let mut parts: Vec<Vec<usize>> = (0..np).map(|i| vec![i]).collect();
        let mut couple = |a: usize, b: usize| {
            parts[a].push(b);
            parts[b].push(a);
        };
        for_each_element(&p.model, &p.layout, &st, |_, w| {
            if let [Some(a), Some(b)] = w.offsets() {
                couple(a / 6, b / 6);
            }
        })
        .ok()?;
        let mut mults: Vec<Vec<usize>> = vec![Vec::new(); np];
        let mut of_mult = Vec::with_capacity(m);
        for (k, &e) in p.kept.iter().enumerate() {
            let (_, w) = evaluate(&p.model, &p.layout, &st, &p.equations[e]);
            let mut on: Vec<usize> = w.offsets().iter().flatten().map(|o| o / 6).collect();
            if on.is_empty() {
                return None;
            }
            on.sort_unstable();
            on.dedup();
            if let [a, b] = on[..] {
                couple(a, b);
            }
            for &q in &on {
                mults[q].push(k);
            }
            of_mult.push(on);
        }
        for v in &mut parts {
            v.sort_unstable();
            v.dedup();
        }
        let (mut col_ptr, mut row_idx, mut coord_end) = (vec![0], Vec::new(), Vec::new());
        for j in 0..n + m {
            if j < n {
                let q = j / 6;
                row_idx.extend(parts[q].iter().flat_map(|&r| 6 * r..6 * r + 6));
                coord_end.push(row_idx.len());
                row_idx.extend(mults[q].iter().map(|k| n + k));
            } else {
                row_idx.extend(of_mult[j - n].iter().flat_map(|&r| 6 * r..6 * r + 6));
                coord_end.push(row_idx.len());
            }
            col_ptr.push(row_idx.len());
        }
        // Equation `k`'s row among the multiplier rows of each of its parts'
        // columns (the multipliers acting on `q`, ascending), after `q`'s
        // coupled parts' coordinate rows; its column's rows are its parts'.
        let mult_blocks = of_mult
            .iter()
            .enumerate()
            .map(|(k, on)| {
                on.iter()
                    .enumerate()
                    .map(|(tp, &q)| {
                        let first = col_ptr[6 * q];
                        Some(ConstraintBlock {
                            row: first + 6 * parts[q].len() + mults[q].binary_search(&k).ok()?,
                            stride: col_ptr[6 * q + 1] - first,
                            column: col_ptr[n + k] + 6 * tp,
                        })
                    })
                    .collect::<Option<Vec<_>>>()
            })
            .collect::<Option<Vec<_>>>()?;
        if u32::try_from(row_idx.len()).is_err() {
            return None;
        }
        let kkt_blocks = kkt_blocks(n, &col_ptr, &coord_end);
        let (order, order_inv) = column_order(n + m, &col_ptr, &row_idx)?;
        let mut block_at = Vec::new();
        if np <= BLOCK_TABLE_PARTS {
            block_at = vec![(NOT_COUPLED, 0); np * np];
            for (c, list) in parts.iter().enumerate() {
                // (The slots fit in 32 bits, checked above.)
                let (first, len) = (col_ptr[6 * c], col_ptr[6 * c + 1] - col_ptr[6 * c]);
                for (t, &r) in list.iter().enumerate() {
                    block_at[c * np + r] = ((first + 6 * t) as u32, len as u32);
                }
            }
        }
        Some(Pattern {
            n,
            m,
            parts,
            block_at,
            of_mult,
            mult_blocks,
            col_ptr,
            row_idx,
            coord_end,
            kkt_blocks,
            order,
            order_inv,
            rows: std::sync::OnceLock::new(),
            pivots: std::sync::OnceLock::new(),
        })
    }

    pub fn dim(&self) -> usize {
        self.n + self.m
    }

    /// The pattern of the slots `keep` holds (the rest left out), with the
    /// column order `order`; None if AMD fails.
    pub fn restricted(&self, keep: &[bool], order: ColumnOrder) -> Option<Pattern> {
        let (mut col_ptr, mut row_idx, mut coord_end) = (vec![0], Vec::new(), Vec::new());
        for j in 0..self.dim() {
            let (top, bottom) = self.column_halves(j);
            row_idx.extend(top.filter(|&k| keep[k]).map(|k| self.row_idx[k]));
            coord_end.push(row_idx.len());
            row_idx.extend(bottom.filter(|&k| keep[k]).map(|k| self.row_idx[k]));
            col_ptr.push(row_idx.len());
        }
        let (order, order_inv) = match order {
            ColumnOrder::Amd => column_order(self.dim(), &col_ptr, &row_idx)?,
            ColumnOrder::Given(o) => (o.to_vec(), inverse(o)),
        };
        // The parts' lists are the assembly's, kept for a whole pattern's
        // shape. The assembly scatters into whole patterns only, so the
        // table of coupled parts is not copied (`block_slots` searches the
        // lists here); the seed pivots are this pattern's, not the new one's.
        Some(Pattern {
            n: self.n,
            m: self.m,
            parts: self.parts.clone(),
            block_at: Vec::new(),
            of_mult: self.of_mult.clone(),
            mult_blocks: Vec::new(),
            kkt_blocks: kkt_blocks(self.n, &col_ptr, &coord_end),
            col_ptr,
            row_idx,
            coord_end,
            order,
            order_inv,
            rows: std::sync::OnceLock::new(),
            pivots: std::sync::OnceLock::new(),
        })
    }

    /// Factorises with the columns in `order` (a permutation of them).
    pub fn set_order(&mut self, order: Vec<usize>) {
        self.order_inv = inverse(&order);
        self.order = order;
    }

    /// The coordinates (the first rows and columns; the multipliers follow).
    pub fn coords(&self) -> usize {
        self.n
    }

    /// The slots of column `j`'s coordinate rows and of its multiplier rows.
    pub fn column_halves(&self, j: usize) -> (Range<usize>, Range<usize>) {
        let (start, mid, end) = (self.col_ptr[j], self.coord_end[j], self.col_ptr[j + 1]);
        (start..mid, mid..end)
    }

    pub fn nnz(&self) -> usize {
        self.row_idx.len()
    }

    /// Every slot row by row: each row's `(column, slot)` pairs at
    /// `pairs[starts[i]..starts[i + 1]]` (a product of a matrix in these
    /// slots with a vector as one sum a row, in a register).
    pub fn rows(&self) -> &(Vec<usize>, Products) {
        self.rows.get_or_init(|| {
            // The live slots' rows ([`super::live::rows`]) with every slot live.
            let every: Vec<usize> = (0..self.nnz()).collect();
            super::live::rows(self, &every)
        })
    }

    /// The sizes of the matrix of `x` (in this pattern's slots), block by
    /// block, and the differences of `x - y`, in one pass a block.
    pub fn sizes_and_difference(&self, x: &[f64], y: &[f64]) -> SizeDifferenceLanes {
        let mut lanes = SizeDifferenceLanes::default();
        for (b, slots) in self.kkt_blocks.iter().enumerate() {
            lanes.take(b, slots, x, y);
        }
        lanes
    }

    /// The slot of entry `(row, col)` for a coordinate `row`: the first of the
    /// contiguous slots of rows `row..` of the same part in column `col`.
    #[cfg(test)]
    pub fn slot(&self, row: usize, col: usize) -> Option<usize> {
        let list = if col < self.n {
            &self.parts[col / 6]
        } else {
            self.of_mult.get(col - self.n)?
        };
        let t = list.binary_search(&(row / 6)).ok()?;
        Some(self.col_ptr[col] + 6 * t + row % 6)
    }

    /// The first slots of rows `row..row + 3` in the three columns
    /// `col..col + 3` of one part (a 3×3 block of `K`): one look-up for all.
    #[inline]
    pub fn block_slots(&self, row: usize, col: usize) -> Option<[usize; 3]> {
        let (c, r) = (col / 6, row / 6);
        if col % 6 > 3 {
            return None;
        }
        if self.block_at.is_empty() {
            let t = self.parts.get(c)?.binary_search(&r).ok()?;
            let off = 6 * t + row % 6;
            return Some([0, 1, 2].map(|b| self.col_ptr[col + b] + off));
        }
        let np = self.parts.len();
        if c >= np || r >= np {
            return None;
        }
        match self.block_at[c * np + r] {
            (NOT_COUPLED, _) => None,
            (first, len) => {
                let len = len as usize;
                let at = first as usize + (col % 6) * len + row % 6;
                Some([at, at + len, at + 2 * len])
            }
        }
    }

    /// The slots of the 3×3 blocks a wrench with coordinate `offsets`
    /// (its parts I and J, [`super::wrench::Wrench::offsets`]) writes, by
    /// [`Self::block_slots`].
    pub fn wrench_slots(&self, offsets: [Option<usize>; 2]) -> WrenchSlots {
        // A block's first row or column: its side's offset and its half.
        let first = |b: usize| offsets[b / 2].map(|o| o + 3 * (b % 2));
        let at = std::array::from_fn(|k| {
            match (first(k / 4), first(k % 4)) {
                // (The slots fit in 32 bits: `Pattern::new`.)
                (Some(r), Some(c)) => self.block_slots(r, c).map(|s| s.map(|a| a as u32)),
                _ => None,
            }
            .unwrap_or([NOT_COUPLED; 3])
        });
        WrenchSlots { offsets, at }
    }

    /// The slots of the two entries of multiplier `k`'s equation at
    /// coordinate `col`: `(n + k, col)` and `(col, n + k)` (the constraint
    /// Jacobian and its transpose).
    #[cfg(test)]
    pub fn constraint_slots(&self, k: usize, col: usize) -> Option<(usize, usize)> {
        self.constraint_block(k, col / 6).map(|b| b.slots(col % 6))
    }

    /// Where multiplier `k`'s equation meets the six coordinates of part
    /// `q` (None: it does not act on `q`), by the positions found once in
    /// `new`: the six columns of a part hold the same rows, so its row is
    /// at one offset in each, a column length apart.
    pub fn constraint_block(&self, k: usize, q: usize) -> Option<ConstraintBlock> {
        let tp = self.of_mult.get(k)?.iter().position(|&x| x == q)?;
        self.mult_blocks.get(k)?.get(tp).copied()
    }
}

/// The slots of `[K Cᵀ; C Z]`'s blocks, in [`SizeDifferenceLanes::take`]'s
/// order (`K`, `C` and `Cᵀ`, `Z`): the coordinate columns' coordinate rows
/// are `K`'s, their multiplier rows `C`'s; the multipliers' columns'
/// coordinate rows are `Cᵀ`'s, their multiplier rows `Z`'s (none in a
/// Newton matrix).
fn kkt_blocks(n: usize, col_ptr: &[usize], coord_end: &[usize]) -> [Slots; 3] {
    let mut at: [Vec<u32>; 3] = Default::default();
    for (j, (w, &mid)) in col_ptr.windows(2).zip(coord_end).enumerate() {
        let (top, bottom) = if j < n { (0, 1) } else { (1, 2) };
        // (The pattern's slots fit in 32 bits: `Pattern::new`.)
        at[top].extend((w[0]..mid).map(|k| k as u32));
        at[bottom].extend((mid..w[1]).map(|k| k as u32));
    }
    at.map(Slots::new)
}

/// AMD's order of the (symmetric) pattern, computed once. Measured against
/// COLAMD's (which bounds the fill of an LU with any row pivoting): on eight
/// coupled corners AMD's factors had 12.5k non-zeros against 13.7k, with
/// partial pivoting; with the pivots of [`super::pivoting`], 9.3k.
fn column_order(
    dim: usize,
    col_ptr: &[usize],
    row_idx: &[usize],
) -> Option<(Vec<usize>, Vec<usize>)> {
    use faer::sparse::linalg::amd;
    let a = SymbolicSparseColMatRef::new_checked(dim, dim, col_ptr, None, row_idx);
    let (mut fwd, mut inv) = (vec![0usize; dim], vec![0usize; dim]);
    let req = amd::order_scratch::<usize>(dim, row_idx.len());
    let mut mem = faer::dyn_stack::MemBuffer::try_new(req).ok()?;
    let stack = faer::dyn_stack::MemStack::new(&mut mem);
    amd::order(&mut fwd, &mut inv, a, amd::Control::default(), stack).ok()?;
    Some((fwd, inv))
}

#[cfg(test)]
#[path = "pattern_tests.rs"]
mod tests;
