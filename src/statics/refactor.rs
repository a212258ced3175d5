//! A refactorisation of the sparse LU ([`super::sparse`]) with fixed pivots
//! and structure, as a list of products computed once per structure.
//!
//! The left-looking elimination it replaces scattered each column into a
//! dense vector and subtracted from it, for each entry of the column's U,
//! that entry times the column of L below it. Every entry of the factors is
//! thus its matrix entry minus a sum of products `L[r, k] U[k, j]`, `k`
//! ascending, and which products are known once the structure is. Here each
//! entry is computed as that sum, in a register and in the same order, so
//! the factors are the elimination's to the bit (a skipped product of a zero
//! `U[k, j]` subtracts an exact zero), without the scatter, the gather and
//! the loop over the column of L per entry of U: a refactorisation's time was
//! mostly spent in those, and in the chains of dependent loads and stores
//! through the dense vector (`docs/performance.md`).

#[cfg(all(target_arch = "x86_64", unix))]
use super::compiled::{CompiledPlan, Structure, Tiered};
use super::live::Live;
use super::pivoting::Factors;
use super::products::Products;

/// The matrix slot of an entry of the factors that is fill (starts at zero).
const FILL: u32 = u32::MAX;

/// The products of a refactorisation for one structure of L and U.
#[derive(Debug, Default)]
pub(crate) struct Plan {
    /// Per entry of the factors in the order they are computed (column by
    /// column, U's then L's below its unit diagonal, each in its array's
    /// order): the (live) slot of the full pattern it starts from, or
    /// [`FILL`], and how many of `ops` it subtracts (they follow the
    /// previous entry's: the counts add up to `ops`' length, which `run`
    /// relies on).
    entries: Vec<(u32, u32)>,
    /// The products `(entry of L, entry of U)`, entry by entry in the order
    /// the entries are computed: column by column, U's (rows ascending, the
    /// pivot last), then L's.
    ops: Products,
    /// One more than the largest slot an entry starts from: the
    /// matrix's values are checked against it once a refactorisation, not
    /// at every entry.
    values_need: usize,
    /// The plan as machine code, once it has run enough times (shared by
    /// the solvers that share the plan).
    #[cfg(all(target_arch = "x86_64", unix))]
    compiled: Tiered<CompiledPlan>,
}

