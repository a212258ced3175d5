//! The candidate causes: each a model extension with its own parameters,
//! made with the model-edit operations ([`crate::edit`]) and changed through
//! parameter addresses ([`Address`]). A candidate is data: which kind of
//! cause, the element it sits on, the structural edits that make room for it
//! (a stop added, a part split), and its parameters in *search* units (log of
//! a stiffness's ratio to a reference, or millimetres from a reference), so a
//! fit moves every parameter on a comparable scale.

use super::kind::Kind;
use crate::edit::{self, Edit, EditError, Split, Why};
use crate::geom::Vec3;
use crate::model::address::Address;
use crate::model::schema::FieldId;
use crate::model::*;
use crate::units::Dim;

/// How a search variable `x` maps to the model value.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Scale {
    /// `value = reference · e^x`: stiffnesses, limits (positive, ratios).
    Log { reference: f64 },
    /// `value = origin + x · unit`: lengths, offsets, cubic terms.
    Linear { origin: f64, unit: f64 },
}

impl Scale {
    pub fn value(self, x: f64) -> f64 {
        match self {
            Scale::Log { reference } => reference * x.exp(),
            Scale::Linear { origin, unit } => origin + x * unit,
        }
    }

    /// The search variable of a model value.
    pub fn search(self, v: f64) -> f64 {
        match self {
            Scale::Log { reference } => (v / reference).ln(),
            Scale::Linear { origin, unit } => (v - origin) / unit,
        }
    }
}

/// One parameter of a candidate: the fields it sets (several for a tied
/// parameter, e.g. an isotropic compliance), and its search scale.
#[derive(Debug, Clone, PartialEq)]
pub struct CandParam {
    /// Its name in tables and JSON: the address of its first field.
    pub name: String,
    pub targets: Vec<Address>,
    pub scale: Scale,
    pub dim: Dim,
    /// The model's value before the extension (internal units); `None` for
    /// a field the extension adds.
    pub nominal: Option<f64>,
    /// Bounds in search units.
    pub lo: f64,
    pub hi: f64,
    /// The screening step in search units.
    pub probe: f64,
}

/// One candidate cause.
#[derive(Debug, Clone, PartialEq)]
pub struct Candidate {
    pub kind: Kind,
    /// The element of the nominal model it sits on.
    pub element: ElementId,
    /// What it changes, in words ("along x", "on part `upright`").
    pub detail: String,
    pub edits: Vec<Edit>,
    pub params: Vec<CandParam>,
    /// Starting points in search units (several where the fit is not
    /// convex, e.g. a stop's contact length).
    pub starts: Vec<Vec<f64>>,
    /// Whether the search point 0 leaves the model as it was (then the
    /// nominal replay is the candidate's at 0 and needs no new solve).
    pub zero_is_nominal: bool,
}

impl Candidate {
    /// The model with the structural edits made (parameters at their values
    /// in the edits).
    pub fn extend(&self, base: &Model) -> Result<Model, EditError> {
        let mut m = base.clone();
        let why = Why::new("diagnose", &format!("{} {}", self.kind.name(), self.detail));
        for e in &self.edits {
            edit::apply(&mut m, e.clone(), &why)?;
        }
        Ok(m)
    }

    /// `extended` with the parameters set to the search point `x`.
    pub fn at(&self, extended: &Model, x: &[f64]) -> Model {
        let mut m = extended.clone();
        for (p, &xi) in self.params.iter().zip(x) {
            let v = p.scale.value(xi);
            for a in &p.targets {
                a.set(&mut m, v);
            }
        }
        m
    }

    /// The element of the extended model that carries the change (the one
    /// an edited file comments): the element itself, or the one the
    /// extension adds (a stop, a friction, a split part's bushing).
    pub fn changed(&self, base: &Model) -> ElementId {
        match self.kind {
            Kind::BumpStop | Kind::ReboundStop => ElementId::Stop(StopId(base.stops.len() as u32)),
            Kind::Friction => ElementId::Friction(FrictionId(base.frictions.len() as u32)),
            Kind::PartCompliance => ElementId::Bushing(BushingId(base.bushings.len() as u32)),
            _ => self.element,
        }
    }

