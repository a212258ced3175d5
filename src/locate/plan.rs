//! Chooses a localisation method for every joint and bushing from the model's
//! structure (which parts are measured, what connects them, how stiff a
//! bushing is along its link), runs it, and states whether the motion
//! determines the result.

use super::linear::{self, Fit};
use super::motion::{max_rotation, observed, relative};
use super::nonlinear::{self, Searched};
use crate::geom::Vec3;
use crate::measure::poses::StepPoses;
use crate::model::*;

/// Options of a localisation run.
#[derive(Debug, Clone, Copy)]
pub struct Options {
    /// Noise of a landmark coordinate, mm (sets the uncertainty floor).
    pub sigma: f64,
    /// A located centre whose uncertainty exceeds this (mm) is reported as not observable.
    pub max_uncertainty: f64,
    /// A bushing stiffer than this along its link (N/mm) is treated as a ball joint.
    pub stiff_bushing: f64,
    /// An axis whose direction is less certain than this (degrees, one
    /// standard deviation) is not reported.
    pub max_axis_uncertainty: f64,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            sigma: 0.05,
            max_uncertainty: 5.0,
            stiff_bushing: 5000.0,
            max_axis_uncertainty: 2.0,
        }
    }
}

/// What was found for one joint or bushing, in design coordinates.
#[derive(Debug, Clone, PartialEq)]
pub struct Located {
    pub element: ElementId,
    pub name: String,
    pub kind: String,
    pub method: String,
    /// Part whose frame carries the result (the I marker's part).
    pub frame: PartId,
    pub center: Option<Vec3>,
    /// Design coordinates, fixed in `axis_part`.
    pub axis: Option<Vec3>,
    /// Part whose frame carries the axis: `frame`, except for a strut top
    /// (a chassis point) whose axis is fixed in the upright.
    pub axis_part: PartId,
    /// One standard deviation of the axis direction along its worst way to
    /// tilt, rad; infinite when not estimated (the axis then stands or falls
    /// with the centre).
    pub axis_uncertainty: f64,
    /// Whether the axis is reported: its own uncertainty within the limit, or,
    /// where that is not estimated, the centre observable.
    pub axis_determined: bool,
    pub residual: f64,
    pub uncertainty: f64,
    pub observable: bool,
    /// A direction along which the motion does not determine the centre (it was
    /// kept from the model), global at design.
    pub undetermined: Option<Vec3>,
    pub note: String,
}

impl Located {
    /// A result not yet located: no centre, unbounded uncertainty.
    pub(super) fn new(element: ElementId, name: &str, kind: &str, frame: PartId) -> Located {
        Located {
            element,
            name: name.to_string(),
            kind: kind.to_string(),
            method: String::new(),
            frame,
            center: None,
            axis: None,
            axis_part: frame,
            axis_uncertainty: f64::INFINITY,
            axis_determined: false,
            residual: 0.0,
            uncertainty: f64::INFINITY,
            observable: false,
            undetermined: None,
            note: String::new(),
        }
    }
}

fn from_fit(f: Fit) -> (Vec3, Option<Vec3>, f64, f64) {
    (f.center, f.axis, f.residual, f.uncertainty)
}

fn from_search(s: Searched) -> (Vec3, Option<Vec3>, f64, f64) {
    (s.center, s.axis, s.residual, s.uncertainty)
}

/// Stiffness of a bushing along a global direction, from its initial laws, N/mm.
fn stiffness_along(model: &Model, b: &Bushing, dir: &Vec3) -> f64 {
    let r = model.marker(b.j).rotation;
    let local = r.transpose() * dir.normalize();
    (0..3)
        .map(|k| b.translational[k].initial_stiffness() * local[k] * local[k])
        .sum()
}

/// A centre that moves more than this (mm) per mm of link-wise bushing
/// deformation is not determined by the motion along that direction.
const CONFOUND: f64 = 2.0;

