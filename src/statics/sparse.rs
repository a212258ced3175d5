//! The sparse LU of the scaled Newton matrix in its [`Pattern`]: the contract
//! of the dense [`super::linear::Lu`] (factor, solve, check a solution,
//! distance to another matrix, condition estimate) for models too large for
//! the dense elimination (see [`super::tangent`] for the choice).
//!
//! The column order is chosen with the pivots of the problem's first
//! factorisation (its seed pivots) and kept, also when a matrix widens the
//! slots factorised. A fresh factorisation ([`pivoting`]) chooses the
//! pivot rows by threshold and fill (a row swap is safe for the zero
//! diagonal block of the multipliers), and its work follows the non-zeros
//! of the factors, so that a chain of N coupled corners costs N times one
//! corner, not N³. Finding each column's structure costs more than its
//! arithmetic, so the next matrix is refactorised KLU's way: with the
//! previous pivot sequence and the structure of L and U (the same
//! for every matrix of the pattern with those pivots), numbers only
//! ([`super::refactor::Plan`]: the products each entry of the factors is
//! made of, listed once per structure), as long as every pivot keeps at
//! least [`PIVOT_THRESHOLD`] of the largest entry left in its column;
//! otherwise it is factorised afresh with new pivots. Only the slots that
//! can be non-zero are factorised ([`Live`]). The substitutions and the
//! residual check run row by row ([`pivoting::Rows`], [`Live::residual`]),
//! each row's sum in a register.

use super::condition::{Direction, Scale, largest};
use super::linear::SOLVED_WITHIN;
use super::live::Live;
use super::pattern::Pattern;
use super::pivoting::{self, Factors};
use super::refactor::Plan;
use std::cell::Cell;
use std::sync::Arc;

/// A reused pivot must be at least this fraction of the largest candidate in
/// its column, which bounds the growth of each elimination step by
/// `1 / PIVOT_THRESHOLD`; every solution is still checked against the matrix
/// (`satisfies`), and a refused one is solved again with fresh pivots. (KLU
/// refactorises with no threshold at all and leaves the check to its user.)
/// The fresh pivots ([`pivoting`]) pass 0.1 of their column's largest entry
/// when chosen; along table 5-1 on eight coupled corners, 2 of 44
/// factorisations needed fresh ones with 0.001 and none with 0.0001, and each
/// fresh one costs about six refactorisations.
const PIVOT_THRESHOLD: f64 = 0.0001;

/// A pivot sequence and the factors' structure to start refactorising from
/// (kept in the [`Pattern`], so that every solver of the problem starts
/// from the same one: a fresh factorisation costs 10-30 refactorisations).
#[derive(Debug, Clone)]
pub(crate) struct Pivots {
    pub(super) live: Arc<Live>,
    own: Factors,
    plan: Arc<Plan>,
    row_perm: Vec<usize>,
    row_perm_inv: Vec<usize>,
    /// The reciprocal condition estimate of the matrix they factorised
    /// ([`SparseLu::reciprocal_condition`]): a guess at the problem's
    /// ([`super::isolation`]).
    pub rcond: f64,
}

impl Pivots {
    /// The multiply-adds of a refactorisation with these pivots.
    #[cfg(test)]
    pub fn updates(&self) -> usize {
        self.own.updates()
    }
}

/// The most slots a pattern may have for a refactorisation to copy its
/// matrix whole ([`SparseLu::gather`]): 8 KiB of values, the matrix and
/// its copy a half of a 32 KiB first-level data cache, beside the factors
/// and the plan. Measured (`docs/performance.md`): the McPherson corner's
/// 828 slots gain by it, two coupled corners' 1 728 lose 1-3 %.
const WHOLE_COPY_UP_TO: usize = 1024;

