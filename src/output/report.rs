//! The per-case report of `solve --format json` (`interfaces.md`), and warnings
//! about bushings driven outside the range of their projected angles.

use crate::geom::Vec3;
use crate::kc::{WheelQuantities, wheel_quantities_from};
use crate::model::{ElementId, FrictionId, FrictionMotion, Model, PartId, SpringId};
use crate::statics::coords::Layout;
use crate::statics::forces::{bushing_state, spring};
use crate::statics::friction;
use crate::statics::{Equilibrium, State, StaticsError};
use serde::Serialize;
use std::sync::Arc;

/// A model element's name in a report: shared by every case's report (a
/// path of 500 cases names each element 500 times), not copied.
pub type Name = Arc<str>;

/// A report's elements by name, in name order (the JSON documents' key
/// order): a list sorted when built (a handful of names, most already in
/// order) rather than a map with a node allocation per case and kind.
#[derive(Debug, Clone, PartialEq)]
pub struct ByName<T>(Vec<(Name, T)>);

impl<T> ByName<T> {
    /// From entries with distinct names, in any order.
    pub fn new(mut entries: Vec<(Name, T)>) -> ByName<T> {
        entries.sort_by(|a, b| a.0.cmp(&b.0));
        debug_assert!(entries.windows(2).all(|w| w[0].0 != w[1].0), "names repeat");
        ByName(entries)
    }

    pub fn get(&self, name: &str) -> Option<&T> {
        let k = self.0.binary_search_by(|e| (*e.0).cmp(name)).ok()?;
        Some(&self.0[k].1)
    }

    pub fn iter(&self) -> impl Iterator<Item = (&Name, &T)> {
        self.0.iter().map(|(k, v)| (k, v))
    }

    pub fn values(&self) -> impl Iterator<Item = &T> {
        self.0.iter().map(|e| &e.1)
    }

    pub fn len(&self) -> usize {
        self.0.len()
    }

    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }
}

impl<T> std::ops::Index<&str> for ByName<T> {
    type Output = T;
    fn index(&self, name: &str) -> &T {
        match self.get(name) {
            Some(v) => v,
            None => panic!("no element `{name}` in the report"),
        }
    }
}

impl<'a, T> IntoIterator for &'a ByName<T> {
    type Item = (&'a Name, &'a T);
    type IntoIter = std::iter::Map<std::slice::Iter<'a, (Name, T)>, fn(&(Name, T)) -> (&Name, &T)>;
    fn into_iter(self) -> Self::IntoIter {
        self.0.iter().map(|(k, v)| (k, v))
    }
}

impl<T> FromIterator<(Name, T)> for ByName<T> {
    fn from_iter<I: IntoIterator<Item = (Name, T)>>(entries: I) -> ByName<T> {
        ByName::new(entries.into_iter().collect())
    }
}

impl<T: Serialize> Serialize for ByName<T> {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_map(self.iter())
    }
}

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
    pub marker: Name,
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
    pub parts: ByName<PartReport>,
    pub wheels: ByName<WheelQuantities>,
    pub bushings: ByName<BushingReport>,
    pub springs: ByName<SpringReport>,
    /// Joint reactions on I (global).
    pub joints: ByName<JointReport>,
    /// The loads the case applies, in the order of their markers.
    pub loads: Vec<LoadReport>,
    /// Absent when the model has no friction (keeps older reports unchanged).
    #[serde(skip_serializing_if = "ByName::is_empty")]
    pub frictions: ByName<FrictionReport>,
    pub substeps: usize,
}

/// The report of one solved case (`step` counts from 1).
pub fn case_report(model: &Model, name: &str, step: usize, eq: &Equilibrium) -> CaseReport {
    Reporter::new(model).case(name, step, eq)
}

/// What the reports of a model's cases share, found once: the names, the
/// coordinate layout, each moving part's marker centroid (the point whose
/// displacement is reported). A path's cases are reported by one.
pub struct Reporter<'m> {
    model: &'m Model,
    layout: Layout,
    /// The design state (the wheels' travel is measured from it).
    design: State,
    /// Moving parts: name, id and the centroid of their markers (design).
    parts: Vec<(Name, PartId, Vec3)>,
    joints: Vec<Name>,
    /// `part.marker` of every marker.
    markers: Vec<Name>,
    wheels: Vec<Name>,
    bushings: Vec<Name>,
    springs: Vec<Name>,
    frictions: Vec<Name>,
}

