//! Mobility at the design configuration (from [`crate::statics::mobility`]) as
//! diagnostics: redundant constraint equations (a warning: solved anyway),
//! unrestrained motions (an error) and nearly unrestrained ones (a warning).

use super::Checker;
use crate::diagnostic::Diagnostic;
use crate::model::{ElementId, JointId};
use crate::statics::mobility::{Mobility, Motion};

/// Moving parts the design-configuration analysis takes: its matrices are
/// 6n x 6n and dense (500 parts: 3000 x 3000, 72 MB, a few seconds).
const MAX_ANALYSED_PARTS: usize = 500;

impl Checker {
    /// Moving parts that no joint, bushing, spring or stop touches: said plainly,
    /// instead of as six free motions.
    fn unconnected_parts(&mut self) -> Vec<crate::model::PartId> {
        let md = &self.model;
        let mut touched = vec![false; md.parts.len()];
        let pairs = md
            .active_joints()
            .map(|(_, j)| (j.i, j.j))
            .chain(md.bushings.iter().map(|b| (b.i, b.j)))
            .chain(md.springs.iter().map(|s| (s.i, s.j)))
            .chain(md.stops.iter().map(|s| (s.i, s.j)));
        for (i, j) in pairs {
            for m in [i, j] {
                if let Some(t) = touched.get_mut(md.marker(m).part.index()) {
                    *t = true;
                }
            }
        }
        let lonely: Vec<crate::model::PartId> = md
            .moving_parts()
            .filter(|p| !touched.get(p.index()).copied().unwrap_or(false))
            .collect();
        for &p in &lonely {
            let d = Diagnostic::error(
                "E0411",
                format!("part `{}` is connected to nothing", self.model.part(p).name),
            )
            .primary(self.span_of(ElementId::Part(p)), "no joint, bushing, spring or stop attaches to this part")
            .note("a moving part needs joints or force elements that hold it in all six directions")
            .hint("connect it with a joint or a bushing, or make it part of the `ground` if it is fixed");
            self.problems.push(d);
        }
        lonely
    }