pub(crate) struct SparseLu {
    pattern: Arc<Pattern>,
    /// The slots factorised, and the values factorised in them.
    live: Arc<Live>,
    live_a: Vec<f64>,
    /// How often a matrix widened `live`.
    pub widened: usize,
    row_perm: Vec<usize>,
    row_perm_inv: Vec<usize>,
    /// The matrix factorised in the pattern's slots: its entries in the
    /// live slots, zero in the others (whose entries [`Live::holds`]
    /// bounded by a rounding's size; the factors are those of this
    /// matrix). The refactorisation reads it in place; `live_a` holds its
    /// live entries in the live slots' order for a fresh elimination.
    a: Vec<f64>,
    /// Largest absolute entry of the matrix factorised.
    a_max: f64,
    /// Its scaling for the condition estimates ([`super::condition`]),
    /// computed when first asked for.
    scale: Cell<Option<Scale>>,
    /// The factors of the last factorisation (refactorised in place), and
    /// the products that refactorise them.
    own: Factors,
    plan: Arc<Plan>,
    /// Whether `own` holds a structure to refactorise with.
    reusable: bool,
    /// Whether `own` holds a factorisation.
    valid: bool,
    /// Whether the last factorisation reused earlier pivots.
    last_reused: bool,
    /// Fresh factorisations and refactorisations with the previous pivots.
    pub fresh: usize,
    pub reused: usize,
    /// The substitutions' vector, in pivot order (overwritten by each solve).
    work: Vec<f64>,
}

impl SparseLu {
    pub fn new(pattern: Arc<Pattern>) -> SparseLu {
        let n = pattern.dim();
        let start = pattern.pivots.get().cloned().flatten();
        // Without seed pivots (their matrix failed), every slot is live.
        let live = match &start {
            Some(pv) => pv.live.clone(),
            None => Arc::new(Live::all(&pattern)),
        };
        let mut lu = SparseLu {
            a: vec![0.0; pattern.nnz()],
            live_a: vec![0.0; live.from().len()],
            live,
            widened: 0,
            pattern,
            row_perm: vec![0; n],
            row_perm_inv: vec![0; n],
            a_max: 0.0,
            scale: Cell::new(None),
            own: Factors::default(),
            plan: Arc::new(Plan::default()),
            reusable: false,
            valid: false,
            last_reused: false,
            fresh: 0,
            reused: 0,
            work: vec![0.0; n],
        };
        if let Some(pv) = start {
            (lu.own, lu.plan) = (pv.own, pv.plan);
            (lu.row_perm, lu.row_perm_inv) = (pv.row_perm, pv.row_perm_inv);
            lu.reusable = true;
        }
        lu
    }

    /// A factorisation on the slots `live`, pivoting afresh at its first
    /// matrix (the seed pivots, if any, are of other slots).
    pub fn starting_with(pattern: Arc<Pattern>, live: Live) -> SparseLu {
        let mut lu = SparseLu::new(pattern);
        lu.live_a = vec![0.0; live.from().len()];
        lu.live = Arc::new(live);
        lu.reusable = false;
        lu
    }

    /// The pivots of the last factorisation, if it succeeded and has a
    /// plan to refactorise with, and its condition estimate.
    pub fn pivots(&mut self) -> Option<Pivots> {
        if !(self.valid && self.reusable) {
            return None;
        }
        Some(Pivots {
            rcond: self.reciprocal_condition(),
            live: self.live.clone(),
            own: self.own.clone(),
            plan: self.plan.clone(),
            row_perm: self.row_perm.clone(),
            row_perm_inv: self.row_perm_inv.clone(),
        })
    }

    pub fn dim(&self) -> usize {
        self.pattern.dim()
    }

    pub fn pattern(&self) -> &Arc<Pattern> {
        &self.pattern
    }

    /// Factorises the matrix of `values` (in the pattern's slots); false if a
    /// pivot is zero or not finite.
    pub fn factor(&mut self, values: &[f64]) -> bool {
        self.factor_with(values, false)
    }

