//! Part compliance: a part split into two, joined by a six-axis bushing at a
//! point. The markers (and landmarks) named move to the new part, so every
//! joint, bushing, spring, stop and wheel on them now acts on the new part.

use super::{Applied, EditError, refuse};
use crate::geom::{Mat3, Vec3};
use crate::model::*;

/// Splits `part`: a new part `name` takes `markers` and `landmarks`, and a
/// bushing `<name>_compliance` (I on the new part, J on the old, global axes)
/// joins them at `at` (mm, global at design) with stiffnesses `k` (N/mm) and
/// `kt` (N·mm/rad).
#[derive(Debug, Clone, PartialEq)]
pub struct Split {
    pub part: PartId,
    pub name: String,
    pub at: Vec3,
    pub markers: Vec<MarkerId>,
    pub landmarks: Vec<LandmarkId>,
    pub k: [f64; 3],
    pub kt: [f64; 3],
}

impl Split {
    pub fn describe(&self, m: &Model) -> String {
        match m.parts.get(self.part.index()) {
            Some(p) => format!("split part `{}` into `{}`", p.name, self.name),
            None => format!("split part #{} into `{}`", self.part.0, self.name),
        }
    }

    pub(super) fn make(self, m: &mut Model, text: &str) -> Result<Applied, EditError> {
        let Some(old) = m.parts.get(self.part.index()) else {
            return Err(refuse(
                text,
                format!("part #{} does not exist", self.part.0),
            ));
        };
        let old_name = old.name.clone();
        if m.part_named(&self.name).is_some() {
            return Err(refuse(
                text,
                format!("a part is already called `{}`", self.name),
            ));
        }
        if self.markers.is_empty() {
            return Err(refuse(text, "no marker moves to the new part".into()));
        }
        for mk in &self.markers {
            match m.markers.get(mk.index()) {
                Some(x) if x.part == self.part => {}
                Some(_) => {
                    return Err(refuse(
                        text,
                        format!(
                            "marker `{}` is not on part `{old_name}`",
                            m.marker_path(*mk)
                        ),
                    ));
                }
                None => return Err(refuse(text, format!("marker #{} does not exist", mk.0))),
            }
        }
        for l in &self.landmarks {
            if m.landmarks
                .get(l.index())
                .is_none_or(|x| x.part != self.part)
            {
                return Err(refuse(
                    text,
                    format!("landmark #{} is not on part `{old_name}`", l.0),
                ));
            }
        }
        let bushing_name = format!("{}_compliance", self.name);
        super::unique(m, &bushing_name, text)?;
        let new = PartId(m.parts.len() as u32);
        m.parts.push(Part {
            name: self.name.clone(),
            ground: false,
        });
        for mk in &self.markers {
            m.markers[mk.index()].part = new;
        }
        for l in &self.landmarks {
            m.landmarks[l.index()].part = new;
        }
        for w in &mut m.wheels {
            if self.markers.contains(&w.centre) {
                w.part = new;
            }
        }
        let marker = |part: PartId, name: &str| Marker {
            name: name.to_string(),
            part,
            position: vals([self.at.x, self.at.y, self.at.z]),
            orientation: Orientation::Identity,
            rotation: Mat3::identity(),
        };
        let joint_name = format!("{}_split", self.name);
        if m.marker_named(self.part, &joint_name).is_some() {
            return Err(refuse(
                text,
                format!("part `{old_name}` already has a marker `{joint_name}`"),
            ));
        }
        m.markers.push(marker(self.part, &joint_name));
        let j = MarkerId(m.markers.len() as u32 - 1);
        m.markers.push(marker(new, &joint_name));
        let i = MarkerId(m.markers.len() as u32 - 1);
        m.bushings
            .push(Bushing::linear(&bushing_name, i, j, self.k, self.kt));
        let bushing = BushingId(m.bushings.len() as u32 - 1);
        Ok(Applied::Split { part: new, bushing })
    }
}
