//! Statements → model: units, parts, markers, joints, wheels; force elements
//! and loads are in [`super::forces`].

use super::at;
use super::expr::{self, Expr};
use super::reader::{self, Statement};
use crate::diagnostic::Diagnostic;
use crate::geom::{Mat3, Vec3, euler_zxz};
use crate::model::*;
use crate::span::FileId;
use std::collections::BTreeMap;

/// A marker of the deck: its global pose at design and its model marker (None
/// for floating and auxiliary markers, and for part frames).
pub(crate) struct MInfo {
    pub pos: Vec3,
    pub rot: Mat3,
    pub model: Option<MarkerId>,
}

pub(crate) struct Deck {
    pub file: FileId,
    pub problems: Vec<Diagnostic>,
    /// Deck length and force units in mm and N.
    pub len: f64,
    pub force: f64,
    pub parts: BTreeMap<u32, PartId>,
    pub markers: BTreeMap<u32, MInfo>,
    pub splines: BTreeMap<u32, Vec<(f64, f64)>>,
    pub variables: BTreeMap<u32, Expr>,
    pub model: Model,
}

impl Deck {
    pub fn warn(&mut self, s: &Statement, msg: impl Into<String>) {
        self.problems.push(at(
            self.file,
            s.span,
            s.line,
            false,
            format!("{}: {}", s.label(), msg.into()),
        ));
    }
    pub fn error(&mut self, s: &Statement, msg: impl Into<String>) {
        self.problems.push(at(
            self.file,
            s.span,
            s.line,
            true,
            format!("{}: {}", s.label(), msg.into()),
        ));
    }
    /// The model marker of a deck marker id, or an error on `s`.
    pub fn marker(&mut self, s: &Statement, key: &str) -> Option<MarkerId> {
        let Some(id) = s.int(key) else {
            self.error(s, format!("needs `{key} = id`"));
            return None;
        };
        match self.markers.get(&id).map(|m| m.model) {
            Some(Some(m)) => Some(m),
            Some(None) => {
                self.error(
                    s,
                    format!(
                        "{key} = {id} is a floating or auxiliary marker; axle needs a fixed one"
                    ),
                );
                None
            }
            None => {
                self.error(
                    s,
                    format!("{key} = {id}: MARKER/{id} is not defined in the deck"),
                );
                None
            }
        }
    }
}

/// An axle identifier from an ADAMS name: its `.` segments (names of
/// instances, `front_left.upright`, come back qualified), each with other
/// characters as `_`; an Adams/View full name's leading `.MODEL` is dropped
/// (`.model_1.PART_2` is `PART_2`).
pub(crate) fn ident(view: Option<&str>, fallback: String) -> String {
    let raw = view.unwrap_or("").trim();
    let raw = match raw.strip_prefix('.') {
        Some(rest) => rest.split_once('.').map_or("", |(_, r)| r),
        None => raw,
    };
    let segments: Vec<String> = raw
        .split('.')
        .map(|seg| {
            let s: String = seg
                .trim()
                .chars()
                .map(|c| {
                    if c.is_ascii_alphanumeric() || c == '_' {
                        c
                    } else {
                        '_'
                    }
                })
                .collect();
            if s.starts_with(|c: char| c.is_ascii_digit()) {
                format!("_{s}")
            } else {
                s
            }
        })
        .filter(|s| !s.is_empty())
        .collect();
    let s = if segments.is_empty() {
        fallback
    } else {
        segments.join(".")
    };
    if !s.starts_with(|c: char| c.is_ascii_alphabetic() || c == '_') {
        return format!("_{s}");
    }
    s
}

/// A marker's name from its qualified ADAMS name: without its part's name
/// (`front_left.upright.WC` on `front_left.upright` is `WC`), else the last
/// segment.
fn marker_ident(view: Option<&str>, part: &str, fallback: String) -> String {
    let full = ident(view, fallback);
    match full.strip_prefix(part).and_then(|r| r.strip_prefix('.')) {
        Some(rest) if !rest.is_empty() => rest.to_string(),
        _ => full.rsplit('.').next().unwrap_or(&full).to_string(),
    }
}

