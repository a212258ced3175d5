//! The compiled substitutions against the loops, to the bit, and what is
//! refused (the compiled plan's tests are beside the plan, in `refactor`).

use super::*;
use crate::statics::Problem;
use crate::statics::live::Live;
use crate::statics::pattern::Pattern;
use crate::statics::pivoting::{self, Factors};
use crate::statics::sparse::substitute_as_loops;
use crate::statics::testkit::{Lcg, coupled_corners, kkt_values};

/// The factors of a random matrix on the KKT pattern of `corners`
/// coupled McPherson corners, its columns chosen with its pivots.
fn factors(corners: usize, rng: &mut Lcg) -> Factors {
    let (m, _) = coupled_corners(corners);
    let p = Problem::new(&m).expect("problem");
    let live = Live::all(&Pattern::new(&p).expect("pattern"));
    let v = kkt_values(&live.pattern, p.layout.n(), rng, 0.1);
    let n = live.pattern.dim();
    let (mut f, mut perm, mut inv) = (Factors::default(), vec![0; n], vec![0; n]);
    pivoting::factor_choosing_columns(&live.pattern, &v, &mut f, &mut perm, &mut inv)
        .expect("factors");
    f
}

fn compiled(f: &Factors) -> Option<CompiledSubstitution> {
    let r = &f.rows;
    CompiledSubstitution::new(&r.l_ptr, r.l.pairs(), &r.u_ptr, r.u.pairs())
}

/// The compiled substitutions give the loops' solution to the bit, for
/// random right-hand sides and for one with a NaN and an infinity (which
/// spread as in the loops), on one and on eight coupled corners.
#[test]
fn the_compiled_substitution_is_the_loops_to_the_bit() {
    let mut rng = Lcg::new(53);
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    for corners in [1, 8] {
        let f = factors(corners, &mut rng);
        let code = compiled(&f).expect("compiled substitutions");
        let n = f.u_inv.len();
        for trial in 0..10 {
            let mut y: Vec<f64> = (0..n).map(|_| 1e3 * rng.next()).collect();
            if trial == 9 {
                (y[3], y[n / 2]) = (f64::NAN, f64::INFINITY);
            }
            let mut by_code = y.clone();
            substitute_as_loops(&f, &mut y);
            code.run(&mut by_code, &f.l_val, &f.u_val, &f.u_inv);
            assert_eq!(bits(&y), bits(&by_code), "N = {corners}, trial {trial}");
        }
    }
}

/// Rows of more than [`MAX_PRODUCTS`] products, or whose ranges are
/// outside their entries, are not compiled.
#[test]
fn rows_too_many_or_inconsistent_are_not_compiled() {
    let f = factors(1, &mut Lcg::new(71));
    let r = &f.rows;
    let (l, u) = (r.l.pairs(), r.u.pairs());
    assert!(CompiledSubstitution::new(&r.l_ptr, l, &r.u_ptr, u).is_some());
    assert!(CompiledSubstitution::new(&r.l_ptr, &l[1..], &r.u_ptr, u).is_none());
    let too_many = vec![l[0]; MAX_PRODUCTS + 1];
    assert!(CompiledSubstitution::new(&r.l_ptr, &too_many, &r.u_ptr, u).is_none());
}

/// A solve's substitutions run as loops for the structure's first
/// [`COMPILE_AFTER`] solves, then as code (shared by a clone of the
/// factors), with the same bits either way.
#[test]
fn substitutions_are_compiled_after_their_first_runs() {
    use crate::statics::sparse::substitute;
    let mut rng = Lcg::new(73);
    let f = factors(1, &mut rng);
    let g = f.clone();
    let n = f.u_inv.len();
    let y: Vec<f64> = (0..n).map(|_| rng.next()).collect();
    let mut want = y.clone();
    substitute_as_loops(&f, &mut want);
    for run in 0..=COMPILE_AFTER {
        assert!(!g.rows.compiled.is_compiled(), "compiled before run {run}");
        let mut z = y.clone();
        substitute(if run % 2 == 0 { &f } else { &g }, &mut z);
        assert!(z.iter().zip(&want).all(|(a, b)| a.to_bits() == b.to_bits()));
    }
    assert!(f.rows.compiled.is_compiled() && g.rows.compiled.is_compiled());
    let mut z = y.clone();
    substitute(&g, &mut z);
    assert!(z.iter().zip(&want).all(|(a, b)| a.to_bits() == b.to_bits()));
}

/// Arrays shorter than the code's are refused before it runs.
#[test]
#[should_panic(expected = "arrays shorter than the compiled substitution's")]
fn a_short_vector_is_refused() {
    let f = factors(1, &mut Lcg::new(61));
    let code = compiled(&f).expect("compiled substitutions");
    let mut y = vec![0.0; f.u_inv.len() - 1];
    code.run(&mut y, &f.l_val, &f.u_val, &f.u_inv);
}
