//! A fresh sparse LU of the scaled Newton matrix with new pivots: the
//! factors' structure every later refactorisation of [`super::sparse`]
//! reuses, so its fill sets the cost of nearly every sparse factorisation and
//! solve.
//!
//! The columns come in the pattern's fill-reducing order (AMD of the
//! symmetric pattern); only the pivot row of each column is chosen here,
//! right-looking, on the active submatrix. Plain partial pivoting (the
//! largest entry of the column) ignores that order's reason: it takes a
//! coordinate's row for a multiplier's column and the other way round, and
//! each such swap fills the rows it couples. Here a row qualifies when its
//! entry is at least [`THRESHOLD`] of the column's largest (threshold
//! pivoting: each step's growth is at most `1 / THRESHOLD`), and among the
//! qualifying rows the column's own row (the diagonal, which keeps the
//! symmetric order's fill) is preferred, then the row with the fewest
//! active entries (Markowitz: its update fills the fewest places). Measured
//! at design, the multiply-adds of a refactorisation fall by an eighth on
//! one McPherson corner, a quarter on the car and two fifths on eight
//! coupled corners (`docs/performance.md`), whose work now grows with their
//! number about as the corners do (1.34 times eight corners').
//!
//! The first factorisation of a problem (its seed pivots) chooses each
//! step's column too ([`factor_choosing_columns`]): the entry of least
//! Markowitz cost over the whole active submatrix, threshold as above. The
//! AMD order plans for a symmetric elimination, which a multiplier's zero
//! diagonal does not allow; choosing the columns with the pivots cuts a
//! refactorisation's multiply-adds by a fifth on the McPherson and by two
//! fifths to a half on the car. Later fresh factorisations, also on slots
//! widened along a path, keep the order so chosen: a search over the whole
//! active submatrix at every step, made again where a bump stop widened
//! the slots, cost more than it saved over the car's 100-step sweep.
//!
//! Entries are kept when their value is zero (a stop out of contact, a term
//! that vanishes at design): the structure must hold every matrix of the
//! pattern, not only this one.

use super::pattern::Pattern;
use super::products::Products;

/// A row may be a pivot when its entry is at least this fraction of the
/// largest in its column (UMFPACK's default for unsymmetric matrices).
const THRESHOLD: f64 = 0.1;

/// L (unit lower) and U by columns in pivot order, rows as pivot positions:
/// each column of L starts with its unit diagonal, each column of U ends with
/// its pivot, and U's other rows ascend (an order in which the left-looking
/// updates of a refactorisation may run: row `i` of U is final once the
/// columns of L before `i` have updated it).
#[derive(Debug, Clone, Default)]
pub(crate) struct Factors {
    pub l_ptr: Vec<usize>,
    pub l_idx: Vec<usize>,
    pub l_val: Vec<f64>,
    pub u_ptr: Vec<usize>,
    pub u_idx: Vec<usize>,
    pub u_val: Vec<f64>,
    /// The reciprocal of each column's pivot: L's multipliers and the back
    /// substitution multiply by it (a division there is a long step on the
    /// substitution's critical path, once per column).
    pub u_inv: Vec<f64>,
    /// The entries of L and U row by row, for the substitutions
    /// ([`Rows`]); the structure's, so a refactorisation keeps them.
    pub rows: Rows,
}

/// The entries of L (below its diagonal) and U (right of its pivots) row
/// by row: `(column, index into l_val or u_val)`, row `i`'s at
/// `l[l_ptr[i]..l_ptr[i + 1]]`, columns ascending, and at
/// `u[u_ptr[i]..u_ptr[i + 1]]`, columns descending. A substitution then
/// sums each row in a register, in the order the column-oriented one
/// subtracted into the row's memory (the same bits), instead of adding
/// into memory, a chain of dependent loads and stores per row.
#[derive(Debug, Clone, Default)]
pub(crate) struct Rows {
    pub l_ptr: Vec<usize>,
    pub l: Products,
    pub u_ptr: Vec<usize>,
    pub u: Products,
    /// The most entries a row of L and a row of U hold here (their
    /// diagonals not counted), for the factors' growth bound
    /// ([`super::sparse::SparseLu::solution_holds`]).
    pub longest: [usize; 2],
    /// The substitutions as machine code, once they have run enough times
    /// (shared by the factors of this structure).
    #[cfg(all(target_arch = "x86_64", unix))]
    pub compiled: std::sync::Arc<super::compiled::Tiered<super::compiled::CompiledSubstitution>>,
}