fn unique(name: String, taken: &[String], id: Option<u32>) -> String {
    if taken.contains(&name) {
        format!("{name}_{}", id.unwrap_or(0))
    } else {
        name
    }
}

fn unit_factor(s: &Statement, key: &str, table: &[(&str, f64)]) -> Result<f64, String> {
    match s.word(key) {
        None => Ok(1.0),
        Some(w) => table
            .iter()
            .find(|(n, _)| n.starts_with(w) || w.starts_with(n))
            .map(|t| t.1)
            .ok_or(format!("{key} = {w} is not supported")),
    }
}

/// The model name: the word after the title's last `:` (`ADAMS/View model
/// name: NAME`, `axle model: NAME`), else the deck's file stem, since a
/// free-text title is no name.
fn model_name(title: Option<&str>, file_stem: &str) -> String {
    let word = title
        .map(|t| t.rsplit(':').next().unwrap_or(t).trim())
        .filter(|w| {
            !w.is_empty()
                && w.chars()
                    .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
        });
    let stem = file_stem.replace(|c: char| !(c.is_ascii_alphanumeric() || c == '_'), "_");
    ident(Some(word.unwrap_or(&stem)), "imported".into())
}

pub(crate) fn build(file: FileId, file_stem: &str, text: &str) -> (Option<Model>, Vec<Diagnostic>) {
    let (title, stmts, errors) = reader::read(text);
    let name = model_name(title.as_deref(), file_stem);
    let mut d = Deck {
        file,
        problems: errors
            .iter()
            .map(|e| at(file, e.span, e.line, true, e.message.clone()))
            .collect(),
        len: 1.0,
        force: 1.0,
        parts: BTreeMap::new(),
        markers: BTreeMap::new(),
        splines: BTreeMap::new(),
        variables: BTreeMap::new(),
        model: Model {
            name,
            ..Model::default()
        },
    };
    fn by<'a>(stmts: &'a [Statement], n: &'a str) -> impl Iterator<Item = &'a Statement> + 'a {
        stmts.iter().filter(move |s| s.name == n)
    }
    // Each statement kind has its own ids; ADAMS rejects a repeated one.
    let mut seen: BTreeMap<(&str, u32), usize> = BTreeMap::new();
    for s in &stmts {
        if let Some(id) = s.id
            && let Some(first) = seen.insert((s.name.as_str(), id), s.line)
        {
            d.error(
                s,
                format!("{}/{id} is already defined at line {first}", s.name),
            );
        }
    }
    for s in by(&stmts, "UNITS") {
        if let Some(sys) = s.word("SYSTEM") {
            d.error(
                s,
                format!("SYSTEM = {sys} is not supported; give FORCE and LENGTH"),
            );
        }
        match unit_factor(
            s,
            "LENGTH",
            &[
                ("MILLIMETER", 1.0),
                ("METER", 1000.0),
                ("CENTIMETER", 10.0),
                ("KILOMETER", 1.0e6),
                ("INCH", 25.4),
                ("FOOT", 304.8),
            ],
        ) {
            Ok(f) => d.len = f,
            Err(e) => d.error(s, e),
        }
        match unit_factor(
            s,
            "FORCE",
            &[
                ("NEWTON", 1.0),
                ("KILONEWTON", 1000.0),
                ("MILLINEWTON", 1.0e-3),
                ("POUND_FORCE", 4.448221615),
                ("KILOGRAM_FORCE", 9.80665),
            ],
        ) {
            Ok(f) => d.force = f,
            Err(e) => d.error(s, e),
        }
    }
    parts(&mut d, by(&stmts, "PART").collect());
    markers(&mut d, by(&stmts, "MARKER").collect());
    for s in by(&stmts, "SPLINE") {
        match (s.id, s.nums("X"), s.nums("Y")) {
            (Some(id), Some(x), Some(y)) if x.len() == y.len() && x.len() >= 2 => {
                d.splines.insert(id, x.into_iter().zip(y).collect());
            }
            _ => d.warn(
                s,
                "only SPLINEs with X and Y lists of equal length are read; skipped",
            ),
        }
    }
    for s in by(&stmts, "VARIABLE") {
        match (s.id, s.expr("FUNCTION").map(expr::parse)) {
            (Some(id), Some(Ok(e))) => {
                d.variables.insert(id, e);
            }
            (_, Some(Err(e))) => d.error(s, e),
            _ => d.warn(s, "a VARIABLE without FUNCTION = expression; skipped"),
        }
    }
    for s in stmts
        .iter()
        .filter(|s| s.name == "JOINT" || s.name == "JPRIM")
    {
        joint(&mut d, s);
    }
    super::forces::all(&mut d, &stmts);
    let mut skipped_requests = Vec::new();
    for s in &stmts {
        match s.name.as_str() {
            "UNITS" | "PART" | "MARKER" | "SPLINE" | "VARIABLE" | "JOINT" | "JPRIM" | "BUSHING"
            | "GFORCE" | "SFORCE" | "SPRINGDAMPER" | "VFORCE" | "VTORQUE" | "OUTPUT"
            | "RESULTS" => {}
            "REQUEST" => {
                if !wheel(&mut d, s) {
                    skipped_requests.push(s.line.to_string());
                }
            }
            "ACCGRAV" => d.warn(
                s,
                "gravity is not part of an axle model (parts have no mass); skipped",
            ),
            _ => d.warn(s, "no axle equivalent; skipped"),
        }
    }
    // Loads at a wheel's contact marker are that wheel's loads.
    for set in &mut d.model.load_sets {
        for ch in &mut set.channels {
            if let LoadTarget::Marker(m) = ch.target
                && let Some(w) = d.model.wheels.iter().position(|w| w.contact == m)
            {
                ch.target = LoadTarget::Wheel(WheelId(w as u32));
            }
        }
    }
    if !skipped_requests.is_empty() {
        let msg = format!(
            "REQUESTs at lines {} are outputs; axle computes its own (solve, kc) and skips them",
            skipped_requests.join(", ")
        );
        d.problems.push(Diagnostic::warning("W0902", msg));
    }
    (Some(d.model), d.problems)
}

