//! Newton's method on `Q(q) + Phi_q^T λ = 0, Phi(q) = 0` for one load; called
//! by [`super::solve`], which sub-steps the load when this fails.
//!
//! The system is scaled before it is factorised: rotation increments are
//! multiplied by the characteristic length (so they read as mm at that radius),
//! moment rows divided by it, and constraint rows normalised. Steps are limited
//! (0.5 rad, half a characteristic length) and damped by a backtracking line
//! search on the scaled residual norm.
//!
//! The loop evaluates into a [`Workspace`] (`assembly`) and factorises with [`Lu`], both
//! kept for the whole solve, so an iteration allocates almost nothing.
//!
//! Near the equilibrium, the step after a factorised one may reuse that
//! factorisation (a chord step, `CHORD_WITHIN`). Not in models with
//! friction (a chord across a stick-slip kink steps along the other
//! branch's tangent), and not in a case whose prediction is corrected
//! (`super::extrapolation`): the case's last factorisation is the next case's
//! predictor, and one a whole Newton step from the equilibrium spoils the
//! corrected prediction (an equal-step McPherson sweep took 84 iterations
//! instead of 67).

use super::Problem;
use super::assembly::Workspace;
use super::condition::Direction;
use super::coords::State;
use super::error::StaticsError;
use super::extrapolation::Extrapolation;
use super::system::singular_direction;
use super::tangent::Factorisation;
use crate::model::{ElementId, PointLoad};
use nalgebra::DVector;

/// Relative tolerance on the force residual (of the force scale at the state
/// judged: the largest element force there or applied load, see
/// [`Workspace::force_scale`]) and on the constraint residual (of the
/// characteristic length).
pub const FORCE_TOL: f64 = 1e-10;
pub const CONSTRAINT_TOL: f64 = 1e-12;
const MAX_ITERATIONS: usize = 40;

/// Below these multiples of the tolerances, the step after a fresh Newton
/// step reuses its factorisation (a chord step) instead of factorising the
/// new iterate's matrix. The matrix changes at first order along a step, so
/// a chord contracts the error by about the matrix's relative change over
/// the last step, not quadratically: on the random McPherson path a median
/// 3e-3 (1e-4 to 0.7) of an error below 1e-4, too little where the error
/// is larger (a chord from a case's prediction barely moves it). From a
/// thousand times the tolerance, the chord step lands below it in 245 of
/// the path's 259 (contracting by 5.5e-5 to 4.8e-2, median 1.2e-3),
/// instead of a factorisation for the case's fourth iteration. One chord
/// step per factorisation: a second would contract no more than the first.
const CHORD_WITHIN: f64 = 1e3;

/// The band of the next iterate's predicted force error (of the force
/// scale, as a multiple of [`FORCE_TOL`]) in which a fresh Newton step's
/// trials are evaluated without their Newton matrix. The prediction is the
/// quadratic rate the last two errors show, `e (e / e₋₁)²`; the errors
/// that follow lie a median 20 times above it (half to 2 000 times for
/// eight in ten). In
/// this band the iterate most likely calls for a chord step, which needs
/// no matrix there: on the random McPherson path 199 of the 247 such
/// iterates did; the other 48 (32 converged, 16 took a fresh step after
/// all) are evaluated again with their matrix. A skipped matrix saves
/// about an evaluation's half (1.0 of 2.1 µs) where a chord follows and
/// costs a residual evaluation (1.1 µs) where none does, so the band is
/// where chords outnumber the others, by the prediction's decades on
/// that path: from 0.01 to 0.03, 20 iterates converged against 11
/// chords; from 10 to 30, 21 chords against 6 fresh steps; from 30 to
/// 100, 14 against 12 (`docs/performance.md`, twenty-sixth session). The
/// band was 0.01 to 10 until measured so.
const MATRIX_SKIPPED: std::ops::Range<f64> = 0.03..30.0;