    /// The element's name in the nominal model.
    pub fn element_name(&self, base: &Model) -> String {
        base.describe(self.element)
            .split('`')
            .nth(1)
            .unwrap_or_default()
            .to_string()
    }
}

/// What the library needs to know of the nominal model's behaviour on the
/// rig: the range of every spring's length along the replay (mm), for the
/// starting contacts of the stops.
#[derive(Debug, Clone, Default)]
pub struct Ranges {
    pub spring_length: Vec<(f64, f64)>,
}

fn address(element: ElementId, field: FieldId, axis: Option<Axis>) -> Address {
    Address {
        element,
        field,
        axis,
    }
}

fn param(
    m: &Model,
    a: Address,
    scale: Scale,
    lo: f64,
    hi: f64,
    probe: f64,
    new: bool,
) -> CandParam {
    CandParam {
        name: a.name(m),
        targets: vec![a],
        scale,
        dim: a.dim(m),
        nominal: if new { None } else { Some(a.get(m)) },
        lo,
        hi,
        probe,
    }
}

/// The independent axes of a bushing family: all three, or radial (x) and axial (z).
fn family_axes(laws: &AxisLaws) -> Vec<(Axis, &'static str)> {
    match laws {
        AxisLaws::General(_) => vec![(Axis::X, "x"), (Axis::Y, "y"), (Axis::Z, "z")],
        AxisLaws::Axisymmetric { .. } => vec![(Axis::X, "radial"), (Axis::Z, "axial")],
    }
}

fn linear_k(laws: &AxisLaws, axis: Axis) -> Option<f64> {
    match laws.get(axis.index()) {
        AxisLaw::Linear { k, .. } if k.value > 0.0 => Some(k.value),
        _ => None,
    }
}

/// A stiffness is searched within a factor 10 of the model's: a bushing or
/// spring farther from its drawing than that is a wrong part, not a
/// tolerance, and without the bound a far-fetched stiffening of another
/// element (35 times, seen) can mimic the real cause.
const STIFFNESS_RANGE: f64 = std::f64::consts::LN_10;

/// Every candidate of the kinds asked, for `model`.
pub fn library(m: &Model, kinds: &[Kind], ranges: &Ranges) -> Vec<Candidate> {
    let mut out = Vec::new();
    for &kind in kinds {
        match kind {
            Kind::Stiffness => stiffness(m, &mut out),
            Kind::JointLocation => joint_location(m, &mut out),
            Kind::BumpStop | Kind::ReboundStop => stops(m, kind, ranges, &mut out),
            Kind::NonlinearBushing => nonlinear(m, &mut out),
            Kind::Preload => preload(m, &mut out),
            Kind::SpringFreeLength => free_length(m, &mut out),
            Kind::PartCompliance => compliance(m, &mut out),
            Kind::Friction => friction(m, &mut out),
            Kind::None => {}
        }
    }
    out
}

fn single(kind: Kind, element: ElementId, detail: String, p: CandParam) -> Candidate {
    Candidate {
        kind,
        element,
        detail,
        edits: vec![],
        params: vec![p],
        starts: vec![vec![0.0]],
        zero_is_nominal: true,
    }
}

fn stiffness(m: &Model, out: &mut Vec<Candidate>) {
    for (b, bu) in m.bushings.iter().enumerate() {
        let id = BushingId(b as u32);
        for (rot, laws) in [(false, &bu.translational), (true, &bu.rotational)] {
            for (axis, word) in family_axes(laws) {
                let Some(k) = linear_k(laws, axis) else {
                    continue;
                };
                let a = Address::bushing(id, rot, axis.index());
                let p = param(
                    m,
                    a,
                    Scale::Log { reference: k },
                    -STIFFNESS_RANGE,
                    STIFFNESS_RANGE,
                    0.3,
                    false,
                );
                let what = if rot {
                    "torsional stiffness"
                } else {
                    "stiffness"
                };
                out.push(single(
                    Kind::Stiffness,
                    ElementId::Bushing(id),
                    format!("{what} {word}"),
                    p,
                ));
            }
        }
    }
    for (s, sp) in m.springs.iter().enumerate() {
        let id = SpringId(s as u32);
        if let SpringLaw::Linear { k, .. } = &sp.law
            && k.value > 0.0
        {
            let a = Address::spring(id, FieldId::SpringK);
            let p = param(
                m,
                a,
                Scale::Log { reference: k.value },
                -STIFFNESS_RANGE,
                STIFFNESS_RANGE,
                0.3,
                false,
            );
            out.push(single(
                Kind::Stiffness,
                ElementId::Spring(id),
                "rate".into(),
                p,
            ));
        }
    }
}