impl Plan {
    /// The plan for the factors `f` of a matrix on the slots `live`, with
    /// the pivot position of each row `row_perm_inv`; None if the structure
    /// does not hold every live slot or is too large for 32-bit indices.
    pub fn new(f: &Factors, live: &Live, row_perm_inv: &[usize]) -> Option<Plan> {
        let p = &live.pattern;
        let n = p.dim();
        let (nu, nl) = (f.u_val.len(), f.l_val.len());
        // (The entries start from the full pattern's slots, `live.from`.)
        let slots = live.matrix_need();
        let big = (nu + nl).max(slots);
        if f.u_ptr.len() != n + 1 || f.l_ptr.len() != n + 1 || big >= FILL as usize {
            return None;
        }
        let (mut u_from, mut u_end) = (vec![FILL; nu], vec![0; nu]);
        let (mut l_from, mut l_end) = (vec![FILL; nl], vec![0; nl]);
        let mut ops = Vec::with_capacity(f.updates());
        // Per pivot position, its entry in the current column (U's entries
        // first, then L's offset by `nu`); FILL elsewhere.
        let mut at = vec![FILL; n];
        // The column's products: (its entry's rank in the column, L, U).
        let mut col: Vec<(u32, u32, u32)> = Vec::new();
        for j in 0..n {
            let (us, ue) = (f.u_ptr[j], f.u_ptr[j + 1]);
            let (ls, le) = (f.l_ptr[j] + 1, f.l_ptr[j + 1]);
            for e in us..ue {
                at[f.u_idx[e]] = e as u32;
            }
            for e in ls..le {
                at[f.l_idx[e]] = (nu + e) as u32;
            }
            let rank = |e: u32| -> u32 {
                let e = e as usize;
                if e < nu {
                    (e - us) as u32
                } else {
                    (ue - us + e - nu - ls) as u32
                }
            };
            let c = p.order[j];
            for k in p.col_ptr[c]..p.col_ptr[c + 1] {
                let e = at[*row_perm_inv.get(p.row_idx[k])?];
                if e == FILL {
                    return None;
                }
                let (e, slot) = (e as usize, *live.from().get(k)? as u32);
                if e < nu {
                    u_from[e] = slot;
                } else {
                    l_from[e - nu] = slot;
                }
            }
            // The left-looking order: U's entries of the column ascending,
            // each times the column of L below its row.
            col.clear();
            for eu in us..ue - 1 {
                let i = f.u_idx[eu];
                for el in f.l_ptr[i] + 1..f.l_ptr[i + 1] {
                    let target = at[f.l_idx[el]];
                    if target == FILL {
                        return None;
                    }
                    col.push((rank(target), el as u32, eu as u32));
                }
            }
            // Stable: each entry's products keep the elimination's order.
            col.sort_by_key(|t| t.0);
            let mut next = col.iter().peekable();
            let mut entry = |r: u32, end: &mut u32, ops: &mut Vec<(u32, u32)>| {
                while let Some(&(_, l, u)) = next.next_if(|t| t.0 == r) {
                    ops.push((l, u));
                }
                *end = ops.len() as u32;
            };
            for (e, end) in (us..ue).zip(&mut u_end[us..ue]) {
                entry(rank(e as u32), end, &mut ops);
            }
            for (e, end) in (ls..le).zip(&mut l_end[ls..le]) {
                entry(rank((nu + e) as u32), end, &mut ops);
            }
            for e in us..ue {
                at[f.u_idx[e]] = FILL;
            }
            for e in ls..le {
                at[f.l_idx[e]] = FILL;
            }
        }
        // Ends to counts, in the order `run` computes the entries.
        let mut entries = Vec::with_capacity(nu + nl - n);
        let mut start = 0;
        for j in 0..n {
            let u = (f.u_ptr[j]..f.u_ptr[j + 1]).map(|e| (u_from[e], u_end[e]));
            let l = (f.l_ptr[j] + 1..f.l_ptr[j + 1]).map(|e| (l_from[e], l_end[e]));
            for (from, end) in u.chain(l) {
                entries.push((from, end - start));
                start = end;
            }
        }
        // (They do by construction: `run` takes the pairs without a check
        // on it, so it is verified, not assumed.)
        if entries.iter().map(|e| e.1 as usize).sum::<usize>() != ops.len() {
            return None;
        }
        let values_need = entries
            .iter()
            .filter(|e| e.0 != FILL)
            .map(|e| e.0 as usize + 1)
            .max()
            .unwrap_or(0);
        Some(Plan {
            entries,
            ops: Products::new(ops),
            values_need,
            ..Plan::default()
        })
    }

    /// Refactorises the matrix of `values` (in the full pattern's slots: the live ones are read) into `f`; false if a pivot is zero, not finite, or under `threshold`
    /// of the largest entry below it in its column (`f` is then to be
    /// factorised afresh).
    ///
    /// Panics if `f` does not hold the structure the plan was made for (as
    /// many entries), or `values` lacks a slot the plan starts from.
    pub fn run(&self, f: &mut Factors, values: &[f64], threshold: f64) -> bool {
        assert_eq!(
            self.entries.len() + f.u_inv.len(),
            f.u_val.len() + f.l_val.len(),
            "a plan for other factors"
        );
        #[cfg(all(target_arch = "x86_64", unix))]
        if let Some(code) = self.compiled.get(|| self.compiled_for(f)) {
            return code.run(values, &mut f.l_val, &mut f.u_val, &mut f.u_inv, threshold);
        }
        self.run_as_loop(f, values, threshold)
    }

