//! The scaled Newton matrix in one of two storages, and its factorisation in
//! the matching one: dense (a zeroed `(n+m)²` matrix and the zero-skipping
//! [`Lu`]) for small models, where it is fastest, and the structural
//! [`Pattern`] with the [`SparseLu`] above [`SPARSE_FROM`] unknowns, where
//! the dense zeroing, copies and `O((n+m)³)` elimination would dominate.

use super::condition::{Direction, Scale};
use super::linear::Lu;
use super::live::Live;
use super::pattern::{ColumnOrder, Pattern};
use super::sparse::SparseLu;
use faer::Mat;
use nalgebra::DMatrix;
use std::sync::Arc;

/// The size `n + m` from which the sparse path is taken. Measured with the
/// McPherson benches (`docs/performance.md`): on the slots that can be
/// non-zero ([`Live`]) the sparse path is faster from one McPherson corner
/// (47 unknowns: a fifth less time on its 500-case path than the dense
/// one); smaller models were not measured and stay dense.
pub(crate) const SPARSE_FROM: usize = 40;

pub(crate) enum NewtonMatrix {
    Dense(Mat<f64>),
    /// The values in the slots of the pattern.
    Sparse(Arc<Pattern>, Vec<f64>),
}

impl NewtonMatrix {
    /// Zeros in the storage chosen for `dim` unknowns and `pattern`.
    pub fn new(dim: usize, pattern: Option<&Arc<Pattern>>) -> NewtonMatrix {
        match pattern {
            Some(p) if p.dim() == dim && dim >= SPARSE_FROM => {
                NewtonMatrix::Sparse(p.clone(), vec![0.0; p.nnz()])
            }
            _ => NewtonMatrix::Dense(Mat::zeros(dim, dim)),
        }
    }

    pub fn dense(dim: usize) -> NewtonMatrix {
        NewtonMatrix::Dense(Mat::zeros(dim, dim))
    }

    pub fn dim(&self) -> usize {
        match self {
            NewtonMatrix::Dense(a) => a.nrows(),
            NewtonMatrix::Sparse(p, _) => p.dim(),
        }
    }

    pub fn clear(&mut self) {
        match self {
            NewtonMatrix::Dense(a) => a.as_mut().fill(0.0),
            NewtonMatrix::Sparse(_, v) => v.iter_mut().for_each(|x| *x = 0.0),
        }
    }

    /// The matrix as a dense nalgebra matrix (for the SVD of error paths and
    /// the sensitivities' refinement).
    pub fn to_dense(&self) -> DMatrix<f64> {
        match self {
            NewtonMatrix::Dense(a) => DMatrix::from_fn(a.nrows(), a.ncols(), |i, j| a[(i, j)]),
            NewtonMatrix::Sparse(p, v) => {
                let n = p.dim();
                let mut d = DMatrix::zeros(n, n);
                for j in 0..n {
                    for k in p.col_ptr[j]..p.col_ptr[j + 1] {
                        d[(p.row_idx[k], j)] = v[k];
                    }
                }
                d
            }
        }
    }
}

/// Factorises the Newton matrix at design (no loads, no multipliers) once,
/// for the pivots every sparse LU of `p` starts refactorising from: the same
/// for every solver of the problem, whatever ran before on which thread (the
/// first call computes them, concurrent ones wait for it, later ones return
/// at once). The factors cover the slots of the pattern that are
/// significant at design or at a generic state near it ([`probe`]; [`Live`]).
pub(crate) fn seed_pivots(p: &super::Problem) {
    if let Some(pat) = &p.pattern {
        pat.pivots.get_or_init(|| seed(p, pat));
    }
}