/// Locates every joint and bushing it can.
pub fn locate_all(model: &Model, steps: &[StepPoses], opt: &Options) -> Vec<Located> {
    let mut out = Vec::new();
    let part_of = |m: MarkerId| model.marker(m).part;
    let seen = |p: PartId| observed(model, steps, p);
    // Ball-joint centres first: bushings on links use them.
    let mut balls: Vec<(PartId, PartId, Vec3)> = Vec::new();
    for (n, j) in model.joints.iter().enumerate() {
        let (p1, p2) = (part_of(j.i), part_of(j.j));
        let prior = model.marker(j.i).origin();
        let base = |method: &str| Located {
            method: method.to_string(),
            ..Located::new(
                ElementId::Joint(JointId(n as u32)),
                &j.name,
                j.kind.keyword(),
                p1,
            )
        };
        if !(seen(p1) && seen(p2)) {
            // Handled below when the unmeasured part is a strut.
            continue;
        }
        let rels = relative(model, steps, p1, p2);
        let result = match j.kind {
            JointKind::Spherical | JointKind::Universal => {
                linear::spherical(&rels, &prior, opt.sigma)
                    .map(|f| ("spherical least squares (eq. 3.12)", from_fit(f)))
            }
            JointKind::Revolute => linear::revolute(&rels, &prior, opt.sigma)
                .map(|f| ("revolute axis from the SVD (eq. 3.16)", from_fit(f))),
            JointKind::Cylindrical => linear::revolute(&rels, &prior, opt.sigma).and_then(|f| {
                let axis = f.axis?;
                linear::sliding_ball(&rels, &axis, &prior, opt.sigma).map(|g| {
                    (
                        "cylindrical: axis from the SVD, point across it (eq. 3.16, 3.21)",
                        (g.center, Some(axis), g.residual, g.uncertainty),
                    )
                })
            }),
            _ => None,
        };
        let mut l = base("");
        match result {
            Some((method, (c, axis, res, unc))) => {
                l.method = method.into();
                l.center = Some(c);
                l.axis = axis;
                l.residual = res;
                l.uncertainty = unc;
                if matches!(j.kind, JointKind::Spherical | JointKind::Universal) {
                    balls.push((p1, p2, c));
                }
            }
            None => {
                l.method = "none".into();
                l.note = format!("a {} joint is not located from motion", j.kind.keyword());
            }
        }
        out.push(verdict(l, &rels, opt));
    }
    for (n, b) in model.bushings.iter().enumerate() {
        let (p1, p2) = (part_of(b.i), part_of(b.j));
        let prior = model.marker(b.i).origin();
        // Two bushings between the same two parts (a wishbone): a pivot (§6.6 a).
        let pair = model.bushings.iter().enumerate().any(|(m, o)| {
            m != n && {
                let (q1, q2) = (part_of(o.i), part_of(o.j));
                (q1 == p1 && q2 == p2) || (q1 == p2 && q2 == p1)
            }
        });
        if pair && seen(p1) && seen(p2) {
            let rels = relative(model, steps, p1, p2);
            let mut l = Located::new(
                ElementId::Bushing(BushingId(n as u32)),
                &b.name,
                "bushing",
                p1,
            );
            if let Some(f) = linear::revolute(&rels, &prior, opt.sigma) {
                let axis = f.axis;
                l.method = "bushing pair as a pivot: axis from the SVD (eq. 3.16)".into();
                // The motion places the axis, not the bushings along it: each keeps
                // its model position along the axis.
                l.center = axis.map(|a| f.center + a * a.dot(&(prior - f.center)));
                (l.axis, l.residual, l.uncertainty, l.undetermined) =
                    (axis, f.residual, f.uncertainty, axis);
                l.note = "a pair of bushings on one part acts as a pivot: the position along the axis is not determined by the motion; kept from the model".into();
            }
            out.push(verdict(l, &rels, opt));
            continue;
        }
        let mut l = Located::new(
            ElementId::Bushing(BushingId(n as u32)),
            &b.name,
            "bushing",
            p1,
        );
        if !(seen(p1) && seen(p2)) {
            continue;
        }
        let rels = relative(model, steps, p1, p2);
        // The link: the bushing's non-ground part, with one ball joint to a measured part.
        let link = if model.part(p2).ground { p1 } else { p2 };
        let other = if link == p1 { p2 } else { p1 };
        let ball = balls
            .iter()
            .find(|(a, c, _)| (*a == link) != (*c == link) && (*a == link || *c == link))
            .map(|x| x.2);
        let k_link = ball.map(|c| stiffness_along(model, b, &(c - prior)));
        let rels_link = relative(model, steps, other, link);
        let (method, res) = match (ball, k_link) {
            (Some(c), Some(k)) if k < opt.stiff_bushing => (
                format!(
                    "bushing on a link with a ball joint, displacement along the link (eq. 3.35; {k:.0} N/mm along the link)"
                ),
                from_search(nonlinear::link_bushing(&rels_link, &c, &prior, opt.sigma)),
            ),
            _ => match linear::spherical(&rels, &prior, opt.sigma) {
                Some(f) => {
                    let mut note = String::new();
                    let mut c = f.center;
                    // A stiff bushing still yields a little along its link; where the
                    // motion cannot tell that from a shifted centre, keep the model's
                    // coordinate (the thesis' treatment of pivots, §6.6 a).
                    if let Some(ball) = ball {
                        let u = (ball - prior).normalize();
                        let dirs: Vec<Vec3> = rels.iter().map(|r| r.rotation * u).collect();
                        if let Some(g) =
                            linear::sensitivity(&rels, &dirs).filter(|g| g.norm() > CONFOUND)
                        {
                            let gh = g.normalize();
                            c -= gh * gh.dot(&(c - prior));
                            l.undetermined = Some(gh);
                            note = format!(
                                "the position along ({:.2}, {:.2}, {:.2}) is confounded with the bushing's deformation along its link ({:.1} mm per mm): kept from the model",
                                gh.x,
                                gh.y,
                                gh.z,
                                g.norm()
                            );
                        }
                    }
                    l.note = note;
                    (
                        match k_link {
                            Some(k) => format!(
                                "stiff bushing as a ball joint (eq. 3.12; {k:.0} N/mm along the link)"
                            ),
                            None => "bushing as a ball joint (eq. 3.12)".to_string(),
                        },
                        (c, None, f.residual, f.uncertainty),
                    )
                }
                None => continue,
            },
        };
        l.method = method;
        (l.center, l.axis, l.residual, l.uncertainty) = (Some(res.0), None, res.2, res.3);
        out.push(verdict(l, &rels, opt));
    }
    out.extend(struts(model, steps, opt));
    out.extend(super::rack::racks(model, steps, opt));
    out
}