/// The part of the start state's residual not yet released: `(1 - s)` times the
/// residual (forces and constraints) the start state had under its own loads.
/// Subtracting it makes the start an exact equilibrium at `s = 0`, so sub-steps
/// also release internal preloads (a spring compressed at design), not only the
/// external loads; at `s = 1` it vanishes and the equilibrium is exact.
pub(crate) struct Homotopy {
    pub r0: Vec<f64>,
    pub phi0: Vec<f64>,
    pub remaining: f64,
}

pub(crate) enum Failure {
    /// No point in sub-stepping: the model itself is at fault.
    Fatal(StaticsError),
    /// Newton stalled or ran out of iterations; a smaller load step may succeed.
    Stalled(State),
}

/// The buffers of one solve: the evaluation at the current state, the
/// factorisation, the step and a trial state.
pub(crate) struct Solver {
    pub ws: Workspace,
    pub lu: Factorisation,
    /// Whether `lu` factorises the Newton matrix of a state of the current
    /// Newton run (not of an earlier load step).
    pub factored: bool,
    /// Take the first step with `lu` as it is: it factorises the matrix of the
    /// previous solve's end, which is where this one starts.
    pub predict: bool,
    /// Factorisations since the start of the solve.
    pub factorizations: usize,
    /// The estimate `lu.reciprocal_condition()` of the current
    /// factorisation, once computed.
    rcond: Option<f64>,
    /// Where the last estimate ended: the next starts there (one solve
    /// instead of two, [`super::condition::Direction`]). A path forgets it
    /// at its start, as it does the predictor.
    pub direction: Direction,
    /// Where the last successful solve with these buffers ended.
    pub ended_at: Option<State>,
    /// A state's allocations kept for the next (a sub-step's trial, the
    /// next end).
    pub spare: State,
    /// Load (sub-)step attempts this solve may still take (a path's budget,
    /// [`super::path::Simulator::with_budget`]); `None`: unlimited.
    pub attempts_left: Option<usize>,
    /// The second-order part of the last case's prediction, added to this
    /// case's when their load steps agree.
    pub extrapolation: Extrapolation,
    /// Whether chord steps may be taken (`CHORD_WITHIN`; the tests compare
    /// with Newton steps throughout).
    pub chords: bool,
    /// The band of predicted errors in which a fresh step's trials skip
    /// their Newton matrix (`MATRIX_SKIPPED`; the tests empty it or widen it
    /// to every step), and how many line searches skipped them.
    pub skip_band: std::ops::Range<f64>,
    pub matrices_skipped: usize,
    /// The step length the last successful line search took.
    alpha: f64,
    /// Whether the line search's trials add the extrapolation's correction
    /// (the prediction's).
    correct: bool,
    x: Vec<f64>,
    b: Vec<f64>,
    dq: DVector<f64>,
    trial: State,
}

impl Solver {
    pub fn new(p: &Problem, st: &State) -> Solver {
        // The sparse LU's seed pivots, computed by the first solver of the
        // problem (a problem compiled and never solved, as the direct
        // identification's, does not pay for them).
        super::tangent::seed_pivots(p);
        let (n, m) = (p.layout.n(), p.kept.len());
        let ws = Workspace::new(p);
        Solver {
            lu: Factorisation::for_matrix(&ws.a, p.layout.n(), || super::blocks::groups(p, st)),
            ws,
            factored: false,
            predict: false,
            factorizations: 0,
            rcond: None,
            direction: Direction::default(),
            ended_at: None,
            spare: State::default(),
            attempts_left: None,
            extrapolation: Extrapolation::default(),
            chords: true,
            skip_band: MATRIX_SKIPPED,
            matrices_skipped: 0,
            alpha: 1.0,
            correct: false,
            x: vec![0.0; n + m],
            b: vec![0.0; n + m],
            dq: DVector::zeros(n),
            trial: st.clone(),
        }
    }

