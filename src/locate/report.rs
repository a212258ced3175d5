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
    /// Unit axis, global at the reference step (carried by `axis_part`).
    pub axis: Option<[f64; 3]>,
    /// The same axis in the model frame at design (every part frame is the
    /// global frame there): what `-o` writes into the joint's markers.
    pub axis_design: Option<[f64; 3]>,
    /// The part that carries the axis (the upright for a strut).
    pub axis_part: Option<String>,
    /// One standard deviation of the axis direction along its worst way to
    /// tilt, degrees; `None` where it is not estimated (the axis is then
    /// reported only with an observable centre).
    pub axis_uncertainty_deg: Option<f64>,
    /// None when the fit had no residual to give (not a number).
    pub residual_mm: Option<f64>,
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

/// The displacement of part I relative to part J from the reference step to
/// one step, in global coordinates at the reference step (`motion::displacements`).
#[derive(Debug, Clone, Serialize)]
pub struct RelativeStep {
    pub step: usize,
    /// How far the element's I marker (its model position, carried by part I) moved relative to part J, mm.
    pub translation_mm: [f64; 3],
    pub rotation_deg: f64,
    /// Unit axis of the rotation (right-handed); `None` for no rotation.
    pub axis: Option<[f64; 3]>,
}

/// The relative motion of the two parts an element joins, over the steps.
#[derive(Debug, Clone, Serialize)]
pub struct RelativeMotion {
    /// `[part I, part J]`: the parts of the element's I and J markers.
    pub parts: [String; 2],
    pub steps: Vec<RelativeStep>,
}

impl RelativeMotion {
    /// The step of largest rotation and the step of largest translation:
    /// `((step, deg), (step, mm))`.
    pub fn largest(&self) -> Option<((usize, f64), (usize, f64))> {
        let rot = self
            .steps
            .iter()
            .map(|s| (s.step, s.rotation_deg))
            .max_by(|a, b| a.1.total_cmp(&b.1))?;
        let tr = self
            .steps
            .iter()
            .map(|s| (s.step, Vec3::from(s.translation_mm).norm()))
            .max_by(|a, b| a.1.total_cmp(&b.1))?;
        Some((rot, tr))
    }
}

#[derive(Debug, Clone, Serialize)]
pub struct Report {
    pub reference_step: usize,
    pub joints: BTreeMap<String, Entry>,
    /// Pose fits by step (as text, a JSON key) and part.
    pub poses: BTreeMap<String, BTreeMap<String, PoseEntry>>,
    /// By joint or bushing name, for every element whose two parts are measured
    /// (or the ground) at the reference step.
    pub relative_motions: BTreeMap<String, RelativeMotion>,
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

/// Relative motions of the parts of every joint and bushing (issue 5: "the
/// relative displacement of every pair of parts joined by a joint").
fn relative_motions(
    model: &Model,
    steps: &[StepPoses],
    reference: usize,
) -> BTreeMap<String, RelativeMotion> {
    let joints = model.joints.iter().map(|j| (&j.name, j.i, j.j));
    let bushings = model.bushings.iter().map(|b| (&b.name, b.i, b.j));
    let Some(at_ref) = steps.iter().find(|s| s.step == reference) else {
        return BTreeMap::new();
    };
    joints
        .chain(bushings)
        .filter_map(|(name, mi, mj)| {
            let (pi, pj) = (model.marker(mi).part, model.marker(mj).part);
            let (ri, ti) = super::motion::pose(model, at_ref, pi)?;
            // The I marker's point at the reference step, global.
            let p = ri * model.marker(mi).origin() + ti;
            let steps = super::motion::displacements(model, steps, reference, pi, pj)
                .into_iter()
                .map(|(step, d)| {
                    let (angle, axis) = d.angle_axis();
                    RelativeStep {
                        step,
                        translation_mm: arr(d.apply(&p) - p),
                        rotation_deg: angle.to_degrees(),
                        axis: axis.map(arr),
                    }
                })
                .collect::<Vec<_>>();
            if steps.is_empty() {
                return None;
            }
            let parts = [model.part(pi).name.clone(), model.part(pj).name.clone()];
            Some((name.clone(), RelativeMotion { parts, steps }))
        })
        .collect()
}

/// Builds the report at `reference` (a step number of the data). Unobservable
/// quantities are `None`, never a number.
pub fn report(model: &Model, steps: &[StepPoses], located: &[Located], reference: usize) -> Report {
    let step = steps.iter().find(|s| s.step == reference);
    let joints = located
        .iter()
        .map(|l| {
            let at = |p| {
                step.and_then(|s| super::motion::pose(model, s, p))
                    .unwrap_or((crate::geom::Mat3::identity(), Vec3::zeros()))
            };
            let (r, t) = at(l.frame);
            let (ra, _) = at(l.axis_part);
            let ok = l.observable;
            let axis = l.axis.filter(|_| l.axis_determined);
            let entry = Entry {
                kind: l.kind.clone(),
                method: l.method.clone(),
                center: l.center.filter(|_| ok).map(|c| arr(r * c + t)),
                axis: axis.map(|a| arr(ra * a)),
                axis_design: axis.map(arr),
                axis_part: axis.map(|_| model.part(l.axis_part).name.clone()),
                axis_uncertainty_deg: axis
                    .filter(|_| l.axis_uncertainty.is_finite())
                    .map(|_| l.axis_uncertainty.to_degrees()),
                residual_mm: l.residual.is_finite().then_some(l.residual),
                uncertainty_mm: (ok && l.uncertainty.is_finite()).then_some(l.uncertainty),
                observable: ok,
                undetermined_direction: l.undetermined.filter(|_| ok).map(|d| arr(ra * d)),
                note: l.note.clone(),
            };
            (l.name.clone(), entry)
        })
        .collect();
    Report {
        reference_step: reference,
        joints,
        poses: poses(model, steps),
        relative_motions: relative_motions(model, steps, reference),
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
