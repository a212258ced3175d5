//! W0311: a marker far from every other marker of its part, the usual trace
//! of a unit slip in one coordinate (`305 m` for `305 mm` would be E0214;
//! `30.5 m`, or `3050 mm` for `305 mm`, passes every range check). Such a
//! marker once swamped the characteristic length of the whole analysis; it
//! no longer changes mobility verdicts (`statics::mobility::PartFrames`),
//! but it still puts a wheel centre, a load point or a joint where nothing
//! of the part is, so it is named with its distance.

use super::Checker;
use crate::diagnostic::Diagnostic;
use crate::model::{ElementId, MarkerId};

/// A marker whose nearest neighbour on its own part is further than this (mm)
/// is flagged: no suspension part (an arm, an upright, an anti-roll bar
/// across the track) has two neighbouring points 2 m apart.
pub const FAR_MARKER_MM: f64 = 2000.0;

impl Checker {
    pub(super) fn far_markers(&mut self) {
        let model = &self.model;
        let mut found = Vec::new();
        for (p, _) in model.parts.iter().enumerate() {
            let on: Vec<(usize, crate::geom::Vec3)> = model
                .markers
                .iter()
                .enumerate()
                .filter(|(k, m)| {
                    m.part.index() == p && !self.bad_markers.contains(&MarkerId(*k as u32))
                })
                .map(|(k, m)| (k, m.origin()))
                .collect();
            // Too many markers for the pairwise distances: a generated model.
            if on.len() < 2 || on.len() > 2000 {
                continue;
            }
            for &(k, x) in &on {
                let nearest = on
                    .iter()
                    .filter(|(o, _)| *o != k)
                    .map(|(o, y)| ((x - y).norm(), *o))
                    .fold((f64::INFINITY, k), |a, b| if b.0 < a.0 { b } else { a });
                if nearest.0 > FAR_MARKER_MM {
                    found.push((MarkerId(k as u32), MarkerId(nearest.1 as u32), nearest.0));
                }
            }
        }
        for (m, near, d) in found {
            let at = self.model.marker(m).origin();
            let d = Diagnostic::warning(
                "W0311",
                format!(
                    "marker `{}` is {:.1} m from every other marker of its part",
                    self.model.marker_path(m),
                    d / 1000.0
                ),
            )
            .primary(
                self.span_of(ElementId::Marker(m)),
                format!("at ({:.1}, {:.1}, {:.1}) mm", at.x, at.y, at.z),
            )
            .secondary_opt(self.model.origins.get(ElementId::Marker(near)), "the nearest marker of the part")
            .note(format!("no part of a suspension has neighbouring points more than {} m apart", FAR_MARKER_MM / 1000.0))
            .hint("check the unit and the digits of its coordinates (`305 mm`, not `305 m` or `3050 mm`)");
            self.problems.push(d);
        }
    }
}