fn names<T>(items: &[T], name: impl Fn(&T) -> &str) -> Vec<Name> {
    items.iter().map(|x| Name::from(name(x))).collect()
}

impl<'m> Reporter<'m> {
    pub fn new(model: &'m Model) -> Reporter<'m> {
        let mut sums = vec![(Vec3::zeros(), 0usize); model.parts.len()];
        for m in &model.markers {
            let s = &mut sums[m.part.index()];
            (s.0, s.1) = (s.0 + m.origin(), s.1 + 1);
        }
        let parts = model
            .moving_parts()
            .map(|p| {
                let (sum, count) = sums[p.index()];
                let c = if count == 0 { sum } else { sum / count as f64 };
                (Name::from(model.part(p).name.as_str()), p, c)
            })
            .collect();
        let markers = (0..model.markers.len())
            .map(|k| Name::from(model.marker_path(crate::model::MarkerId(k as u32))))
            .collect();
        Reporter {
            model,
            layout: Layout::new(model),
            design: State::design(model),
            parts,
            joints: names(&model.joints, |j| &j.name),
            markers,
            wheels: names(&model.wheels, |w| &w.name),
            bushings: names(&model.bushings, |b| &b.name),
            springs: names(&model.springs, |s| &s.name),
            frictions: names(&model.frictions, |f| &f.name),
        }
    }

    /// Every friction element at a converged (committed) state.
    fn frictions(&self, st: &State) -> ByName<FrictionReport> {
        let model = self.model;
        model
            .frictions
            .iter()
            .enumerate()
            .map(|(k, f)| {
                let id = FrictionId(k as u32);
                let e = friction::evaluate(model, &self.layout, st, id);
                let sp = st.slip_offset(model, id);
                let unit = match f.motion {
                    FrictionMotion::Slide => 1.0,
                    FrictionMotion::Rotation => 1.0f64.to_degrees(),
                };
                (
                    self.frictions[k].clone(),
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
    pub fn case(&self, name: &str, step: usize, eq: &Equilibrium) -> CaseReport {
        let (model, st) = (self.model, &eq.state);
        let parts = self
            .parts
            .iter()
            .map(|(name, p, c)| {
                let (x, r) = st.part_pose(*p);
                let report = PartReport {
                    position: x.into(),
                    rotation: [0, 1, 2].map(|i| [r[(i, 0)], r[(i, 1)], r[(i, 2)]]),
                    displacement: (x + r * c - c).into(),
                };
                (name.clone(), report)
            })
            .collect();
        let joints = eq
            .reactions
            .iter()
            .map(|re| {
                let j = &model.joints[re.joint.index()];
                let mk = model.marker(j.i);
                let (x, r) = st.part_pose(mk.part);
                (
                    self.joints[re.joint.index()].clone(),
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
                marker: self.markers[l.marker.index()].clone(),
                force: l.force.into(),
                torque: l.torque.into(),
            })
            .collect();
        let wheels = model
            .wheels
            .iter()
            .zip(&self.wheels)
            .map(|(w, name)| {
                let q = wheel_quantities_from(model, &self.design, st, w);
                (name.clone(), q)
            })
            .collect();
        let bushings = model
            .bushings
            .iter()
            .zip(&self.bushings)
            .map(|(b, name)| {
                let e = bushing_state(model, &self.layout, st, b);
                let a = e.angles.map(f64::to_degrees);
                let report = BushingReport {
                    deformation: [e.t.x, e.t.y, e.t.z, a.x, a.y, a.z],
                    force: [
                        e.force.x, e.force.y, e.force.z, e.torque.x, e.torque.y, e.torque.z,
                    ],
                };
                (name.clone(), report)
            })
            .collect();
        let springs = model
            .springs
            .iter()
            .enumerate()
            .filter_map(|(k, s)| {
                // A converged state never has a zero-length spring (its force
                // is undefined there).
                let (l, push, _) = spring(model, &self.layout, st, SpringId(k as u32), s).ok()?;
                let report = SpringReport {
                    length: l,
                    force: -push,
                };
                Some((self.springs[k].clone(), report))
            })
            .collect();
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
            frictions: self.frictions(st),
            substeps: eq.substeps,
        }
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
