//! Relative displacements between two parts over the measured steps (thesis
//! eq. 3.6): `B_c = A_1(c)⁻¹ A_2(c)`, with every pose relative to the design
//! configuration, so a point fixed in both parts satisfies `R_c x + T_c = x`.

use crate::geom::{Mat3, Vec3};
use crate::measure::poses::StepPoses;
use crate::model::{Model, PartId};

/// One relative displacement: `x ↦ rotation · x + translation`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rel {
    pub rotation: Mat3,
    pub translation: Vec3,
}

impl Rel {
    pub fn apply(&self, x: &Vec3) -> Vec3 {
        self.rotation * x + self.translation
    }
}

/// The pose of a part at a step: measured, or identity for an unmeasured ground.
pub fn pose(model: &Model, step: &StepPoses, part: PartId) -> Option<(Mat3, Vec3)> {
    match step.parts.get(&part) {
        Some(p) => Some((p.rotation, p.translation)),
        None if model.part(part).ground => Some((Mat3::identity(), Vec3::zeros())),
        None => None,
    }
}

/// Whether every step measures the part (or it is the ground).
pub fn observed(model: &Model, steps: &[StepPoses], part: PartId) -> bool {
    !steps.is_empty() && steps.iter().all(|s| pose(model, s, part).is_some())
}

/// Displacements of part 2 relative to part 1 at every step where both are known.
pub fn relative(model: &Model, steps: &[StepPoses], p1: PartId, p2: PartId) -> Vec<Rel> {
    steps
        .iter()
        .filter_map(|s| {
            let (r1, t1) = pose(model, s, p1)?;
            let (r2, t2) = pose(model, s, p2)?;
            Some(Rel {
                rotation: r1.transpose() * r2,
                translation: r1.transpose() * (t2 - t1),
            })
        })
        .collect()
}

/// The largest relative rotation angle over the steps, rad: how much the
/// motion can say about centres and axes.
pub fn max_rotation(rels: &[Rel]) -> f64 {
    rels.iter()
        .map(|r| ((r.rotation.trace() - 1.0) / 2.0).clamp(-1.0, 1.0).acos())
        .fold(0.0, f64::max)
}
