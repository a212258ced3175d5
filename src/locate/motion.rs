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

    /// A part pose `x_design ↦ R x + t` as a displacement.
    fn of((rotation, translation): (Mat3, Vec3)) -> Rel {
        Rel {
            rotation,
            translation,
        }
    }

    /// `self ∘ other`: `other` first.
    fn then_after(&self, other: &Rel) -> Rel {
        Rel {
            rotation: self.rotation * other.rotation,
            translation: self.rotation * other.translation + self.translation,
        }
    }

    fn inverse(&self) -> Rel {
        let rt = self.rotation.transpose();
        Rel {
            rotation: rt,
            translation: -(rt * self.translation),
        }
    }

    /// Rotation angle (rad, in [0, π]) and unit axis (right-handed); no axis
    /// below `1e-9` rad, where it is not defined. `atan2` keeps small angles
    /// exact, where `acos` of the trace loses half the digits.
    pub fn angle_axis(&self) -> (f64, Option<Vec3>) {
        let r = &self.rotation;
        let v = Vec3::new(
            r[(2, 1)] - r[(1, 2)],
            r[(0, 2)] - r[(2, 0)],
            r[(1, 0)] - r[(0, 1)],
        );
        let angle = v.norm().atan2(r.trace() - 1.0);
        if angle < 1e-9 {
            return (angle, None);
        }
        if angle < 3.0 {
            return (angle, Some(v.normalize()));
        }
        // Near π the skew part vanishes: (R + Rᵀ)/2 − cos θ I = (1 − cos θ) a aᵀ,
        // so the axis is its largest column, signed like the skew part.
        let s = (r + r.transpose()) * 0.5 + Mat3::identity() * (1.0 - r.trace()) * 0.5;
        let k = (0..3)
            .max_by(|&a, &b| s[(a, a)].total_cmp(&s[(b, b)]))
            .unwrap_or(0);
        let a = s.column(k).normalize();
        (angle, Some(if a.dot(&v) < 0.0 { -a } else { a }))
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

/// The motion of part `i` relative to part `j` from the `reference` step to
/// every step where both are known, in global coordinates at the reference
/// step: hold `j` at its reference pose and follow `i`,
/// `D_c = A_j(r) A_j(c)⁻¹ A_i(c) A_i(r)⁻¹` (identity at the reference step).
/// Empty when either part is unknown at the reference step.
pub fn displacements(
    model: &Model,
    steps: &[StepPoses],
    reference: usize,
    i: PartId,
    j: PartId,
) -> Vec<(usize, Rel)> {
    let at = |s: &StepPoses| Some((Rel::of(pose(model, s, i)?), Rel::of(pose(model, s, j)?)));
    let Some((ir, jr)) = steps.iter().find(|s| s.step == reference).and_then(at) else {
        return Vec::new();
    };
    let ir_inv = ir.inverse();
    steps
        .iter()
        .filter_map(|s| {
            let (ic, jc) = at(s)?;
            Some((
                s.step,
                jr.then_after(&jc.inverse().then_after(&ic.then_after(&ir_inv))),
            ))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Rotation3, Unit};

    /// The angle and axis a rotation was built from come back, from tiny angles
    /// to nearly a half turn.
    #[test]
    fn angle_axis_inverts_the_axis_angle_rotation() {
        let axis = Unit::new_normalize(Vec3::new(0.3, -0.5, 0.8));
        for angle in [1e-7, 0.01, 1.0, 2.5, 3.1, std::f64::consts::PI - 1e-6] {
            let rel = Rel {
                rotation: *Rotation3::from_axis_angle(&axis, angle).matrix(),
                translation: Vec3::zeros(),
            };
            let (a, u) = rel.angle_axis();
            assert!((a - angle).abs() < 1e-12, "{angle}: {a}");
            let u = u.expect("an axis");
            assert!((u - axis.into_inner()).norm() < 1e-9, "{angle}: {u}");
        }
        let still = Rel {
            rotation: Mat3::identity(),
            translation: Vec3::x(),
        };
        assert_eq!(still.angle_axis(), (0.0, None));
    }
}
