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
//! contiguous runs of the value array found by one search of a short list.

use super::Problem;
use super::constraint::evaluate;
use super::coords::State;
use super::forces::for_each_element;
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
    pub fn slots(&self, a: usize) -> (usize, usize) {
        (self.row + a * self.stride, self.column + a)
    }
}

#[derive(Debug, Clone)]
pub(crate) struct Pattern {
    /// Coordinates (6 per moving part) and multipliers.
    n: usize,
    m: usize,
    /// Per part, the parts coupled to it (itself included), ascending.
    parts: Vec<Vec<usize>>,
    /// Per multiplier, the parts its equation acts on, ascending.
    of_mult: Vec<Vec<usize>>,
    /// Per multiplier `k` and each of its parts `q` (as in `of_mult`), the
    /// position of `k` among the multipliers acting on `q` (ascending): the
    /// row of `k` among the multiplier rows of `q`'s columns, found once
    /// instead of at every evaluation.
    mult_pos: Vec<Vec<usize>>,
    pub col_ptr: Vec<usize>,
    pub row_idx: Vec<usize>,
    /// Per column, the end of its coordinate rows (they come first, the
    /// multipliers' after; a multiplier's column has only coordinate rows).
    pub coord_end: Vec<usize>,
    /// A fill-reducing column order (AMD, or the one a factorisation chose,
    /// [`Pattern::set_order`]) and its inverse, for the sparse LU.
    pub order: Vec<usize>,
    pub order_inv: Vec<usize>,
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
        let mult_pos = of_mult
            .iter()
            .enumerate()
            .map(|(k, on)| {
                on.iter()
                    .map(|&q| mults[q].binary_search(&k).ok())
                    .collect::<Option<Vec<usize>>>()
            })
            .collect::<Option<Vec<_>>>()?;
        if u32::try_from(row_idx.len()).is_err() {
            return None;
        }
        let (order, order_inv) = column_order(n + m, &col_ptr, &row_idx)?;
        Some(Pattern {
            n,
            m,
            parts,
            of_mult,
            mult_pos,
            col_ptr,
            row_idx,
            coord_end,
            order,
            order_inv,
            pivots: std::sync::OnceLock::new(),
        })
    }

    pub fn dim(&self) -> usize {
        self.n + self.m
    }

    /// The pattern of the slots `keep` holds (the rest left out), with its
    /// own fill-reducing order (`reorder`) or this pattern's; None if AMD
    /// fails.
    pub fn restricted(&self, keep: &[bool], reorder: bool) -> Option<Pattern> {
        let (mut col_ptr, mut row_idx, mut coord_end) = (vec![0], Vec::new(), Vec::new());
        for j in 0..self.dim() {
            let (top, bottom) = self.column_halves(j);
            row_idx.extend(top.filter(|&k| keep[k]).map(|k| self.row_idx[k]));
            coord_end.push(row_idx.len());
            row_idx.extend(bottom.filter(|&k| keep[k]).map(|k| self.row_idx[k]));
            col_ptr.push(row_idx.len());
        }
        let (order, order_inv) = if reorder {
            column_order(self.dim(), &col_ptr, &row_idx)?
        } else {
            (self.order.clone(), self.order_inv.clone())
        };
        // The parts' lists are the assembly's, kept for a whole pattern's
        // shape; the seed pivots are this pattern's, not the new one's.
        Some(Pattern {
            order,
            order_inv,
            col_ptr,
            row_idx,
            coord_end,
            pivots: std::sync::OnceLock::new(),
            ..self.clone()
        })
    }

    /// Factorises with the columns in `order` (a permutation of them).
    pub fn set_order(&mut self, order: Vec<usize>) {
        self.order_inv.resize(order.len(), 0);
        for (k, &c) in order.iter().enumerate() {
            self.order_inv[c] = k;
        }
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
    /// `col..col + 3` of one part (a 3×3 block of `K`): one search for all.
    pub fn block_slots(&self, row: usize, col: usize) -> Option<[usize; 3]> {
        let list = self.parts.get(col / 6)?;
        if col % 6 > 3 {
            return None;
        }
        let t = list.binary_search(&(row / 6)).ok()?;
        let off = 6 * t + row % 6;
        Some([0, 1, 2].map(|b| self.col_ptr[col + b] + off))
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
        let first = self.col_ptr[6 * q];
        Some(ConstraintBlock {
            row: first + 6 * self.parts[q].len() + self.mult_pos[k][tp],
            stride: self.col_ptr[6 * q + 1] - first,
            column: self.col_ptr[self.n + k] + 6 * tp,
        })
    }
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
mod tests {
    use super::*;
    use crate::statics::assembly::Workspace;

    /// The slots found once per equation and part are the entries
    /// `(n + k, col)` and `(col, n + k)` of the stored structure (found by
    /// scanning its rows), for every multiplier and every coordinate of
    /// three coupled corners; none for a part the equation does not act on.
    #[test]
    fn constraint_slots_are_the_stored_entries() {
        let (m, _) = crate::statics::testkit::coupled_corners(3);
        let p = Problem::new(&m).expect("problem");
        let pat = Pattern::new(&p).expect("pattern");
        let (n, mm) = (p.layout.n(), p.kept.len());
        let entry = |row: usize, col: usize| {
            (pat.col_ptr[col]..pat.col_ptr[col + 1]).find(|&s| pat.row_idx[s] == row)
        };
        let mut found = 0;
        for k in 0..mm {
            for col in 0..n {
                let searched = entry(n + k, col).zip(entry(col, n + k));
                assert_eq!(pat.constraint_slots(k, col), searched, "({k}, {col})");
                found += usize::from(searched.is_some());
            }
        }
        assert!(found >= 6 * mm, "{found}");
        // Each column's coordinate rows come first, up to `coord_end`.
        for col in 0..n + mm {
            let (start, mid, end) = (pat.col_ptr[col], pat.coord_end[col], pat.col_ptr[col + 1]);
            assert!(start < mid && mid <= end, "column {col}");
            assert!(
                pat.row_idx[start..mid].iter().all(|&r| r < n),
                "column {col}"
            );
            assert!(
                pat.row_idx[mid..end].iter().all(|&r| r >= n),
                "column {col}"
            );
            assert_eq!(
                mid == end,
                col >= n || pat.row_idx[start..end].iter().all(|&r| r < n)
            );
        }
    }

    /// Every entry the dense assembly writes, at a loaded state away from
    /// equilibrium, is in the pattern: the structure read at design holds
    /// elsewhere.
    #[test]
    fn the_pattern_holds_every_entry_of_the_mcpherson_matrix() {
        let (_, c) = crate::check::check_str(
            "mcpherson.axle",
            include_str!("../../examples/mcpherson.axle"),
        );
        let m = c.model.expect("the example checks");
        let p = Problem::new(&m).expect("problem");
        let pat = Pattern::new(&p).expect("pattern");
        let mut st = State::design(&m);
        let dq = nalgebra::DVector::from_fn(p.layout.n(), |i, _| 0.01 * ((i as f64) * 0.7).sin());
        st.apply(&p.layout, &dq);
        st.lambda = (0..p.kept.len()).map(|k| 1.0 + k as f64).collect();
        let loads = vec![crate::model::PointLoad {
            marker: m.wheels[0].contact,
            force: crate::geom::Vec3::new(2000.0, -3000.0, 4500.0),
            torque: crate::geom::Vec3::zeros(),
        }];
        let mut ws = Workspace::dense(&p);
        ws.eval(&p, &st, &loads, true).expect("evaluates");
        let a = ws.matrix();
        let mut inside = vec![false; pat.dim() * pat.dim()];
        for j in 0..pat.dim() {
            for &i in &pat.row_idx[pat.col_ptr[j]..pat.col_ptr[j + 1]] {
                inside[i + pat.dim() * j] = true;
            }
        }
        let mut written = 0;
        for j in 0..pat.dim() {
            for i in 0..pat.dim() {
                if a[(i, j)] != 0.0 {
                    written += 1;
                    assert!(inside[i + pat.dim() * j], "({i}, {j}) outside the pattern");
                }
            }
        }
        assert!(
            written > 300 && pat.nnz() < pat.dim() * pat.dim() / 2,
            "{written} {}",
            pat.nnz()
        );
    }
}