/// A joint's point displaced in x, y, z on both of its parts (thesis ch. 2:
/// assembly clearance puts a joint elsewhere than drawn; the model's design
/// configuration must stay assembled, so the joint moves as a whole).
fn joint_location(m: &Model, out: &mut Vec<Candidate>) {
    for (jid, j) in m.active_joints() {
        if matches!(
            j.kind,
            JointKind::Fixed | JointKind::Inplane | JointKind::Inline
        ) {
            continue;
        }
        let params: Vec<CandParam> = Axis::ALL
            .into_iter()
            .map(|a| {
                let ad = address(ElementId::Joint(jid), FieldId::Position, Some(a));
                let origin = ad.get(m);
                param(
                    m,
                    ad,
                    Scale::Linear { origin, unit: 1.0 },
                    -20.0,
                    20.0,
                    1.0,
                    false,
                )
            })
            .collect();
        out.push(Candidate {
            kind: Kind::JointLocation,
            element: ElementId::Joint(jid),
            detail: String::new(),
            edits: vec![],
            starts: vec![vec![0.0; 3]],
            params,
            zero_is_nominal: true,
        });
    }
}

/// A one-sided stop along each spring (where bump and rebound stops sit).
fn stops(m: &Model, kind: Kind, ranges: &Ranges, out: &mut Vec<Candidate>) {
    let bump = kind == Kind::BumpStop;
    for (s, sp) in m.springs.iter().enumerate() {
        let Some(&(lo, hi)) = ranges.spring_length.get(s) else {
            continue;
        };
        if hi - lo < 1.0 {
            continue;
        }
        let l0 = (m.marker(sp.i).origin() - m.marker(sp.j).origin()).norm();
        let name = format!(
            "{}_{}",
            sp.name,
            if bump { "bump_stop" } else { "rebound_stop" }
        );
        let stop = Stop {
            name: name.clone(),
            kind: if bump {
                StopKind::Compression
            } else {
                StopKind::Rebound
            },
            i: sp.i,
            j: sp.j,
            contact_length: Val::lit(l0),
            law: StopLaw::Polynomial(vec![Val::lit(200.0)]),
        };
        let id = ElementId::Stop(StopId(m.stops.len() as u32));
        let mut ext = m.clone();
        ext.stops.push(stop.clone());
        let contact = address(id, FieldId::ContactLength, None);
        let rate = address(id, FieldId::Coefficient(1), None);
        let params = vec![
            param(
                &ext,
                contact,
                Scale::Linear {
                    origin: l0,
                    unit: 1.0,
                },
                (lo - l0) - 50.0,
                (hi - l0) + 50.0,
                1.0,
                true,
            ),
            param(
                &ext,
                rate,
                Scale::Log { reference: 200.0 },
                -4.0,
                4.0,
                0.3,
                true,
            ),
        ];
        // Starts: contact a fifth, two fifths and three fifths into the
        // travel from the end where the stop acts.
        let starts = [0.2, 0.4, 0.6]
            .iter()
            .map(|f| {
                let c = if bump {
                    lo + f * (hi - lo)
                } else {
                    hi - f * (hi - lo)
                };
                vec![c - l0, 0.0]
            })
            .collect();
        out.push(Candidate {
            kind,
            element: ElementId::Spring(SpringId(s as u32)),
            detail: format!("`{name}` along spring `{}`", sp.name),
            edits: vec![Edit::AddStop(stop)],
            params,
            starts,
            zero_is_nominal: false,
        });
    }
}

