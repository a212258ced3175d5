//! The checked model: the single input of every backend (statics, identification,
//! diagnosis, ADAMS emitters, the printer). Names are resolved to typed ids,
//! values are in internal units (mm, N, rad), parameters are first-class, and
//! [`origin::Origins`] maps elements back to source.

pub mod address;
mod address_error;
mod address_parse;
pub mod elements;
pub mod id;
pub mod joint;
pub mod law;
pub mod load;
pub mod origin;
pub mod param;
pub mod schema;

pub use elements::*;
pub use id::*;
pub use joint::*;
pub use law::*;
pub use load::*;
pub use param::*;

use crate::geom::{Mat3, Vec3};

/// A rigid body. Every part frame equals the global frame at the design
/// configuration (`conventions.md`, "Frames").
#[derive(Debug, Clone, PartialEq)]
pub struct Part {
    pub name: String,
    pub ground: bool,
}

/// How a marker's orientation was written, kept for printing back.
#[derive(Debug, Clone, PartialEq)]
pub enum Orientation {
    Identity,
    /// ZXZ Euler angles (psi, theta, phi), rad.
    Euler(Val3),
    /// A z direction and an optional x hint (made orthogonal to z).
    Directions {
        z: Vec3,
        x: Option<Vec3>,
    },
}

/// A frame fixed to a part: origin and axes in global coordinates at design.
#[derive(Debug, Clone, PartialEq)]
pub struct Marker {
    pub name: String,
    pub part: PartId,
    /// Origin, mm, global at design.
    pub position: Val3,
    pub orientation: Orientation,
    /// Axes as columns, global at design; derived from `orientation`.
    pub rotation: Mat3,
}

impl Marker {
    pub fn origin(&self) -> Vec3 {
        values(&self.position)
    }
}

/// A measured point on a part (a conical landmark, thesis §2.1), mm, global at design.
#[derive(Debug, Clone, PartialEq)]
pub struct Landmark {
    pub name: String,
    pub part: PartId,
    pub position: Val3,
}

/// A module imported by the file (`import mcpherson_loads`).
#[derive(Debug, Clone, PartialEq)]
pub struct Import {
    pub module: String,
}

#[derive(Debug, Clone, PartialEq, Default)]
pub struct Model {
    pub name: String,
    pub imports: Vec<Import>,
    pub params: Vec<Param>,
    pub parts: Vec<Part>,
    pub markers: Vec<Marker>,
    pub landmarks: Vec<Landmark>,
    pub joints: Vec<Joint>,
    pub bushings: Vec<Bushing>,
    pub springs: Vec<Spring>,
    pub stops: Vec<Stop>,
    /// Dry friction on joints (path-dependent).
    pub frictions: Vec<Friction>,
    pub wheels: Vec<Wheel>,
    pub load_sets: Vec<LoadSet>,
    /// Index of the set `solve` uses when none is named.
    pub default_load_set: Option<LoadSetId>,
    /// Source spans of the elements written in a file.
    pub origins: origin::Origins,
    /// Load sets that came from imported modules (not printed back with the model).
    pub imported_load_sets: Vec<LoadSetId>,
    /// Joints replaced by an edit (e.g. by a bushing): kept in the arena so
    /// every `JointId` a caller holds stays valid, skipped by every backend.
    pub retired_joints: std::collections::BTreeSet<JointId>,
}

impl Model {
    /// Whether an edit replaced this joint (it then constrains nothing).
    pub fn is_retired(&self, j: JointId) -> bool {
        self.retired_joints.contains(&j)
    }