    pub(super) fn mobility(&mut self) {
        let lonely = self.unconnected_parts();
        // A model with a part held by nothing is wrong already: the dense
        // analysis would only repeat it (and 10 000 parts need 28 GB).
        if !lonely.is_empty() {
            return;
        }
        let moving = self.model.moving_parts().count();
        if moving > MAX_ANALYSED_PARTS {
            self.problems.push(
                Diagnostic::warning(
                    "W0604",
                    format!(
                        "mobility not analysed: {moving} moving parts, more than the {MAX_ANALYSED_PARTS} the dense analysis takes"
                    ),
                )
                .primary(
                    self.span_of(ElementId::Part(crate::model::PartId(0))),
                    "in this model",
                )
                .note("unrestrained and redundant motions of this model are not reported"),
            );
            return;
        }
        let mut m = crate::statics::mobility(&self.model);
        m.unrestrained.retain(|mo| !lonely.contains(&mo.part));
        let counts = counts(&m);
        if !m.redundant.is_empty() {
            let mut joints: Vec<JointId> = m
                .redundant
                .iter()
                .flat_map(|r| r.with.iter().copied().chain([r.joint]))
                .collect();
            joints.sort();
            joints.dedup();
            let names: Vec<String> = joints
                .iter()
                .map(|j| format!("`{}`", self.model.joints[j.index()].name))
                .collect();
            let first = self.span_of(ElementId::Joint(m.redundant[0].joint));
            let mut d = Diagnostic::warning(
                "W0601",
                format!(
                    "{} redundant constraint equation{} among joints {}",
                    m.redundant.len(),
                    if m.redundant.len() == 1 { "" } else { "s" },
                    names.join(", ")
                ),
            )
            .primary(first, "this joint's equation is implied by the others");
            for j in &joints {
                if *j != m.redundant[0].joint {
                    d = d.secondary(self.span_of(ElementId::Joint(*j)), "in the loop");
                }
            }
            for r in &m.redundant {
                let with: Vec<&str> = r
                    .with
                    .iter()
                    .map(|j| self.model.joints[j.index()].name.as_str())
                    .collect();
                d = d.note(format!(
                    "`{}` of joint `{}` follows from joints {}",
                    r.equation,
                    self.model.joints[r.joint.index()].name,
                    with.join(", ")
                ));
            }
            d = d.note(counts.clone()).hint("axle solves with the redundant equations left out; their reactions are not unique (a closed planar loop of revolutes is overconstrained in 3-D)");
            self.problems.push(d);
        }
        // One error per part, listing all of its free motions (a part held by
        // nothing has six).
        for (part, motions) in by_part(&m.unrestrained) {
            let first = motions[0];
            let name = &self.model.part(part).name;
            let title = if motions.len() == 1 {
                format!("part `{name}` can move with nothing to resist it")
            } else {
                format!(
                    "part `{name}` can move with nothing to resist it, in {} ways",
                    motions.len()
                )
            };
            let mut d = Diagnostic::error("E0601", title).primary(
                self.span_of(ElementId::Part(part)),
                format!("free: {}", words(first)),
            );
            for mo in &motions[1..] {
                d = d.note(format!("also free: {}", words(mo)));
            }
            let d = d.note(counts.clone()).hint(if motions.len() == 6 {
                "nothing holds this part: connect it with a joint or a bushing"
            } else if motions.iter().any(|mo| mo.rotation) {
                "add a stiffness about that axis (a bushing), or a joint that holds it (e.g. a universal instead of a spherical joint at one end)"
            } else {
                "add a joint or a force element that holds this translation"
            });
            self.problems.push(d);
        }
        for (part, motions) in by_part(&m.unstable) {
            let mut d = Diagnostic::warning("W0603", format!("part `{}` is unstable at the design configuration", self.model.part(part).name))
                .primary(self.span_of(ElementId::Part(part)), format!("negative stiffness: {}", words(motions[0])))
                .note(format!("along this motion the loads built into the design state (a compressed spring, a bushing written deformed) outweigh the stiffness: {:.1e} of the stiffest mode", motions[0].ratio));
            for mo in &motions[1..] {
                d = d.note(format!("also negative: {} ({:.1e})", words(mo), mo.ratio));
            }
            let d = d.hint("the solver may run away from the design state; check spring free lengths and preloads against the stiffnesses that hold the parts");
            self.problems.push(d);
        }
        for (part, motions) in by_part(&m.nearly_unrestrained) {
            let mut d = Diagnostic::warning(
                "W0602",
                format!(
                    "part `{}` is nearly unrestrained",
                    self.model.part(part).name
                ),
            )
            .primary(
                self.span_of(ElementId::Part(part)),
                format!("soft: {}", words(motions[0])),
            )
            .note(format!(
                "this motion's stiffness is {:.1e} of the stiffest mode's",
                motions[0].ratio
            ));
            for mo in &motions[1..] {
                d = d.note(format!("also soft: {} ({:.1e})", words(mo), mo.ratio));
            }
            let d = d.hint("under load the solver may land on an unstable equilibrium; add stiffness to this motion (for a strut, the top mount's kt_z)");
            self.problems.push(d);
        }
    }
}

/// Motions grouped by the part that moves most, parts in order of first mention,
/// each motion described once.
fn by_part(motions: &[Motion]) -> Vec<(crate::model::PartId, Vec<&Motion>)> {
    let mut out: Vec<(crate::model::PartId, Vec<&Motion>)> = Vec::new();
    for mo in motions {
        match out.iter_mut().find(|(p, _)| *p == mo.part) {
            Some((_, list)) => {
                if !list.iter().any(|x| x.words == mo.words) {
                    list.push(mo);
                }
            }
            None => out.push((mo.part, vec![mo])),
        }
    }
    out
}

fn words(m: &Motion) -> String {
    m.words.clone()
}

fn counts(m: &Mobility) -> String {
    format!(
        "Grübler: {} coordinates − {} constraint equations = {}; rank {} → {} degree{} of freedom",
        m.coordinates,
        m.equations,
        m.grubler,
        m.rank,
        m.dof,
        if m.dof == 1 { "" } else { "s" }
    )
}