/// A stiffening cubic term `S d³` on one translational axis (thesis ch. 4).
/// Its unit is `k / (10 mm)²`: at 10 mm of deformation, 1 doubles the force.
fn nonlinear(m: &Model, out: &mut Vec<Candidate>) {
    for (b, bu) in m.bushings.iter().enumerate() {
        let id = BushingId(b as u32);
        for (axis, word) in family_axes(&bu.translational) {
            let Some(k) = linear_k(&bu.translational, axis) else {
                continue;
            };
            let a = address(ElementId::Bushing(id), FieldId::K3, Some(axis));
            let p = param(
                m,
                a,
                Scale::Linear {
                    origin: 0.0,
                    unit: k / 100.0,
                },
                0.0,
                100.0,
                0.5,
                false,
            );
            out.push(single(
                Kind::NonlinearBushing,
                ElementId::Bushing(id),
                format!("cubic term {word}"),
                p,
            ));
        }
    }
}

/// A bushing's deformation offset (a preload; the same forces as the
/// bushing's point displaced on one part by that much).
fn preload(m: &Model, out: &mut Vec<Candidate>) {
    for (b, _) in m.bushings.iter().enumerate() {
        let id = BushingId(b as u32);
        let params: Vec<CandParam> = Axis::ALL
            .into_iter()
            .map(|a| {
                let ad = address(ElementId::Bushing(id), FieldId::Offset, Some(a));
                let origin = ad.get(m);
                param(
                    m,
                    ad,
                    Scale::Linear { origin, unit: 1.0 },
                    -15.0,
                    15.0,
                    0.5,
                    false,
                )
            })
            .collect();
        out.push(Candidate {
            kind: Kind::Preload,
            element: ElementId::Bushing(id),
            detail: "deformation offset".into(),
            edits: vec![],
            starts: vec![vec![0.0; 3]],
            params,
            zero_is_nominal: true,
        });
    }
}

fn free_length(m: &Model, out: &mut Vec<Candidate>) {
    for (s, sp) in m.springs.iter().enumerate() {
        let id = SpringId(s as u32);
        if let SpringLaw::Linear { free_length, .. } = &sp.law {
            let a = Address::spring(id, FieldId::FreeLength);
            let origin = free_length.value;
            let p = param(
                m,
                a,
                Scale::Linear { origin, unit: 1.0 },
                -40.0,
                40.0,
                2.0,
                false,
            );
            out.push(single(
                Kind::SpringFreeLength,
                ElementId::Spring(id),
                "free length".into(),
                p,
            ));
        }
    }
}

/// The markers of `part` split into two groups at the widest gap along the
/// line through its two farthest markers; `None` for a part with fewer than
/// two distinct points. Returns the smaller group and the split point.
pub fn split_of(m: &Model, part: PartId) -> Option<(Vec<MarkerId>, Vec<LandmarkId>, Vec3)> {
    let mks: Vec<(MarkerId, Vec3)> = m
        .markers
        .iter()
        .enumerate()
        .filter(|(_, x)| x.part == part)
        .map(|(i, x)| (MarkerId(i as u32), x.origin()))
        .collect();
    let mut far = (0, 0, 0.0);
    for a in 0..mks.len() {
        for b in a + 1..mks.len() {
            let d = (mks[a].1 - mks[b].1).norm();
            if d > far.2 {
                far = (a, b, d);
            }
        }
    }
    if far.2 < 10.0 {
        return None;
    }
    let origin = mks[far.0].1;
    let dir = (mks[far.1].1 - origin) / far.2;
    let mut t: Vec<(f64, MarkerId)> = mks
        .iter()
        .map(|(i, p)| ((p - origin).dot(&dir), *i))
        .collect();
    t.sort_by(|a, b| a.0.total_cmp(&b.0));
    let (mut gap, mut at) = (0.0, 0);
    for k in 1..t.len() {
        if t[k].0 - t[k - 1].0 > gap {
            gap = t[k].0 - t[k - 1].0;
            at = k;
        }
    }
    let cut = 0.5 * (t[at].0 + t[at - 1].0);
    let (low, high): (Vec<_>, Vec<_>) = t.iter().partition(|(s, _)| *s < cut);
    let moved: Vec<MarkerId> = if high.len() <= low.len() { high } else { low }
        .iter()
        .map(|(_, i)| *i)
        .collect();
    let high_side = moved
        .iter()
        .all(|i| (m.marker(*i).origin() - origin).dot(&dir) > cut);
    let landmarks = m
        .landmarks
        .iter()
        .enumerate()
        .filter(|(_, l)| l.part == part)
        .filter(|(_, l)| ((values(&l.position) - origin).dot(&dir) > cut) == high_side)
        .map(|(i, _)| LandmarkId(i as u32))
        .collect();
    Some((moved, landmarks, origin + dir * cut))
}