    /// [`Self::factor`]; a fresh factorisation chooses the columns' order
    /// too when `choose_columns` ([`Self::factor_choosing_columns`]).
    fn factor_with(&mut self, values: &[f64], choose_columns: bool) -> bool {
        self.valid = false;
        if values.len() != self.a.len() {
            return false;
        }
        self.scale.set(None);
        // The largest live entry is the matrix's largest when the other
        // entries are at most `DROP` times it, which is what `holds` asks.
        let clean;
        (self.a_max, clean) = self.gather(values);
        if !clean && !self.live.holds(values, self.a_max) {
            let Some(live) = self.live.widened(&self.pattern, values) else {
                return false;
            };
            self.live = Arc::new(live);
            self.live_a.resize(self.live.from().len(), 0.0);
            self.reusable = false;
            self.widened += 1;
            (self.a_max, _) = self.gather(values);
        }
        self.last_reused = self.reusable && self.plan.run(&mut self.own, &self.a, PIVOT_THRESHOLD);
        if self.last_reused {
            self.reused += 1;
            self.valid = true;
            return true;
        }
        self.fresh += 1;
        // (The elimination takes the live entries in the live slots' order.)
        for (v, &k) in self.live_a.iter_mut().zip(self.live.from()) {
            *v = self.a[k];
        }
        let ok = self.factor_fresh(choose_columns);
        let plan = ok
            .then(|| Plan::new(&self.own, &self.live, &self.row_perm_inv))
            .flatten();
        // Without a plan (a structure missing a live slot: not met), every
        // matrix is factorised afresh, and no stale plan stays paired with
        // these factors.
        self.reusable = plan.is_some();
        self.plan = Arc::new(plan.unwrap_or_default());
        self.valid = ok
            && (0..self.dim()).all(|j| {
                let d = self.own.u_val[self.own.u_ptr[j + 1] - 1];
                d.is_finite() && d != 0.0
            });
        self.valid
    }

    /// Factorises `values` with fresh pivots, if the last factorisation
    /// reused earlier ones (its pivots passed the threshold, yet its solve
    /// may fail the residual check); `None`: there is nothing else to try.
    pub fn factor_afresh(&mut self, values: &[f64]) -> Option<bool> {
        if !self.last_reused {
            return None;
        }
        self.reusable = false;
        Some(self.factor(values))
    }

    /// `values` into `a`, zero outside the live slots, and the largest
    /// live entry; whether `values` is known to be zero outside them.
    ///
    /// A pattern up to [`WHOLE_COPY_UP_TO`] slots is copied whole, its
    /// other slots checked by their bits in one pass (zero in every matrix
    /// met so far) and zeroed only where one is not: the copy and its
    /// passes stay in the first-level cache, and an indexed copy of the
    /// live entries, one load and two stores an entry, took a seventh of a
    /// McPherson refactorisation. A larger one has its live entries copied
    /// by index (their largest in the same pass), and leaves the
    /// check to [`Live::holds`]: copied whole, two and eight coupled corners
    /// and the car lost 1-3 %, though their share of live slots is the
    /// corner's; the copy's size decides (`docs/performance.md`).
    fn gather(&mut self, values: &[f64]) -> (f64, bool) {
        if self.a.len() <= WHOLE_COPY_UP_TO {
            self.a.copy_from_slice(values);
            let clean = self.live.outside_bits(&self.a) == 0;
            if !clean {
                self.live.clear_outside(&mut self.a);
            }
            return (largest(&self.a), clean);
        }
        (self.live.copy_into(values, &mut self.a), false)
    }

    /// [`Self::factor`] with fresh pivots whose columns are chosen with
    /// them ([`pivoting::factor_choosing_columns`]); the live slots' order
    /// becomes the one taken. For the seed pivots, on slots of this
    /// factorisation's own ([`Self::starting_with`]); on slots shared with
    /// another solver their order is kept.
    pub fn factor_choosing_columns(&mut self, values: &[f64]) -> bool {
        self.reusable = false;
        self.factor_with(values, true)
    }

    /// A factorisation of `live_a` with fresh pivots ([`pivoting`]) into
    /// `own`, choosing the columns' order too when `choose_columns` and the
    /// live slots are this factorisation's own.
    fn factor_fresh(&mut self, choose_columns: bool) -> bool {
        if choose_columns && let Some(live) = Arc::get_mut(&mut self.live) {
            let Some(order) = pivoting::factor_choosing_columns(
                &live.pattern,
                &self.live_a,
                &mut self.own,
                &mut self.row_perm,
                &mut self.row_perm_inv,
            ) else {
                return false;
            };
            live.pattern.set_order(order);
            return true;
        }
        let (p, f) = (&self.live.pattern, &mut self.own);
        pivoting::factor(
            p,
            &self.live_a,
            f,
            &mut self.row_perm,
            &mut self.row_perm_inv,
        )
    }

    /// Solves `A x = b` in place; false if there is no factorisation or the
    /// result is not finite.
    pub fn solve(&mut self, b: &mut [f64]) -> bool {
        let n = self.dim();
        if !self.valid || b.len() != n {
            return false;
        }
        // P A Q = L U: y = P b, then L U z = y, then x = Q z.
        let (f, p) = (&self.own, &self.live.pattern);
        let y = &mut self.work[..n];
        for (yp, &r) in y.iter_mut().zip(&self.row_perm) {
            *yp = b[r];
        }
        substitute(f, y);
        for (yj, &c) in y.iter_mut().zip(&p.order) {
            b[c] = std::mem::replace(yj, 0.0);
        }
        b.iter().all(|v| v.is_finite())
    }