/// An unmeasured part joined by a cylindrical joint to a measured part and by
/// a bushing or ball joint to another measured part: a McPherson strut. Its
/// top is the point of the second part that moves along a line fixed in the
/// first (thesis §6.5).
fn struts(model: &Model, steps: &[StepPoses], opt: &Options) -> Vec<Located> {
    let mut out = Vec::new();
    let part_of = |m: MarkerId| model.marker(m).part;
    for strut in (0..model.parts.len()).map(|i| PartId(i as u32)) {
        if observed(model, steps, strut) || model.part(strut).ground {
            continue;
        }
        let other = |i: MarkerId, j: MarkerId| {
            if part_of(i) == strut {
                Some(part_of(j))
            } else if part_of(j) == strut {
                Some(part_of(i))
            } else {
                None
            }
        };
        let Some((cyl, slide_part)) = model.joints.iter().enumerate().find_map(|(n, j)| {
            (j.kind == JointKind::Cylindrical)
                .then(|| other(j.i, j.j).map(|p| (n, p)))
                .flatten()
        }) else {
            continue;
        };
        let top = model.bushings.iter().enumerate().find_map(|(n, b)| {
            other(b.i, b.j).map(|p| {
                (
                    ElementId::Bushing(BushingId(n as u32)),
                    b.name.clone(),
                    "bushing",
                    b.i,
                    b.j,
                    p,
                )
            })
        });
        let top = top.or_else(|| {
            model.joints.iter().enumerate().find_map(|(n, j)| {
                (j.kind == JointKind::Spherical)
                    .then(|| {
                        other(j.i, j.j).map(|p| {
                            (
                                ElementId::Joint(JointId(n as u32)),
                                j.name.clone(),
                                "spherical",
                                j.i,
                                j.j,
                                p,
                            )
                        })
                    })
                    .flatten()
            })
        });
        let Some((element, name, kind, mi, mj, top_part)) = top else {
            continue;
        };
        if !(observed(model, steps, slide_part) && observed(model, steps, top_part)) {
            continue;
        }
        let prior = if part_of(mi) == top_part {
            model.marker(mi).origin()
        } else {
            model.marker(mj).origin()
        };
        let rels = relative(model, steps, slide_part, top_part);
        let mut s = nonlinear::strut_top(&rels, &prior, opt.sigma);
        // The axis points the way the model's cylindrical joint does, so that
        // `-o` does not turn its markers over.
        let cj = &model.joints[cyl];
        let model_axis = model.marker(cj.j).rotation.column(2).into_owned();
        s.axis = s
            .axis
            .map(|a| if a.dot(&model_axis) < 0.0 { -a } else { a });
        // The height along the strut axis is kept from the model (see strut_top).
        let (center, undetermined) = match s.axis {
            Some(a) => (s.center - a * a.dot(&(s.center - prior)), Some(a)),
            None => (s.center, None),
        };
        let l = Located {
            element,
            name: name.clone(),
            kind: kind.into(),
            method: format!(
                "strut top: point of `{}` moving on a line fixed in `{}` (eq. 3.22–3.25)",
                model.part(top_part).name,
                model.part(slide_part).name
            ),
            frame: top_part,
            center: Some(center),
            axis: s.axis,
            axis_part: slide_part,
            axis_uncertainty: s.axis_uncertainty,
            axis_determined: false,
            residual: s.residual,
            uncertainty: s.uncertainty,
            observable: false,
            undetermined,
            note: "the height along the strut axis is not determined by the motion (confounded with the top mount's deformation): kept from the model".into(),
        };
        let located = verdict(l, &rels, opt);
        out.push(Located {
            element: ElementId::Joint(JointId(cyl as u32)),
            name: cj.name.clone(),
            kind: "cylindrical".into(),
            method: format!("strut axis through the located top of `{name}`"),
            // A point of the upright's axis: carried by the upright.
            frame: slide_part,
            center: located
                .center
                .zip(located.axis)
                .map(|(c, a)| c + a * a.dot(&(model.marker(cj.j).origin() - c))),
            ..located.clone()
        });
        out.push(located);
    }
    out
}