fn parts(d: &mut Deck, stmts: Vec<&Statement>) {
    let mut frames = BTreeMap::new();
    for s in stmts {
        let Some(id) = s.id else {
            d.error(s, "a PART needs an id");
            continue;
        };
        let ground = s.has("GROUND");
        let taken: Vec<String> = d.model.parts.iter().map(|p| p.name.clone()).collect();
        let name = unique(
            ident(
                s.view_name.as_deref(),
                if ground {
                    "ground".into()
                } else {
                    format!("part_{id}")
                },
            ),
            &taken,
            Some(id),
        );
        let qg = s.nums("QG").unwrap_or_else(|| vec![0.0; 3]);
        let eu = s.nums("REULER").unwrap_or_else(|| vec![0.0; 3]);
        if qg.len() != 3 || eu.len() != 3 {
            d.error(s, "QG and REULER need 3 values");
            continue;
        }
        if s.has("XG") || s.has("ZG") {
            d.error(
                s,
                "part frames given by XG/ZG are not supported; use REULER",
            );
            continue;
        }
        frames.insert(
            id,
            (
                Vec3::new(qg[0], qg[1], qg[2]) * d.len,
                euler_zxz(eu[0], eu[1], eu[2]),
            ),
        );
        d.parts.insert(id, PartId(d.model.parts.len() as u32));
        d.model.parts.push(Part { name, ground });
    }
    // Part frames are only needed to place markers; keep them on the markers.
    for (id, f) in frames {
        d.markers.insert(
            u32::MAX - id,
            MInfo {
                pos: f.0,
                rot: f.1,
                model: None,
            },
        );
    }
}

