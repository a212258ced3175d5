//! What the data must hold before anything is located, identified or
//! corrected (issue 15): at least two measured states with relative motion
//! between connected parts (`locate`, `identify`), and a pose of every part
//! the model gives landmarks (all three). Without them every centre is
//! "unbounded" and the tables filled with NaN and 1e14 mm, or elements are
//! silently left alone; instead the user gets one error naming what is
//! missing (E0810, E0811).

use super::motion::pose;
use crate::diagnostic::Diagnostic;
use crate::measure::poses::StepPoses;
use crate::model::{Model, PartId};

/// Relative rotation (rad, about 0.01°) and translation (mm) below which
/// two measured states are the same state, for landmarks with the thesis'
/// noise (0.05 mm over arms of 100 mm or more).
const STILL_ROTATION: f64 = 2e-4;
const STILL_TRANSLATION: f64 = 0.01;

/// The command whose data is checked: it names itself in the errors.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Purpose {
    Locate,
    Identify,
    Correct,
}

impl Purpose {
    fn command(self) -> &'static str {
        match self {
            Purpose::Locate => "locate",
            Purpose::Identify => "identify",
            Purpose::Correct => "correct",
        }
    }

    /// What cannot be done to an element without its part's pose.
    fn participle(self) -> &'static str {
        match self {
            Purpose::Locate => "located",
            Purpose::Identify => "identified",
            Purpose::Correct => "corrected",
        }
    }
}

/// The first problem found in the data for `locate`, as an error.
pub fn check(model: &Model, steps: &[StepPoses]) -> Option<Diagnostic> {
    check_for(model, steps, Purpose::Locate)
}

/// The first problem found in the data for `purpose`, as an error: a part
/// missing (E0811), then too few states (E0810; not for `correct`, which
/// uses one state: give it the one step it uses).
pub fn check_for(model: &Model, steps: &[StepPoses], purpose: Purpose) -> Option<Diagnostic> {
    missing_parts(model, steps, purpose).or_else(|| match purpose {
        Purpose::Correct => None,
        _ => too_little_motion(model, steps, purpose),
    })
}

/// E0811: parts the model gives landmarks that no step of the data measures.
pub fn missing_parts(model: &Model, steps: &[StepPoses], purpose: Purpose) -> Option<Diagnostic> {
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
    // `correct` uses one step: say which.
    let at = match (purpose, steps) {
        (Purpose::Correct, [s]) => format!(" at step {}", s.step),
        _ => String::new(),
    };
    let mut d = Diagnostic::error(
        "E0811",
        format!(
            "the landmark data measures no pose of part{} {}{at} (the model gives {} landmarks)",
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
            "without {}, these cannot be {}: {}",
            if missing.len() == 1 { "it" } else { "them" },
            purpose.participle(),
            needing.join(", ")
        ));
    }
    Some(d)
}

/// E0810: fewer than two measured states, or no connected pair of parts
/// moving relative to each other between them.
pub fn too_little_motion(
    model: &Model,
    steps: &[StepPoses],
    purpose: Purpose,
) -> Option<Diagnostic> {
    let listed: Vec<String> = steps.iter().map(|s| s.step.to_string()).collect();
    let error = |why: String| {
        Diagnostic::error(
            "E0810",
            format!(
                "{} needs at least two measured states with relative motion: {why}",
                purpose.command()
            ),
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
