//! The ball joint on a steering rack (thesis eq. 3.17–3.21): the rack is not
//! measured, but it slides on a measured part (the chassis) along a known
//! direction, and carries a ball or universal joint to a measured part (the
//! tie rod). The joint centre, fixed in the tie rod, moves relative to the
//! chassis only along the slide, so only the components of its displacement
//! across the slide must vanish; the rack travel itself is unknown and left out.

use super::linear;
use super::motion::{observed, relative};
use super::plan::{Located, Options, verdict};
use crate::measure::poses::StepPoses;
use crate::model::*;

/// Locates every ball or universal joint on an unmeasured part that slides on
/// a measured one by a translational joint.
pub fn racks(model: &Model, steps: &[StepPoses], opt: &Options) -> Vec<Located> {
    let part_of = |m: MarkerId| model.marker(m).part;
    let seen = |p: PartId| observed(model, steps, p);
    let mut out = Vec::new();
    for (r, rack) in model.parts.iter().enumerate() {
        let rack_id = PartId(r as u32);
        if rack.ground || seen(rack_id) {
            continue;
        }
        // The slide: a translational joint between the rack and a measured part.
        let Some((base, u)) = model.joints.iter().find_map(|j| {
            if j.kind != JointKind::Translational {
                return None;
            }
            let (pi, pj) = (part_of(j.i), part_of(j.j));
            let on_base = if pi == rack_id {
                j.j
            } else if pj == rack_id {
                j.i
            } else {
                return None;
            };
            let base = part_of(on_base);
            seen(base).then(|| (base, model.marker(on_base).rotation.column(2).into_owned()))
        }) else {
            continue;
        };
        for (n, j) in model.joints.iter().enumerate() {
            if !matches!(j.kind, JointKind::Spherical | JointKind::Universal) {
                continue;
            }
            let (pi, pj) = (part_of(j.i), part_of(j.j));
            let on_link = if pi == rack_id {
                j.j
            } else if pj == rack_id {
                j.i
            } else {
                continue;
            };
            let link = part_of(on_link);
            if link == base || !seen(link) {
                continue;
            }
            let rels = relative(model, steps, base, link);
            let prior = model.marker(on_link).origin();
            let mut l = Located::new(
                ElementId::Joint(JointId(n as u32)),
                &j.name,
                j.kind.keyword(),
                link,
            );
            l.method = format!(
                "ball joint on `{}` sliding along a known direction on `{}` (eq. 3.21)",
                rack.name,
                model.part(base).name
            );
            let full = linear::sliding_ball(&rels, &u, &prior, opt.sigma);
            // A link that turns about two axes only (a tie rod on a universal
            // joint: bump and steer, no spin) fixes the centre along its own
            // axis only to second order: keep the model's coordinate along the
            // least determined direction rather than report noise.
            let partial = full
                .as_ref()
                .filter(|f| f.uncertainty > opt.max_uncertainty)
                .and_then(|_| linear::sliding_ball_keeping(&rels, &u, &prior, opt.sigma, 1))
                .filter(|g| g.uncertainty <= opt.max_uncertainty);
            match (full, partial) {
                (_, Some(g)) => {
                    (l.center, l.residual, l.uncertainty) =
                        (Some(g.center), g.residual, g.uncertainty);
                    l.undetermined = g.axis;
                    l.note = "the motion does not determine the centre along `undetermined_direction` (the link does not turn about it): kept from the model".into();
                }
                (Some(f), None) => {
                    (l.center, l.residual, l.uncertainty) =
                        (Some(f.center), f.residual, f.uncertainty);
                }
                (None, None) => l.note = "the sliding-ball system could not be solved".into(),
            }
            out.push(verdict(l, &rels, opt));
        }
    }
    out
}
