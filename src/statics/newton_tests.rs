//! Newton's loop: the start's matrix, the load exchange, an undefined
//! residual, and the Newton matrix against finite differences.

use super::*;
use crate::geom::Vec3;
use crate::statics::assembly::col_scale;
use crate::statics::system::assemble;
use crate::statics::testkit::{mcpherson, perturbed, random_walk, wheel_load};
use crate::statics::{State, solve};

/// A case that starts at its own equilibrium converges at the start,
/// where its first evaluation skipped the Newton matrix (a prediction was
/// due); the solver must still end with the equilibrium's matrix (for the
/// singularity check and the next case's prediction), not the previous
/// case's. The second case adds a self-balanced pair of forces along the
/// upright's L7-L8 line: no net force or moment, but a load stiffness, so
/// the two matrices differ.
#[test]
fn a_case_converged_at_its_start_ends_with_its_own_newton_matrix() {
    let m = mcpherson();
    let p = Problem::new(&m).expect("problem");
    let first = wheel_load(&m, 500.0, -800.0, 3500.0);
    let mut buffers = None;
    let eq = crate::statics::solve_reusing(&p, &first, &State::design(&m), &mut buffers)
        .expect("first case");
    let up = m.part_named("upright").expect("upright");
    let at = |name: &str| {
        let id = m.marker_named(up, name).expect("marker");
        (
            id,
            super::super::coords::marker_kin(&m, &p.layout, &eq.state, id).p,
        )
    };
    let ((l7, p7), (l8, p8)) = (at("L7"), at("L8"));
    let f = (p8 - p7).normalize() * 2000.0;
    let mut second = first.clone();
    for (marker, force) in [(l7, f), (l8, -f)] {
        second.push(PointLoad {
            marker,
            force,
            torque: Vec3::zeros(),
        });
    }
    let eq2 =
        crate::statics::solve_reusing(&p, &second, &eq.state, &mut buffers).expect("second case");
    assert_eq!(eq2.iterations, 0, "converged at the start");
    let fresh = |loads: &[PointLoad]| {
        let mut ws = Workspace::new(&p);
        ws.eval(&p, &eq.state, loads, true).expect("evaluates");
        ws.matrix()
    };
    let (own, previous) = (fresh(&second), fresh(&first));
    let held = buffers.as_ref().expect("solver").ws.matrix();
    assert!((&own - &previous).amax() > 1e-3, "the pair adds stiffness");
    assert_eq!(held, own);
}

/// The next case's start residual is the last evaluation's with the
/// loads exchanged (`Workspace::exchange_loads`): it must equal a fresh
/// evaluation at the same state under the new loads, here with a load
/// moved to another marker and a torque added, to rounding.
#[test]
fn exchanging_the_loads_equals_a_fresh_evaluation() {
    let m = mcpherson();
    let p = Problem::new(&m).expect("problem");
    let old = wheel_load(&m, 500.0, -800.0, 3500.0);
    let st = solve(&p, &old, &State::design(&m)).expect("solves").state;
    let up = m.part_named("upright").expect("upright");
    let mut new = wheel_load(&m, -1200.0, 2000.0, 6000.0);
    new.push(PointLoad {
        marker: m.marker_named(up, "L7").expect("marker"),
        force: Vec3::new(0.0, 300.0, 0.0),
        torque: Vec3::new(40.0, 0.0, -25.0),
    });
    let mut exchanged = Workspace::new(&p);
    exchanged.eval(&p, &st, &old, false).expect("evaluates");
    exchanged.exchange_loads(&p, &st, &old, &new);
    let mut fresh = Workspace::new(&p);
    fresh.eval(&p, &st, &new, false).expect("evaluates");
    let scale = fresh.force_scale();
    assert!(scale > 6000.0, "{scale}");
    let worst = exchanged
        .r
        .iter()
        .zip(&fresh.r)
        .fold(0.0f64, |w, (a, b)| w.max((a - b).abs()));
    assert!(worst < 1e-12 * scale, "{worst}");
    assert!(
        fresh.r.iter().any(|v| v.abs() > 1e3),
        "far from equilibrium"
    );
    assert_eq!(exchanged.phi, fresh.phi);
    assert_eq!(exchanged.load_scale, fresh.load_scale);
    assert_eq!(exchanged.element_scale, fresh.element_scale);
}