/// Decides observability from the uncertainty and the amount of motion.
pub(super) fn verdict(mut l: Located, rels: &[super::motion::Rel], opt: &Options) -> Located {
    let rotation = max_rotation(rels).to_degrees();
    if l.center.is_none() {
        l.observable = false;
        return l;
    }
    let axis_estimated = l.axis.is_some() && l.axis_uncertainty.is_finite();
    let axis_deg = l.axis_uncertainty.to_degrees();
    if !l.uncertainty.is_finite() || l.uncertainty > opt.max_uncertainty {
        l.observable = false;
        l.note = format!(
            "not observable: the measured motion (largest relative rotation {rotation:.2}°) leaves the centre uncertain by {} mm (limit {} mm); more varied motion is needed (for a strut top, steering)",
            // Beyond a kilometre the number says nothing but "unbounded".
            if l.uncertainty.is_finite() && l.uncertainty < 1e6 {
                format!("{:.1}", l.uncertainty)
            } else {
                "an unbounded".into()
            },
            opt.max_uncertainty
        );
        l.axis_determined = axis_estimated && axis_deg <= opt.max_axis_uncertainty;
        if l.axis_determined {
            l.note += &format!(
                "; the axis direction is determined all the same, within {axis_deg:.2}° (one standard deviation)"
            );
        }
    } else {
        l.observable = true;
        l.axis_determined =
            l.axis.is_some() && (!axis_estimated || axis_deg <= opt.max_axis_uncertainty);
        if l.note.is_empty() {
            l.note = format!("largest relative rotation {rotation:.2}°");
        }
    }
    if axis_estimated && !l.axis_determined {
        l.note += &format!(
            "; the axis direction is uncertain by {axis_deg:.2}° (limit {}°): not reported",
            opt.max_axis_uncertainty
        );
    }
    l
}