    /// [`Self::residual_within`] with the sizes of `x` and `b` found here.
    #[cfg(test)]
    pub fn satisfies(&mut self, values: &[f64], x: &[f64], b: &[f64]) -> bool {
        if values.len() != self.a.len() || x.len() != self.dim() || b.len() != self.dim() {
            return false;
        }
        self.residual_within(values, x, b, largest(x), largest(b))
    }

    /// Whether `x` solves `A x = b` to a residual of [`SOLVED_WITHIN`] of
    /// the sizes involved (`x_max`, `b_max` their largest entries; as
    /// [`super::linear::Lu::satisfies`]), `A` the matrix of `values` in the
    /// live slots (its other entries, which `holds` bounds, change the
    /// residual by far less than that).
    fn residual_within(
        &self,
        values: &[f64],
        x: &[f64],
        b: &[f64],
        x_max: f64,
        b_max: f64,
    ) -> bool {
        let r = self.live.residual(values, x, b);
        r <= SOLVED_WITHIN * (b_max + self.a_max * x_max)
    }

    /// The scaling of [`super::condition`] for the matrix last factorised
    /// (found with [`Self::distance_to`] when that comes first, as in the
    /// isolation check).
    pub fn scale(&self) -> Scale {
        if let Some(s) = self.scale.get() {
            return s;
        }
        // Over the pattern's slots, as `distance_to` finds it, to the bit
        // (the dead slots of `a` are zero).
        let lanes = self.pattern.sizes_and_difference(&self.a, &self.a);
        let s = lanes.sizes.sizes().scale(self.pattern.coords());
        self.scale.set(Some(s));
        s
    }

    /// Whether `x`, which [`Self::solve`] gave for `b` with the matrix
    /// last factorised (`values`), passes the residual check
    /// ([`Self::residual_within`]): without computing the residual where the
    /// factors' growth bounds it below the check's tolerance, otherwise by
    /// computing it. (Of another `x`, the bound says nothing.)
    ///
    /// Solving with factors `L̂ Û` computed in floating point gives the
    /// exact solution of `(A + ΔA) x = b` with `|ΔA| ≤ γ₃ₙ |L̂| |Û|`
    /// (Higham, *Accuracy and Stability of Numerical Algorithms*, 2nd ed.,
    /// theorem 9.4, for any order of the sums), so `‖A x - b‖∞ ≤ γ₃ₙ
    /// ‖|L̂|‖∞ ‖|Û|‖∞ ‖x‖∞`. Each norm is at most its factor's longest row,
    /// with the diagonal, times its largest entry; γ is taken as `5 n u`
    /// (the multipliers and the back substitution multiply by the pivots'
    /// reciprocals: a rounding more each). Reused pivots need pass only
    /// [`PIVOT_THRESHOLD`] of their column, a bound on the growth far too
    /// loose for the check: the growth itself is measured, and where it is
    /// too large the residual is computed.
    pub fn solution_holds(&mut self, values: &[f64], x: &[f64], b: &[f64]) -> bool {
        let n = self.dim();
        if !self.valid || values.len() != self.a.len() || x.len() != n || b.len() != n {
            return false;
        }
        let (x_max, b_max) = (largest(x), largest(b));
        if self.residual_bound() * x_max <= SOLVED_WITHIN * (b_max + self.a_max * x_max) {
            return true;
        }
        self.residual_within(values, x, b, x_max, b_max)
    }

    /// `γ ‖|L̂|‖∞ ‖|Û|‖∞` of [`Self::solution_holds`] (bounded through each
    /// factor's longest row): a solution `x` leaves a residual of at most
    /// this times `‖x‖∞`.
    fn residual_bound(&self) -> f64 {
        let f = &self.own;
        let n = self.dim() as f64;
        let [long_l, long_u] = f.rows.longest;
        // (L's stored diagonal is 1: its largest entry is at least 1.)
        let l_norm = (1 + long_l) as f64 * largest(&f.l_val);
        let u_norm = (1 + long_u) as f64 * largest(&f.u_val);
        let u = f64::EPSILON / 2.0;
        let gamma = 5.0 * n * u / (1.0 - 5.0 * n * u);
        gamma * l_norm * u_norm
    }

