//! Whether an equilibrium is isolated: an estimate of the reciprocal
//! condition of its Newton matrix, for [`super::finish`], which runs the
//! exact singular-value test ([`super::system::singular_direction`]) below
//! [`CHECK_SINGULAR_BELOW`]. A load that happens not to excite a free
//! motion still converges; the equilibrium is then not unique, which is an
//! error, not a result.
//!
//! The last Newton iteration's factorisation of `A_f` stands for the
//! equilibrium's matrix `A` when it shows `A` regular, by either bound:
//! `σ_min` moves by at most `‖A - A_f‖` (the relative distance, one pass
//! over the matrix; both weighed as in [`super::condition`], where the
//! estimate measures the softest motion against the stiffest element and
//! the bound rarely fails), or, when that bound is too coarse (a matrix
//! whose stiff entries moved by more than its softest direction's
//! `σ_min`), `A = A_f (I + E)` with a small `E` and `σ_min(A) ≥ (1 - ‖E‖)
//! σ_min(A_f)`, `‖E‖` estimated by two power steps (two solves, an
//! understatement, see [`STAND_IN`]) and taken [`STAND_IN_MARGIN`] times
//! over. Otherwise (or when the last step converged at once: the
//! multipliers changed from zero, say) `A` is factorised. The condition
//! estimate costs one inverse iteration continued from the last estimate
//! (two for a path's first, [`super::condition::Direction`]), once per
//! factorisation.

use super::Problem;
use super::newton::Solver;

/// Below this estimate of the Newton matrix's reciprocal condition (its
/// multipliers weighed as stiffnesses, [`super::condition`]) the exact
/// singular-value test runs, on the matrix weighed the same way; it flags
/// at `1e-12`, so the estimate (from above, within 1.3 of the ratio on a
/// mechanism's matrices, `condition`'s test) has two orders of magnitude of
/// margin. The McPherson example's matrices are near `1.3e-5` (1.26e-5 to
/// 1.38e-5 along the random 500-case path), the car's near `2e-7` to
/// `3.6e-7` (its cases and front bump sweep; counted on d3e8784, since the
/// parts' coordinates are centred and the seed's columns chosen with its
/// pivots).
pub(crate) const CHECK_SINGULAR_BELOW: f64 = 1e-10;

/// How far (`‖D⁻¹ A_f⁻¹ (A - A_f) D‖`, `D` the weights of
/// [`super::condition`], [`super::tangent::Factorisation::perturbation`])
/// the matrix `A_f` of the last Newton iteration may be from the
/// equilibrium's `A` for its condition estimate to stand for `A`'s, and the
/// factor the estimate is taken over. The estimate (power steps) follows
/// the dominant eigenvalue, not the norm, which may be larger: up to 18
/// times on random perturbations of a McPherson KKT matrix
/// (`sparse::tests`). At the limit `A` keeps at least half of `A_f`'s
/// smallest singular value. Most equilibria need neither this nor a
/// factorisation: their distance to `A_f` is below the weighed condition
/// estimate. Counted on d3e8784, all 500 cases of the random McPherson
/// path passed on that bound (distances at most 3.7e-6 against estimates of
/// at least 1.26e-5), and so do the car's two cases and every case of its
/// front bump sweep (the closest, its curb case from design: 2.2e-7
/// against 3.5e-7; estimates at least 2.07e-7). Since a case may end with
/// a chord step ([`super::newton`]), `A_f` is then two steps from the
/// equilibrium: on the random path 397 cases pass on the bound (distances
/// up to 6.5e-5), 93 stand in by the estimate of `‖E‖` (at most 7.4e-3),
/// and 10 are factorised (one estimate of 1.1e-2, nine beyond
/// [`PERTURBATION_WITHIN`]); the car's cases and sweep are as before. Before the parts'
/// coordinates were referred to their markers' centroid
/// ([`super::coords::Layout::reference`]), 26 McPherson cases needed this
/// limit (7e-4 to 8e-3) and the car's case from design was factorised at
/// its end (3.4e-2 after three steps).
pub(crate) const STAND_IN: f64 = 0.01;
pub(crate) const STAND_IN_MARGIN: f64 = 50.0;

/// The largest ratio of the distance `‖A - A_f‖` to `A_f`'s condition
/// estimate at which the estimate of `‖E‖` is worth its two solves and two
/// passes over the matrix. Measured on every example's load sets and the
/// random McPherson path (49 equilibria whose distance bound failed),
/// `‖E‖` was `c` times that ratio with `c` from 4e-4 to 8e-3 (one four-bar
/// case 0.14): it stood in up to a ratio of 4.0 and for none of the 12
/// equilibria beyond 3.6 (the car's two single cases, 5.5 and 7.1; the
/// twist beam's ten, 3.6 to 24). Beyond this, `A` is factorised at once:
/// the same factorisation the refused estimate led to, 2 solves and 2
/// passes sooner (7 % of the car's single case then). Since the parts'
/// coordinates are centred ([`super::coords::Layout::reference`]) the
/// distance bound fails far less often: across every example's load sets
/// and the car's single cases, the rule now skips one estimate.
pub(crate) const PERTURBATION_WITHIN: f64 = 4.0;

