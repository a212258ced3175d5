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
pub(crate) fn largest(x: &[f64]) -> f64 {
    let mut mx = [0.0f64; 8];
    let mut chunks = x.chunks_exact(8);
    for c in &mut chunks {
        for k in 0..8 {
            let v = c[k].abs();
            mx[k] = if v > mx[k] { v } else { mx[k] };
        }
    }
    for (k, v) in chunks.remainder().iter().enumerate() {
        let v = v.abs();
        mx[k] = if v > mx[k] { v } else { mx[k] };
    }
    mx.iter().fold(0.0f64, |m, v| m.max(*v))
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
mod tests {
    use super::*;

    /// The weight is `√(max|K| / max|C|)`, the scaled Frobenius norm that of
    /// the matrix scaled entry by entry, and the scaled inverse iteration
    /// the inverse iteration of that matrix.
    #[test]
    fn the_scale_is_that_of_the_matrix_scaled_entry_by_entry() {
        // [K Cᵀ; C 0] with K = diag(400, 9) and C = [0.5 1].
        let a = DMatrix::from_row_slice(3, 3, &[400.0, 0.0, 0.5, 0.0, 9.0, 1.0, 0.5, 1.0, 0.0]);
        let sizes = dense_sizes(&a, 2);
        assert_eq!(sizes.alpha(), 20.0);
        let s = sizes.scale(2);
        let das = scaled(&a, 2);
        assert_eq!(das[(2, 0)], 10.0);
        assert_eq!(das[(1, 2)], 20.0);
        assert!((s.fro - das.norm()).abs() < 1e-12 * das.norm());
        let lu_s = das.clone().lu();
        let lu = a.clone().lu();
        let direct = inverse_iteration(3, das.norm(), |y| {
            let x = lu_s
                .solve(&nalgebra::DVector::from_column_slice(y))
                .expect("regular");
            y.copy_from_slice(x.as_slice());
            true
        });
        let through = s.reciprocal_condition(3, |y| {
            let x = lu
                .solve(&nalgebra::DVector::from_column_slice(y))
                .expect("regular");
            y.copy_from_slice(x.as_slice());
            true
        });
        assert!(
            (direct - through).abs() < 1e-12 * direct,
            "{direct} {through}"
        );
        // Without constraints, or without stiffness, nothing is weighed.
        assert_eq!(dense_sizes(&a, 3).alpha(), 1.0);
        assert_eq!(BlockSizes::default().alpha(), 1.0);
    }

    /// The lanes give the plain running maximum and sum of each block,
    /// whatever the halves' lengths and remainders, and a NaN entry does
    /// not replace the maximum.
    #[test]
    fn lanes_give_the_running_maximum_and_sum() {
        for n in [0usize, 1, 3, 7, 8, 9, 23] {
            let mut x: Vec<f64> = (0..n).map(|i| ((i * 37 % 11) as f64 - 5.0) * 1.5).collect();
            let y: Vec<f64> = x.iter().map(|v| 0.5 * v + 1.0).collect();
            let max = x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            let sum: f64 = x.iter().map(|v| v * v).sum();
            let diff: f64 = x.iter().zip(&y).map(|(a, b)| (a - b) * (a - b)).sum();
            // As one coordinate column's coordinate rows (K), and as two
            // columns' halves split unevenly (C of each).
            let mut one = SizeLanes::default();
            one.add_column(true, &x, &[]);
            let mut two = SizeLanes::default();
            let (a, b) = x.split_at(n / 3);
            two.add_column(true, &[], a);
            two.add_column(false, b, &[]);
            let (k, c) = (one.sizes(), two.sizes());
            assert_eq!((largest(&x), k.k_max, c.c_max), (max, max, max), "n = {n}");
            assert_eq!((k.c_max, k.z_max, c.k_max, c.z_sq), (0.0, 0.0, 0.0, 0.0));
            for s in [k.k_sq, c.c_sq] {
                assert!((s - sum).abs() <= 1e-12 * sum.max(1.0), "n = {n}");
            }
            // The differences, weighed by block: all in C here, times α².
            let scale = Scale {
                coords: 0,
                alpha: 3.0,
                fro: 1.0,
            };
            let mut d = DifferenceLanes::default();
            d.add_column(true, (&[], &[]), (a, &y[..a.len()]));
            d.add_column(false, (b, &y[a.len()..]), (&[], &[]));
            assert!((d.total(&scale) - 9.0 * diff).abs() <= 1e-12 * diff.max(1.0));
            if n > 3 {
                // (the largest, 7.5, is at index 0)
                x[3] = f64::NAN;
                let mut nan = SizeLanes::default();
                nan.add_column(true, &x, &[]);
                assert_eq!(largest(&x), max, "n = {n}");
                assert_eq!(nan.sizes().k_max, max, "n = {n}");
            }
        }
    }

    /// The problem of two coupled McPherson corners and the Newton
    /// matrices at its equilibria along table 5-1, in order.
    fn corner_matrices() -> (crate::statics::Problem, Vec<DMatrix<f64>>) {
        use crate::statics::Problem;
        use crate::statics::path::{set_loads, solve_path};
        use crate::statics::system::{assemble, kkt};
        use crate::statics::testkit::coupled_corners;
        let (m, set) = coupled_corners(2);
        let p = Problem::new(&m).expect("problem");
        let loads = set_loads(&m, set).expect("loads");
        let eqs = solve_path(&p, set).expect("solves");
        let matrices = eqs
            .iter()
            .zip(&loads)
            .map(|(eq, l)| kkt(&assemble(&p, &eq.state, l).expect("assembles")))
            .collect();
        (p, matrices)
    }

    /// At the equilibria of a mechanism (two coupled McPherson corners,
    /// table 5-1), weighing the multipliers raises the ratio
    /// `σ_min / ‖D A D‖_F` of the SVD more than tenfold, and the estimate
    /// of both factorisations (dense and sparse) is within 1.3 of it, from
    /// above: the estimate a threshold is set on is that of the matrix.
    #[test]
    fn on_a_mechanism_the_weighed_estimate_is_close_and_far_from_singular() {
        use crate::statics::linear::Lu;
        use crate::statics::tangent::{Factorisation, NewtonMatrix};
        let (p, matrices) = corner_matrices();
        let n = p.layout.n();
        for k in [0, matrices.len() - 1] {
            let a = &matrices[k];
            let dim = a.nrows();
            let raw = a.singular_values().min() / a.norm();
            let s = scaled(a, n);
            let ratio = s.singular_values().min() / s.norm();
            assert!(
                ratio > 10.0 * raw,
                "case {k}: {ratio:.3e} against {raw:.3e}"
            );
            let mut dense = Lu::new(dim, n);
            let fa = faer::Mat::from_fn(dim, dim, |i, j| a[(i, j)]);
            assert!(dense.factor(&fa));
            let pat = p.pattern.clone().expect("the sparse path");
            let mut values = vec![0.0; pat.nnz()];
            for j in 0..dim {
                for slot in pat.col_ptr[j]..pat.col_ptr[j + 1] {
                    values[slot] = a[(pat.row_idx[slot], j)];
                }
            }
            let sparse_m = NewtonMatrix::Sparse(pat.clone(), values);
            let mut sparse = Factorisation::for_matrix(&sparse_m, n, Vec::new);
            assert!(sparse.factor(&sparse_m));
            for est in [dense.reciprocal_condition(), sparse.reciprocal_condition()] {
                assert!(
                    est >= ratio * (1.0 - 1e-9) && est < 1.3 * ratio,
                    "case {k}: estimate {est:.4e}, SVD {ratio:.4e}"
                );
            }
        }
    }

    /// Continued along a path (the equilibria of every case of table 5-1 on
    /// two coupled McPherson corners, in order), each estimate after the
    /// first takes one solve instead of two and stays within 1.3 of the
    /// SVD's ratio, from above, as the cold estimates do.
    #[test]
    fn a_continued_estimate_takes_one_solve_and_is_as_close() {
        use crate::statics::linear::Lu;
        let (p, matrices) = corner_matrices();
        let n = p.layout.n();
        let mut direction = Direction::default();
        for (k, a) in matrices.iter().enumerate() {
            let s = scaled(a, n);
            let ratio = s.singular_values().min() / s.norm();
            let dim = a.nrows();
            let mut lu = Lu::new(dim, n);
            assert!(lu.factor(&faer::Mat::from_fn(dim, dim, |i, j| a[(i, j)])));
            let scale = lu.scale();
            let mut solves = 0;
            let est = scale.reciprocal_condition_along(dim, &mut direction, |y| {
                solves += 1;
                lu.solve(y)
            });
            assert_eq!(solves, if k == 0 { 2 } else { 1 }, "case {k}");
            assert!(
                est >= ratio * (1.0 - 1e-9) && est < 1.3 * ratio,
                "case {k}: estimate {est:.4e}, SVD {ratio:.4e}"
            );
        }
    }

    /// A matrix whose softest direction is one the last matrix held
    /// stiffly, and which the last estimate's direction holds none of:
    /// the continued estimate still finds it singular (below the threshold
    /// of the exact test), by the irregular part of its start. From the
    /// last direction alone it would read the matrix as regular (the
    /// growth of a unit vector the matrix holds at 1).
    #[test]
    fn a_continued_estimate_finds_a_new_soft_direction() {
        use nalgebra::{DMatrix, DVector};
        let n = 12;
        let estimate = |d: &DMatrix<f64>, direction: &mut Direction| {
            let lu = d.clone().lu();
            inverse_iteration_along(n, d.norm(), direction, |y| {
                let x = lu.solve(&DVector::from_column_slice(y)).expect("regular");
                y.copy_from_slice(x.as_slice());
                true
            })
        };
        // Soft along the first coordinate, then stiff there and singular
        // to rounding along the sixth.
        let soft_first = DMatrix::from_fn(n, n, |i, j| match (i, j) {
            (0, 0) => 1e-3,
            _ if i == j => 1.0 + i as f64,
            _ => 0.0,
        });
        let soft_sixth = DMatrix::from_fn(n, n, |i, j| match (i, j) {
            (5, 5) => 1e-15,
            _ if i == j => 1.0 + i as f64,
            _ => 0.0,
        });
        let mut direction = Direction::default();
        let first = estimate(&soft_first, &mut direction);
        assert!(
            first > 1e-5 && first < 1.3e-3 / soft_first.norm(),
            "{first:e}"
        );
        // The last direction is the first coordinate's, to rounding.
        assert!(direction.last[0].abs() > 1.0 - 1e-6, "{:?}", direction.last);
        let next = estimate(&soft_sixth, &mut direction);
        assert!(
            next < crate::statics::isolation::CHECK_SINGULAR_BELOW,
            "{next:e}"
        );
        let mut bare = Direction {
            last: (0..n).map(|i| if i == 0 { 1.0 } else { 0.0 }).collect(),
            irregular: vec![0.0; n],
        };
        assert!(estimate(&soft_sixth, &mut bare) > 1e-3);
    }
}
