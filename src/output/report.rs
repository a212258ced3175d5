//! The per-case report of `solve --format json` (`interfaces.md`), and warnings
//! about bushings driven outside the range of their projected angles.

use crate::geom::Vec3;
use crate::kc::{WheelQuantities, wheel_quantities};
use crate::model::{BushingId, ElementId, FrictionId, FrictionMotion, Model, SpringId};
use crate::statics::coords::Layout;
use crate::statics::forces::{bushing, spring};
use crate::statics::friction;
use crate::statics::{Equilibrium, State, StaticsError};
use serde::Serialize;
use std::collections::BTreeMap;

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PartReport {
    /// Part frame origin, mm, global.
    pub position: [f64; 3],
    /// Part frame axes as columns, rows of the matrix listed.
    pub rotation: [[f64; 3]; 3],
    /// Displacement from design of the centroid of the part's markers (mm,
    /// global): a point of the part, unlike `position`, which is the global
    /// origin carried by the part and moves by the rotation times its lever.
    pub displacement: [f64; 3],
}

/// A load applied in a case, at its marker (global, N and N·mm).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LoadReport {
    /// `part.marker`.
    pub marker: String,
    pub force: [f64; 3],
    pub torque: [f64; 3],
}

/// The reaction of a joint on its I part at equilibrium: a force at the I
/// marker's origin (`point`) and a torque, global axes (N, N·mm). J carries
/// the opposite. A joint whose equations were all left out as redundant has
/// none (the loop's reaction shows on the joints kept).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct JointReport {
    pub force: [f64; 3],
    pub torque: [f64; 3],
    /// The I marker's origin at equilibrium, mm, global.
    pub point: [f64; 3],
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BushingReport {
    /// `[tx, ty, tz]` mm and projected angles `[ax, ay, az]` deg, J axes.
    pub deformation: [f64; 6],
    /// Force (N) and torque (N·mm) on I, J axes.
    pub force: [f64; 6],
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SpringReport {
    /// mm.
    pub length: f64,
    /// Tension positive, N (a compressed spring has a negative force).
    pub force: f64,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FrictionReport {
    /// Slide along z_J (mm), or rotation about z_J (deg).
    pub slide: f64,
    /// Force on I along z_J (N), or torque about z_J (N·mm).
    pub force: f64,
    /// Committed slip offset `s_p` (mm or deg).
    pub slip_offset: f64,
    /// `stick` or `slip` (at its limit).
    pub state: &'static str,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CaseReport {
    pub name: String,
    pub step: usize,
    pub converged: bool,
    pub iterations: usize,
    pub parts: BTreeMap<String, PartReport>,
    pub wheels: BTreeMap<String, WheelQuantities>,
    pub bushings: BTreeMap<String, BushingReport>,
    pub springs: BTreeMap<String, SpringReport>,
    /// Joint reactions on I (global).
    pub joints: BTreeMap<String, JointReport>,
    /// The loads the case applies, in the order of their markers.
    pub loads: Vec<LoadReport>,
    /// Absent when the model has no friction (keeps older reports unchanged).
    #[serde(skip_serializing_if = "BTreeMap::is_empty")]
    pub frictions: BTreeMap<String, FrictionReport>,
    pub substeps: usize,
}

/// Every friction element at a converged (committed) state.
pub fn friction_reports(model: &Model, st: &State) -> BTreeMap<String, FrictionReport> {
    let layout = Layout::new(model);
    model
        .frictions
        .iter()
        .enumerate()
        .map(|(k, f)| {
            let id = FrictionId(k as u32);
            let e = friction::evaluate(model, &layout, st, id);
            let sp = st.slip_offset(model, id);
            let unit = match f.motion {
                FrictionMotion::Slide => 1.0,
                FrictionMotion::Rotation => 1.0f64.to_degrees(),
            };
            (
                f.name.clone(),
                FrictionReport {
                    slide: e.coordinate * unit,
                    force: e.force,
                    slip_offset: sp * unit,
                    state: friction::committed_state(f, e.force).word(),
                },
            )
        })
        .collect()
}

/// The report of one solved case (`step` counts from 1).
pub fn case_report(model: &Model, name: &str, step: usize, eq: &Equilibrium) -> CaseReport {
    let st = &eq.state;
    let layout = Layout::new(model);
    let mut parts = BTreeMap::new();
    for p in model.moving_parts() {
        let (x, r) = st.part_pose(p);
        let pts: Vec<Vec3> = model
            .markers
            .iter()
            .filter(|m| m.part == p)
            .map(|m| m.origin())
            .collect();
        let c = if pts.is_empty() {
            Vec3::zeros()
        } else {
            pts.iter().sum::<Vec3>() / pts.len() as f64
        };
        parts.insert(
            model.part(p).name.clone(),
            PartReport {
                position: x.into(),
                rotation: [0, 1, 2].map(|i| [r[(i, 0)], r[(i, 1)], r[(i, 2)]]),
                displacement: (x + r * c - c).into(),
            },
        );
    }
    let joints = eq
        .reactions
        .iter()
        .map(|re| {
            let j = &model.joints[re.joint.index()];
            let mk = model.marker(j.i);
            let (x, r) = st.part_pose(mk.part);
            (
                j.name.clone(),
                JointReport {
                    force: re.force.into(),
                    torque: re.torque.into(),
                    point: (x + r * mk.origin()).into(),
                },
            )
        })
        .collect();
    let loads = st
        .loads()
        .iter()
        .map(|l| LoadReport {
            marker: model.marker_path(l.marker),
            force: l.force.into(),
            torque: l.torque.into(),
        })
        .collect();
    let wheels = model
        .wheels
        .iter()
        .map(|w| (w.name.clone(), wheel_quantities(model, st, w)))
        .collect();
    let mut bushings = BTreeMap::new();
    for b in &model.bushings {
        let e = bushing(model, &layout, st, b);
        let a = e.angles.map(f64::to_degrees);
        bushings.insert(
            b.name.clone(),
            BushingReport {
                deformation: [e.t.x, e.t.y, e.t.z, a.x, a.y, a.z],
                force: [
                    e.force.x, e.force.y, e.force.z, e.torque.x, e.torque.y, e.torque.z,
                ],
            },
        );
    }
    let mut springs = BTreeMap::new();
    for (k, s) in model.springs.iter().enumerate() {
        // A converged state never has a zero-length spring (its force is undefined there).
        if let Ok((l, push, _)) = spring(model, &layout, st, SpringId(k as u32), s) {
            springs.insert(
                s.name.clone(),
                SpringReport {
                    length: l,
                    force: -push,
                },
            );
        }
    }
    CaseReport {
        name: name.to_string(),
        step,
        converged: true,
        iterations: eq.iterations,
        parts,
        wheels,
        bushings,
        springs,
        joints,
        loads,
        frictions: friction_reports(model, st),
        substeps: eq.substeps,
    }
}

/// The case a path stopped at: what `solve` and `kc` print after the
/// converged cases (the diagnostic itself goes to stderr).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FailedCase {
    pub name: String,
    pub step: usize,
    pub converged: bool,
    /// The error code (`E10xx`) and message, naming the element responsible.
    pub code: &'static str,
    pub error: String,
    /// The elements responsible, as the model names them.
    pub elements: Vec<String>,
}

impl FailedCase {
    pub fn new(model: &Model, name: &str, step: usize, e: &StaticsError) -> FailedCase {
        FailedCase {
            name: name.to_string(),
            step,
            converged: false,
            code: e.kind.code(),
            error: e.message(model),
            elements: e.elements.iter().map(|id| model.describe(*id)).collect(),
        }
    }

    /// The one line a table prints for it.
    pub fn line(&self) -> String {
        format!(
            "case {} (step {}): no equilibrium ({}): {}\n",
            self.name, self.step, self.code, self.error
        )
    }
}

/// Projected angles are meaningful within about ±15° (`methods.md` §4.2).
pub const ANGLE_LIMIT_DEG: f64 = 15.0;

/// A bushing tilted beyond ±15°: its projected angles lose accuracy.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AngleWarning {
    pub bushing: ElementId,
    pub name: String,
    /// "ax" or "ay": the tilts (torsion "az" is exact and never warned).
    pub angle: &'static str,
    pub value_deg: f64,
}

pub fn angle_warnings(model: &Model, state: &State) -> Vec<AngleWarning> {
    let layout = Layout::new(model);
    let mut out = Vec::new();
    for (k, b) in model.bushings.iter().enumerate() {
        let e = bushing(model, &layout, state, b);
        // Only the tilts: ax and ay read the direction of z_I alone, and the
        // projections are exact for a rotation about z_J (az = the angle), so
        // torsion about the bushing's own axis, however large, is no reason
        // to doubt them (docs/language.md, "Deformation").
        for (i, name) in ["ax", "ay"].into_iter().enumerate() {
            let v = e.angles[i].to_degrees();
            if v.abs() > ANGLE_LIMIT_DEG {
                out.push(AngleWarning {
                    bushing: ElementId::Bushing(BushingId(k as u32)),
                    name: b.name.clone(),
                    angle: name,
                    value_deg: v,
                });
            }
        }
    }
    out
}
