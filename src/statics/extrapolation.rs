//! The second-order part of a path's linear predictor, extrapolated from
//! one case to the next along a sweep.
//!
//! A case of a path starts from the previous equilibrium with the step
//! `A⁻¹ (f - f₋)` of the tangent there. Its error `c` (what Newton adds to
//! the prediction) is second order in the load step, and removing it takes
//! two Newton iterations: on the car's front bump, 5e-4 of the force scale
//! after the prediction, 1e-7 after one iteration, 1e-12 after two, against
//! a tolerance of 1e-10 (and 1e-12 of the length on the constraints).
//! Along a sweep the load steps are equal and `c` changes smoothly from one
//! case to the next, so the prediction adds `c` extrapolated from the last
//! cases with the same load step: `c₋₁`, then `2 c₋₁ - c₋₂`, then
//! `3 c₋₁ - 3 c₋₂ + c₋₃` ([`ORDER`]). Measured on the car's front bump
//! (57 cases), the error after the prediction falls to 1e-5..1e-7 and
//! 22 cases converge after one Newton iteration instead of two; with the
//! linear extrapolation the constraints stay near 2e-6 and one case in
//! five does.
//!
//! Each part's correction is kept in the part's own frame: a twist is the
//! displacement of the part's reference point ([`Layout::reference`]) and a
//! rotation, so the same twist in space moves a point far from that point
//! differently once the part has turned by a load step (a lower arm's
//! bushing 0.5 m from its frame origin, the reference point then), which a stiff
//! bushing turns into a force error (kept in space, the force error after
//! the prediction rose from 5e-4 to 1e-2).
//!
//! Where the load step differs (a random load path, a sweep's turning point),
//! the model has friction (whose stick/slip kink breaks the smoothness), or
//! the case needed more than its prediction and Newton (sub-steps, a
//! refused or shortened prediction, a friction kink) nothing is carried over.
//! The prediction with its correction is a line search's trial like any other:
//! one that does not lower the residual is refused.

use super::coords::{Layout, State};
use crate::geom::Vec3;
use crate::model::PointLoad;
use nalgebra::DVector;

/// The load steps of two cases count as the same when they differ by at most
/// this fraction (the correction then errs by about twice that fraction of
/// itself, far less than it removes).
const SAME_STEP: f64 = 0.01;

/// Corrections of earlier cases the next one is extrapolated from: with
/// three, the quadratic `3 c₋₁ - 3 c₋₂ + c₋₃`.
const ORDER: usize = 3;

/// A correction: each moving part's twist in the part's own frame (see
/// [`Extrapolation::record`]), six numbers a part, and the multipliers'
/// increments.
#[derive(Debug, Clone, Default)]
struct Correction {
    body: Vec<f64>,
    dlambda: Vec<f64>,
}

#[derive(Debug)]
pub(crate) struct Extrapolation {
    /// Whether predictions are corrected at all (the tests compare with
    /// the plain linear predictor).
    pub(crate) enabled: bool,
    /// The last case's load step, six numbers a load (force, torque).
    step: Vec<f64>,
    /// The corrections of the last cases that had this load step, the
    /// latest last.
    history: Vec<Correction>,
    /// Whether this case's prediction adds a correction, and which.
    pub(crate) apply: bool,
    now: Correction,
    /// Whether this case's steps after its prediction are being summed, and
    /// their sum.
    recording: bool,
    sum: Correction,
    /// A twist as `State::apply` takes it.
    twist: DVector<f64>,
}

impl Default for Extrapolation {
    fn default() -> Self {
        Extrapolation {
            enabled: true,
            step: Vec::new(),
            history: Vec::new(),
            apply: false,
            now: Correction::default(),
            recording: false,
            sum: Correction::default(),
            twist: DVector::zeros(0),
        }
    }
}

impl Extrapolation {
    /// The start of a case from `from` to `to` (`predicted`: it starts where
    /// the last case ended, with its factorisation); decides whether the
    /// prediction adds a correction extrapolated from the last cases'.
    pub(crate) fn begin(&mut self, from: &[PointLoad], to: &[PointLoad], predicted: bool) {
        let step = load_step(from, to);
        let same = step.as_ref().is_some_and(|s| same_step(s, &self.step));
        if !(predicted && same) {
            // The sum's allocations from the last entry dropped (`end`
            // moved the last sum into the history).
            if let Some(last) = self.history.pop()
                && self.sum.body.capacity() == 0
            {
                self.sum = last;
            }
            self.history.clear();
        }
        self.apply = self.enabled && !self.history.is_empty();
        if self.apply {
            extrapolate(&self.history, &mut self.now);
        }
        self.recording = predicted && step.is_some();
        self.step = step.unwrap_or_default();
        self.sum.body.clear();
        self.sum.dlambda.clear();
    }