    /// `‖D (B - A) D‖_F / ‖D A D‖_F` for the matrix `A` last factorised and
    /// its scaling `D` (as [`super::linear::Lu::distance_to`]), which is
    /// found in the same pass (the same as [`Self::scale`]'s, to the bit).
    pub fn distance_to(&self, values: &[f64]) -> f64 {
        if !self.valid || values.len() != self.a.len() {
            return f64::INFINITY;
        }
        let lanes = self.pattern.sizes_and_difference(&self.a, values);
        let s = lanes.sizes.sizes().scale(self.pattern.coords());
        self.scale.set(Some(s));
        lanes.difference.total(&s).sqrt() / s.fro
    }

    /// Adds `(B - A) y` to `out`, `A` the matrix last factorised and `B` the
    /// matrix of `values`: row by row, each row's sum in a register (a
    /// column's entries added into `out` one by one were a chain through
    /// memory, most of the isolation check's time where it estimates
    /// `‖E‖`). False, `out` untouched, if the rows do not cover it (a
    /// pattern past 32-bit slots, which [`Pattern::new`] refuses): the
    /// estimate then stands for nothing.
    pub fn add_difference_times(&self, values: &[f64], y: &[f64], out: &mut [f64]) -> bool {
        let (starts, pairs) = self.pattern.rows();
        if starts.len() != out.len() + 1 {
            return false;
        }
        for (o, row) in out.iter_mut().zip(starts.windows(2)) {
            *o = pairs.add_difference_to(*o, row[0]..row[1], y, values, &self.a);
        }
        true
    }

    /// [`Self::reciprocal_condition_along`] from the cold start (two
    /// inverse iterations).
    pub fn reciprocal_condition(&mut self) -> f64 {
        self.reciprocal_condition_along(&mut Direction::default())
    }

    /// An estimate of `σ_min / σ_max` of the matrix scaled as `D A D`, from
    /// where the last estimate of `direction` ended (as
    /// [`super::linear::Lu::reciprocal_condition_along`]).
    pub fn reciprocal_condition_along(&mut self, direction: &mut Direction) -> f64 {
        if !self.valid {
            return 0.0;
        }
        let (n, s) = (self.dim(), self.scale());
        s.reciprocal_condition_along(n, direction, |y| self.solve(y))
    }
}

/// `L U z = y` in place with the factors `f`: as machine code once the
/// structure's substitutions have run enough times
/// ([`super::compiled::CompiledSubstitution`]), else as loops.
pub(super) fn substitute(f: &Factors, y: &mut [f64]) {
    #[cfg(all(target_arch = "x86_64", unix))]
    {
        let r = &f.rows;
        let compiled = r.compiled.get(|| {
            super::compiled::CompiledSubstitution::new(&r.l_ptr, r.l.pairs(), &r.u_ptr, r.u.pairs())
        });
        if let Some(code) = compiled {
            return code.run(y, &f.l_val, &f.u_val, &f.u_inv);
        }
    }
    substitute_as_loops(f, y);
}

/// [`substitute`] as loops, row by row ([`super::pivoting::Rows`]), each
/// row's sum in a register; the rows' pairs `(column, entry)` (the entry's
/// value times y's) come one row after the other, L's from the first row,
/// U's from the last.
pub(super) fn substitute_as_loops(f: &Factors, y: &mut [f64]) {
    // (Written while the rows' products read it.)
    let y = std::cell::Cell::from_mut(y).as_slice_of_cells();
    let rows = &f.rows;
    let mut l = rows.l.sweep(y, &f.l_val[..]);
    for (yi, w) in y.iter().zip(rows.l_ptr.windows(2)) {
        yi.set(l.subtract_next(yi.get(), w[1] - w[0]));
    }
    let mut u = rows.u.sweep(y, &f.u_val[..]);
    let ends = rows.u_ptr.windows(2).rev();
    for ((yi, w), inv) in y.iter().rev().zip(ends).zip(f.u_inv.iter().rev()) {
        yi.set(u.subtract_last(yi.get(), w[1] - w[0]) * inv);
    }
}

#[cfg(test)]
#[path = "sparse_tests.rs"]
mod tests;