/// A moving part that bends: split in two, joined by a six-axis bushing of
/// isotropic stiffness (one translational and one rotational rate, fitted).
fn compliance(m: &Model, out: &mut Vec<Candidate>) {
    const K0: f64 = 1e5; // N/mm
    const KT0: f64 = 1e9; // N·mm/rad
    for pid in m.moving_parts() {
        let Some((markers, landmarks, at)) = split_of(m, pid) else {
            continue;
        };
        let part = m.part(pid).name.clone();
        let name = format!("{part}_b");
        let split = Split {
            part: pid,
            name: name.clone(),
            at,
            markers,
            landmarks,
            k: [K0; 3],
            kt: [KT0; 3],
        };
        let bushing = ElementId::Bushing(BushingId(m.bushings.len() as u32));
        let tied = |field| {
            Axis::ALL
                .into_iter()
                .map(|a| address(bushing, field, Some(a)))
                .collect::<Vec<_>>()
        };
        let params = vec![
            CandParam {
                name: format!("{name}_compliance.k"),
                targets: tied(FieldId::K),
                scale: Scale::Log { reference: K0 },
                dim: Dim::STIFFNESS,
                nominal: None,
                lo: -8.0,
                hi: 2.0,
                probe: -1.5,
            },
            CandParam {
                name: format!("{name}_compliance.kt"),
                targets: tied(FieldId::Kt),
                scale: Scale::Log { reference: KT0 },
                dim: Dim::ROT_STIFFNESS,
                nominal: None,
                lo: -8.0,
                hi: 2.0,
                probe: -1.5,
            },
        ];
        out.push(Candidate {
            kind: Kind::PartCompliance,
            element: ElementId::Part(pid),
            detail: format!("split at ({:.0}, {:.0}, {:.0}) mm", at.x, at.y, at.z),
            edits: vec![Edit::SplitPart(split)],
            params,
            starts: vec![vec![0.0, 0.0]],
            zero_is_nominal: false,
        });
    }
}

/// Dry friction on each joint that slides or turns.
fn friction(m: &Model, out: &mut Vec<Candidate>) {
    for (jid, j) in m.active_joints() {
        if m.frictions.iter().any(|f| f.joint == jid) {
            continue;
        }
        let (motion, kf, limit) = match j.kind {
            JointKind::Cylindrical | JointKind::Translational => {
                (FrictionMotion::Slide, 1000.0, 100.0)
            }
            JointKind::Revolute | JointKind::Spherical => (FrictionMotion::Rotation, 1e6, 1e4),
            _ => continue,
        };
        let name = format!("{}_friction", j.name);
        let f = Friction {
            name: name.clone(),
            joint: jid,
            motion,
            stiffness: Val::lit(kf),
            limit: Val::lit(limit),
        };
        let id = ElementId::Friction(FrictionId(m.frictions.len() as u32));
        let mut ext = m.clone();
        ext.frictions.push(f.clone());
        let a = address(id, FieldId::FrictionLimit, None);
        let p = param(
            &ext,
            a,
            Scale::Log { reference: limit },
            -5.0,
            3.0,
            0.5,
            true,
        );
        let word = if motion == FrictionMotion::Slide {
            "slide"
        } else {
            "rotation"
        };
        out.push(Candidate {
            kind: Kind::Friction,
            element: ElementId::Joint(jid),
            detail: format!("on the {word} of joint `{}`", j.name),
            edits: vec![Edit::AddFriction(f)],
            params: vec![p],
            // Several limits (0.6, 2 and 6 times the reference): a
            // stick-slip path that one limit does not solve (Newton at a
            // slip transition) leaves the others.
            starts: vec![vec![0.6f64.ln()], vec![2f64.ln()], vec![6f64.ln()]],
            zero_is_nominal: false,
        });
    }
}