    /// Adds `alpha` times the correction to `st` (the predicted state), as
    /// a twist of its own after the prediction's.
    pub(crate) fn correct(&mut self, layout: &Layout, st: &mut State, alpha: f64) {
        if self.now.body.len() != 6 * layout.moving.len() {
            return;
        }
        // Every entry is written below: only its length matters.
        if self.twist.len() != self.now.body.len() {
            self.twist = DVector::zeros(self.now.body.len());
        }
        for (b, p) in layout.moving.iter().enumerate() {
            let r = st.poses[p.index()].1;
            for h in 0..2 {
                let local =
                    Vec3::from_column_slice(&self.now.body[6 * b + 3 * h..6 * b + 3 * h + 3]);
                let global = alpha * (r * local);
                self.twist.as_mut_slice()[6 * b + 3 * h..6 * b + 3 * h + 3]
                    .copy_from_slice(global.as_slice());
            }
        }
        st.apply(layout, &self.twist);
        for (l, v) in st.lambda.iter_mut().zip(&self.now.dlambda) {
            *l += alpha * v;
        }
    }

    /// A step `dq` Newton took after the prediction, from the state `from`.
    /// Summed in each part's frame: a part's twist is its reference point's
    /// displacement and a rotation, so the same correction in space moves a
    /// point away from that point differently once the part has turned by a
    /// load step; in the part's frame it moves the part's material points as
    /// it did.
    pub(crate) fn record(
        &mut self,
        layout: &Layout,
        from: &State,
        dq: &[f64],
        dlambda: impl Iterator<Item = f64>,
    ) {
        if !self.recording || dq.len() != 6 * layout.moving.len() {
            return;
        }
        if self.sum.body.is_empty() {
            self.sum.body.resize(dq.len(), 0.0);
        }
        for (b, p) in layout.moving.iter().enumerate() {
            let r = from.poses[p.index()].1;
            for h in 0..2 {
                let k = 6 * b + 3 * h;
                let local = r.transpose() * Vec3::from_column_slice(&dq[k..k + 3]);
                for (s, v) in self.sum.body[k..k + 3].iter_mut().zip(local.iter()) {
                    *s += v;
                }
            }
        }
        add(&mut self.sum.dlambda, dlambda);
    }

    /// This case's steps after its prediction cannot be summed into a
    /// correction (the prediction was refused or shortened, a sub-step was
    /// taken, a friction kink was stepped over).
    pub(crate) fn abandon(&mut self) {
        self.recording = false;
    }

    /// The case converged: what Newton added to its prediction, plus the
    /// correction the prediction already had, is this case's correction.
    pub(crate) fn end(&mut self) {
        if !self.recording {
            self.history.clear();
            return;
        }
        self.recording = false;
        let mut c = std::mem::take(&mut self.sum);
        if self.apply {
            add(&mut c.body, self.now.body.iter().copied());
            add(&mut c.dlambda, self.now.dlambda.iter().copied());
        }
        if self.history.len() == ORDER {
            self.history.remove(0);
        }
        self.history.push(c);
    }
}

/// The next of the corrections `history` (the latest last): the polynomial
/// through its last (up to three) entries at the next point, by Newton's
/// backward differences.
fn extrapolate(history: &[Correction], out: &mut Correction) {
    let weights: &[f64] = match history.len() {
        0 => &[],
        1 => &[1.0],
        2 => &[-1.0, 2.0],
        _ => &[1.0, -3.0, 3.0],
    };
    let h = &history[history.len() - weights.len()..];
    combine(&mut out.body, h.iter().map(|c| &c.body[..]), weights);
    combine(&mut out.dlambda, h.iter().map(|c| &c.dlambda[..]), weights);
}

/// `out = Σ w_k x_k`.
fn combine<'a>(out: &mut Vec<f64>, xs: impl Iterator<Item = &'a [f64]>, weights: &[f64]) {
    out.clear();
    for (x, w) in xs.zip(weights) {
        if out.is_empty() {
            out.extend(x.iter().map(|v| w * v));
        } else {
            out.iter_mut().zip(x).for_each(|(o, v)| *o += w * v);
        }
    }
}

