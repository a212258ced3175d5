//! How close the Newton matrix is to singular, cheaply: the estimates that
//! decide when the exact SVD test of [`super::system::singular_direction`]
//! must run, and when the factorisation of a nearby matrix may stand for
//! the equilibrium's ([`super::isolation`]).
//!
//! The Newton matrix is the saddle point `[K Cᵀ; C 0]` of the scaled
//! stiffness `K` (forces per length) and the constraint gradients `C`
//! (rows of unit norm). Its raw condition mixes the two units: the
//! constrained directions' singular values are about `‖C‖² / ‖K‖`, far
//! below any stiffness. So the estimates here are of `D A D`, with `D` one
//! on the coordinates and `α = √(max|K| / max|C|)` on the multipliers: a
//! change of the multipliers' unit, which leaves singularity and the
//! equilibrium as they are, after which the constrained directions weigh
//! about as the stiffnesses do. Measured by SVD at the car's curb
//! equilibrium (`examples/vehicle.axle`, 255 unknowns), `σ_min / ‖A‖_F` is
//! 3.5e-10 raw and 1.2e-7 scaled (the same from `α` = 100 to 1000); the
//! McPherson's 8.6e-8 and 2.6e-6. The raw ratio left the car 4.8 times
//! above the threshold of the SVD test's estimate, and every case of a
//! sweep needed two more solves to show its matrix regular.

use nalgebra::DMatrix;

/// A start vector of irregular signs and sizes for the power and inverse
/// iterations: no structure of a mechanism lines up with it.
pub(crate) fn irregular_start(n: usize) -> Vec<f64> {
    (0..n)
        .map(|i| {
            let t = (i as f64 + 1.0) * 0.618_033_988_749_895;
            (t - t.floor()) - 0.5
        })
        .collect()
}

/// The growth of two power steps `y ← step(y / ‖y‖)` from the irregular
/// start: the largest `‖step(ŷ)‖` (`step` an operator applied in place,
/// false if it fails). `None` when a step fails or an iterate is not a
/// number; the growth so far when an iterate vanishes.
pub(crate) fn power_growth(n: usize, step: impl FnMut(&mut [f64]) -> bool) -> Option<f64> {
    power_steps(&mut irregular_start(n), 2, step)
}

/// `steps` power steps from `y` (see [`power_growth`]); `y` ends as the
/// last iterate, not normalised.
fn power_steps(
    y: &mut [f64],
    steps: usize,
    mut step: impl FnMut(&mut [f64]) -> bool,
) -> Option<f64> {
    let mut growth = 0.0f64;
    for _ in 0..steps {
        let norm = y.iter().map(|v| v * v).sum::<f64>().sqrt();
        if norm.is_nan() {
            return None;
        }
        if norm == 0.0 {
            return Some(growth);
        }
        y.iter_mut().for_each(|v| *v /= norm);
        if !step(y) {
            return None;
        }
        growth = growth.max(y.iter().map(|v| v * v).sum::<f64>().sqrt());
    }
    (!growth.is_nan()).then_some(growth)
}

/// `1 / (‖A‖_F · ‖A⁻¹ y‖)` after two inverse iterations with `solve` from a
/// fixed irregular start: an estimate of `σ_min / σ_max` from above (it may
/// overstate the ratio, by a small factor for any matrix met in practice)
/// for any factorisation of an `n`×`n` matrix of Frobenius norm `a_fro`.
/// (The solvers continue their estimates, [`inverse_iteration_along`].)
#[cfg(test)]
pub(crate) fn inverse_iteration(
    n: usize,
    a_fro: f64,
    solve: impl FnMut(&mut [f64]) -> bool,
) -> f64 {
    inverse_iteration_along(n, a_fro, &mut Direction::default(), solve)
}

/// `1 / (‖A‖_F · growth)`, zero where there is no growth to show.
fn reciprocal(a_fro: f64, growth: Option<f64>) -> f64 {
    match growth {
        Some(growth) if growth > 0.0 && a_fro > 0.0 => 1.0 / (a_fro * growth),
        _ => 0.0,
    }
}