/// A NaN in the residual (an element force undefined at a state) or an
/// overflowing force scale is an infinite error: `f64::max` would drop
/// the NaN and report 0, that is, "converged".
#[test]
fn an_undefined_residual_is_never_converged() {
    let m = mcpherson();
    let p = Problem::new(&m).expect("problem");
    let mut ws = Workspace::new(&p);
    ws.eval(
        &p,
        &State::design(&m),
        &wheel_load(&m, 0.0, 0.0, 1500.0),
        false,
    )
    .expect("evaluates");
    let (ef, _) = ws.errors(&p);
    assert!(ef.is_finite() && ef > FORCE_TOL, "{ef}");
    ws.r[3] = f64::NAN;
    assert_eq!(ws.errors(&p), (f64::INFINITY, f64::INFINITY));
    ws.r[3] = 0.0;
    ws.element_scale = f64::INFINITY;
    assert_eq!(ws.errors(&p).0, f64::INFINITY);
}

/// The whole Newton matrix (elements, the moving load, the λ-weighted
/// constraint curvature, the constraint Jacobian), scaled as Newton uses it,
/// equals a central difference of the scaled residual, at a loaded McPherson
/// state away from equilibrium (nonzero multipliers, bushings deflected).
#[test]
fn newton_matrix_equals_a_finite_difference_jacobian() {
    let m = mcpherson();
    let p = Problem::new(&m).expect("problem");
    let st = solve(&p, &wheel_load(&m, 0.0, 0.0, 1500.0), &State::design(&m))
        .expect("c1")
        .state;
    let loads = wheel_load(&m, 2000.0, -3000.0, 4500.0);
    let sys = assemble(&p, &st, &loads).expect("assembles");
    assert!(sys.r.amax() > 100.0, "away from equilibrium");
    let (n, nm) = (p.layout.n(), p.kept.len());
    // (Below this step the central difference's rounding, the residuals'
    // 1e4 times the machine epsilon over h, outgrows its truncation: at
    // 1e-6 it read 2.8e-6.)
    let h = 1e-4;
    let (mut worst_k, mut worst_j) = (0.0f64, 0.0f64);
    for c in 0..n {
        let at = |s: f64| {
            let t = perturbed(&p.layout, &st, c, s * col_scale(c, p.length));
            let sy = assemble(&p, &t, &loads).expect("assembles");
            (sy.r, sy.phi)
        };
        let ((rp, pp), (rm, pm)) = (at(h), at(-h));
        let scale = 1.0 + sys.k.column(c).amax();
        for r in 0..n {
            let fd = (rp[r] - rm[r]) / (2.0 * h);
            worst_k = worst_k.max((fd - sys.k[(r, c)]).abs() / scale);
        }
        for r in 0..nm {
            // Rows have unit norm, so this error is relative.
            let fd = (pp[r] - pm[r]) / (2.0 * h);
            worst_j = worst_j.max((fd - sys.jac[(r, c)]).abs());
        }
    }
    eprintln!("Newton matrix vs central differences: K {worst_k:.1e}, J {worst_j:.1e}");
    assert!(worst_k < 1e-7 && worst_j < 1e-7, "{worst_k} {worst_j}");
}

