//! Geometric correction at one measured equilibrium (thesis chapter 2,
//! eq. 2.33–2.35): the model's parts are as measured disassembled; the
//! assembled axle is measured under one load. Joint centres do not meet and
//! bushings do not sit at their computed deformation because of assembly
//! clearances on the clamped part, so the I marker (on the part that carries
//! the clamp and the inner sleeve) is moved: for a joint onto its measured J
//! marker, for a bushing to where the model's equilibrium deformation puts it
//! relative to the measured J marker. Forces change a little when markers move,
//! so the correction is repeated until the model's equilibrium reproduces the
//! measured poses.

use super::motion::pose;
use crate::geom::{Mat3, Vec3, matrix_to_zxz};
use crate::measure::poses::StepPoses;
use crate::model::*;
use crate::statics::{self, Problem, State, StaticsError};

/// Correction passes at most (the thesis does one).
const MAX_PASSES: usize = 20;

/// What the correction did.
#[derive(Debug, Clone)]
pub struct Correction {
    /// The corrected model, still written at the original design configuration
    /// (its joints meet at the measured state, not at design).
    pub model: Model,
    /// Its equilibrium under the measured load.
    pub state: State,
    /// Each moved I marker: the element, and how far it moved in total (mm).
    pub moved: Vec<(ElementId, f64)>,
    /// Elements left alone, with the reason (a part without landmarks).
    pub skipped: Vec<(ElementId, String)>,
    /// The correction pass kept (the one whose equilibrium matched best).
    pub iterations: usize,
    /// Largest distance between a landmark placed by the corrected model's
    /// equilibrium and the same landmark placed by the measured pose, mm.
    pub misfit: f64,
}

fn set_frame(m: &mut Model, id: MarkerId, p: Vec3, r: Mat3) {
    let (a, b, c) = matrix_to_zxz(&r);
    let mk = &mut m.markers[id.index()];
    mk.position = vals([p.x, p.y, p.z]);
    mk.rotation = r;
    mk.orientation = Orientation::Euler(vals([a, b, c]));
}

/// Largest landmark distance between the model's equilibrium and the measurement.
fn misfit(model: &Model, state: &State, measured: &StepPoses) -> f64 {
    model
        .landmarks
        .iter()
        .filter_map(|l| {
            let (rm, tm) = measured
                .parts
                .get(&l.part)
                .map(|p| (p.rotation, p.translation))?;
            let (t, r) = state.part_pose(l.part);
            let x = values(&l.position);
            Some(((t + r * x) - (tm + rm * x)).norm())
        })
        .fold(0.0, f64::max)
}