/// How much of the irregular start a continued estimate adds to the last
/// direction ([`Direction`]).
const IRREGULAR_PART: f64 = 0.1;

/// Where the last condition estimate of a sequence of related matrices
/// (the factorisations along a load path) ended, for the next to start
/// from ([`inverse_iteration_along`]).
///
/// Two inverse iterations from the irregular start go most of the way to
/// the softest direction and stop; the matrices of a path's cases differ
/// little in that direction (the McPherson's is its wheel travel against
/// the spring), so one inverse iteration from where the last estimate
/// ended goes as far. Measured on the random McPherson path (500
/// estimates) the continued estimate was 0.981-0.992 of the two
/// iterations' (lower: both are from above, so nearer the ratio), and
/// 0.953-0.996 on the coupled corners, N = 2 to 8: one solve an estimate
/// instead of two.
///
/// A matrix whose softest direction is new (a motion the last matrix held
/// stiffly) is what an estimate must not miss, and the last direction
/// holds little of it. So each start adds [`IRREGULAR_PART`] of the
/// irregular start, whose part along any direction is that of the cold
/// start, a tenth as large: one inverse iteration then grows it by the
/// new `1 / σ_min`.
#[derive(Debug, Clone, Default)]
pub(crate) struct Direction {
    /// The last estimate's final iterate, of unit norm; empty before the
    /// first or after [`Direction::forget`].
    last: Vec<f64>,
    /// The irregular start of unit norm, times [`IRREGULAR_PART`]
    /// (computed once for its length).
    irregular: Vec<f64>,
}

impl Direction {
    /// Starts over: the next estimate takes the two cold iterations.
    pub fn forget(&mut self) {
        self.last.clear();
    }

    /// Whether the next estimate starts cold.
    #[cfg(test)]
    pub fn is_cold(&self) -> bool {
        self.last.is_empty()
    }
}

/// [`inverse_iteration`] continued from where the last estimate of
/// `direction` ended (one inverse iteration, see [`Direction`]), or the
/// two cold iterations when it holds none of length `n`; `direction` then
/// holds this estimate's end.
pub(crate) fn inverse_iteration_along(
    n: usize,
    a_fro: f64,
    direction: &mut Direction,
    solve: impl FnMut(&mut [f64]) -> bool,
) -> f64 {
    if n == 0 {
        return 0.0;
    }
    let Direction { last, irregular } = direction;
    let growth = if last.len() == n {
        if irregular.len() != n {
            *irregular = irregular_start(n);
            let norm = irregular.iter().map(|v| v * v).sum::<f64>().sqrt();
            irregular
                .iter_mut()
                .for_each(|v| *v *= IRREGULAR_PART / norm);
        }
        for (y, u) in last.iter_mut().zip(irregular.iter()) {
            *y += u;
        }
        power_steps(last, 1, solve)
    } else {
        *last = irregular_start(n);
        power_steps(last, 2, solve)
    };
    let norm = last.iter().map(|v| v * v).sum::<f64>().sqrt();
    if norm > 0.0 && norm.is_finite() {
        last.iter_mut().for_each(|v| *v /= norm);
    } else {
        last.clear();
    }
    reciprocal(a_fro, growth)
}

/// The sizes of the blocks of a Newton matrix `[K Cᵀ; C Z]` whose first
/// `coords` rows and columns are the coordinates': largest entries and
/// sums of squares, `c` counting both `C` and `Cᵀ`.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(crate) struct BlockSizes {
    pub k_max: f64,
    pub c_max: f64,
    pub z_max: f64,
    pub k_sq: f64,
    pub c_sq: f64,
    pub z_sq: f64,
}

impl BlockSizes {
    /// Adds a run of entries (largest absolute value `max`, sum of squares
    /// `sq`) whose row and column are coordinates or not.
    pub fn add(&mut self, row_coord: bool, col_coord: bool, max: f64, sq: f64) {
        let (m, s) = match (row_coord, col_coord) {
            (true, true) => (&mut self.k_max, &mut self.k_sq),
            (false, false) => (&mut self.z_max, &mut self.z_sq),
            _ => (&mut self.c_max, &mut self.c_sq),
        };
        // Like `f64::max`, a NaN entry does not replace the maximum (the
        // factorisation refuses such a matrix; the sums carry the NaN).
        *m = if max > *m { max } else { *m };
        *s += sq;
    }