impl Rows {
    /// The rows of `f`'s structure (its columns' entries); None if an index
    /// does not fit in 32 bits.
    fn of(f: &Factors) -> Option<Rows> {
        let n = f.u_inv.len();
        let (l_ptr, l) = by_rows(
            n,
            (0..n).map(|j| (j, f.l_ptr[j] + 1..f.l_ptr[j + 1])),
            &f.l_idx,
        )?;
        let (u_ptr, u) = by_rows(
            n,
            (0..n).rev().map(|j| (j, f.u_ptr[j]..f.u_ptr[j + 1] - 1)),
            &f.u_idx,
        )?;
        let longest = |ptr: &[usize]| ptr.windows(2).map(|w| w[1] - w[0]).max().unwrap_or(0);
        Some(Rows {
            longest: [longest(&l_ptr), longest(&u_ptr)],
            l_ptr,
            l: Products::new(l),
            u_ptr,
            u: Products::new(u),
            #[cfg(all(target_arch = "x86_64", unix))]
            compiled: Default::default(),
        })
    }
}

/// Rows' starts and their entries `(column, index)`, as [`Rows`] holds them.
pub(super) type ByRows = (Vec<usize>, Vec<(u32, u32)>);

/// The entries of `columns` (each a column and its range in `idx`, which
/// holds the entries' rows), row by row in the order the columns come:
/// `(column, index into idx)`; None if an index does not fit in 32 bits.
pub(super) fn by_rows(
    n: usize,
    columns: impl Iterator<Item = (usize, std::ops::Range<usize>)> + Clone,
    idx: &[usize],
) -> Option<ByRows> {
    let mut ptr = vec![0usize; n + 1];
    for (_, range) in columns.clone() {
        for &i in &idx[range] {
            ptr[i + 1] += 1;
        }
    }
    for i in 0..n {
        ptr[i + 1] += ptr[i];
    }
    let mut next = ptr.clone();
    let mut out = vec![(0u32, 0u32); ptr[n]];
    for (j, range) in columns {
        for e in range {
            let i = idx[e];
            out[next[i]] = (u32::try_from(j).ok()?, u32::try_from(e).ok()?);
            next[i] += 1;
        }
    }
    Some((ptr, out))
}

impl Factors {
    /// Multiply-adds of one refactorisation: for each entry `(i, j)` of U
    /// off the diagonal, the entries of L's column `i` below its diagonal.
    pub fn updates(&self) -> usize {
        let n = self.u_ptr.len().saturating_sub(1);
        (0..n)
            .flat_map(|j| self.u_idx[self.u_ptr[j]..self.u_ptr[j + 1] - 1].iter())
            .map(|&i| self.l_ptr[i + 1] - self.l_ptr[i] - 1)
            .sum()
    }

    /// Entries of L and U (diagonals included).
    #[cfg(test)]
    pub fn entries(&self) -> usize {
        self.l_idx.len() + self.u_idx.len()
    }
}

/// Factorises the matrix of `values` (in `pattern`'s slots) with the
/// pattern's column order into `f`, `row_perm` (the original row pivoted at
/// each step) and `row_perm_inv`; false if a column has no nonzero entry left
/// (the matrix is singular) or a value is not finite.
pub(crate) fn factor(
    pattern: &Pattern,
    values: &[f64],
    f: &mut Factors,
    row_perm: &mut [usize],
    row_perm_inv: &mut [usize],
) -> bool {
    eliminate(pattern, values, None, f, row_perm, row_perm_inv)
}

/// [`factor`] choosing each step's column as well as its row: of the
/// entries that pass [`THRESHOLD`] in their column, the one of least
/// Markowitz cost `(r - 1)(c - 1)` (its row's and its column's active
/// entries: the fill its step can make), ties to the shorter column, then
/// to the larger entry relative to its column. The symmetric order (AMD)
/// cannot see that a multiplier's column has a zero diagonal, so every
/// multiplier's pivot is a row swap it did not plan for; this pass plans
/// them. On the McPherson at design the refactorisation's multiply-adds
/// fall from 1 736 to 1 346. Returns the column order taken (the
/// pattern's is ignored), for the pattern the factors are of; None where
/// [`factor`] is false.
pub(crate) fn factor_choosing_columns(
    pattern: &Pattern,
    values: &[f64],
    f: &mut Factors,
    row_perm: &mut [usize],
    row_perm_inv: &mut [usize],
) -> Option<Vec<usize>> {
    let mut order = Vec::with_capacity(pattern.dim());
    eliminate(pattern, values, Some(&mut order), f, row_perm, row_perm_inv).then_some(order)
}