    /// The joints in force, with their ids (retired ones skipped).
    pub fn active_joints(&self) -> impl Iterator<Item = (JointId, &Joint)> + '_ {
        self.joints
            .iter()
            .enumerate()
            .map(|(k, j)| (JointId(k as u32), j))
            .filter(|(id, _)| !self.is_retired(*id))
    }

    pub fn ground(&self) -> Option<PartId> {
        self.parts
            .iter()
            .position(|p| p.ground)
            .map(|i| PartId(i as u32))
    }

    /// Moving parts in declaration order.
    pub fn moving_parts(&self) -> impl Iterator<Item = PartId> + '_ {
        self.parts
            .iter()
            .enumerate()
            .filter(|(_, p)| !p.ground)
            .map(|(i, _)| PartId(i as u32))
    }

    pub fn part(&self, id: PartId) -> &Part {
        &self.parts[id.index()]
    }

    pub fn marker(&self, id: MarkerId) -> &Marker {
        &self.markers[id.index()]
    }

    pub fn part_named(&self, name: &str) -> Option<PartId> {
        self.parts
            .iter()
            .position(|p| p.name == name)
            .map(|i| PartId(i as u32))
    }

    pub fn marker_named(&self, part: PartId, name: &str) -> Option<MarkerId> {
        self.markers
            .iter()
            .position(|m| m.part == part && m.name == name)
            .map(|i| MarkerId(i as u32))
    }

    pub fn param_named(&self, name: &str) -> Option<ParamId> {
        self.params
            .iter()
            .position(|p| p.name == name)
            .map(|i| ParamId(i as u32))
    }

    pub fn load_set_named(&self, name: &str) -> Option<LoadSetId> {
        self.load_sets
            .iter()
            .position(|s| s.name == name)
            .map(|i| LoadSetId(i as u32))
    }

    /// The wheel pairs (axles) of the model: each wheel left of the plane of
    /// symmetry (design centre y > 0) with the right wheel nearest its mirror
    /// image, in declaration order of the left wheels. K&C metrics and the
    /// Adams/Car loadcase file pair wheels by this one rule.
    pub fn wheel_pairs(&self) -> Vec<(WheelId, WheelId)> {
        let centres: Vec<Vec3> = self
            .wheels
            .iter()
            .map(|w| self.marker(w.centre).origin())
            .collect();
        let mut used = vec![false; centres.len()];
        let mut pairs = Vec::new();
        for (l, cl) in centres.iter().enumerate() {
            if cl.y <= 0.0 {
                continue;
            }
            let mirror = Vec3::new(cl.x, -cl.y, cl.z);
            let best = (0..centres.len())
                .filter(|&r| !used[r] && centres[r].y < 0.0)
                .min_by(|&a, &b| {
                    (centres[a] - mirror)
                        .norm()
                        .total_cmp(&(centres[b] - mirror).norm())
                });
            if let Some(r) = best {
                used[r] = true;
                pairs.push((WheelId(l as u32), WheelId(r as u32)));
            }
        }
        pairs
    }

    /// `part.marker`, as diagnostics and reports write a marker.
    pub fn marker_path(&self, id: MarkerId) -> String {
        let m = self.marker(id);
        format!("{}.{}", self.part(m.part).name, m.name)
    }

    /// The kind and name of an element, for messages: "bushing `A`".
    pub fn describe(&self, id: ElementId) -> String {
        match id {
            ElementId::Part(p) => format!("part `{}`", self.part(p).name),
            ElementId::Marker(m) => format!("marker `{}`", self.marker_path(m)),
            ElementId::Landmark(l) => {
                let l = &self.landmarks[l.index()];
                format!("landmark `{}.{}`", self.part(l.part).name, l.name)
            }
            ElementId::Joint(j) => {
                let j = &self.joints[j.index()];
                format!("{} joint `{}`", j.kind.keyword(), j.name)
            }
            ElementId::Bushing(b) => format!("bushing `{}`", self.bushings[b.index()].name),
            ElementId::Spring(s) => format!("spring `{}`", self.springs[s.index()].name),
            ElementId::Stop(s) => format!("stop `{}`", self.stops[s.index()].name),
            ElementId::Friction(f) => format!("friction `{}`", self.frictions[f.index()].name),
            ElementId::Wheel(w) => format!("wheel `{}`", self.wheels[w.index()].name),
            ElementId::Param(p) => format!("parameter `{}`", self.params[p.index()].name),
            ElementId::LoadSet(s) => format!("load set `{}`", self.load_sets[s.index()].name),
        }
    }

    /// Sets a parameter and every field written as that parameter.
    pub fn set_param(&mut self, id: ParamId, value: f64) {
        self.params[id.index()].value = value;
        self.for_each_val_mut(|v| {
            if v.param == Some(id) {
                v.value = value;
            }
        });
        // Marker frames written with Euler angles depend on their values.
        for m in &mut self.markers {
            if let Orientation::Euler(a) = &m.orientation {
                m.rotation = crate::geom::euler_zxz(a[0].value, a[1].value, a[2].value);
            }
        }
    }

    /// Visits every numeric field of every element (not load-case values).
    pub fn for_each_val_mut(&mut self, mut f: impl FnMut(&mut Val)) {
        let law = |l: &mut AxisLaw, f: &mut dyn FnMut(&mut Val)| {
            if let AxisLaw::Linear { k, k3 } = l {
                f(k);
                f(k3);
            }
        };
        for m in &mut self.markers {
            m.position.iter_mut().for_each(&mut f);
            if let Orientation::Euler(a) = &mut m.orientation {
                a.iter_mut().for_each(&mut f);
            }
        }
        for l in &mut self.landmarks {
            l.position.iter_mut().for_each(&mut f);
        }
        for b in &mut self.bushings {
            for l in b
                .translational
                .stored_mut()
                .into_iter()
                .chain(b.rotational.stored_mut())
            {
                law(l, &mut f);
            }
            for v in b
                .offset
                .iter_mut()
                .chain(b.angle_offset.iter_mut())
                .chain(b.preload.iter_mut())
                .chain(b.torque_preload.iter_mut())
            {
                f(v);
            }
        }
        for s in &mut self.springs {
            if let SpringLaw::Linear {
                k,
                free_length,
                preload,
            } = &mut s.law
            {
                f(k);
                f(free_length);
                f(preload);
            }
        }
        for s in &mut self.stops {
            f(&mut s.contact_length);
            if let StopLaw::Polynomial(c) = &mut s.law {
                c.iter_mut().for_each(&mut f);
            }
        }
        for fr in &mut self.frictions {
            f(&mut fr.stiffness);
            f(&mut fr.limit);
        }
    }

    /// The loads of one case as point loads at markers (wheel loads at contact markers).
    /// Channels still aimed at [`LoadTarget::DefaultWheel`] go to the only wheel; with
    /// none or several wheels they are skipped (the checker reports that case).
    pub fn point_loads(&self, set: LoadSetId, case: usize) -> Vec<PointLoad> {
        let set = &self.load_sets[set.index()];
        let mut loads: Vec<PointLoad> = Vec::new();
        for (ch, &v) in set.channels.iter().zip(&set.cases[case].values) {
            let marker = match ch.target {
                LoadTarget::Marker(m) => m,
                LoadTarget::Wheel(w) => self.wheels[w.index()].contact,
                LoadTarget::DefaultWheel => match self.wheels.as_slice() {
                    [w] => w.contact,
                    _ => continue,
                },
            };
            let idx = match loads.iter().position(|l| l.marker == marker) {
                Some(i) => i,
                None => {
                    loads.push(PointLoad {
                        marker,
                        force: Vec3::zeros(),
                        torque: Vec3::zeros(),
                    });
                    loads.len() - 1
                }
            };
            let c = ch.component as usize;
            if c < 3 {
                loads[idx].force[c] += v;
            } else {
                loads[idx].torque[c - 3] += v;
            }
        }
        loads
    }
}