    /// Factorises the workspace's Newton matrix; false if a pivot is zero or
    /// not finite.
    pub fn factor_matrix(&mut self) -> bool {
        self.factorizations += 1;
        self.rcond = None;
        self.lu.factor(&self.ws.a)
    }

    /// The reciprocal condition estimate of the current factorisation
    /// (one solve from where the last ended, two for the first; computed
    /// once per factorisation).
    pub fn reciprocal_condition(&mut self) -> f64 {
        let Solver {
            rcond,
            lu,
            direction,
            ..
        } = self;
        *rcond.get_or_insert_with(|| lu.reciprocal_condition_along(direction))
    }

    /// The estimate of [`Self::reciprocal_condition`], if computed already.
    pub fn known_condition(&self) -> Option<f64> {
        self.rcond
    }

    /// The workspace's matrix factorised again with fresh pivots when the
    /// last factorisation reused earlier ones ([`Factorisation::factor_afresh`]).
    fn factor_afresh(&mut self) -> Option<bool> {
        let ok = self.lu.factor_afresh(&self.ws.a)?;
        self.factorizations += 1;
        self.rcond = None;
        Some(ok)
    }
}

/// Newton from `st` to equilibrium under `loads`; returns the iterations used.
/// `evaluated`: `sv.ws` already holds the residual and matrix at `st` under
/// `loads` with the homotopy applied. On success `sv.ws` holds them at the
/// equilibrium.
pub(crate) fn newton(
    p: &Problem,
    loads: &[PointLoad],
    st: &mut State,
    force: f64,
    homotopy: &Homotopy,
    sv: &mut Solver,
    evaluated: bool,
) -> Result<usize, Failure> {
    let n = p.layout.n();
    let m = p.kept.len();
    if st.lambda.len() != m {
        st.lambda = vec![0.0; m];
    }
    sv.factored = false;
    if !evaluated {
        evaluate(p, loads, st, homotopy, sv)?;
    }
    // One step per solve may be taken whole when the merit does not fall
    // along it (see below).
    let mut kink_step = !p.model.frictions.is_empty();
    // Whether `sv.lu` factorises the matrix of the iterate the last step
    // started from (a fresh Newton step led here): a chord step may follow.
    let mut chord = false;
    let chords = sv.chords && p.model.frictions.is_empty();
    // Whether `sv.ws` lacks the Newton matrix of `st` (evaluated without it).
    let mut stale = false;
    let mut last_ef = f64::NAN;
    for it in 0..MAX_ITERATIONS {
        let (ef, ec) = sv.ws.errors(p);
        let before = std::mem::replace(&mut last_ef, ef);
        if ef < FORCE_TOL && ec < CONSTRAINT_TOL {
            if sv.predict || stale {
                // Converged where the matrix was skipped (at a predicted
                // case's start, or after `MATRIX_SKIPPED`): the caller's
                // checks need the equilibrium's.
                evaluate(p, loads, st, homotopy, sv)?;
            }
            return Ok(it);
        }
        // (By slices: indexed, each store made the next load re-read the
        // vectors' pointers and lengths.)
        let (bq, bl) = sv.b.split_at_mut(n);
        for (b, r) in bq.iter_mut().zip(&sv.ws.r) {
            *b = -r;
        }
        for (b, phi) in bl.iter_mut().zip(&sv.ws.phi) {
            *b = -phi;
        }
        sv.x.copy_from_slice(&sv.b);
        // A step with the factorisation at hand (at the start of a solve, the
        // tangent at the previous equilibrium: a linear predictor for the new
        // load). Anything doubtful falls back on a fresh factorisation below.
        // The caller evaluated the start without its Newton matrix when it
        // asked for a prediction (the matrix is then not needed).
        let predicted = std::mem::take(&mut sv.predict);
        if predicted {
            if sv.lu.dim() == n + m && sv.lu.solve(&mut sv.x) {
                let biggest = sv.x[..n].iter().fold(0.0f64, |a, v| a.max(v.abs()));
                sv.correct = sv.extrapolation.apply;
                let taken = biggest <= 0.5 * p.length
                    && line_search(p, loads, st, force, homotopy, sv, true);
                sv.correct = false;
                if taken {
                    if sv.alpha < 1.0 {
                        sv.extrapolation.abandon();
                    }
                    continue;
                }
            }
            sv.extrapolation.abandon();
            // Back to the state this iteration started from, and a Newton step.
            evaluate(p, loads, st, homotopy, sv)?;
        }
        // Near the equilibrium, the factorisation of the last iterate's
        // matrix again (see `CHORD_WITHIN`).
        if std::mem::take(&mut chord)
            && chords
            && !sv.extrapolation.apply
            && ef < CHORD_WITHIN * FORCE_TOL
            && ec < CHORD_WITHIN * CONSTRAINT_TOL
            && sv.lu.solve(&mut sv.x)
        {
            if line_search(p, loads, st, force, homotopy, sv, true) {
                record_step(p, st, sv);
                stale = false;
                continue;
            }
            // Refused: a fresh Newton step from the same state, whose
            // evaluation the workspace no longer holds (a rejected trial).
            stale = true;
        }
        if std::mem::take(&mut stale) {
            // A fresh step after all: it needs the matrix skipped.
            evaluate(p, loads, st, homotopy, sv)?;
        }
        sv.x.copy_from_slice(&sv.b);
        let mut solved = sv.factor_matrix()
            && sv.lu.solve(&mut sv.x)
            && sv.lu.solution_holds(&sv.ws.a, &sv.x, &sv.b);
        sv.factored = true;
        // Pivots reused from an earlier matrix passed their threshold but gave
        // a solution the residual check refused: pivot afresh before taking
        // the matrix for singular.
        if !solved && let Some(ok) = sv.factor_afresh() {
            sv.x.copy_from_slice(&sv.b);
            solved = ok && sv.lu.solve(&mut sv.x) && sv.lu.solution_holds(&sv.ws.a, &sv.x, &sv.b);
        }
        let biggest = sv.x[..n].iter().fold(0.0f64, |a, v| a.max(v.abs()));
        if (!solved || biggest > 1e3 * p.length)
            && let Some(mut e) = singular_direction(p, &sv.ws.matrix())
        {
            // A slipping friction adds no stiffness along its slide: when that
            // leaves a motion free, it is responsible too.
            let slipping = super::friction::near_limit(&p.model, &p.layout, st);
            e.elements
                .extend(slipping.into_iter().map(ElementId::Friction));
            return Err(Failure::Fatal(e));
        }
        if !solved {
            return Err(Failure::Stalled(st.clone()));
        }
        // Limit the step: 0.5 rad of rotation, half a characteristic length of
        // travel (both are length-scaled here).
        if biggest > 0.5 * p.length {
            let f = 0.5 * p.length / biggest;
            sv.x.iter_mut().for_each(|v| *v *= f);
        }
        // The next iterate's error predicted from the quadratic rate: where
        // it will call for a chord step, its matrix is not needed.
        let next = ef * (ef / before) * (ef / before);
        let lazy = chords && !sv.extrapolation.apply && sv.skip_band.contains(&(next / FORCE_TOL));
        sv.matrices_skipped += usize::from(lazy);
        if !line_search(p, loads, st, force, homotopy, sv, !lazy) {
            // A friction element's law has a kink (stick: -kf, slip: 0): a
            // Newton step from one side along the other side's tangent need
            // not lower the merit at any length, and backtracking then stalls
            // at the kink (seen at a load reversal, residual 1e-5). The whole
            // step lands on the right branch, whose tangent the next
            // iteration uses; taken once per solve, it cannot cycle.
            if kink_step && !super::friction::near_limit(&p.model, &p.layout, st).is_empty() {
                kink_step = false;
                sv.extrapolation.abandon();
                trial_step(p, st, sv, 1.0);
                if sv.ws.eval(p, &sv.trial, loads, true).is_ok() {
                    sv.ws.release(homotopy);
                    std::mem::swap(st, &mut sv.trial);
                    continue;
                }
                evaluate(p, loads, st, homotopy, sv)?;
            }
            // Rounding floor: no decrease possible, but already nearly converged.
            if ef < 1e3 * FORCE_TOL && ec < 1e3 * CONSTRAINT_TOL {
                // The workspace holds a rejected trial: evaluate the state kept.
                evaluate(p, loads, st, homotopy, sv)?;
                return Ok(it);
            }
            return Err(Failure::Stalled(st.clone()));
        }
        record_step(p, st, sv);
        chord = true;
        stale = lazy;
    }
    Err(Failure::Stalled(st.clone()))
}