/// The cases of `loads` solved along a path from design by one solver,
/// set up by `setup`; the solver comes back too. Each case must leave the
/// solver's workspace with its equilibrium's own Newton matrix (the
/// isolation check and the next case's steps read it).
fn solve_walk(
    p: &Problem,
    loads: &[Vec<PointLoad>],
    setup: impl Fn(&mut Solver),
) -> (Vec<crate::statics::Equilibrium>, Solver) {
    let design = State::design(&p.model);
    let mut sv = Solver::new(p, &design);
    setup(&mut sv);
    let (mut buffers, mut st) = (Some(sv), design);
    let mut out = Vec::new();
    for l in loads {
        let eq = crate::statics::solve_reusing(p, l, &st, &mut buffers).expect("solves");
        let mut own = super::super::assembly::Workspace::new(p);
        own.eval(p, &eq.state, l, true).expect("evaluates");
        let sv = buffers.as_ref().expect("the solver");
        assert!(sv.ws.matrix() == own.matrix(), "case {}", out.len());
        st = eq.state.clone();
        out.push(eq);
    }
    (out, buffers.expect("the solver"))
}

/// Chord steps (`CHORD_WITHIN`) save factorisations and reach the
/// equilibria Newton steps reach, up to where each solve may stop (see
/// `stopping_error`), along the random walk.
#[test]
fn chord_steps_reach_the_newton_equilibria_with_fewer_factorisations() {
    use crate::statics::Equilibrium;
    use crate::statics::testkit::assert_same_equilibrium;
    let m = mcpherson();
    let p = Problem::new(&m).expect("problem");
    let loads = random_walk(&m);
    let (newton, _) = solve_walk(&p, &loads, |sv| sv.chords = false);
    let (chord, _) = solve_walk(&p, &loads, |_| {});
    let sum = |r: &[Equilibrium], f: fn(&Equilibrium) -> usize| r.iter().map(f).sum::<usize>();
    let (fa, fb) = (
        sum(&newton, |e| e.factorizations),
        sum(&chord, |e| e.factorizations),
    );
    let (ia, ib) = (
        sum(&newton, |e| e.iterations),
        sum(&chord, |e| e.iterations),
    );
    // Each chord step replaces a factorisation; a few may not converge and
    // cost an iteration more.
    assert!(fb + 8 <= fa, "{fb} factorisations against {fa}");
    assert!(ib <= ia + 3, "{ib} iterations against {ia}");
    for (k, (a, b)) in newton.iter().zip(&chord).enumerate() {
        assert!(b.iterations <= 2 * b.factorizations + 1, "case {k}");
        assert_same_equilibrium(&p, a, b, k);
    }
}

/// Trials evaluated without their Newton matrix (`MATRIX_SKIPPED`) change
/// nothing but the work: along the random walk, the same iterations,
/// factorisations, poses and multipliers to the bit as with every matrix
/// evaluated, whether the matrices are skipped where the band predicts a
/// chord step or after every fresh step (where the iterate then converges,
/// takes a chord step or a fresh step, each branch re-evaluating what it
/// needs). A matrix left stale and factorised, or judged by the isolation
/// check, would show.
#[test]
fn skipped_matrices_change_no_bit_of_the_equilibria() {
    let m = mcpherson();
    let p = Problem::new(&m).expect("problem");
    let loads = random_walk(&m);
    let (every, _) = solve_walk(&p, &loads, |sv| sv.skip_band = 0.0..0.0);
    for band in [MATRIX_SKIPPED, f64::NEG_INFINITY..f64::INFINITY] {
        let (skipping, sv) = solve_walk(&p, &loads, |sv| sv.skip_band = band.clone());
        assert!(
            sv.matrices_skipped >= 5,
            "{band:?}: {} skipped",
            sv.matrices_skipped
        );
        for (k, (a, b)) in every.iter().zip(&skipping).enumerate() {
            assert_eq!(a.iterations, b.iterations, "{band:?}, case {k}");
            assert_eq!(a.factorizations, b.factorizations, "{band:?}, case {k}");
            assert_eq!(a.state.poses, b.state.poses, "{band:?}, case {k}");
            assert_eq!(a.state.lambda, b.state.lambda, "{band:?}, case {k}");
        }
    }
}