    /// The plan compiled for the structure of `f` (None: too large, or the
    /// system gives no executable memory).
    #[cfg(all(target_arch = "x86_64", unix))]
    fn compiled_for(&self, f: &Factors) -> Option<CompiledPlan> {
        CompiledPlan::new(&Structure {
            u_ptr: &f.u_ptr,
            l_ptr: &f.l_ptr,
            entries: &self.entries,
            products: self.ops.pairs(),
            fill: FILL,
        })
    }

    /// [`Self::run`] as a loop over the plan's entries and products (the
    /// factors' entries checked against the plan's there).
    fn run_as_loop(&self, f: &mut Factors, values: &[f64], threshold: f64) -> bool {
        let Factors {
            l_ptr,
            l_val,
            u_ptr,
            u_val,
            u_inv,
            ..
        } = f;
        let n = u_inv.len();
        assert!(
            values.len() >= self.values_need,
            "a matrix without a slot the plan starts from"
        );
        // The entries are read by the products while they are written.
        let l = std::cell::Cell::from_mut(&mut l_val[..]).as_slice_of_cells();
        let u = std::cell::Cell::from_mut(&mut u_val[..]).as_slice_of_cells();
        let mut ops = self.ops.sweep(l, u);
        let start = |from: u32| {
            if from == FILL {
                0.0
            } else {
                // SAFETY: `from < values_need <= values.len()` (checked above).
                unsafe { *values.get_unchecked(from as usize) }
            }
        };
        // Each column's entries as a slice the length of its factors' run
        // (two slices zipped count once; a zip with the entries' iterator
        // checked both ends at every entry).
        let mut entries = &self.entries[..];
        let mut next = |k: usize| {
            let (now, rest) = entries.split_at(k);
            entries = rest;
            now
        };
        for j in 0..n {
            let (us, ue) = (u_ptr[j], u_ptr[j + 1]);
            for (x, &(from, count)) in u[us..ue].iter().zip(next(ue - us)) {
                // SAFETY: the entries' counts add up to the pairs (`entries`).
                x.set(unsafe { ops.subtract_next_unchecked(start(from), count as usize) });
            }
            let (ls, le) = (l_ptr[j] + 1, l_ptr[j + 1]);
            // The pivot's reciprocal first, and each entry of L times it as
            // it is computed (no column's other L entries read it): one
            // store an entry, not a store, a load and a store; the test
            // below judges the entries before scaling, as before. (A
            // refused column is left scaled, the others as they were.)
            let piv = u[ue - 1].get();
            let inv = 1.0 / piv;
            // (A NaN is passed over, as by `f64::max`; the solve's
            // finiteness check finds it.)
            let mut big = 0.0f64;
            for (x, &(from, count)) in l[ls..le].iter().zip(next(le - ls)) {
                // SAFETY: as above.
                let v = unsafe { ops.subtract_next_unchecked(start(from), count as usize) };
                x.set(v * inv);
                big = if v.abs() > big { v.abs() } else { big };
            }
            if !(piv.is_finite() && piv != 0.0 && piv.abs() >= threshold * big) {
                return false;
            }
            u_inv[j] = inv;
        }
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::statics::Problem;
    use crate::statics::pattern::Pattern;
    use crate::statics::pivoting;
    use crate::statics::testkit::{Lcg, coupled_corners, kkt_values};

    /// `L U` against the rows and columns of `values` in pivot order: the
    /// largest difference over the largest entry.
    fn reconstruction_error(
        f: &Factors,
        p: &Pattern,
        values: &[f64],
        row_perm_inv: &[usize],
    ) -> f64 {
        let n = p.dim();
        let mut l = vec![vec![0.0; n]; n];
        let mut u = vec![vec![0.0; n]; n];
        for j in 0..n {
            for e in f.l_ptr[j]..f.l_ptr[j + 1] {
                l[f.l_idx[e]][j] = f.l_val[e];
            }
            for e in f.u_ptr[j]..f.u_ptr[j + 1] {
                u[f.u_idx[e]][j] = f.u_val[e];
            }
        }
        let mut a = vec![vec![0.0; n]; n];
        for (j, &c) in p.order.iter().enumerate() {
            for k in p.col_ptr[c]..p.col_ptr[c + 1] {
                a[row_perm_inv[p.row_idx[k]]][j] = values[k];
            }
        }
        let big = values.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let mut worst = 0.0f64;
        for i in 0..n {
            for j in 0..n {
                let lu: f64 = (0..n).map(|k| l[i][k] * u[k][j]).sum();
                worst = worst.max((lu - a[i][j]).abs());
            }
        }
        worst / big
    }

    /// The whole KKT pattern of `corners` coupled McPherson corners, all
    /// its slots live, and values drawn from `rng` (some exactly zero, as
    /// structural zeros of a real matrix are).
    fn corners_matrix(corners: usize, rng: &mut Lcg) -> (Live, Vec<f64>) {
        let (m, _) = coupled_corners(corners);
        let p = Problem::new(&m).expect("problem");
        let pat = Pattern::new(&p).expect("pattern");
        let v = kkt_values(&pat, p.layout.n(), rng, 0.1);
        (Live::all(&pat), v)
    }

    /// [`corners_matrix`] factorised by the elimination in its pattern's
    /// order (its row pivots' positions `inv`), and the plan of its factors.
    fn factorised(corners: usize, rng: &mut Lcg) -> (Live, Vec<f64>, Factors, Vec<usize>, Plan) {
        let (live, v) = corners_matrix(corners, rng);
        let n = live.pattern.dim();
        let (mut f, mut perm, mut inv) = (Factors::default(), vec![0; n], vec![0; n]);
        assert!(pivoting::factor(
            &live.pattern,
            &v,
            &mut f,
            &mut perm,
            &mut inv
        ));
        let plan = Plan::new(&f, &live, &inv).expect("a plan");
        (live, v, f, inv, plan)
    }

    /// On the KKT patterns of one and two coupled McPherson corners (47 and
    /// 94 unknowns): the plan refactorises the matrix a fresh elimination
    /// factorised into the same factors (the same products in the same
    /// order: equal to the bit), and another matrix of the pattern into
    /// factors whose product is that matrix, permuted, to rounding.
    #[test]
    fn the_plan_refactorises_as_the_elimination() {
        for corners in [1, 2] {
            let mut rng = Lcg::new(17 + corners as u64);
            let (live, v, f, inv, plan) = factorised(corners, &mut rng);
            let n = live.pattern.dim();
            assert_eq!(plan.ops.len(), f.updates());
            // Every entry overwritten (L's unit diagonal is not computed).
            let mut g = f.clone();
            g.u_val.iter_mut().for_each(|x| *x = f64::NAN);
            for j in 0..n {
                g.l_val[f.l_ptr[j] + 1..f.l_ptr[j + 1]].fill(f64::NAN);
            }
            assert!(plan.run(&mut g, &v, 1e-4));
            let same = g.l_val == f.l_val && g.u_val == f.u_val && g.u_inv == f.u_inv;
            assert!(same, "N = {corners}: not the elimination's factors");
            assert!(reconstruction_error(&f, &live.pattern, &v, &inv) < 1e-14);
            // Another matrix: near v (so that the pivots pass the threshold).
            let w: Vec<f64> = v.iter().map(|x| x * (1.0 + 0.1 * rng.next())).collect();
            assert!(plan.run(&mut g, &w, 1e-4));
            assert!(g.u_val != f.u_val);
            let err = reconstruction_error(&g, &live.pattern, &w, &inv);
            assert!(err < 1e-14, "N = {corners}: {err:e}");
            // A pivot under the threshold is refused.
            assert!(!plan.run(&mut g, &w, 1e6));
        }
    }

    /// [`corners_matrix`] factorised choosing its columns with its pivots,
    /// as the solver's seed is (fewer products than in the pattern's
    /// order), and the plan of its factors.
    #[cfg(all(target_arch = "x86_64", unix))]
    fn factorised_choosing_columns(corners: usize, rng: &mut Lcg) -> (Vec<f64>, Factors, Plan) {
        let (mut live, v) = corners_matrix(corners, rng);
        let n = live.pattern.dim();
        let (mut f, mut perm, mut inv) = (Factors::default(), vec![0; n], vec![0; n]);
        let order =
            pivoting::factor_choosing_columns(&live.pattern, &v, &mut f, &mut perm, &mut inv)
                .expect("factors");
        live.pattern.set_order(order);
        let plan = Plan::new(&f, &live, &inv).expect("a plan");
        (v, f, plan)
    }

    /// Whether two factorisations hold the same bits (NaNs included).
    #[cfg(all(target_arch = "x86_64", unix))]
    fn same_bits(a: &Factors, b: &Factors) -> bool {
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        bits(&a.l_val) == bits(&b.l_val)
            && bits(&a.u_val) == bits(&b.u_val)
            && bits(&a.u_inv) == bits(&b.u_inv)
    }

    /// The plan compiled to machine code computes the loop's factors to the
    /// bit, on the whole KKT patterns of one and two coupled McPherson
    /// corners (3 366 and 7 231 products): for the matrix the elimination
    /// factorised and for others near it; and where a pivot is refused (a
    /// threshold no pivot meets, a matrix of zeros, a NaN or an infinity in
    /// a slot) it refuses too, having written what the loop wrote up to
    /// that column, no more.
    #[cfg(all(target_arch = "x86_64", unix))]
    #[test]
    fn the_compiled_plan_is_the_loop_to_the_bit() {
        for corners in [1, 2] {
            let mut rng = Lcg::new(41 + corners as u64);
            let (v, f, plan) = factorised_choosing_columns(corners, &mut rng);
            let code = plan.compiled_for(&f).expect("a compiled plan");
            let run_both = |w: &[f64], threshold: f64| {
                let (mut by_loop, mut by_code) = (f.clone(), f.clone());
                let looped = plan.run_as_loop(&mut by_loop, w, threshold);
                let g = &mut by_code;
                let coded = code.run(w, &mut g.l_val, &mut g.u_val, &mut g.u_inv, threshold);
                assert_eq!(
                    looped, coded,
                    "N = {corners}: refused by one, not the other"
                );
                assert!(same_bits(&by_loop, &by_code), "N = {corners}: other bits");
                looped
            };
            assert!(run_both(&v, 1e-4));
            for _ in 0..8 {
                let w: Vec<f64> = v.iter().map(|x| x * (1.0 + 0.1 * rng.next())).collect();
                assert!(run_both(&w, 1e-4));
            }
            assert!(!run_both(&v, 1e6));
            assert!(!run_both(&vec![0.0; v.len()], 1e-4));
            for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
                // Early, midway, and in the last columns' slots.
                for k in [0, v.len() / 2, v.len() - 1] {
                    let mut w = v.clone();
                    w[k] = bad;
                    run_both(&w, 1e-4);
                }
            }
        }
    }

