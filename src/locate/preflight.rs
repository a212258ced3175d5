//! What the data must hold before anything is located (issue 15): at least
//! two measured states with relative motion between connected parts, and a
//! pose of every part the model gives landmarks. Without them every centre
//! is "unbounded" and the tables filled with NaN and 1e14 mm; instead the
//! user gets one error naming what is missing (E0810, E0811).

use super::motion::pose;
use crate::diagnostic::Diagnostic;
use crate::measure::poses::StepPoses;
use crate::model::{Model, PartId};

/// Relative rotation (rad, about 0.01°) and translation (mm) below which
/// two measured states are the same state, for landmarks with the thesis'
/// noise (0.05 mm over arms of 100 mm or more).
const STILL_ROTATION: f64 = 2e-4;
const STILL_TRANSLATION: f64 = 0.01;

/// The first problem found in the data, as an error.
pub fn check(model: &Model, steps: &[StepPoses]) -> Option<Diagnostic> {
    missing_parts(model, steps).or_else(|| too_little_motion(model, steps))
}

/// E0811: parts the model gives landmarks that no step of the data measures.
fn missing_parts(model: &Model, steps: &[StepPoses]) -> Option<Diagnostic> {
    let mut missing: Vec<PartId> = Vec::new();
    for l in &model.landmarks {
        let p = l.part;
        if model.part(p).ground || missing.contains(&p) {
            continue;
        }
        if !steps.iter().any(|s| s.parts.contains_key(&p)) {
            missing.push(p);
        }
    }
    if missing.is_empty() {
        return None;
    }
    let names: Vec<String> = missing
        .iter()
        .map(|p| format!("`{}`", model.part(*p).name))
        .collect();
    let needing: Vec<String> = model
        .joints
        .iter()
        .map(|j| (j.name.as_str(), j.i, j.j))
        .chain(model.bushings.iter().map(|b| (b.name.as_str(), b.i, b.j)))
        .filter(|(_, i, j)| {
            missing.contains(&model.marker(*i).part) || missing.contains(&model.marker(*j).part)
        })
        .map(|(n, ..)| format!("`{n}`"))
        .collect();
    let mut d = Diagnostic::error(
        "E0811",
        format!(
            "the landmark data measures no pose of part{} {} (the model gives {} landmarks)",
            if missing.len() == 1 { "" } else { "s" },
            names.join(", "),
            if missing.len() == 1 { "it" } else { "them" }
        ),
    )
    .secondary_opt(
        model.origins.get(crate::model::ElementId::Part(missing[0])),
        "this part has landmarks",
    )
    .hint("add the part's landmarks to the data (its name in the `part` column), or remove its landmarks from the model");
    if !needing.is_empty() {
        d = d.note(format!(
            "without {}, these cannot be located: {}",
            if missing.len() == 1 { "it" } else { "them" },
            needing.join(", ")
        ));
    }
    Some(d)
}

/// E0810: fewer than two measured states, or no connected pair of parts
/// moving relative to each other between them.
fn too_little_motion(model: &Model, steps: &[StepPoses]) -> Option<Diagnostic> {
    let listed: Vec<String> = steps.iter().map(|s| s.step.to_string()).collect();
    let error = |why: String| {
        Diagnostic::error(
            "E0810",
            format!("locate needs at least two measured states with relative motion: {why}"),
        )
        .hint("measure the axle in several states of a load path (bump, steering, lateral load)")
    };
    if steps.len() < 2 {
        return Some(error(format!(
            "the data has {} (step{} {})",
            steps.len(),
            if steps.len() == 1 { "" } else { "s" },
            if listed.is_empty() {
                "none".to_string()
            } else {
                listed.join(", ")
            }
        )));
    }
    let pairs = model
        .joints
        .iter()
        .map(|j| (j.i, j.j))
        .chain(model.bushings.iter().map(|b| (b.i, b.j)));
    let first = &steps[0];
    for (i, j) in pairs {
        let (p1, p2) = (model.marker(i).part, model.marker(j).part);
        let Some((r1, t1)) = pose(model, first, p1) else {
            continue;
        };
        let Some((r2, t2)) = pose(model, first, p2) else {
            continue;
        };
        // Part 2 in part 1 at the first step, and at every other.
        let (r0, t0) = (r1.transpose() * r2, r1.transpose() * (t2 - t1));
        for s in &steps[1..] {
            let (Some((q1, u1)), Some((q2, u2))) = (pose(model, s, p1), pose(model, s, p2)) else {
                continue;
            };
            let (r, t) = (q1.transpose() * q2, q1.transpose() * (u2 - u1));
            let d = r0.transpose() * r;
            let angle = ((d.trace() - 1.0) / 2.0).clamp(-1.0, 1.0).acos();
            if angle > STILL_ROTATION || (t - t0).norm() > STILL_TRANSLATION {
                return None;
            }
        }
    }
    Some(error(format!(
        "no two connected parts move relative to each other between steps {}",
        listed.join(", ")
    )))
}