/// `to - from`, six numbers a load, when both act on the same markers.
fn load_step(from: &[PointLoad], to: &[PointLoad]) -> Option<Vec<f64>> {
    if from.len() != to.len() || from.iter().zip(to).any(|(a, b)| a.marker != b.marker) {
        return None;
    }
    let d: Vec<f64> = from
        .iter()
        .zip(to)
        .flat_map(|(a, b)| {
            let (f, t) = (b.force - a.force, b.torque - a.torque);
            [f.x, f.y, f.z, t.x, t.y, t.z]
        })
        .collect();
    d.iter().any(|v| *v != 0.0).then_some(d)
}

fn same_step(a: &[f64], b: &[f64]) -> bool {
    let norm = |it: &mut dyn Iterator<Item = f64>| it.map(|v| v * v).sum::<f64>().sqrt();
    a.len() == b.len()
        && norm(&mut a.iter().zip(b).map(|(x, y)| x - y))
            <= SAME_STEP * norm(&mut a.iter().copied())
}

/// `sum += v` entry by entry, `sum` taking `v`'s length when empty.
fn add(sum: &mut Vec<f64>, v: impl Iterator<Item = f64>) {
    if sum.is_empty() {
        sum.extend(v);
    } else {
        sum.iter_mut().zip(v).for_each(|(s, x)| *s += x);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::statics::testkit::assert_same_equilibrium;
    use crate::statics::{Equilibrium, Problem, solve_reusing};

    /// With one, two and three corrections the next is the constant, line
    /// and parabola through them (exact on such sequences).
    #[test]
    fn the_extrapolation_continues_a_polynomial_of_its_degree() {
        let c = |k: f64, degree: usize| {
            let terms = [1.5, -0.25 * k, 0.125 * k * k];
            let v: f64 = terms[..=degree].iter().sum();
            Correction {
                body: vec![v, 2.0 * v],
                dlambda: vec![-v],
            }
        };
        for degree in 0..3 {
            let history: Vec<Correction> = (0..=degree).map(|k| c(k as f64, degree)).collect();
            let mut out = Correction::default();
            extrapolate(&history, &mut out);
            let want = c((degree + 1) as f64, degree);
            let got = out.body.iter().chain(&out.dlambda);
            for (a, b) in got.zip(want.body.iter().chain(&want.dlambda)) {
                assert!((a - b).abs() < 1e-12, "degree {degree}: {a} against {b}");
            }
        }
    }

    /// Along an equal-step sweep of the McPherson's wheel load, the
    /// corrected predictions reach the equilibria of the plain linear
    /// predictor (to the solver's tolerance) in fewer Newton iterations;
    /// where the step changes (the sweep turns back with steps twice as
    /// large) the correction starts afresh and the equilibria still agree.
    #[test]
    fn a_sweep_with_corrected_predictions_reaches_the_same_equilibria_sooner() {
        let m = crate::statics::testkit::mcpherson();
        let p = Problem::new(&m).expect("problem");
        let load = |fz: f64| {
            vec![PointLoad {
                marker: m.wheels[0].contact,
                force: Vec3::new(0.3 * fz - 600.0, -0.2 * fz, fz),
                torque: Vec3::zeros(),
            }]
        };
        let fz: Vec<f64> = (0..=16)
            .map(|k| 2000.0 + 250.0 * k as f64)
            .chain((1..=8).map(|k| 6000.0 - 500.0 * k as f64))
            .collect();
        let run = |enabled: bool| {
            let (mut buffers, mut st) = (None, State::design(&m));
            let mut out: Vec<Equilibrium> = Vec::new();
            for &f in &fz {
                let eq = solve_reusing(&p, &load(f), &st, &mut buffers).expect("solves");
                if let Some(sv) = buffers.as_mut() {
                    sv.extrapolation.enabled = enabled;
                }
                st = eq.state.clone();
                out.push(eq);
            }
            out
        };
        let (plain, corrected) = (run(false), run(true));
        let iterations = |r: &[Equilibrium]| r.iter().map(|e| e.iterations).sum::<usize>();
        let (a, b) = (iterations(&plain), iterations(&corrected));
        assert!(b + 8 <= a, "{b} iterations against {a}");
        // The same equilibria, up to where each solve stopped.
        for (k, (a, b)) in plain.iter().zip(&corrected).enumerate() {
            assert_same_equilibrium(&p, a, b, k);
        }
    }
}