/// Corrects `model` so that its equilibrium under `loads` reproduces `measured`.
pub fn correct(
    model: &Model,
    measured: &StepPoses,
    loads: &[PointLoad],
) -> Result<Correction, StaticsError> {
    let mut m = model.clone();
    let original: Vec<Vec3> = m.markers.iter().map(Marker::origin).collect();
    let mut skipped = Vec::new();
    let mut touched: Vec<(ElementId, MarkerId)> = Vec::new();
    let mut state = State::design(&m);
    let mut best: Option<(f64, Model, State, usize)> = None;
    for k in 0..MAX_PASSES {
        let iterations = k + 1;
        let problem = Problem::new(&m)?;
        let eq = statics::path::solve_case(&problem, loads, &state)?;
        state = eq.state;
        let mut largest: f64 = 0.0;
        let elements: Vec<(ElementId, MarkerId, MarkerId, bool)> = m
            .joints
            .iter()
            .enumerate()
            .map(|(n, j)| (ElementId::Joint(JointId(n as u32)), j.i, j.j, false))
            .chain(
                m.bushings
                    .iter()
                    .enumerate()
                    .map(|(n, b)| (ElementId::Bushing(BushingId(n as u32)), b.i, b.j, true)),
            )
            .collect();
        for (id, i, j, bushing) in elements {
            let (p1, p2) = (m.marker(i).part, m.marker(j).part);
            let (Some((r1, t1)), Some((r2, t2))) = (pose(&m, measured, p1), pose(&m, measured, p2))
            else {
                if k == 0 {
                    let missing = if pose(&m, measured, p1).is_none() {
                        p1
                    } else {
                        p2
                    };
                    skipped.push((
                        id,
                        format!(
                            "part `{}` carries no measured landmarks",
                            m.part(missing).name
                        ),
                    ));
                }
                continue;
            };
            let (mi, mj) = (m.marker(i).clone(), m.marker(j).clone());
            // The relative frame of I in J: the model's equilibrium deformation for a
            // bushing (eq. 2.34), the design relation for a joint (it satisfies the joint).
            let (t_rel, q_rel) = if bushing {
                let (ti, ri) = state.part_pose(p1);
                let (tj, rj) = state.part_pose(p2);
                let (pi, ri_m) = (ti + ri * mi.origin(), ri * mi.rotation);
                let (pj, rj_m) = (tj + rj * mj.origin(), rj * mj.rotation);
                (rj_m.transpose() * (pi - pj), rj_m.transpose() * ri_m)
            } else {
                // A joint's I sits on J's point (eq. 2.33) with the orientation it has at design.
                (Vec3::zeros(), mj.rotation.transpose() * mi.rotation)
            };
            // Measured J frame, global; the I frame it implies, in part 1's design frame.
            let (pj, rj) = (t2 + r2 * mj.origin(), r2 * mj.rotation);
            let (pi, ri) = (pj + rj * t_rel, rj * q_rel);
            let p_new = r1.transpose() * (pi - t1);
            let r_new = r1.transpose() * ri;
            largest = largest.max((p_new - mi.origin()).norm());
            set_frame(&mut m, i, p_new, r_new);
            if !touched.iter().any(|(e, _)| *e == id) {
                touched.push((id, i));
            }
        }
        // The measured state does not fix every bushing deformation and joint
        // reaction (more unknowns than equilibrium equations), so repeated passes
        // can wander: keep the pass whose equilibrium matches best.
        let problem = Problem::new(&m)?;
        let eq = statics::path::solve_case(&problem, loads, &state)?;
        let fit = misfit(&m, &eq.state, measured);
        let improved = best.as_ref().is_none_or(|b| fit < b.0 * (1.0 - 1e-3));
        if improved {
            best = Some((fit, m.clone(), eq.state.clone(), iterations));
        }
        if !improved || largest < 1e-7 {
            break;
        }
    }
    let Some((misfit, m, state, iterations)) = best else {
        return Err(StaticsError::new(
            crate::statics::StaticsErrorKind::BadInput,
            Vec::new(),
            "no correction pass ran",
        ));
    };
    let moved = touched
        .iter()
        .map(|(e, i)| (*e, (m.marker(*i).origin() - original[i.index()]).norm()))
        .collect();
    Ok(Correction {
        model: m,
        state,
        moved,
        skipped,
        iterations,
        misfit,
    })
}

/// The model written anew with `state` as its design configuration: every
/// marker and landmark placed by its part's pose. The thesis builds its ADAMS
/// model this way, from the joint poses of the measured, loaded axle (§5.1):
/// joints meet there, and bushings sit at their equilibrium deformation (their
/// markers apart, no offset; §5.4).
pub fn redesign(model: &Model, state: &State) -> Model {
    let mut m = model.clone();
    for id in 0..m.markers.len() {
        let mk = m.markers[id].clone();
        let (t, r) = state.part_pose(mk.part);
        set_frame(
            &mut m,
            MarkerId(id as u32),
            t + r * mk.origin(),
            r * mk.rotation,
        );
    }
    for l in &mut m.landmarks {
        let (t, r) = state.part_pose(l.part);
        let x = t + r * values(&l.position);
        l.position = vals([x.x, x.y, x.z]);
    }
    m
}
