//! The sparse LU of the scaled Newton matrix in its [`Pattern`]: the contract
//! of the dense [`super::linear::Lu`] (factor, solve, check a solution,
//! distance to another matrix, condition estimate) for models too large for
//! the dense elimination (see [`super::tangent`] for the choice).
//!
//! The fill-reducing column order is the pattern's, computed once per
//! problem. A fresh factorisation ([`pivoting`]) chooses the pivot rows by
//! threshold and fill (a row swap is safe for the zero diagonal block of the
//! multipliers), and its work follows the non-zeros of the factors, so that
//! a chain of N coupled corners costs N times one corner, not N³. Finding
//! each column's structure costs more than its arithmetic, so the next
//! matrix is refactorised KLU's way:
//! with the previous pivot sequence and the structure of L and U (the same
//! for every matrix of the pattern with those pivots), numbers only
//! ([`super::refactor::Plan`]: the products each entry of the factors is
//! made of, listed once per structure), as long as every pivot keeps at
//! least [`PIVOT_THRESHOLD`] of the largest entry left in its column;
//! otherwise it is factorised afresh with new pivots. Only the slots that
//! can be non-zero are factorised ([`Live`]). The substitutions and the
//! residual check run row by row ([`pivoting::Rows`], [`Live::residual`]),
//! each row's sum in a register.

use super::condition::{BlockSizes, Scale, largest};
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
}

impl Pivots {
    /// The multiply-adds of a refactorisation with these pivots.
    pub fn updates(&self) -> usize {
        self.own.updates()
    }
}

