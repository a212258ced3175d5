//! Landmark observations → the pose of every measured part at every step.
//!
//! Per step and part, the measured points are matched to the part's declared
//! landmarks by their distance tables (names in the data are not trusted: arms
//! name points automatically), a corrupted point is left out, and the pose is
//! fitted. When the ground carries landmarks, every pose is registered to the
//! model frame through one ground pose fitted from all steps.

use super::matching::{MatchError, match_points};
use super::pose_fit::{PoseFitError, fit};
use crate::geom::{Mat3, Vec3};
use crate::model::{LandmarkId, Model, PartId};
use std::collections::BTreeMap;

/// One measured point, as read from a landmark file.
#[derive(Debug, Clone, PartialEq)]
pub struct Observation {
    pub step: usize,
    pub part: PartId,
    /// The name the data gave the point (kept for messages).
    pub label: String,
    pub position: Vec3,
    /// 1-based line in the data file.
    pub line: usize,
}

/// The fitted pose of a part: `x_measured = translation + rotation · x_design`.
#[derive(Debug, Clone, PartialEq)]
pub struct PartPose {
    pub rotation: Mat3,
    pub translation: Vec3,
    pub rms: f64,
    /// Residual of each matched landmark, mm.
    pub residuals: Vec<(LandmarkId, f64)>,
    /// The measured point matched to each landmark (in the model frame once
    /// registered), in the order of `residuals`.
    pub points: Vec<(LandmarkId, Vec3)>,
}

/// Poses of the measured parts at one step.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct StepPoses {
    pub step: usize,
    pub parts: BTreeMap<PartId, PartPose>,
}

/// Something about the data worth telling the user; the data stays usable.
#[derive(Debug, Clone, PartialEq)]
pub enum MeasureIssue {
    /// A point left out of a pose fit (it fits no permutation).
    LeftOut {
        step: usize,
        part: PartId,
        line: usize,
        label: String,
    },
    /// No pose for this part at this step.
    NoPose {
        step: usize,
        part: PartId,
        why: String,
        lines: Vec<usize>,
    },
}

impl MeasureIssue {
    pub fn message(&self, model: &Model) -> String {
        match self {
            MeasureIssue::LeftOut {
                step,
                part,
                line,
                label,
            } => format!(
                "line {line}: point `{label}` of `{}` at step {step} fits none of its landmarks and was left out",
                model.part(*part).name
            ),
            MeasureIssue::NoPose {
                step,
                part,
                why,
                lines,
            } => format!(
                "no pose for `{}` at step {step} (lines {}): {why}",
                model.part(*part).name,
                lines
                    .iter()
                    .map(|l| l.to_string())
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        }
    }
}

/// Fits every part at every step. `tol` is the matching tolerance in mm (0.5 in the thesis).
pub fn fit_poses(
    model: &Model,
    observations: &[Observation],
    tol: f64,
) -> (Vec<StepPoses>, Vec<MeasureIssue>) {
    let mut groups: BTreeMap<(usize, PartId), Vec<&Observation>> = BTreeMap::new();
    for o in observations {
        groups.entry((o.step, o.part)).or_default().push(o);
    }
    let mut steps: BTreeMap<usize, StepPoses> = BTreeMap::new();
    let mut issues = Vec::new();
    // Matched (part, landmark at design, measured) pairs of every step.
    let mut pooled: Vec<(PartId, Vec3, Vec3)> = Vec::new();
    for ((step, part), obs) in groups {
        let ids: Vec<LandmarkId> = (0..model.landmarks.len())
            .filter(|&i| model.landmarks[i].part == part)
            .map(|i| LandmarkId(i as u32))
            .collect();
        let declared: Vec<Vec3> = ids
            .iter()
            .map(|l| crate::model::values(&model.landmarks[l.index()].position))
            .collect();
        let measured: Vec<Vec3> = obs.iter().map(|o| o.position).collect();
        let lines: Vec<usize> = obs.iter().map(|o| o.line).collect();
        let no_pose = |why: String| MeasureIssue::NoPose {
            step,
            part,
            why,
            lines: lines.clone(),
        };
        let m = match match_points(&measured, &declared, tol) {
            Ok(m) => m,
            Err(e) => {
                let why = match e {
                    MatchError::Ambiguous => {
                        "the landmarks' distances cannot tell the points apart".to_string()
                    }
                    MatchError::NoMatch { best_worst } => format!(
                        "the points match no order of the declared landmarks (best misfit {best_worst:.2} mm, tolerance {tol} mm)"
                    ),
                    MatchError::Count { measured, declared } => {
                        format!("{measured} points measured for {declared} declared landmarks")
                    }
                };
                issues.push(no_pose(why));
                continue;
            }
        };
        let (mut p, mut q, mut used) = (Vec::new(), Vec::new(), Vec::new());
        for (k, a) in m.assignment.iter().enumerate() {
            match a {
                Some(i) => {
                    p.push(declared[*i]);
                    q.push(measured[k]);
                    pooled.push((part, declared[*i], measured[k]));
                    used.push(ids[*i]);
                }
                None => issues.push(MeasureIssue::LeftOut {
                    step,
                    part,
                    line: obs[k].line,
                    label: obs[k].label.clone(),
                }),
            }
        }
        match fit(&p, &q) {
            Ok(f) => {
                let points = used.iter().copied().zip(q.iter().copied()).collect();
                let residuals = used.into_iter().zip(f.residuals).collect();
                steps
                    .entry(step)
                    .or_insert_with(|| StepPoses {
                        step,
                        ..Default::default()
                    })
                    .parts
                    .insert(
                        part,
                        PartPose {
                            rotation: f.rotation,
                            translation: f.translation,
                            rms: f.rms,
                            residuals,
                            points,
                        },
                    );
            }
            Err(e @ (PoseFitError::TooFewPoints(_) | PoseFitError::Collinear)) => {
                issues.push(no_pose(e.to_string()))
            }
        }
    }
    let mut steps: Vec<StepPoses> = steps.into_values().collect();
    if let Some(g) = model.ground().and_then(|g| ground_registration(g, &pooled)) {
        for s in &mut steps {
            register(s, &g);
        }
    }
    (steps, issues)
}

/// One pose of the ground from its matched points of every step: the ground does
/// not move, so pooling the steps averages the measuring noise out of the
/// registration.
fn ground_registration(ground: PartId, pooled: &[(PartId, Vec3, Vec3)]) -> Option<PartPose> {
    let (p, q): (Vec<Vec3>, Vec<Vec3>) = pooled
        .iter()
        .filter(|(part, _, _)| *part == ground)
        .map(|(_, a, b)| (*a, *b))
        .unzip();
    let f = fit(&p, &q).ok()?;
    Some(PartPose {
        rotation: f.rotation,
        translation: f.translation,
        rms: f.rms,
        residuals: Vec::new(),
        points: Vec::new(),
    })
}

/// Expresses every pose in the model frame through the ground's measured pose.
fn register(s: &mut StepPoses, g: &PartPose) {
    let rt = g.rotation.transpose();
    for p in s.parts.values_mut() {
        p.rotation = rt * p.rotation;
        p.translation = rt * (p.translation - g.translation);
        for (_, x) in &mut p.points {
            *x = rt * (*x - g.translation);
        }
    }
}