/// The least-cost pivot of the active submatrix (`rows` of the rows not
/// `pivoted`, each column's active entries in `count`), as
/// [`factor_choosing_columns`] chooses it: `(row, column)`; None if no
/// entry is a non-zero number. `max` is scratch of the matrix's size.
fn markowitz_pivot(
    rows: &[Vec<(usize, f64)>],
    pivoted: &[bool],
    count: &[usize],
    max: &mut [f64],
) -> Option<(usize, usize)> {
    max.fill(0.0);
    let active = || rows.iter().enumerate().filter(|(i, _)| !pivoted[*i]);
    for (_, row) in active() {
        for &(c, v) in row {
            max[c] = max[c].max(v.abs());
        }
    }
    // (cost, column count, entry over its column's largest, row, column)
    let mut best: Option<(usize, usize, f64, usize, usize)> = None;
    for (i, row) in active() {
        // (An empty row, a singular matrix's, has no entry to look at.)
        let r = row.len().saturating_sub(1);
        for &(c, v) in row {
            let (n_c, big) = (count[c], max[c]);
            let cost = r * n_c.saturating_sub(1);
            // (The cheap test first: most entries cost more.)
            if best.is_some_and(|(bc, bn, ..)| (cost, n_c) > (bc, bn))
                || !(big.is_finite() && big > 0.0 && v.abs() >= THRESHOLD * big)
            {
                continue;
            }
            let rel = v.abs() / big;
            let better = best.is_none_or(|(bc, bn, br, _, _)| (cost, n_c) < (bc, bn) || rel > br);
            if better {
                best = Some((cost, n_c, rel, i, c));
            }
        }
    }
    best.map(|(_, _, _, i, c)| (i, c))
}

