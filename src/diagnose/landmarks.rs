//! Landmark data in a diagnosis (`--landmarks`): measured points of the
//! parts joined to the rig steps, and the `landmarks_mm` channel they give.
//!
//! Each landmark file goes with one K&C path: with one `--kc` file every
//! landmark file joins it; with several, one landmark CSV per K&C file in
//! the same order (each K&C file numbers its own steps, so a step number
//! alone cannot say which path it belongs to). Within a path a landmark row
//! joins the K&C row of the same `step`; an IGES file is one state, numbered
//! after the last CSV step as everywhere else (`interfaces.md`). Steps may
//! carry landmarks or not (a measuring arm is slower than a rig); a landmark
//! step that the K&C file does not have means the files are of two runs, and
//! is an error.
//!
//! The points are matched to the declared landmarks of their part by their
//! distance tables and registered to the model frame through the ground's
//! landmarks ([`crate::measure::poses`]), then compared with the same points
//! of the simulated parts, coordinate by coordinate. The rigid pose fits'
//! residuals estimate the measuring noise: `σ² = Σ r² / Σ (3 n − 6)` over
//! every part and step (`n` matched points, six pose parameters fitted).

use super::rig::{PoseFitResidual, RigPath};
use crate::diagnostic::Diagnostic;
use crate::geom::Vec3;
use crate::measure::inputs::{LandmarkFile, LandmarkFormat, Remarks, read_landmarks};
use crate::model::{LandmarkId, Model, values};
use crate::source::SourceMap;
use crate::span::Span;
use crate::statics::State;

/// The thesis' matching tolerance for a measured point (mm).
const MATCH_TOLERANCE: f64 = 0.5;

/// Reads the landmark files and attaches their points to the steps of
/// `paths` (see the module's rules for which file goes with which path).
/// Points left out go to `remarks` as warnings.
pub fn attach(
    sources: &SourceMap,
    model: &Model,
    paths: &mut [RigPath],
    files: &[LandmarkFile],
    remarks: &mut Remarks,
) -> Result<(), Diagnostic> {
    if files.is_empty() {
        return Ok(());
    }
    if paths.len() > 1 {
        if let Some(f) = files.iter().find(|f| f.format == LandmarkFormat::Iges) {
            return Err(Diagnostic::error(
                "E1306",
                format!(
                    "an IGES file holds one state without a step number, and with {} K&C files it cannot say which path it belongs to",
                    paths.len()
                ),
            )
            .primary(Span::new(f.id, 0, 0), "this IGES file")
            .hint("give one landmark CSV (step, part, landmark, x, y, z) per --kc file, in the same order"));
        }
        if files.len() != paths.len() {
            return Err(Diagnostic::error(
                "E1306",
                format!(
                    "{} landmark files for {} K&C files: with several K&C paths, give one landmark CSV per --kc file, in the same order",
                    files.len(),
                    paths.len()
                ),
            )
            .primary(Span::new(files[0].id, 0, 0), "first landmark file")
            .note("each K&C file numbers its own steps, so a landmark row's step alone cannot say which path it was measured on"));
        }
        for (p, f) in paths.iter_mut().zip(files) {
            attach_to(sources, model, p, std::slice::from_ref(f), remarks)?;
        }
        return Ok(());
    }
    attach_to(sources, model, &mut paths[0], files, remarks)
}

fn attach_to(
    sources: &SourceMap,
    model: &Model,
    path: &mut RigPath,
    files: &[LandmarkFile],
    remarks: &mut Remarks,
) -> Result<(), Diagnostic> {
    let data = read_landmarks(sources, files, model, remarks)?;
    let steps = data.fit(sources, model, MATCH_TOLERANCE, remarks);
    // No step with a pose: E0807 with the steps the data has.
    data.step(&steps, None)?;
    let mut fit = PoseFitResidual::default();
    for s in &steps {
        let Some(k) = path.steps.iter().position(|r| r.step == s.step) else {
            let (lo, hi) = (
                path.steps.first().map_or(0, |r| r.step),
                path.steps.last().map_or(0, |r| r.step),
            );
            let d = Diagnostic::error(
                "E1305",
                format!(
                    "the landmarks hold step {} but the K&C file `{}` has no such step (its steps run {lo}-{hi}): the files are of two runs",
                    s.step, path.name
                ),
            )
            .hint("give the landmark file measured on the same run as the K&C file, with the same step numbers");
            return Err(match data.span_of_step(sources, s.step) {
                Some(sp) => d.primary(sp, "no K&C row has this step"),
                None => d,
            });
        };
        let points = &mut path.steps[k].landmarks;
        for (part, pose) in &s.parts {
            // The ground's points only register the others.
            if model.part(*part).ground {
                continue;
            }
            points.extend(pose.points.iter().copied());
            let n = pose.residuals.len();
            if n >= 3 {
                fit.sum_sq += pose.residuals.iter().map(|(_, r)| r * r).sum::<f64>();
                fit.dof += 3 * n - 6;
            }
        }
    }
    path.pose_fit = fit;
    Ok(())
}

/// The sum of squared distances (mm²) between the simulated points `at`
/// and the measured `points` of one step.
pub fn misfit(at: &[Vec3], points: &[(LandmarkId, Vec3)]) -> f64 {
    at.iter()
        .zip(points)
        .map(|(x, (_, m))| (x - m).norm_squared())
        .sum()
}

/// Where the landmarks `points` are on their parts at `state` (model frame).
pub fn simulated(model: &Model, state: &State, points: &[(LandmarkId, Vec3)]) -> Vec<Vec3> {
    points
        .iter()
        .map(|(l, _)| {
            let l = &model.landmarks[l.index()];
            let (t, r) = state.part_pose(l.part);
            t + r * values(&l.position)
        })
        .collect()
}