/// The seed pivots of [`seed_pivots`]; None if the design matrix cannot be
/// evaluated or factorised.
fn seed(p: &super::Problem, pat: &Arc<Pattern>) -> Option<super::sparse::Pivots> {
    let mut ws = super::assembly::Workspace::new(p);
    let design = super::coords::State::design(&p.model);
    // Without the generic state (an element degenerate there), the slots
    // of the design matrix: later matrices widen them as they need.
    let generic = probe(p, &mut ws, &design);
    ws.eval(p, &design, &[], true).ok()?;
    let NewtonMatrix::Sparse(_, v) = &ws.a else {
        return None;
    };
    let mut keep = Live::significant(v);
    if let Some(g) = &generic {
        keep.iter_mut()
            .zip(Live::significant(g))
            .for_each(|(k, s)| *k |= s);
    }
    // The columns' order chosen with the pivots (threshold Markowitz,
    // [`pivoting::factor_choosing_columns`]), or, should that fail, AMD's
    // order of the live slots. Measured at design, the multiply-adds of a
    // refactorisation with the order chosen against the better of AMD's
    // and the whole pattern's (the order taken until then): McPherson
    // 1 346 against 1 736; the car 6 032 against 9 758, with 35 parts
    // 7 643 against 14 350; two corners 2 692 against 3 472, coupled 4 016
    // against 4 109; eight corners 10 768 against 13 888, coupled 18 140
    // against 19 000 (`docs/performance.md`).
    let factored = |choose: bool| {
        // (With `choose`, the order the factorisation takes replaces it.)
        let order = if choose {
            ColumnOrder::Given(&pat.order)
        } else {
            ColumnOrder::Amd
        };
        let live = Live::ordered(pat, &keep, order)?;
        let mut lu = SparseLu::starting_with(pat.clone(), live);
        let ok = if choose {
            lu.factor_choosing_columns(v)
        } else {
            lu.factor(v)
        };
        if ok { lu.pivots() } else { None }
    };
    factored(true).or_else(|| factored(false))
}