fn markers(d: &mut Deck, stmts: Vec<&Statement>) {
    for s in stmts {
        let (Some(id), Some(part)) = (s.id, s.int("PART")) else {
            d.error(s, "a MARKER needs an id and PART = id");
            continue;
        };
        let Some(&pid) = d.parts.get(&part) else {
            d.error(s, format!("PART = {part} is not defined"));
            continue;
        };
        let (fp, fr) = d
            .markers
            .get(&(u32::MAX - part))
            .map(|f| (f.pos, f.rot))
            .unwrap_or((Vec3::zeros(), Mat3::identity()));
        let floating = s.has("FLOATING");
        let qp = s.nums("QP").unwrap_or_else(|| vec![0.0; 3]);
        if qp.len() != 3 {
            d.error(s, "QP needs 3 values");
            continue;
        }
        let local = Vec3::new(qp[0], qp[1], qp[2]) * d.len;
        let (orientation, rot) = if let Some(e) = s.nums("REULER") {
            if e.len() != 3 {
                d.error(s, "REULER needs 3 values");
                continue;
            }
            let r = euler_zxz(e[0], e[1], e[2]);
            let o = if e.iter().all(|v| *v == 0.0) {
                Orientation::Identity
            } else {
                Orientation::Euler(vals([e[0], e[1], e[2]]))
            };
            (o, r)
        } else if let Some(zp) = s.nums("ZP").filter(|v| v.len() == 3) {
            let z = Vec3::new(zp[0], zp[1], zp[2]) * d.len - local;
            let x = s
                .nums("XP")
                .filter(|v| v.len() == 3)
                .map(|xp| Vec3::new(xp[0], xp[1], xp[2]) * d.len - local);
            match crate::geom::frame_from_z_x(z, x) {
                Ok(r) => (Orientation::Directions { z, x }, r),
                Err(_) => {
                    d.error(s, "ZP/XP do not define a frame");
                    continue;
                }
            }
        } else {
            (Orientation::Identity, Mat3::identity())
        };
        let pos = fp + fr * local;
        let rot = fr * rot;
        // A part frame away from the global frame: write the marker's global axes.
        let orientation = if fr != Mat3::identity() {
            Orientation::Directions {
                z: rot.column(2).into(),
                x: Some(rot.column(0).into()),
            }
        } else {
            orientation
        };
        let name = marker_ident(
            s.view_name.as_deref(),
            &d.model.part(pid).name,
            format!("m{id}"),
        );
        let aux = floating || name.starts_with("axle_");
        let model = (!aux).then(|| {
            let taken: Vec<String> = d
                .model
                .markers
                .iter()
                .filter(|m| m.part == pid)
                .map(|m| m.name.clone())
                .collect();
            let name = unique(name, &taken, Some(id));
            d.model.markers.push(Marker {
                name,
                part: pid,
                position: vals([pos.x, pos.y, pos.z]),
                orientation,
                rotation: rot,
            });
            MarkerId(d.model.markers.len() as u32 - 1)
        });
        if d.markers.contains_key(&id) {
            // Reported with the other repeated ids in `build`.
            continue;
        }
        d.markers.insert(id, MInfo { pos, rot, model });
    }
}

