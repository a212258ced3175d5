//! The `locate` report (`interfaces.md`, "locate --format json"): centres and
//! axes in global coordinates at the reference step, and the model with the
//! located geometry written back (design coordinates).

use super::plan::Located;
use crate::geom::Vec3;
use crate::measure::poses::StepPoses;
use crate::model::*;
use serde::Serialize;
use std::collections::BTreeMap;

#[derive(Debug, Clone, Serialize)]
pub struct Entry {
    pub kind: String,
    pub method: String,
    pub center: Option<[f64; 3]>,
    pub axis: Option<[f64; 3]>,
    pub residual_mm: f64,
    pub uncertainty_mm: Option<f64>,
    pub observable: bool,
    /// A direction (global, at the reference step) along which the motion does
    /// not determine the centre; the centre's coordinate along it is the model's.
    pub undetermined_direction: Option<[f64; 3]>,
    pub note: String,
}

/// The pose fit of one part at one step (thesis eq. 2.17–2.25): how well its
/// matched landmarks fit a rigid motion.
#[derive(Debug, Clone, Serialize)]
pub struct PoseEntry {
    pub rms_mm: f64,
    /// Distance of each matched landmark from its fitted position, mm.
    pub residuals_mm: BTreeMap<String, f64>,
}

#[derive(Debug, Clone, Serialize)]
pub struct Report {
    pub reference_step: usize,
    pub joints: BTreeMap<String, Entry>,
    /// Pose fits by step (as text, a JSON key) and part.
    pub poses: BTreeMap<String, BTreeMap<String, PoseEntry>>,
}

impl Report {
    /// The landmark that fits its part's pose worst: (step, part, landmark, mm).
    pub fn worst_landmark(&self) -> Option<(&str, &str, &str, f64)> {
        self.poses
            .iter()
            .flat_map(|(s, parts)| {
                parts.iter().flat_map(move |(p, e)| {
                    e.residuals_mm
                        .iter()
                        .map(move |(l, r)| (s.as_str(), p.as_str(), l.as_str(), *r))
                })
            })
            .max_by(|a, b| a.3.total_cmp(&b.3))
    }
}

fn poses(model: &Model, steps: &[StepPoses]) -> BTreeMap<String, BTreeMap<String, PoseEntry>> {
    steps
        .iter()
        .map(|s| {
            let parts = s
                .parts
                .iter()
                .map(|(p, pose)| {
                    let residuals_mm = pose
                        .residuals
                        .iter()
                        .map(|(l, r)| (model.landmarks[l.index()].name.clone(), *r))
                        .collect();
                    (
                        model.part(*p).name.clone(),
                        PoseEntry {
                            rms_mm: pose.rms,
                            residuals_mm,
                        },
                    )
                })
                .collect();
            (s.step.to_string(), parts)
        })
        .collect()
}

fn arr(v: Vec3) -> [f64; 3] {
    [v.x, v.y, v.z]
}

/// Builds the report at `reference` (a step number of the data). Unobservable
/// quantities are `None`, never a number.
pub fn report(model: &Model, steps: &[StepPoses], located: &[Located], reference: usize) -> Report {
    let step = steps.iter().find(|s| s.step == reference);
    let joints = located
        .iter()
        .map(|l| {
            let (r, t) = step
                .and_then(|s| super::motion::pose(model, s, l.frame))
                .unwrap_or((crate::geom::Mat3::identity(), Vec3::zeros()));
            let ok = l.observable;
            let entry = Entry {
                kind: l.kind.clone(),
                method: l.method.clone(),
                center: l.center.filter(|_| ok).map(|c| arr(r * c + t)),
                axis: l.axis.filter(|_| ok).map(|a| arr(r * a)),
                residual_mm: l.residual,
                uncertainty_mm: (ok && l.uncertainty.is_finite()).then_some(l.uncertainty),
                observable: ok,
                undetermined_direction: l.undetermined.filter(|_| ok).map(|d| arr(r * d)),
                note: l.note.clone(),
            };
            (l.name.clone(), entry)
        })
        .collect();
    Report {
        reference_step: reference,
        joints,
        poses: poses(model, steps),
    }
}

/// The model with every observable located centre (and axis) written into the
/// markers of its joint or bushing, both I and J, at the design configuration.
pub fn apply(model: &Model, located: &[Located]) -> Model {
    let mut m = model.clone();
    for l in located.iter().filter(|l| l.observable) {
        let Some(c) = l.center else { continue };
        let (i, j) = match l.element {
            ElementId::Joint(id) => (m.joints[id.index()].i, m.joints[id.index()].j),
            ElementId::Bushing(id) => (m.bushings[id.index()].i, m.bushings[id.index()].j),
            _ => continue,
        };
        for mk in [i, j] {
            m.markers[mk.index()].position = vals([c.x, c.y, c.z]);
        }
        // A located axis orients revolute and cylindrical joints (z along it).
        if let (Some(a), true) = (
            l.axis,
            matches!(l.kind.as_str(), "revolute" | "cylindrical"),
        ) {
            for mk in [i, j] {
                let old_x = m.markers[mk.index()].rotation.column(0).into_owned();
                if let Ok(r) = crate::geom::frame_from_z_x(a, Some(old_x)) {
                    m.markers[mk.index()].rotation = r;
                    m.markers[mk.index()].orientation = Orientation::Directions {
                        z: a,
                        x: Some(r.column(0).into_owned()),
                    };
                }
            }
        }
    }
    m
}