/// The Newton matrix's values (in the pattern's slots) at a generic state
/// near `design`: every moving part displaced and turned by up to 1e-3 (mm,
/// rad) and every multiplier non-zero, so that an entry that is zero only by
/// the design's symmetry or for want of a reaction (a joint's curvature is
/// its multiplier times its second derivative) is not taken for a
/// structural zero. An element whose stiffness is zero near design (a stop
/// out of contact) stays out; a matrix that needs it widens the factors'
/// slots when it comes ([`SparseLu::factor`]).
fn probe(
    p: &super::Problem,
    ws: &mut super::assembly::Workspace,
    design: &super::coords::State,
) -> Option<Vec<f64>> {
    // A fixed pseudo-random sequence (an LCG): the same slots every run.
    let mut seed = 0x9e37_79b9_7f4a_7c15u64;
    let mut next = move || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((seed >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    };
    let mut st = design.clone();
    let n = p.layout.n();
    let dq = nalgebra::DVector::from_fn(n, |_, _| 1e-3 * next());
    st.apply(&p.layout, &dq);
    st.lambda = (0..p.kept.len()).map(|_| 1.0 + next().abs()).collect();
    ws.eval(p, &st, &[], true).ok()?;
    match &ws.a {
        NewtonMatrix::Sparse(_, v) => Some(v.clone()),
        NewtonMatrix::Dense(_) => None,
    }
}

/// The factorisation of a [`NewtonMatrix`], in the storage of the last
/// matrix factorised.
// One per solver, built once and never moved in a loop: the size of the
// variants does not matter.
#[allow(clippy::large_enum_variant)]
pub(crate) enum Factorisation {
    Dense(Lu),
    Sparse(SparseLu),
}

impl Factorisation {
    /// A factorisation for matrices stored as `a` is, whose first `coords`
    /// unknowns are coordinates; `groups`: the independent blocks of
    /// [`super::blocks`], used by the dense path.
    pub fn for_matrix(
        a: &NewtonMatrix,
        coords: usize,
        groups: impl FnOnce() -> Vec<Vec<usize>>,
    ) -> Self {
        match a {
            NewtonMatrix::Dense(m) => {
                Factorisation::Dense(Lu::with_blocks(m.nrows(), coords, groups()))
            }
            NewtonMatrix::Sparse(p, _) => Factorisation::Sparse(SparseLu::new(p.clone())),
        }
    }

    pub fn dim(&self) -> usize {
        match self {
            Factorisation::Dense(lu) => lu.dim(),
            Factorisation::Sparse(lu) => lu.dim(),
        }
    }

    /// Factorises `a`; false if a pivot is zero or not finite. A matrix in
    /// the other storage (a workspace that fell back to dense) switches this
    /// factorisation to it.
    pub fn factor(&mut self, a: &NewtonMatrix) -> bool {
        match (&mut *self, a) {
            (Factorisation::Dense(lu), NewtonMatrix::Dense(m)) => lu.factor(m),
            (Factorisation::Sparse(lu), NewtonMatrix::Sparse(p, v))
                if Arc::ptr_eq(lu.pattern(), p) =>
            {
                lu.factor(v)
            }
            _ => {
                let coords = self.coords();
                *self = Factorisation::for_matrix(a, coords, || vec![(0..a.dim()).collect()]);
                self.factor(a)
            }
        }
    }

    /// Factorises `a` again with fresh pivots when the last factorisation
    /// reused earlier ones; `None` when there is nothing else to try (the
    /// dense path always pivots afresh).
    pub fn factor_afresh(&mut self, a: &NewtonMatrix) -> Option<bool> {
        match (self, a) {
            (Factorisation::Sparse(lu), NewtonMatrix::Sparse(_, v)) => lu.factor_afresh(v),
            _ => None,
        }
    }

    pub fn solve(&mut self, b: &mut [f64]) -> bool {
        match self {
            Factorisation::Dense(lu) => lu.solve(b),
            Factorisation::Sparse(lu) => lu.solve(b),
        }
    }

    /// Whether `x`, this factorisation's solution of `a x = b` (`a` the
    /// matrix last factorised), passes the residual check: computed on the
    /// dense path, on the sparse one only where the factors' growth does
    /// not bound it ([`SparseLu::solution_holds`]).
    pub fn solution_holds(&mut self, a: &NewtonMatrix, x: &[f64], b: &[f64]) -> bool {
        match (self, a) {
            (Factorisation::Dense(lu), NewtonMatrix::Dense(m)) => lu.satisfies(m, x, b),
            (Factorisation::Sparse(lu), NewtonMatrix::Sparse(_, v)) => lu.solution_holds(v, x, b),
            _ => false,
        }
    }

    /// `‖D (b - A) D‖_F / ‖D A D‖_F` for the matrix `A` last factorised and
    /// its scaling `D` ([`super::condition`]; infinite for a matrix in the
    /// other storage).
    pub fn distance_to(&self, b: &NewtonMatrix) -> f64 {
        match (self, b) {
            (Factorisation::Dense(lu), NewtonMatrix::Dense(m)) => lu.distance_to(m),
            (Factorisation::Sparse(lu), NewtonMatrix::Sparse(_, v)) => lu.distance_to(v),
            _ => f64::INFINITY,
        }
    }

    /// An estimate of `‖E‖₂`, `E = (D A D)⁻¹ D (B - A) D = D⁻¹ A⁻¹ (B - A) D`,
    /// for the matrix `A` last factorised, its scaling `D`
    /// ([`super::condition`]) and `b`: two steps of the power method from
    /// the irregular start of the condition estimate (two solves), a lower
    /// bound that follows the dominant eigenvalue of `E` and may understate
    /// its norm (see [`super::isolation::STAND_IN`]). A singular `B` has an eigenvalue
    /// `-1` of `E`. With `‖E‖ < 1`, `D B D = D A D (I + E)` is regular and
    /// `σ_min(D B D) ≥ (1 - ‖E‖) σ_min(D A D)`: how a factorisation of a
    /// nearby matrix stands for `b` ([`super::isolation`]). Infinite without a
    /// factorisation or for a matrix in the other storage.
    pub fn perturbation(&mut self, b: &NewtonMatrix) -> f64 {
        let n = self.dim();
        if b.dim() != n || n == 0 {
            return f64::INFINITY;
        }
        let s = self.scale();
        let mut z = vec![0.0; n];
        super::condition::power_growth(n, |y| {
            s.times(y);
            z.iter_mut().for_each(|v| *v = 0.0);
            match (&*self, b) {
                (Factorisation::Dense(lu), NewtonMatrix::Dense(m)) => {
                    lu.add_difference_times(m, y, &mut z)
                }
                (Factorisation::Sparse(lu), NewtonMatrix::Sparse(p, v))
                    if Arc::ptr_eq(lu.pattern(), p) =>
                {
                    if !lu.add_difference_times(v, y, &mut z) {
                        return false;
                    }
                }
                _ => return false,
            }
            let solved = self.solve(&mut z);
            s.divide(&mut z);
            y.copy_from_slice(&z);
            solved
        })
        .unwrap_or(f64::INFINITY)
    }

    /// The unknowns that are coordinates (the first; the multipliers follow).
    fn coords(&self) -> usize {
        match self {
            Factorisation::Dense(lu) => lu.coords(),
            Factorisation::Sparse(lu) => lu.pattern().coords(),
        }
    }

    /// The scaling of [`super::condition`] for the matrix last factorised.
    pub fn scale(&self) -> Scale {
        match self {
            Factorisation::Dense(lu) => lu.scale(),
            Factorisation::Sparse(lu) => lu.scale(),
        }
    }

    /// The estimate from the cold start (for the tests; a solver
    /// continues its estimates along a path).
    #[cfg(test)]
    pub fn reciprocal_condition(&mut self) -> f64 {
        self.reciprocal_condition_along(&mut Direction::default())
    }

    /// The estimate of `σ_min / σ_max` of the factorised matrix scaled as
    /// `D A D`, from where the last estimate of `direction` ended
    /// ([`super::linear::Lu::reciprocal_condition_along`]).
    pub fn reciprocal_condition_along(&mut self, direction: &mut Direction) -> f64 {
        match self {
            Factorisation::Dense(lu) => lu.reciprocal_condition_along(direction),
            Factorisation::Sparse(lu) => lu.reciprocal_condition_along(direction),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::statics::Problem;
    use crate::statics::condition::largest;
    use crate::statics::path::solve_path;

    /// The slots the seed pivots cover ([`seed_pivots`],
    /// found at design and at a generic state near it) hold every Newton
    /// matrix at the equilibria of the McPherson's bump sweep and of the
    /// car's load cases (so no solver along them widens its factors), and
    /// they are about half the structural pattern: a refactorisation on them
    /// takes under half the multiply-adds of one on the whole pattern.
    #[test]
    fn the_seed_slots_hold_every_matrix_along_real_paths() {
        for (file, set) in [
            ("examples/mcpherson.axle", "bump"),
            ("examples/vehicle.axle", "vehicle"),
        ] {
            let src = std::fs::read_to_string(file).expect("example");
            let (_, c) = crate::check::check_str(file, &src);
            let m = c.model.expect("the example checks");
            let p = Problem::new(&m).expect("problem");
            let pat = p.pattern.clone().expect("the sparse path");
            seed_pivots(&p);
            let pv = pat
                .pivots
                .get()
                .and_then(Option::as_ref)
                .expect("seed pivots");
            let (live, all) = pv.live.count();
            let mut whole = SparseLu::starting_with(pat.clone(), Live::all(&pat));
            let mut ws = crate::statics::assembly::Workspace::new(&p);
            let design = crate::statics::coords::State::design(&m);
            ws.eval(&p, &design, &[], true).expect("evaluates");
            let NewtonMatrix::Sparse(_, v) = &ws.a else {
                panic!("sparse storage")
            };
            assert!(whole.factor(v));
            let full = whole.pivots().expect("pivots").updates();
            let narrow = pv.updates();
            eprintln!("{file}: {live} of {all} slots, {narrow} multiply-adds against {full}");
            assert!(
                2 * live < all + all / 10 && 2 * narrow < full,
                "{live} {all} {narrow} {full}"
            );
            let id = m.load_set_named(set).expect("load set");
            let path = solve_path(&p, id).expect("solves");
            for eq in &path {
                ws.eval(&p, &eq.state, eq.state.loads(), true)
                    .expect("evaluates");
                let NewtonMatrix::Sparse(_, v) = &ws.a else {
                    panic!("sparse storage")
                };
                assert!(pv.live.holds(v, largest(v)), "{file}");
            }
        }
    }
}