    pub fn merge(&mut self, o: &BlockSizes) {
        self.add(true, true, o.k_max, o.k_sq);
        self.add(true, false, o.c_max, o.c_sq);
        self.add(false, false, o.z_max, o.z_sq);
    }

    /// The multipliers' weight `α` (one without a stiffness or a
    /// constraint to weigh against).
    pub fn alpha(&self) -> f64 {
        let a = (self.k_max / self.c_max).sqrt();
        if a.is_finite() && a > 0.0 { a } else { 1.0 }
    }

    /// The scaling of `D A D` for a matrix with `coords` coordinates.
    pub fn scale(&self, coords: usize) -> Scale {
        let alpha = self.alpha();
        let a2 = alpha * alpha;
        Scale {
            coords,
            alpha,
            fro: (self.k_sq + a2 * self.c_sq + a2 * a2 * self.z_sq).sqrt(),
        }
    }
}

/// `D = diag(1, …, 1, α, …, α)` (`coords` ones) and `‖D A D‖_F` for the
/// matrix `A` of a factorisation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Scale {
    pub coords: usize,
    pub alpha: f64,
    pub fro: f64,
}

impl Scale {
    /// The weight of row or column `i`.
    pub fn weight(&self, i: usize) -> f64 {
        if i < self.coords { 1.0 } else { self.alpha }
    }

    /// `y ← D y`.
    pub fn times(&self, y: &mut [f64]) {
        y.iter_mut()
            .skip(self.coords)
            .for_each(|v| *v *= self.alpha);
    }

    /// `y ← D⁻¹ y`.
    pub fn divide(&self, y: &mut [f64]) {
        y.iter_mut()
            .skip(self.coords)
            .for_each(|v| *v /= self.alpha);
    }

    /// [`Self::reciprocal_condition_along`] from the cold start.
    #[cfg(test)]
    pub fn reciprocal_condition(&self, n: usize, solve: impl FnMut(&mut [f64]) -> bool) -> f64 {
        self.reciprocal_condition_along(n, &mut Direction::default(), solve)
    }

    /// [`inverse_iteration_along`] of `D A D`, whose inverse is
    /// `D⁻¹ A⁻¹ D⁻¹`, with `solve` the factorisation of `A`.
    pub fn reciprocal_condition_along(
        &self,
        n: usize,
        direction: &mut Direction,
        mut solve: impl FnMut(&mut [f64]) -> bool,
    ) -> f64 {
        inverse_iteration_along(n, self.fro, direction, |y| self.inverse_step(y, &mut solve))
    }

    /// `y ← D⁻¹ A⁻¹ D⁻¹ y` with `solve` the factorisation of `A`.
    fn inverse_step(&self, y: &mut [f64], solve: &mut impl FnMut(&mut [f64]) -> bool) -> bool {
        self.divide(y);
        let ok = solve(y);
        self.divide(y);
        ok
    }
}

/// The largest absolute value of `x`, in lanes as [`SizeLanes`]
/// (every factorisation takes it, the sum of squares only a case's scale).
/// A NaN is passed over (a factorisation refuses its pivots anyway).
pub(crate) fn largest(x: &[f64]) -> f64 {
    lanes_of_largest(x).0
}

/// The largest absolute value of `x`, infinite when an entry is NaN (which
/// a maximum passes over): a residual's size for the convergence test,
/// where an undefined force must never read as a small one.
pub(crate) fn largest_or_infinite(x: &[f64]) -> f64 {
    match lanes_of_largest(x) {
        (_, true) => f64::INFINITY,
        (max, false) => max,
    }
}