    /// A structure of more than [`MAX_PRODUCTS`] products, or whose entries
    /// do not add up to its products, is not compiled.
    #[cfg(all(target_arch = "x86_64", unix))]
    #[test]
    fn a_plan_too_large_or_inconsistent_is_not_compiled() {
        use crate::statics::compiled::{CompiledPlan, MAX_PRODUCTS, Structure};
        let (_, f, plan) = factorised_choosing_columns(1, &mut Lcg::new(67));
        let structure = |products| Structure {
            u_ptr: &f.u_ptr,
            l_ptr: &f.l_ptr,
            entries: &plan.entries,
            products,
            fill: FILL,
        };
        let pairs = plan.ops.pairs();
        assert!(CompiledPlan::new(&structure(pairs)).is_some());
        assert!(CompiledPlan::new(&structure(&pairs[1..])).is_none());
        let mut more = pairs.to_vec();
        more.push(pairs[0]);
        assert!(CompiledPlan::new(&structure(&more)).is_none());
        let too_many = vec![pairs[0]; MAX_PRODUCTS + 1];
        assert!(CompiledPlan::new(&structure(&too_many)).is_none());
    }

    /// A plan runs as the loop for its first
    /// [`COMPILE_AFTER`](crate::statics::compiled::COMPILE_AFTER) runs, then
    /// as compiled code, with the same factors either way.
    #[cfg(all(target_arch = "x86_64", unix))]
    #[test]
    fn a_plan_is_compiled_after_its_first_runs() {
        let (v, f, plan) = factorised_choosing_columns(1, &mut Lcg::new(47));
        let mut g = f.clone();
        for run in 0..=crate::statics::compiled::COMPILE_AFTER {
            assert!(!plan.compiled.is_compiled(), "compiled before run {run}");
            assert!(plan.run(&mut g, &v, 1e-4));
        }
        assert!(plan.compiled.is_compiled());
        assert!(plan.run(&mut g, &v, 1e-4));
        assert!(same_bits(&g, &f));
    }