pub(crate) struct SparseLu {
    pattern: Arc<Pattern>,
    /// The slots factorised, and the values factorised in them.
    live: Arc<Live>,
    live_a: Vec<f64>,
    /// How often a matrix widened `live`.
    pub widened: usize,
    row_perm: Vec<usize>,
    row_perm_inv: Vec<usize>,
    /// The matrix factorised in the pattern's slots: `live_a` in the live
    /// slots, zero in the others (whose entries [`Live::holds`] bounded by a
    /// rounding's size; the factors are those of this matrix).
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
    /// A dense vector, zero between uses.
    work: Vec<f64>,
    res: Vec<f64>,
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
            live_a: vec![0.0; live.from.len()],
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
            res: vec![0.0; n],
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
        lu.live_a = vec![0.0; live.from.len()];
        lu.live = Arc::new(live);
        lu.reusable = false;
        lu
    }

    /// The pivots of the last factorisation, if it succeeded and has a
    /// plan to refactorise with.
    pub fn pivots(&self) -> Option<Pivots> {
        (self.valid && self.reusable).then(|| Pivots {
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
        self.valid = false;
        if values.len() != self.a.len() {
            return false;
        }
        self.scale.set(None);
        // The largest live entry is the matrix's largest when the other
        // entries are at most `DROP` times it, which is what `holds` asks.
        self.a_max = self.gather(values);
        if !self.live.holds(values, self.a_max) {
            let Some(live) = self.live.widened(&self.pattern, values) else {
                return false;
            };
            self.live = Arc::new(live);
            self.live_a.resize(self.live.from.len(), 0.0);
            self.reusable = false;
            self.widened += 1;
            self.a_max = self.gather(values);
        }
        self.last_reused =
            self.reusable && self.plan.run(&mut self.own, &self.live_a, PIVOT_THRESHOLD);
        if self.last_reused {
            self.reused += 1;
            self.valid = true;
            return true;
        }
        self.fresh += 1;
        let ok = self.factor_fresh();
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

    /// The live entries of `values` into `live_a` and `a`; their largest
    /// magnitude (a NaN passed over, as by `f64::max`).
    fn gather(&mut self, values: &[f64]) -> f64 {
        for (v, &k) in self.live_a.iter_mut().zip(&self.live.from) {
            let x = values[k];
            *v = x;
            self.a[k] = x;
        }
        // In lanes: a running maximum is a chain of dependent steps.
        largest(&self.live_a)
    }

    /// A factorisation of `live_a` with fresh pivots ([`pivoting`]) into `own`.
    fn factor_fresh(&mut self) -> bool {
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
        let (f, y, p) = (&self.own, &mut self.work, &self.live.pattern);
        for (pos, &r) in self.row_perm.iter().enumerate() {
            y[pos] = b[r];
        }
        // Row by row ([`super::pivoting::Rows`]), each row's sum in a register.
        let rows = &f.rows;
        for i in 0..n {
            let mut acc = y[i];
            for &(j, e) in &rows.l[rows.l_ptr[i]..rows.l_ptr[i + 1]] {
                acc -= f.l_val[e as usize] * y[j as usize];
            }
            y[i] = acc;
        }
        for i in (0..n).rev() {
            let mut acc = y[i];
            for &(j, e) in &rows.u[rows.u_ptr[i]..rows.u_ptr[i + 1]] {
                acc -= f.u_val[e as usize] * y[j as usize];
            }
            y[i] = acc * f.u_inv[i];
        }
        for (j, &c) in p.order.iter().enumerate() {
            b[c] = y[j];
            y[j] = 0.0;
        }
        b.iter().all(|v| v.is_finite())
    }

    /// Whether `x` solves `A x = b` to a residual of `1e-8` of the sizes
    /// involved (as [`super::linear::Lu::satisfies`]), `A` the matrix of
    /// `values` in the live slots (its other entries, which `holds` bounds,
    /// change the residual by far less than that).
    pub fn satisfies(&mut self, values: &[f64], x: &[f64], b: &[f64]) -> bool {
        if values.len() != self.a.len() || x.len() != self.dim() || b.len() != self.dim() {
            return false;
        }
        let x_max = x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let b_max = b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let r = self.live.residual(values, x, b, &mut self.res);
        r <= 1e-8 * (b_max + self.a_max * x_max)
    }

    /// The scaling of [`super::condition`] for the matrix last factorised.
    pub fn scale(&self) -> Scale {
        if let Some(s) = self.scale.get() {
            return s;
        }
        // On the live slots: the others of `a` are zero.
        let (p, c) = (&self.live.pattern, self.pattern.coords());
        let mut sizes = BlockSizes::default();
        for j in 0..p.dim() {
            let (top, bottom) = p.column_halves(j);
            sizes.add_column(j < c, &self.live_a[top], &self.live_a[bottom]);
        }
        let s = sizes.scale(c);
        self.scale.set(Some(s));
        s
    }

    /// `‖D (B - A) D‖_F / ‖D A D‖_F` for the matrix `A` last factorised and
    /// its scaling `D` (as [`super::linear::Lu::distance_to`]).
    pub fn distance_to(&self, values: &[f64]) -> f64 {
        if !self.valid || values.len() != self.a.len() {
            return f64::INFINITY;
        }
        let (p, s) = (&*self.pattern, self.scale());
        let mut d = 0.0f64;
        for j in 0..p.dim() {
            let (top, bottom) = p.column_halves(j);
            d += s.column_squares(
                j,
                (&self.a[top.clone()], &values[top]),
                (&self.a[bottom.clone()], &values[bottom]),
            );
        }
        d.sqrt() / s.fro
    }

    /// Adds `(B - A) y` to `out`, `A` the matrix last factorised and `B` the
    /// matrix of `values`.
    pub fn add_difference_times(&self, values: &[f64], y: &[f64], out: &mut [f64]) {
        let p = &self.pattern;
        for (j, yj) in y.iter().enumerate() {
            let range = p.col_ptr[j]..p.col_ptr[j + 1];
            let rows = p.row_idx[range.clone()].iter();
            for (&i, (a, b)) in rows.zip(self.a[range.clone()].iter().zip(&values[range])) {
                out[i] += (b - a) * yj;
            }
        }
    }

    /// An estimate of `σ_min / σ_max` of the matrix scaled as `D A D` (as
    /// [`super::linear::Lu::reciprocal_condition`]).
    pub fn reciprocal_condition(&mut self) -> f64 {
        if !self.valid {
            return 0.0;
        }
        let (n, s) = (self.dim(), self.scale());
        s.reciprocal_condition(n, |y| self.solve(y))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::statics::Problem;
    use crate::statics::linear::Lu;
    use crate::statics::path::solve_path;
    use crate::statics::tangent::SPARSE_FROM;
    use crate::statics::testkit::{Lcg, coupled_corners, kkt_values};

    /// The pattern of the coupled model of `n` corners, whatever its size.
    fn pattern(n: usize) -> (Problem, Arc<Pattern>) {
        let (m, _) = coupled_corners(n);
        let p = Problem::new(&m).expect("problem");
        let pat = Arc::new(Pattern::new(&p).expect("pattern"));
        (p, pat)
    }

    /// [`kkt_values`] without zeros, from a seed.
    fn values(pat: &Pattern, n: usize, seed: u64) -> Vec<f64> {
        kkt_values(pat, n, &mut Lcg::new(seed), 0.0)
    }

    fn dense(pat: &Pattern, v: &[f64]) -> faer::Mat<f64> {
        let mut a = faer::Mat::zeros(pat.dim(), pat.dim());
        for j in 0..pat.dim() {
            for k in pat.col_ptr[j]..pat.col_ptr[j + 1] {
                a[(pat.row_idx[k], j)] = v[k];
            }
        }
        a
    }

    /// On random matrices with the KKT pattern of one and of three coupled
    /// corners (47 and 141 unknowns), the sparse LU's solutions agree with the
    /// dense LU's to 1e-12 relative times the condition over 1e4 (the random
    /// saddle points reach condition numbers of 1e4-1e5, and the two LUs
    /// pivot in different orders) and satisfy the system; its norms,
    /// distance and condition estimate agree too.
    #[test]
    fn sparse_lu_solves_kkt_matrices_as_the_dense_lu() {
        for (n, seed) in [(1, 5), (3, 9), (3, 10)] {
            let (p, pat) = pattern(n);
            let v = values(&pat, p.layout.n(), seed);
            let a = dense(&pat, &v);
            let dim = pat.dim();
            let (mut d, mut s) = (Lu::new(dim, p.layout.n()), SparseLu::new(pat.clone()));
            assert!(d.factor(&a) && s.factor(&v));
            let b: Vec<f64> = (0..dim).map(|i| (i as f64 * 0.37).sin()).collect();
            let (mut x, mut y) = (b.clone(), b.clone());
            assert!(d.solve(&mut x) && s.solve(&mut y));
            let cond = 1.0 / d.reciprocal_condition();
            assert!(cond < 1e6, "{cond}");
            let tol = 1e-12 * (cond / 1e4).max(1.0);
            let scale = x.iter().fold(0.0f64, |m, u| m.max(u.abs()));
            for (u, w) in x.iter().zip(&y) {
                assert!(
                    (u - w).abs() <= tol * scale,
                    "{u} {w} (N = {n}, condition {cond:.1e})"
                );
            }
            assert!(s.satisfies(&v, &y, &b));
            let mut wrong = y.clone();
            wrong[dim - 1] += 1e-3 * scale;
            assert!(!s.satisfies(&v, &wrong, &b));
            let mut moved = v.clone();
            moved[0] += 0.25;
            let mut am = a.clone();
            am[(pat.row_idx[0], 0)] += 0.25;
            assert!((d.distance_to(&am) - s.distance_to(&moved)).abs() < 1e-12);
            let (rd, rs) = (d.reciprocal_condition(), s.reciprocal_condition());
            assert!((rd - rs).abs() < 1e-9 * rd, "{rd} {rs}");
            // The estimate is of the matrix with its multipliers weighed
            // (`condition`): from above against its SVD, and within 100 on
            // these random saddle points (3, 8 and 80: two inverse
            // iterations do not always find their smallest direction; a
            // mechanism's are within 1.3, `condition`'s test).
            let ad = nalgebra::DMatrix::from_fn(dim, dim, |i, j| am[(i, j)]);
            let scaled = crate::statics::condition::scaled(&ad, p.layout.n());
            let sv = scaled.singular_values();
            let ratio = sv.min() / scaled.norm();
            d.factor(&am);
            let est = d.reciprocal_condition();
            eprintln!("N = {n}: estimate {est:.3e}, SVD {ratio:.3e}");
            assert!(
                est >= ratio * (1.0 - 1e-9) && est < 100.0 * ratio,
                "{est} {ratio}"
            );
            // A nearby matrix is refactorised with the same pivots, and
            // solved as accurately.
            let mut rng = Lcg::new(seed + 100);
            let v2: Vec<f64> = v.iter().map(|x| x * (1.0 + 0.05 * rng.next())).collect();
            assert!(d.factor(&dense(&pat, &v2)) && s.factor(&v2));
            assert_eq!((s.fresh, s.reused), (1, 1));
            let (mut x, mut y) = (b.clone(), b.clone());
            assert!(d.solve(&mut x) && s.solve(&mut y) && s.satisfies(&v2, &y, &b));
            let scale = x.iter().fold(0.0f64, |m, u| m.max(u.abs()));
            for (u, w) in x.iter().zip(&y) {
                assert!((u - w).abs() <= tol * scale, "{u} {w} (N = {n}, reused)");
            }
            // Pivoting afresh (Newton's fallback when a reused factorisation's
            // solve fails the residual check) gives the same solution; after a
            // fresh factorisation there is nothing else to try.
            assert_eq!(s.factor_afresh(&v2), Some(true));
            assert_eq!((s.fresh, s.reused), (2, 1));
            assert_eq!(s.factor_afresh(&v2), None);
            let mut z = b.clone();
            assert!(s.solve(&mut z) && s.satisfies(&v2, &z, &b));
            for (u, w) in x.iter().zip(&z) {
                assert!((u - w).abs() <= tol * scale, "{u} {w} (N = {n}, afresh)");
            }
        }
    }

    /// `Factorisation::perturbation` (what `finish` relies on to let the last
    /// Newton iterate's factorisation stand for the equilibrium's matrix)
    /// against the exact `‖D⁻¹ A⁻¹ (B - A) D‖₂` of an SVD (`D` the
    /// scaling of `condition`), in both storages, on
    /// the KKT pattern of one and of three corners, for random
    /// perturbations of three sizes: from below, and wherever `finish`
    /// accepts it (at most `STAND_IN`), the norm is within the factor
    /// `STAND_IN_MARGIN` it takes, below 1; and at least 1 (so `finish`
    /// factorises `B`) for a singular `B`, a column of `A` zeroed
    /// (`E = -e_j e_jᵀ` exactly), whatever the column.
    #[test]
    fn perturbation_estimates_the_distance_to_a_factorised_matrix() {
        use crate::statics::tangent::{Factorisation, NewtonMatrix};
        use crate::statics::{STAND_IN, STAND_IN_MARGIN};
        let mut accepted = 0;
        let storages = |pat: &Arc<Pattern>, v: &[f64]| {
            let d = dense(pat, v);
            [
                NewtonMatrix::Sparse(pat.clone(), v.to_vec()),
                NewtonMatrix::Dense(d),
            ]
        };
        for (corners, seed) in [(1, 31), (3, 33)] {
            let (p, pat) = pattern(corners);
            let (n, dim) = (p.layout.n(), pat.dim());
            let va = values(&pat, n, seed);
            let ad = nalgebra::DMatrix::from_fn(dim, dim, |i, j| dense(&pat, &va)[(i, j)]);
            let inv = ad.clone().try_inverse().expect("regular");
            let sc = crate::statics::condition::dense_sizes(&ad, n).scale(n);
            let d = nalgebra::DMatrix::from_fn(
                dim,
                dim,
                |i, j| {
                    if i == j { sc.weight(i) } else { 0.0 }
                },
            );
            let d_inv = d.clone().try_inverse().expect("positive");
            for (k, size) in [1e-6, 1e-3, 3e-2].into_iter().enumerate() {
                let mut rng = Lcg::new(seed + 7 * k as u64);
                let vb: Vec<f64> = va.iter().map(|a| a + size * rng.next()).collect();
                let bd = nalgebra::DMatrix::from_fn(dim, dim, |i, j| dense(&pat, &vb)[(i, j)]);
                let exact = (&d_inv * &inv * (&bd - &ad) * &d).singular_values().max();
                for (a, b) in storages(&pat, &va).iter().zip(storages(&pat, &vb)) {
                    let mut f = Factorisation::for_matrix(a, n, || vec![(0..dim).collect()]);
                    assert!(f.factor(a));
                    let est = f.perturbation(&b);
                    eprintln!(
                        "N = {corners}, size {size:.0e}: exact {exact:.3e}, estimate {est:.3e}"
                    );
                    assert!(est <= exact * (1.0 + 1e-8), "{est} {exact}");
                    assert!(
                        est > STAND_IN || exact <= STAND_IN_MARGIN * est.max(1e-300),
                        "{est} {exact}"
                    );
                    accepted += usize::from(est <= STAND_IN);
                    assert_eq!(f.perturbation(a), 0.0, "B = A");
                }
            }
            for j in [0, n / 2, n, dim - 1] {
                let mut vb = va.clone();
                vb[pat.col_ptr[j]..pat.col_ptr[j + 1]]
                    .iter_mut()
                    .for_each(|x| *x = 0.0);
                for (a, b) in storages(&pat, &va).iter().zip(storages(&pat, &vb)) {
                    let mut f = Factorisation::for_matrix(a, n, || vec![(0..dim).collect()]);
                    assert!(f.factor(a));
                    let est = f.perturbation(&b);
                    assert!(est >= 1.0 - 1e-9, "column {j}: {est}");
                }
            }
        }
        // The smallest perturbations are accepted (both sizes, both storages).
        assert!(accepted >= 4, "{accepted}");
    }

    /// Two constraint rows made equal (a redundant joint equation): the sparse
    /// LU reports a failed factorisation or a condition estimate that flags it.
    #[test]
    fn sparse_lu_detects_a_singular_kkt_matrix() {
        let (p, pat) = pattern(3);
        let n = p.layout.n();
        let mut v = values(&pat, n, 21);
        // Multipliers 0 and 1 belong to one joint: the same parts, the same
        // slots (in the Jacobian's rows and in its transpose's columns).
        for j in 0..n {
            if let (Some((ra, ca)), Some((rb, cb))) =
                (pat.constraint_slots(0, j), pat.constraint_slots(1, j))
            {
                v[rb] = v[ra];
                v[cb] = v[ca];
            }
        }
        let mut s = SparseLu::new(pat.clone());
        let ok = s.factor(&v);
        assert!(!ok || s.reciprocal_condition() < 1e-12);
        // A regular matrix of the same pattern is not flagged.
        assert!(s.factor(&values(&pat, n, 22)) && s.reciprocal_condition() > 1e-8);
    }

    /// The coupled model of two corners (94 unknowns, the sparse path) solves
    /// table 5-1 to the equilibria of the dense path, part by part.
    #[test]
    fn coupled_corners_solve_by_the_sparse_path_as_by_the_dense_path() {
        let (m, set) = coupled_corners(2);
        let sparse = Problem::new(&m).expect("problem");
        assert!(sparse.layout.n() + sparse.kept.len() >= SPARSE_FROM);
        assert!(sparse.pattern.is_some(), "the sparse path is chosen");
        let dense = Problem {
            pattern: None,
            ..sparse.clone()
        };
        let (es, ed) = (
            solve_path(&sparse, set).expect("solves"),
            solve_path(&dense, set).expect("solves"),
        );
        for (a, b) in es.iter().zip(&ed) {
            for part in 0..m.parts.len() {
                let id = crate::model::PartId(part as u32);
                if m.parts[part].ground {
                    continue;
                }
                let ((xa, ra), (xb, rb)) = (a.state.part_pose(id), b.state.part_pose(id));
                assert!((xa - xb).norm() < 1e-9, "{} mm", (xa - xb).norm());
                assert!((ra - rb).norm() < 1e-12, "{} rad", (ra - rb).norm());
            }
        }
    }

    /// The factors' work grows with the number of coupled corners as the
    /// corners do: the multiply-adds of a refactorisation of N corners (with
    /// the fresh pivots of their design matrix, which every solve of the
    /// problem starts from) stay within 1.4 N those of one corner (1.21 at
    /// N = 2, 1.34 at N = 8). Partial pivoting (the largest entry of each
    /// column, faer's, used before) needed 78 295 at N = 8, 2.4 N
    /// (`docs/performance.md`).
    #[test]
    fn the_fill_of_coupled_corners_grows_with_their_number() {
        let work = |n: usize| {
            let (p, pat) = pattern(n);
            let mut ws = crate::statics::assembly::Workspace::new(&p);
            let design = crate::statics::coords::State::design(&p.model);
            ws.eval(&p, &design, &[], true).expect("evaluates");
            // In the pattern's slots whatever the storage (one corner is dense).
            let a = ws.matrix();
            let v: Vec<f64> = (0..pat.dim())
                .flat_map(|j| (pat.col_ptr[j]..pat.col_ptr[j + 1]).map(move |k| (k, j)))
                .map(|(k, j)| a[(pat.row_idx[k], j)])
                .collect();
            let mut lu = SparseLu::new(pat.clone());
            assert!(lu.factor(&v));
            (lu.own.updates(), lu.own.entries())
        };
        let one = work(1);
        for n in [2, 8] {
            let (updates, entries) = work(n);
            eprintln!(
                "{n} corners: {updates} multiply-adds ({:.2} per corner of one), {entries} entries ({:.2})",
                updates as f64 / (n * one.0) as f64,
                entries as f64 / (n * one.1) as f64
            );
            assert!(
                updates as f64 <= 1.4 * (n * one.0) as f64,
                "{updates} vs {}",
                one.0
            );
        }
    }

    /// A matrix with a non-zero outside the slots the factors cover widens
    /// them (once) and is solved as the dense LU solves it; a matrix inside
    /// is solved on the narrower slots.
    #[test]
    fn a_non_zero_outside_the_live_slots_widens_them() {
        let (p, pat) = pattern(1);
        let v = values(&pat, p.layout.n(), 21);
        // Every fifth slot off the diagonal left out.
        let mut keep: Vec<bool> = (0..pat.nnz()).map(|k| k % 5 != 0).collect();
        for j in 0..pat.dim() {
            if let Some(k) = pat.slot(j, j) {
                keep[k] = true;
            }
        }
        let narrow = Live::new(&pat, &keep).expect("order");
        assert!(narrow.count().0 < pat.nnz());
        let inside: Vec<f64> = v
            .iter()
            .zip(&keep)
            .map(|(x, k)| if *k { *x } else { 0.0 })
            .collect();
        let b: Vec<f64> = (0..pat.dim()).map(|i| (i as f64 * 0.61).cos()).collect();
        let check = |s: &mut SparseLu, vals: &[f64]| {
            let mut d = Lu::new(pat.dim(), p.layout.n());
            assert!(d.factor(&dense(&pat, vals)) && s.factor(vals));
            let (mut x, mut y) = (b.clone(), b.clone());
            assert!(d.solve(&mut x) && s.solve(&mut y) && s.satisfies(vals, &y, &b));
            let scale = x.iter().fold(0.0f64, |m, u| m.max(u.abs()));
            for (u, w) in x.iter().zip(&y) {
                assert!((u - w).abs() <= 1e-10 * scale, "{u} {w}");
            }
        };
        let mut s = SparseLu::starting_with(pat.clone(), narrow);
        check(&mut s, &inside);
        assert_eq!(
            (s.widened, s.live.count().0),
            (0, keep.iter().filter(|k| **k).count())
        );
        check(&mut s, &v);
        assert_eq!((s.widened, s.live.count().0), (1, pat.nnz()));
        check(&mut s, &inside);
        assert_eq!(s.widened, 1);
    }
}