fn joint(d: &mut Deck, s: &Statement) {
    const KINDS: [(&str, JointKind); 10] = [
        ("SPHERICAL", JointKind::Spherical),
        ("ATPOINT", JointKind::Spherical),
        ("UNIVERSAL", JointKind::Universal),
        ("REVOLUTE", JointKind::Revolute),
        ("CYLINDRICAL", JointKind::Cylindrical),
        ("TRANSLATIONAL", JointKind::Translational),
        ("FIXED", JointKind::Fixed),
        ("INLINE", JointKind::Inline),
        ("INPLANE", JointKind::Inplane),
        ("HOOKE", JointKind::Universal),
    ];
    let Some(&(kw, kind)) = KINDS.iter().find(|(k, _)| s.has(k)) else {
        let kind = s
            .args
            .iter()
            .find(|a| a.values.is_empty())
            .map_or("?".to_string(), |a| a.key.clone());
        d.warn(s, format!("{kind} has no axle equivalent; skipped"));
        return;
    };
    let (Some(mut i), Some(mut j)) = (d.marker(s, "I"), d.marker(s, "J")) else {
        return;
    };
    if kw == "HOOKE" {
        // HOOKE keeps x_I perpendicular to y_J (its z axes run along the shafts);
        // axle's universal keeps z_I perpendicular to z_J, so the cross axes get
        // their own markers: z along x_I on I's part and along y_J on J's part.
        let mut cross = |m: MarkerId, col: usize, tag: &str| {
            let src = d.model.marker(m).clone();
            // cos(90°) leaves 6e-17 in the axes; such noise is not a direction.
            let clean = |v: Vec3| v.map(|c| if c.abs() < 1e-12 { 0.0 } else { c });
            let z: Vec3 = clean(src.rotation.column(col).into());
            let x: Vec3 = clean(src.rotation.column(2).into());
            let rot = crate::geom::frame_from_z_x(z, Some(x)).unwrap_or(src.rotation);
            d.model.markers.push(Marker {
                name: format!("{}_{tag}", src.name),
                orientation: Orientation::Directions { z, x: Some(x) },
                rotation: rot,
                ..src
            });
            MarkerId(d.model.markers.len() as u32 - 1)
        };
        i = cross(i, 0, "hooke_i");
        j = cross(j, 1, "hooke_j");
        d.warn(
            s,
            "HOOKE read as a universal joint on cross-axis markers (x_I ⟂ y_J, see docs/adams.md)",
        );
    }
    let taken: Vec<String> = d.model.joints.iter().map(|j| j.name.clone()).collect();
    let name = unique(
        ident(
            s.view_name.as_deref(),
            format!("{}_{}", s.name.to_lowercase(), s.id.unwrap_or(0)),
        ),
        &taken,
        s.id,
    );
    d.model.joints.push(Joint { name, kind, i, j });
}

/// A wheel from the `wheel.<name>.centre` / `.contact` requests axle writes.
fn wheel(d: &mut Deck, s: &Statement) -> bool {
    let Some(v) = s.view_name.as_deref() else {
        return false;
    };
    // `wheel.NAME.what`, NAME itself qualified for a wheel of an instance.
    let Some((name, what)) = v.strip_prefix("wheel.").and_then(|r| r.rsplit_once('.')) else {
        return false;
    };
    if what == "angles" {
        return true;
    }
    let Some(m) = s
        .int("I")
        .and_then(|i| d.markers.get(&i))
        .and_then(|m| m.model)
    else {
        return false;
    };
    let part = d.model.marker(m).part;
    let name = ident(Some(name), "wheel".into());
    let k = match d.model.wheels.iter().position(|w| w.name == name) {
        Some(k) => k,
        None => {
            d.model.wheels.push(Wheel {
                name,
                part,
                centre: m,
                contact: m,
            });
            d.model.wheels.len() - 1
        }
    };
    match what {
        "centre" => d.model.wheels[k].centre = m,
        "contact" => d.model.wheels[k].contact = m,
        _ => return false,
    }
    true
}

#[cfg(test)]
mod tests {
    use super::{ident, marker_ident};

    #[test]
    fn qualified_names_come_back_whole_and_view_paths_lose_their_model() {
        assert_eq!(
            ident(Some("front_left.upright"), "p".into()),
            "front_left.upright"
        );
        assert_eq!(ident(Some(".model_1.PART_2"), "p".into()), "PART_2");
        assert_eq!(ident(Some("arm"), "p".into()), "arm");
        assert_eq!(ident(Some("2nd arm.b-1"), "p".into()), "_2nd_arm.b_1");
        assert_eq!(ident(None, "part_3".into()), "part_3");
        assert_eq!(ident(Some("."), "part_3".into()), "part_3");
        // A marker drops its part's name, qualified or not, else keeps its last segment.
        let m = |v: &str, part: &str| marker_ident(Some(v), part, "m1".into());
        assert_eq!(m("front_left.upright.WC", "front_left.upright"), "WC");
        assert_eq!(m("chassis.front_left.B", "chassis"), "front_left.B");
        assert_eq!(m(".model_1.PART_2.MARKER_5", "PART_2"), "MARKER_5");
        assert_eq!(m("other.B", "arm"), "B");
    }
}