/// An estimate of the reciprocal condition of the equilibrium's Newton
/// matrix (`sv.ws.a`), from the last Newton iteration's factorisation
/// (`sv.lu`, when `sv.factored`) if it may stand for it, otherwise from a
/// factorisation of the matrix itself, which `sv.lu` then holds.
///
/// The problem's design condition (its seed pivots' estimate,
/// [`super::sparse::Pivots::rcond`]; none on the dense path) is a guess
/// that stands for `A_f`'s estimate until that is computed: a distance
/// beyond [`PERTURBATION_WITHIN`] times the guess goes to the
/// factorisation at once, without `A_f`'s estimate (two more solves). The
/// guess only chooses the way; every verdict is an estimate of the matrix
/// judged. A guess too low factorises where `A_f` might have stood in;
/// too high, it costs the two solves it was to save.
pub(crate) fn equilibrium_condition(p: &Problem, sv: &mut Solver) -> f64 {
    let guess = p
        .pattern
        .as_ref()
        .and_then(|pat| pat.pivots.get()?.as_ref())
        .map(|pv| pv.rcond);
    let dist = if sv.factored {
        sv.lu.distance_to(&sv.ws.a)
    } else {
        f64::INFINITY
    };
    // (A distance that is not a number stands for nothing.)
    let hopeless = |rcond: f64| dist.is_nan() || dist > PERTURBATION_WITHIN * rcond;
    let guessed = sv.factored
        && sv
            .known_condition()
            .or(guess)
            .is_some_and(|g| g > 0.0 && hopeless(g));
    let mut rcond = 0.0;
    if guessed {
        #[cfg(test)]
        tests::record_skipped(sv);
    } else if sv.factored {
        rcond = sv.reciprocal_condition();
        if rcond - dist < CHECK_SINGULAR_BELOW {
            rcond = if hopeless(rcond) {
                #[cfg(test)]
                tests::record_skipped(sv);
                0.0
            } else {
                let delta = sv.lu.perturbation(&sv.ws.a);
                if delta <= STAND_IN {
                    rcond * (1.0 - STAND_IN_MARGIN * delta)
                } else {
                    0.0
                }
            };
        }
    }
    if rcond < CHECK_SINGULAR_BELOW {
        sv.factor_matrix();
        rcond = sv.reciprocal_condition();
    }
    rcond
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::LoadSetId;
    use crate::statics::path::{set_loads, solve_case, solve_path};
    use std::cell::RefCell;

    thread_local! {
        /// For each `A_f` passed over: its distance bound (`rcond - dist`,
        /// computed anyway) and the estimate of `‖E‖` skipped.
        static SKIPPED: RefCell<Vec<(f64, f64)>> = const { RefCell::new(Vec::new()) };
    }

    /// Computes what the rule skipped (it reads the factors only, and
    /// leaves the solver's estimates where they were: a copy of their
    /// direction).
    pub(super) fn record_skipped(sv: &mut Solver) {
        let rcond = sv.lu.reciprocal_condition_along(&mut sv.direction.clone());
        let bound = rcond - sv.lu.distance_to(&sv.ws.a);
        let delta = sv.lu.perturbation(&sv.ws.a);
        SKIPPED.with(|s| s.borrow_mut().push((bound, delta)));
    }

    fn example(name: &str, text: &str) -> crate::model::Model {
        let (_, c) = crate::check::check_str(name, text);
        c.model.expect("the example checks")
    }

    /// `A_f` is passed over only where it could not have stood in: on
    /// every example's load sets (solved along their paths; failing sets,
    /// as a four-bar pushed through its limit, end where they end) and the
    /// car's curb and laden cases from new solvers, and the car's design
    /// matrix judged with its curb equilibrium's factors (where the rule
    /// skips, so the test fails without it), for every `A_f` passed over
    /// (by its own estimate or the problem's guess) the distance bound
    /// fails and the estimate of `‖E‖` exceeds `STAND_IN`.
    #[test]
    fn the_skipped_perturbation_estimates_would_have_refused() {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("examples");
        let mut files: Vec<_> = std::fs::read_dir(&dir)
            .expect("examples")
            .filter_map(|e| Some(e.ok()?.path()))
            .filter(|f| f.extension().is_some_and(|x| x == "axle"))
            .collect();
        files.sort();
        assert!(files.len() >= 10);
        for file in &files {
            let text = std::fs::read_to_string(file).expect("readable");
            let m = example(&file.display().to_string(), &text);
            let p = Problem::new(&m).expect("the example compiles");
            for set in 0..m.load_sets.len() as u32 {
                let _ = solve_path(&p, LoadSetId(set));
            }
        }
        let car = example("vehicle.axle", include_str!("../../examples/vehicle.axle"));
        let p = Problem::new(&car).expect("problem");
        let set = car.load_set_named("vehicle").expect("the vehicle set");
        let cases = set_loads(&car, set).expect("loads");
        let design = crate::statics::State::design(&car);
        let curb = solve_case(&p, &cases[0], &design).expect("solves");
        solve_case(&p, &cases[1], &curb.state).expect("solves");
        // (Five before the parts' coordinates were centred, one since,
        // none since the seed's columns are chosen with its pivots.) A
        // matrix far from the one factorised: the car's at design, judged
        // with the factors of its curb equilibrium's.
        let mut sv = Solver::new(&p, &design);
        sv.ws
            .eval(&p, &curb.state, &cases[0], true)
            .expect("evaluates");
        assert!(sv.factor_matrix());
        sv.factored = true;
        sv.ws.eval(&p, &design, &[], true).expect("evaluates");
        equilibrium_condition(&p, &mut sv);
        let skipped = SKIPPED.with(|s| s.take());
        assert!(!skipped.is_empty(), "nothing skipped");
        for (bound, delta) in skipped {
            assert!(
                bound < CHECK_SINGULAR_BELOW,
                "the distance bound would hold: {bound:e}"
            );
            assert!(
                delta > STAND_IN,
                "a skipped estimate would stand in: {delta:e}"
            );
        }
    }
}
