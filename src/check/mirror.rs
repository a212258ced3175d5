//! Mirrored instances: the reflection about the vehicle xz plane applied to
//! the checked frames of their parts and ground markers (after `parts`,
//! before the elements read the frames).
//!
//! With `R = diag(1, -1, 1)`, a position `p` becomes `R p` (y -> -y) and a
//! frame with axes `x, y, z` becomes `x' = R x`, `z' = R z`, `y' = z' × x'`
//! (right-handed again; `y' = -R y`). A left bushing's stiffness axes are so
//! the right's: its radial and axial directions are the mirror images.

use super::Checker;
use crate::diagnostic::Diagnostic;
use crate::geom::{Mat3, Vec3};
use crate::model::{Orientation, Val};
use crate::syntax::ast::{File, ItemKind};

/// How close to the plane of symmetry (mm) a part of a mirrored instance may
/// come: nearer, its mirror image would overlap it.
const PLANE_TOL: f64 = 1e-6;

/// The mirror image of a frame (axes as columns), right-handed.
pub fn mirror_frame(r: &Mat3) -> Mat3 {
    let m = |v: Vec3| Vec3::new(v.x, -v.y, v.z);
    let x = m(r.column(0).into_owned());
    let z = m(r.column(2).into_owned());
    Mat3::from_columns(&[x, z.cross(&x), z])
}

/// The mirror image of a y coordinate: no longer the parameter it was written as.
fn mirror_y(v: &Val) -> Val {
    Val {
        value: -v.value,
        param: None,
        written: None,
    }
}

impl Checker {
    pub(super) fn mirror(&mut self, ast: &File) {
        if self.mirrored_parts.is_empty() && self.mirrored_markers.is_empty() {
            return;
        }
        self.parts_on_the_plane(ast);
        let parts = &self.model.parts;
        let mirrored = |part: crate::model::PartId, name: &str| {
            let p = &parts[part.index()].name;
            self.mirrored_parts.contains(p)
                || self
                    .mirrored_markers
                    .contains(&(p.clone(), name.to_string()))
        };
        for m in &mut self.model.markers {
            if !mirrored(m.part, &m.name) {
                continue;
            }
            m.position[1] = mirror_y(&m.position[1]);
            if !matches!(m.orientation, Orientation::Identity) {
                m.rotation = mirror_frame(&m.rotation);
                let z = m.rotation.column(2).into_owned();
                let x = m.rotation.column(0).into_owned();
                m.orientation = Orientation::Directions { z, x: Some(x) };
            }
        }
        for l in &mut self.model.landmarks {
            if mirrored(l.part, &l.name) {
                l.position[1] = mirror_y(&l.position[1]);
            }
        }
    }
}

impl Checker {
    /// A part of a mirrored instance must lie on one side of the plane of
    /// symmetry: one that reaches it (a rack, an anti-roll bar across the
    /// car) would be stamped twice, the mirror image overlapping the
    /// original, and neither side would be the one part the car has (E0117).
    fn parts_on_the_plane(&mut self, ast: &File) {
        let mut found = Vec::new();
        for (k, part) in self.model.parts.iter().enumerate() {
            if part.ground || !self.mirrored_parts.contains(&part.name) {
                continue;
            }
            let pid = crate::model::PartId(k as u32);
            let ys: Vec<f64> = self
                .model
                .markers
                .iter()
                .enumerate()
                .filter(|(i, m)| {
                    m.part == pid
                        && !self
                            .bad_markers
                            .contains(&crate::model::MarkerId(*i as u32))
                })
                .map(|(_, m)| m.position[1].value)
                .chain(
                    self.model
                        .landmarks
                        .iter()
                        .filter(|l| l.part == pid)
                        .map(|l| l.position[1].value),
                )
                .collect();
            let lo = ys.iter().fold(f64::INFINITY, |a, v| a.min(*v));
            let hi = ys.iter().fold(f64::NEG_INFINITY, |a, v| a.max(*v));
            if lo <= PLANE_TOL && hi >= -PLANE_TOL {
                found.push((part.name.clone(), lo, hi));
            }
        }
        for (name, lo, hi) in found {
            let Some(span) = ast.items.iter().find_map(|i| match &i.kind {
                ItemKind::Part(p) if p.name.name == name => Some(p.name.span),
                _ => None,
            }) else {
                continue;
            };
            self.problems.push(
                Diagnostic::error(
                    "E0117",
                    format!("part `{name}` of a mirrored instance reaches the plane of symmetry"),
                )
                .primary(span, format!("its markers span y = {lo} to {hi} mm"))
                .note("its mirror image would overlap it: the car would have two of this part, one inside the other")
                .hint("write a part that crosses the car (a rack, an anti-roll bar) once, in a template instanced without `mirror` (as stdlib `anti_roll_bar`), and mirror only the corners"),
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_mirrored_frame_is_the_reflection_and_right_handed() {
        let r = crate::geom::euler_zxz(0.3, 1.1, -0.7);
        let m = mirror_frame(&r);
        let refl = Mat3::from_diagonal(&Vec3::new(1.0, -1.0, 1.0));
        // x and z reflect; y flips against the reflection to stay right-handed.
        assert!((m.column(0) - refl * r.column(0)).norm() < 1e-15);
        assert!((m.column(2) - refl * r.column(2)).norm() < 1e-15);
        assert!((m.column(1) + refl * r.column(1)).norm() < 1e-15);
        assert!((m.determinant() - 1.0).abs() < 1e-12);
        // Twice is the identity.
        assert!((mirror_frame(&m) - r).norm() < 1e-15);
    }
}