/// The elimination of [`factor`], on the pattern's column order, or, with
/// `chosen`, on the columns [`markowitz_pivot`] chooses (pushed onto it).
fn eliminate(
    pattern: &Pattern,
    values: &[f64],
    mut chosen: Option<&mut Vec<usize>>,
    f: &mut Factors,
    row_perm: &mut [usize],
    row_perm_inv: &mut [usize],
) -> bool {
    let n = pattern.dim();
    if values.len() != pattern.nnz() || row_perm.len() != n || row_perm_inv.len() != n {
        return false;
    }
    // The active submatrix: by rows, (column, value); by columns, the rows
    // that may hold an entry (pivoted rows are skipped when read).
    let mut rows: Vec<Vec<(usize, f64)>> = vec![Vec::new(); n];
    let mut cols: Vec<Vec<usize>> = vec![Vec::new(); n];
    for (j, col) in cols.iter_mut().enumerate() {
        let slots = pattern.col_ptr[j]..pattern.col_ptr[j + 1];
        for (&i, &v) in pattern.row_idx[slots.clone()].iter().zip(&values[slots]) {
            rows[i].push((j, v));
            col.push(i);
        }
    }
    let mut pivoted = vec![false; n];
    // Per step: its U row (columns and values, the pivot's left out), pivot,
    // and L column (original rows, multipliers).
    let mut u_rows: Vec<Vec<(usize, f64)>> = Vec::with_capacity(n);
    let mut pivots = Vec::with_capacity(n);
    let mut l_cols: Vec<Vec<(usize, f64)>> = Vec::with_capacity(n);
    // Per column, its place in the pivot row being eliminated with (usize::MAX:
    // absent), and the last row whose update met it there.
    let mut at = vec![usize::MAX; n];
    let mut met = vec![usize::MAX; n];
    // The column's candidate rows: row, entry, and where the row holds it.
    let mut cand: Vec<(usize, f64, usize)> = Vec::new();
    // For a choice of columns: each column's active entries.
    let mut count: Vec<usize> = cols.iter().map(Vec::len).collect();
    // (Scratch of the Markowitz search; none on a given order.)
    let mut max = vec![0.0; if chosen.is_some() { n } else { 0 }];
    for (k, pivot_row) in row_perm.iter_mut().enumerate() {
        // The Markowitz pivot's row, chosen with its column.
        let mut planned = None;
        let c = match chosen.as_deref_mut() {
            None => pattern.order[k],
            Some(order) => {
                let Some((r, c)) = markowitz_pivot(&rows, &pivoted, &count, &mut max) else {
                    return false;
                };
                planned = Some(r);
                order.push(c);
                c
            }
        };
        cand.clear();
        for &i in &cols[c] {
            if pivoted[i] {
                continue;
            }
            if let Some(p) = rows[i].iter().position(|e| e.0 == c) {
                cand.push((i, rows[i][p].1, p));
            }
        }
        let big = cand.iter().fold(0.0f64, |m, e| m.max(e.1.abs()));
        if !(big.is_finite() && big > 0.0) {
            return false;
        }
        let qualifies = |v: f64| v.abs() >= THRESHOLD * big;
        let r = match planned.or_else(|| {
            cand.iter()
                .find(|e| e.0 == c && qualifies(e.1))
                .map(|e| e.0)
        }) {
            Some(r) => r,
            None => {
                let mut best: Option<(usize, f64, usize)> = None;
                for &(i, v, _) in cand.iter().filter(|e| qualifies(e.1)) {
                    let len = rows[i].len();
                    let better = match best {
                        None => true,
                        Some((bl, bv, _)) => len < bl || (len == bl && v.abs() > bv),
                    };
                    if better {
                        best = Some((len, v.abs(), i));
                    }
                }
                match best {
                    Some((_, _, i)) => i,
                    None => return false,
                }
            }
        };
        pivoted[r] = true;
        *pivot_row = r;
        let mut urow = std::mem::take(&mut rows[r]);
        for e in &urow {
            count[e.0] -= 1;
        }
        let Some(&(_, piv, pos)) = cand.iter().find(|e| e.0 == r) else {
            return false;
        };
        urow.swap_remove(pos);
        let mut lcol = Vec::with_capacity(cand.len().saturating_sub(1));
        for (p, e) in urow.iter().enumerate() {
            at[e.0] = p;
        }
        let inv = 1.0 / piv;
        for &(i, a, pos) in cand.iter().filter(|e| e.0 != r) {
            let l = a * inv;
            lcol.push((i, l));
            let row = &mut rows[i];
            // The column leaves the active submatrix (its entry becomes L's);
            // one pass over the rest updates the pivot row's columns.
            row.swap_remove(pos);
            for e in row.iter_mut() {
                if let Some(&(_, v)) = urow.get(at[e.0]) {
                    e.1 -= l * v;
                    met[e.0] = i;
                }
            }
            // The pivot row's other columns fill this row.
            for &(cc, v) in &urow {
                if met[cc] != i {
                    row.push((cc, -l * v));
                    cols[cc].push(i);
                    count[cc] += 1;
                }
            }
        }
        for e in &urow {
            at[e.0] = usize::MAX;
        }
        u_rows.push(urow);
        pivots.push(piv);
        l_cols.push(lcol);
    }
    for (k, &r) in row_perm.iter().enumerate() {
        row_perm_inv[r] = k;
    }
    // The columns' pivot positions: the pattern's, or those taken.
    let taken;
    let order_inv = match &chosen {
        None => &pattern.order_inv,
        Some(order) => {
            taken = super::pattern::inverse(order);
            &taken
        }
    };
    // L by columns, rows as pivot positions, the unit diagonal first.
    f.l_ptr.clear();
    f.l_idx.clear();
    f.l_val.clear();
    f.l_ptr.push(0);
    for (k, col) in l_cols.iter().enumerate() {
        f.l_idx.push(k);
        f.l_val.push(1.0);
        for &(i, l) in col {
            f.l_idx.push(row_perm_inv[i]);
            f.l_val.push(l);
        }
        f.l_ptr.push(f.l_idx.len());
    }
    // U by columns (pivot positions of the columns): rows ascending, as the
    // steps that wrote them, then the pivot.
    let mut count = vec![1usize; n];
    for urow in &u_rows {
        for &(cc, _) in urow {
            count[order_inv[cc]] += 1;
        }
    }
    f.u_ptr.clear();
    f.u_ptr.push(0);
    let mut end = 0;
    for c in &count {
        end += c;
        f.u_ptr.push(end);
    }
    let total = f.u_ptr[n];
    f.u_idx.clear();
    f.u_idx.resize(total, 0);
    f.u_val.clear();
    f.u_val.resize(total, 0.0);
    let mut next: Vec<usize> = f.u_ptr[..n].to_vec();
    for (k, urow) in u_rows.iter().enumerate() {
        for &(cc, v) in urow {
            let j = order_inv[cc];
            f.u_idx[next[j]] = k;
            f.u_val[next[j]] = v;
            next[j] += 1;
        }
    }
    f.u_inv.clear();
    for (j, &piv) in pivots.iter().enumerate() {
        f.u_idx[next[j]] = j;
        f.u_val[next[j]] = piv;
        f.u_inv.push(1.0 / piv);
    }
    // (Factors too large for 32-bit indices are refused, as by the
    // refactorisation's plan: far beyond any mechanism's.)
    let Some(rows) = Rows::of(f) else {
        return false;
    };
    f.rows = rows;
    f.l_val.iter().chain(&f.u_val).all(|v| v.is_finite())
}

#[cfg(test)]
#[path = "pivoting_tests.rs"]
mod tests;
