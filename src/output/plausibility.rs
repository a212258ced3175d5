//! Warnings on converged states that are equilibria of the model but not of
//! any real suspension (issue 15): a bushing deformed tens of millimetres
//! (W1002) and a wheel centre below the ground (W1003). Each names the
//! element, its worst value and the cases, once per element, like W1001.
//! They are hints that a load, a stiffness or a unit is wrong, not errors:
//! the numbers printed are the model's true equilibrium.

use super::warning::BushingReading;
use crate::diagnostic::Diagnostic;
use crate::model::{BushingId, ElementId, Model, WheelId};
use crate::statics::State;
use std::collections::BTreeMap;

/// Translational deformation (mm) beyond which a bushing is implausible:
/// rubber suspension bushings travel a few millimetres (soft hydro-mounts
/// about 10-15 mm) before their stops; 25 mm is beyond all of them, so a
/// deformation past it means a load or a stiffness off by a unit or more.
pub const BUSHING_DEFORMATION_LIMIT_MM: f64 = 25.0;

/// What is implausible about one element at one state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Finding {
    /// `|t|` of a bushing, mm.
    BushingDeformed { bushing: BushingId, mm: f64 },
    /// The wheel centre's height above the ground plane (negative), mm. The
    /// ground plane is the height of the wheel's contact marker at design
    /// (z = 0 when the model follows `conventions.md`: origin on the ground).
    WheelBelowGround { wheel: WheelId, mm: f64 },
}

impl Finding {
    fn element(&self) -> ElementId {
        match *self {
            Finding::BushingDeformed { bushing, .. } => ElementId::Bushing(bushing),
            Finding::WheelBelowGround { wheel, .. } => ElementId::Wheel(wheel),
        }
    }

    /// The size compared across cases (the worst one is shown).
    fn size(&self) -> f64 {
        match *self {
            Finding::BushingDeformed { mm, .. } | Finding::WheelBelowGround { mm, .. } => mm.abs(),
        }
    }
}

/// Everything implausible at one converged state (`design`: the model's,
/// found once for a path; `readings[k]`: the model's bushing `k` there).
pub fn findings(
    model: &Model,
    design: &State,
    state: &State,
    readings: &[BushingReading],
) -> Vec<Finding> {
    let mut out = Vec::new();
    for (k, r) in readings.iter().enumerate() {
        if r.mm > BUSHING_DEFORMATION_LIMIT_MM {
            out.push(Finding::BushingDeformed {
                bushing: BushingId(k as u32),
                mm: r.mm,
            });
        }
    }
    for (k, w) in model.wheels.iter().enumerate() {
        let ground = height(model, design, w.contact);
        let above = height(model, state, w.centre) - ground;
        if above < 0.0 {
            out.push(Finding::WheelBelowGround {
                wheel: WheelId(k as u32),
                mm: above,
            });
        }
    }
    out
}

/// The global height (z, mm) of a marker's origin at `state`.
fn height(model: &Model, state: &State, m: crate::model::MarkerId) -> f64 {
    let mk = model.marker(m);
    let (x, r) = state.part_pose(mk.part);
    (x + r * mk.origin()).z
}

/// One warning per element implausible in some case: the worst value and the
/// cases. `per_case[k]` holds the findings of the case named `names[k]`.
pub fn warnings(model: &Model, names: &[String], per_case: &[Vec<Finding>]) -> Vec<Diagnostic> {
    let mut worst: BTreeMap<ElementId, (Finding, Vec<&str>)> = BTreeMap::new();
    for (k, fs) in per_case.iter().enumerate() {
        let case = names.get(k).map_or("?", String::as_str);
        for f in fs {
            let e = worst.entry(f.element()).or_insert((*f, Vec::new()));
            if f.size() > e.0.size() {
                e.0 = *f;
            }
            e.1.push(case);
        }
    }
    worst
        .into_iter()
        .map(|(id, (f, cases))| {
            let what = model.describe(id);
            let d = match f {
                Finding::BushingDeformed { mm, .. } => Diagnostic::warning(
                    "W1002",
                    format!(
                        "{what} is deformed {mm:.1} mm at most, more than any rubber bushing travels ({BUSHING_DEFORMATION_LIMIT_MM} mm)"
                    ),
                )
                .hint("check the size of the load and the unit of the bushing's stiffness"),
                Finding::WheelBelowGround { mm, .. } => Diagnostic::warning(
                    "W1003",
                    format!(
                        "the centre of {what} goes {:.1} mm below the ground plane (the height of its contact marker at design)",
                        -mm
                    ),
                )
                .hint("check the size and the sign of the vertical load (upward on the tyre is +)"),
            };
            let shown: Vec<&str> = cases.iter().take(6).copied().collect();
            let more = if cases.len() > shown.len() {
                format!(" and {} more", cases.len() - shown.len())
            } else {
                String::new()
            };
            let label = match f {
                Finding::BushingDeformed { .. } => "this bushing",
                Finding::WheelBelowGround { .. } => "this wheel",
            };
            d.secondary_opt(model.origins.get(id), label).note(format!(
                "in case{} {}{more}",
                if cases.len() == 1 { "" } else { "s" },
                shown.join(", ")
            ))
        })
        .collect()
}