/// `x`'s largest absolute value (NaNs passed over) and whether it holds a
/// NaN, in eight lanes: one running maximum is a chain of dependent
/// comparisons, each waiting on the last (perf put 2.5 % of a McPherson
/// case's samples on a Newton iteration's two residual sizes; the lanes
/// took 0.5 % off the clock). The maximum is exact, so the lanes give the
/// bits one chain would.
#[inline(always)]
fn lanes_of_largest(x: &[f64]) -> (f64, bool) {
    let mut mx = [0.0f64; 8];
    let mut nan = [false; 8];
    let mut chunks = x.chunks_exact(8);
    for c in &mut chunks {
        for k in 0..8 {
            let v = c[k].abs();
            nan[k] |= v.is_nan();
            mx[k] = if v > mx[k] { v } else { mx[k] };
        }
    }
    for (k, v) in chunks.remainder().iter().enumerate() {
        let v = v.abs();
        nan[k] |= v.is_nan();
        mx[k] = if v > mx[k] { v } else { mx[k] };
    }
    (
        mx.iter().fold(0.0f64, |m, v| m.max(*v)),
        nan.iter().any(|b| *b),
    )
}

/// Lanes of the running sums and maxima below: a single running sum is a
/// chain of dependent additions, which cost as much as a fifth of the whole
/// solve; independent lanes let them overlap. The lanes run on across the
/// columns and are added up once at the end, for a column's halves are
/// short (3 to 8 entries on the McPherson): added up half by half, the
/// lanes cost more than the entries did.
const LANES: usize = 4;

/// The block of `[K Cᵀ; C Z]` of a column's coordinate rows (`top`) or its
/// multiplier rows: 0 for `K`, 1 for `C` or `Cᵀ`, 2 for `Z`.
fn block(col_coord: bool, top: bool) -> usize {
    match (col_coord, top) {
        (true, true) => 0,
        (false, false) => 2,
        _ => 1,
    }
}

/// [`BlockSizes`] gathered column by column.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct SizeLanes {
    max: [[f64; LANES]; 3],
    sq: [[f64; LANES]; 3],
}

impl SizeLanes {
    /// Adds a column (a coordinate's or not) as its coordinate rows `top`
    /// and its multiplier rows `bottom`.
    pub fn add_column(&mut self, col_coord: bool, top: &[f64], bottom: &[f64]) {
        self.take(block(col_coord, true), top);
        self.take(block(col_coord, false), bottom);
    }