    /// A matrix shorter than the slots the plan starts from is refused
    /// before any entry is computed (the entries then read the matrix
    /// without a check each).
    #[test]
    #[should_panic(expected = "a matrix without a slot the plan starts from")]
    fn a_matrix_without_the_plans_slots_is_refused() {
        let (_, v, mut f, _, plan) = factorised(1, &mut Lcg::new(5));
        // Every slot is live, so the last is an entry's start.
        plan.run(&mut f, &v[..v.len() - 1], 1e-4);
    }

    /// The elimination that chooses its columns with its pivots (threshold
    /// Markowitz) factorises the matrix in the order it took: `L U` is the
    /// matrix so permuted, to rounding; every pivot is at least the
    /// threshold (0.1) of the largest entry below it in its column, the
    /// bound on each step's growth that the elimination on a given order
    /// keeps (checked by the plan, which computes the same factors to the
    /// bit); and a refactorisation takes fewer multiply-adds than with the
    /// pattern's AMD order, on the McPherson's pattern and two coupled
    /// corners' (3 366 against 4 609 and 7 231 against 10 605: the whole
    /// patterns, random values).
    #[test]
    fn the_columns_chosen_with_the_pivots_factorise_the_matrix() {
        for corners in [1, 2] {
            let mut rng = Lcg::new(29 + corners as u64);
            let (mut live, v, amd, _, _) = factorised(corners, &mut rng);
            let n = live.pattern.dim();
            let (mut perm, mut inv) = (vec![0; n], vec![0; n]);
            let mut f = Factors::default();
            let order =
                pivoting::factor_choosing_columns(&live.pattern, &v, &mut f, &mut perm, &mut inv)
                    .expect("factors");
            live.pattern.set_order(order);
            let err = reconstruction_error(&f, &live.pattern, &v, &inv);
            assert!(err < 1e-14, "N = {corners}: {err:e}");
            let (chosen, given) = (f.updates(), amd.updates());
            eprintln!("N = {corners}: {chosen} multiply-adds against {given}");
            assert!(chosen < given, "N = {corners}: {chosen} against {given}");
            let plan = Plan::new(&f, &live, &inv).expect("a plan");
            let mut g = f.clone();
            assert!(
                plan.run(&mut g, &v, 0.1),
                "N = {corners}: a pivot under 0.1"
            );
            assert!(g.l_val == f.l_val && g.u_val == f.u_val);
        }
    }
}