/// Evaluates `st` into `sv.ws` with its Newton matrix, the homotopy's
/// residual released (what every fresh step and every converged state needs).
fn evaluate(
    p: &Problem,
    loads: &[PointLoad],
    st: &State,
    homotopy: &Homotopy,
    sv: &mut Solver,
) -> Result<(), Failure> {
    sv.ws.eval(p, st, loads, true).map_err(Failure::Fatal)?;
    sv.ws.release(homotopy);
    Ok(())
}

/// Records the step the line search took for the extrapolation: `sv.dq`
/// from the state before it (now in `sv.trial`), and the multipliers' change.
fn record_step(p: &Problem, st: &State, sv: &mut Solver) {
    let dl = st.lambda.iter().zip(&sv.trial.lambda).map(|(a, b)| a - b);
    sv.extrapolation
        .record(&p.layout, &sv.trial, sv.dq.as_slice(), dl);
}

/// `sv.trial` = `st` moved by `alpha` times the step `sv.x` (unscaled into
/// `sv.dq` for the coordinates, by the rows' scales for the multipliers):
/// each line-search trial's, and the whole step a friction kink takes.
/// (By slices: indexed, each store made the next load re-read the vectors'
/// pointers and lengths.)
fn trial_step(p: &Problem, st: &State, sv: &mut Solver, alpha: f64) {
    sv.trial.clone_from(st);
    let (xq, xl) = sv.x.split_at(p.layout.n());
    // (The zips below stop at the shortest: every multiplier has its
    // entry, `newton` sizes them on entry.)
    debug_assert_eq!(sv.trial.lambda.len(), xl.len());
    for ((d, x), s) in sv.dq.iter_mut().zip(xq).zip(&sv.ws.scale) {
        *d = alpha * x * s;
    }
    sv.trial.apply(&p.layout, &sv.dq);
    for ((l, x), s) in sv.trial.lambda.iter_mut().zip(xl).zip(&sv.ws.row_scale) {
        *l += alpha * x / s;
    }
}

/// Backtracking from the step `sv.x` until the merit decreases (Armijo); on
/// success `st` is the new state and `sv.ws` holds its evaluation (with its
/// Newton matrix when `tangent`), otherwise `st` is unchanged and `sv.ws`
/// holds a rejected trial.
fn line_search(
    p: &Problem,
    loads: &[PointLoad],
    st: &mut State,
    force: f64,
    homotopy: &Homotopy,
    sv: &mut Solver,
    tangent: bool,
) -> bool {
    let m0 = sv.ws.merit(p, force);
    let mut alpha = 1.0;
    for _ in 0..12 {
        trial_step(p, st, sv, alpha);
        if sv.correct {
            sv.extrapolation.correct(&p.layout, &mut sv.trial, alpha);
        }
        if sv.ws.eval(p, &sv.trial, loads, tangent).is_ok() {
            sv.ws.release(homotopy);
            let m1 = sv.ws.merit(p, force);
            if m1.is_finite() && m1 < (1.0 - 1e-4 * alpha) * m0 {
                std::mem::swap(st, &mut sv.trial);
                sv.alpha = alpha;
                return true;
            }
        }
        alpha *= 0.5;
    }
    false
}

#[cfg(test)]
#[path = "newton_tests.rs"]
mod tests;