    fn take(&mut self, b: usize, x: &[f64]) {
        let (mx, sq) = (&mut self.max[b], &mut self.sq[b]);
        let mut chunks = x.chunks_exact(LANES);
        for c in &mut chunks {
            for k in 0..LANES {
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

    pub fn sizes(&self) -> BlockSizes {
        let max = |b: usize| self.max[b].iter().fold(0.0f64, |m, v| m.max(*v));
        let sq = |b: usize| self.sq[b].iter().sum::<f64>();
        BlockSizes {
            k_max: max(0),
            c_max: max(1),
            z_max: max(2),
            k_sq: sq(0),
            c_sq: sq(1),
            z_sq: sq(2),
        }
    }
}

/// `‖D (x - y) D‖²_F` of two matrices gathered column by column, block by
/// block (as [`SizeLanes`]).
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct DifferenceLanes {
    sq: [[f64; LANES]; 3],
}

impl DifferenceLanes {
    /// Adds a column (a coordinate's or not) of both matrices as their
    /// coordinate rows `top` and their multiplier rows `bottom`.
    pub fn add_column(&mut self, col_coord: bool, top: (&[f64], &[f64]), bottom: (&[f64], &[f64])) {
        self.take(block(col_coord, true), top.0, top.1);
        self.take(block(col_coord, false), bottom.0, bottom.1);
    }

    fn take(&mut self, b: usize, x: &[f64], y: &[f64]) {
        let d = &mut self.sq[b];
        let (xs, ys) = (x.chunks_exact(LANES), y.chunks_exact(LANES));
        let (xr, yr) = (xs.remainder(), ys.remainder());
        for (a, c) in xs.zip(ys) {
            for k in 0..LANES {
                d[k] += (a[k] - c[k]) * (a[k] - c[k]);
            }
        }
        for (k, (a, c)) in xr.iter().zip(yr).enumerate() {
            d[k] += (a - c) * (a - c);
        }
    }

    /// The sum with `D`'s weights: `K`'s entries once, `C`'s times `α²`,
    /// `Z`'s times `α⁴`.
    pub fn total(&self, s: &Scale) -> f64 {
        let a2 = s.alpha * s.alpha;
        let sum = |b: usize| self.sq[b].iter().sum::<f64>();
        sum(0) + a2 * sum(1) + a2 * a2 * sum(2)
    }
}

/// Slots of a matrix's value array (a sparse matrix's), with the least
/// length an array needs for all of them: checked once a pass, not once
/// an entry (as [`super::products::Products`] does its pairs).
#[derive(Debug, Clone, Default)]
pub(crate) struct Slots {
    at: Vec<u32>,
    need: usize,
}

impl Slots {
    pub fn new(at: Vec<u32>) -> Slots {
        let need = at.iter().map(|&k| k as usize + 1).max().unwrap_or(0);
        Slots { at, need }
    }
}

/// [`SizeLanes`] of one matrix and [`DifferenceLanes`] of it and another,
/// in one flat pass a block over its slots ([`Slots`]): the isolation
/// check ([`super::isolation`]) needs both of the factorised matrix, its
/// scaling and its distance to the equilibrium's. Passes column half by
/// column half (3 to 9 entries each on the McPherson) cost a hundred
/// instructions a half, most of them the half's own; here a block is one
/// run of lanes.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct SizeDifferenceLanes {
    pub sizes: SizeLanes,
    pub difference: DifferenceLanes,
}

impl SizeDifferenceLanes {
    /// Adds the entries at `slots` of `x` (sizes) and of `x - y`
    /// (difference) to block `b` (0 for `K`, 1 for `C` and `Cᵀ`, 2 for
    /// `Z`). Panics if `x` or `y` is shorter than the slots need.
    pub fn take(&mut self, b: usize, slots: &Slots, x: &[f64], y: &[f64]) {
        assert!(
            x.len() >= slots.need && y.len() >= slots.need,
            "a matrix shorter than its slots"
        );
        let (mx, sq) = (&mut self.sizes.max[b], &mut self.sizes.sq[b]);
        let d = &mut self.difference.sq[b];
        let mut add = |k: usize, i: u32| {
            // SAFETY: the assertion above: `i < slots.need <= x.len(), y.len()`.
            let (a, c) = unsafe { (*x.get_unchecked(i as usize), *y.get_unchecked(i as usize)) };
            let v = a.abs();
            mx[k] = if v > mx[k] { v } else { mx[k] };
            sq[k] += v * v;
            d[k] += (a - c) * (a - c);
        };
        // Lane `k` takes every `LANES`-th slot from the `k`-th.
        let mut chunks = slots.at.chunks_exact(LANES);
        for c in &mut chunks {
            for (k, &i) in c.iter().enumerate() {
                add(k, i);
            }
        }
        for (k, &i) in chunks.remainder().iter().enumerate() {
            add(k, i);
        }
    }
}

/// The sizes of a dense Newton matrix with `coords` coordinates.
pub(crate) fn dense_sizes(a: &DMatrix<f64>, coords: usize) -> BlockSizes {
    let mut s = SizeLanes::default();
    let c = coords.min(a.nrows());
    for (j, col) in a.column_iter().enumerate() {
        let (top, bottom) = col.as_slice().split_at(c);
        s.add_column(j < c, top, bottom);
    }
    s.sizes()
}

/// `D A D` of a dense Newton matrix with `coords` coordinates.
pub(crate) fn scaled(a: &DMatrix<f64>, coords: usize) -> DMatrix<f64> {
    let d = dense_sizes(a, coords).scale(coords);
    DMatrix::from_fn(a.nrows(), a.ncols(), |i, j| {
        a[(i, j)] * d.weight(i) * d.weight(j)
    })
}

#[cfg(test)]
#[path = "condition_tests.rs"]
mod tests;
