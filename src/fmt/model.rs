//! A checked [`Model`] printed back as canonical axle source, so that models
//! extended by identification or diagnosis can be written out. Values are in
//! boundary units; fields bound to a parameter print the parameter's name.

use crate::geom::Vec3;
use crate::model::schema::{self, FieldId};
use crate::model::*;
use crate::units::{Dim, to_boundary};
use std::fmt::Write;

/// A number in boundary units, shortest form that survives unit conversion
/// noise (12 significant digits).
pub fn number(v: f64) -> String {
    if v == 0.0 {
        return "0".into();
    }
    let s = format!("{:.*e}", 11, v);
    let parsed: f64 = s.parse().unwrap_or(v);
    let plain = format!("{parsed}");
    if plain.len() <= 18 {
        plain
    } else {
        format!("{parsed:e}")
    }
}

fn val(m: &Model, v: &Val, dim: Dim) -> String {
    match v.param {
        Some(p) => m.params[p.index()].name.clone(),
        None => number(to_boundary(v.value, dim)),
    }
}

/// `(a, b, c) unit`, or with units per component when a parameter is involved.
fn vec3(m: &Model, v: &Val3, dim: Dim) -> String {
    let unit = dim.boundary_unit();
    if v.iter().any(|x| x.param.is_some()) {
        let parts: Vec<String> = v
            .iter()
            .map(|x| match x.param {
                Some(_) => val(m, x, dim),
                None if unit.is_empty() => val(m, x, dim),
                None => format!("{} {unit}", val(m, x, dim)),
            })
            .collect();
        return format!("({})", parts.join(", "));
    }
    let body = v
        .iter()
        .map(|x| val(m, x, dim))
        .collect::<Vec<_>>()
        .join(", ");
    if unit.is_empty() {
        format!("({body})")
    } else {
        format!("({body}) {unit}")
    }
}

fn plain3(v: &Vec3) -> String {
    format!("({}, {}, {})", number(v.x), number(v.y), number(v.z))
}

fn scalar(m: &Model, v: &Val, dim: Dim) -> String {
    match v.param {
        Some(_) => val(m, v, dim),
        None => format!("{} {}", val(m, v, dim), dim.boundary_unit()),
    }
}

fn table(t: &Table, x: Dim, y: Dim) -> String {
    let pts: Vec<String> = t
        .points
        .iter()
        .map(|(a, b)| {
            format!(
                "({}, {})",
                number(to_boundary(*a, x)),
                number(to_boundary(*b, y))
            )
        })
        .collect();
    format!(
        "table ({}, {}) [{}]",
        x.boundary_unit(),
        y.boundary_unit(),
        pts.join(", ")
    )
}

pub fn print_model(m: &Model) -> String {
    let mut o = String::new();
    let _ = writeln!(o, "model {}", m.name);
    if !m.imports.is_empty() || m.default_load_set.is_some() {
        o.push('\n');
    }
    for i in &m.imports {
        let _ = writeln!(o, "import {}", i.module);
    }
    if let Some(d) = m.default_load_set {
        let _ = writeln!(o, "default loads {}", m.load_sets[d.index()].name);
    }
    if !m.params.is_empty() {
        o.push('\n');
    }
    for p in &m.params {
        o.push_str(&param_line(p));
        o.push('\n');
    }
    for pi in 0..m.parts.len() {
        o.push('\n');
        o.push_str(&part_block(m, PartId(pi as u32)));
    }
    let elements = m
        .active_joints()
        .map(|(id, _)| ElementId::Joint(id))
        .chain((0..m.bushings.len()).map(|i| ElementId::Bushing(BushingId(i as u32))))
        .chain((0..m.springs.len()).map(|i| ElementId::Spring(SpringId(i as u32))))
        .chain((0..m.stops.len()).map(|i| ElementId::Stop(StopId(i as u32))))
        .chain((0..m.frictions.len()).map(|i| ElementId::Friction(FrictionId(i as u32))))
        .chain((0..m.wheels.len()).map(|i| ElementId::Wheel(WheelId(i as u32))));
    for id in elements {
        o.push('\n');
        o.push_str(&element(m, id).unwrap_or_default());
    }
    for (si, set) in m.load_sets.iter().enumerate() {
        if !m.imported_load_sets.contains(&LoadSetId(si as u32)) {
            load_set(&mut o, m, set);
        }
    }
    o
}

/// `param NAME = VALUE unit [unknown [lo, hi]]`, without a line break.
pub fn param_line(p: &Param) -> String {
    let mut o = format!("param {} = {}", p.name, number(to_boundary(p.value, p.dim)));
    let unit = p.dim.boundary_unit();
    if !unit.is_empty() {
        let _ = write!(o, " {unit}");
    }
    if let Some(b) = &p.unknown {
        o.push_str(" unknown");
        if b.lower.is_some() || b.upper.is_some() {
            let side = |x: Option<f64>| match x {
                Some(v) if unit.is_empty() => number(to_boundary(v, p.dim)),
                Some(v) => format!("{} {unit}", number(to_boundary(v, p.dim))),
                None => "_".into(),
            };
            let _ = write!(o, " [{}, {}]", side(b.lower), side(b.upper));
        }
    }
    o
}

/// A part block with its markers and landmarks, ending in `}` and a line break.
pub fn part_block(m: &Model, id: PartId) -> String {
    let part = m.part(id);
    let kw = if part.ground { "ground" } else { "part" };
    let mut o = format!("{kw} {} {{\n", part.name);
    for mk in m.markers.iter().filter(|x| x.part == id) {
        let _ = writeln!(o, "    {}", marker_line(m, mk));
    }
    for l in m.landmarks.iter().filter(|x| x.part == id) {
        let _ = writeln!(o, "    {}", landmark_line(m, l));
    }
    o.push_str("}\n");
    o
}

/// `marker NAME at (x, y, z) mm [orientation]`, without indent or line break.
pub fn marker_line(m: &Model, mk: &Marker) -> String {
    format!(
        "marker {} at {}{}",
        mk.name,
        vec3(m, &mk.position, Dim::LENGTH),
        orientation(m, mk)
    )
}

/// ` euler (a, b, c) deg`, ` z (..) [x (..)]`, or nothing for the part's axes.
pub fn orientation(m: &Model, mk: &Marker) -> String {
    match &mk.orientation {
        Orientation::Identity => String::new(),
        Orientation::Euler(a) => format!(" euler {}", vec3(m, a, Dim::ANGLE)),
        Orientation::Directions { z, x } => match x {
            Some(x) => format!(" z {} x {}", plain3(z), plain3(x)),
            None => format!(" z {}", plain3(z)),
        },
    }
}

/// `landmark NAME at (x, y, z) mm`, without indent or line break.
pub fn landmark_line(m: &Model, l: &Landmark) -> String {
    format!(
        "landmark {} at {}",
        l.name,
        vec3(m, &l.position, Dim::LENGTH)
    )
}

/// One element block (joint, bushing, spring, stop, friction, wheel), ending in `}` and a
/// line break; `None` for ids that are not such elements (parts, markers,
/// landmarks, parameters, load sets have printers of their own).
pub fn element(m: &Model, id: ElementId) -> Option<String> {
    let mut o = String::new();
    match id {
        ElementId::Joint(j) => joint(&mut o, m, &m.joints[j.index()]),
        ElementId::Bushing(b) => bushing(&mut o, m, &m.bushings[b.index()]),
        ElementId::Spring(s) => spring(&mut o, m, &m.springs[s.index()]),
        ElementId::Stop(s) => stop(&mut o, m, &m.stops[s.index()]),
        ElementId::Friction(f) => friction(&mut o, m, &m.frictions[f.index()]),
        ElementId::Wheel(w) => {
            let w = &m.wheels[w.index()];
            let _ = writeln!(
                o,
                "wheel {} {{\n    centre {}\n    contact {}\n}}",
                w.name,
                m.marker_path(w.centre),
                m.marker_path(w.contact)
            );
        }
        _ => return None,
    }
    Some(o)
}

fn joint(o: &mut String, m: &Model, j: &Joint) {
    let _ = writeln!(o, "joint {} {} {{", j.name, j.kind.keyword());
    let _ = writeln!(
        o,
        "    i {}\n    j {}\n}}",
        m.marker_path(j.i),
        m.marker_path(j.j)
    );
}

fn spring(o: &mut String, m: &Model, s: &Spring) {
    let _ = writeln!(o, "spring {} {{", s.name);
    let _ = writeln!(
        o,
        "    i {}\n    j {}",
        m.marker_path(s.i),
        m.marker_path(s.j)
    );
    match &s.law {
        SpringLaw::Linear {
            k,
            free_length,
            preload,
        } => {
            let _ = writeln!(o, "    k {}", scalar(m, k, Dim::STIFFNESS));
            let _ = writeln!(o, "    free_length {}", scalar(m, free_length, Dim::LENGTH));
            if preload.value != 0.0 || preload.param.is_some() {
                let _ = writeln!(o, "    preload {}", scalar(m, preload, Dim::FORCE));
            }
        }
        SpringLaw::Table(t) => {
            let _ = writeln!(o, "    law {}", table(t, Dim::LENGTH, Dim::FORCE));
        }
    }
    o.push_str("}\n");
}

fn stop(o: &mut String, m: &Model, s: &Stop) {
    let kind = match s.kind {
        StopKind::Compression => "compression",
        StopKind::Rebound => "rebound",
    };
    let _ = writeln!(o, "stop {} {kind} {{", s.name);
    let _ = writeln!(
        o,
        "    i {}\n    j {}",
        m.marker_path(s.i),
        m.marker_path(s.j)
    );
    let _ = writeln!(
        o,
        "    contact_length {}",
        scalar(m, &s.contact_length, Dim::LENGTH)
    );
    match &s.law {
        StopLaw::Polynomial(c) if c.len() == 1 => {
            let _ = writeln!(o, "    k {}", scalar(m, &c[0], Dim::STIFFNESS));
        }
        StopLaw::Polynomial(c) => {
            let items: Vec<String> = c
                .iter()
                .enumerate()
                .map(|(n, v)| scalar(m, v, Dim::new(-(n as i8) - 1, 1, 0)))
                .collect();
            let _ = writeln!(o, "    poly [{}]", items.join(", "));
        }
        StopLaw::Table(t) => {
            let _ = writeln!(o, "    law {}", table(t, Dim::LENGTH, Dim::FORCE));
        }
    }
    o.push_str("}\n");
}

/// A friction with its motion written out (the default depends on the joint).
fn friction(o: &mut String, m: &Model, f: &Friction) {
    let (kf, limit) = match f.motion {
        FrictionMotion::Slide => (Dim::STIFFNESS, Dim::FORCE),
        FrictionMotion::Rotation => (Dim::ROT_STIFFNESS, Dim::TORQUE),
    };
    let joint = m
        .joints
        .get(f.joint.index())
        .map_or("", |j| j.name.as_str());
    let _ = writeln!(o, "friction {} {{", f.name);
    let _ = writeln!(o, "    joint {joint}");
    let _ = writeln!(o, "    kf {}", scalar(m, &f.stiffness, kf));
    let _ = writeln!(o, "    limit {}", scalar(m, &f.limit, limit));
    let _ = writeln!(
        o,
        "    motion {}",
        crate::check::friction_motion_word(f.motion)
    );
    o.push_str("}\n");
}

fn bushing(o: &mut String, m: &Model, b: &Bushing) {
    let _ = writeln!(o, "bushing {} {{", b.name);
    let _ = writeln!(
        o,
        "    i {}\n    j {}",
        m.marker_path(b.i),
        m.marker_path(b.j)
    );
    for (laws, id) in [(&b.translational, FieldId::K), (&b.rotational, FieldId::Kt)] {
        let spec = schema::BUSHING.field(id);
        let (base, dim) = (spec.name, spec.dim);
        let Some(law) = spec.law else { continue };
        let (x, y) = (law.from, law.to);
        let lin: Vec<Option<Val>> = laws
            .iter()
            .map(|l| match l {
                AxisLaw::Linear { k, .. } => Some(*k),
                AxisLaw::Table(_) => None,
            })
            .collect();
        match (&lin[..], laws) {
            ([Some(r), _, Some(a)], AxisLaws::Axisymmetric { .. }) => {
                let _ = writeln!(o, "    {base}_radial {}", scalar(m, r, dim));
                let _ = writeln!(o, "    {base}_axial {}", scalar(m, a, dim));
            }
            ([Some(a), Some(b2), Some(c)], _) => {
                let _ = writeln!(o, "    {base} {}", vec3(m, &[*a, *b2, *c], dim));
            }
            _ => {
                for (n, l) in laws.iter().enumerate() {
                    let axis = ["x", "y", "z"][n];
                    match l {
                        AxisLaw::Linear { k, .. } => {
                            let _ = writeln!(o, "    {base}_{axis} {}", scalar(m, k, dim));
                        }
                        AxisLaw::Table(t) => {
                            let _ = writeln!(o, "    {base}_{axis} {}", table(t, x, y));
                        }
                    }
                }
            }
        }
        let cubic: Val3 = std::array::from_fn(|n| match &laws[n] {
            AxisLaw::Linear { k3, .. } => *k3,
            AxisLaw::Table(_) => Val::ZERO,
        });
        if let Some(cubic_id) = law.cubic
            && cubic.iter().any(|v| v.value != 0.0 || v.param.is_some())
        {
            let c = schema::BUSHING.field(cubic_id);
            let _ = writeln!(o, "    {} {}", c.name, vec3(m, &cubic, c.dim));
        }
    }
    for (id, v) in [
        (FieldId::Offset, &b.offset),
        (FieldId::AngleOffset, &b.angle_offset),
        (FieldId::Preload, &b.preload),
        (FieldId::TorquePreload, &b.torque_preload),
    ] {
        if v.iter().any(|x| x.value != 0.0 || x.param.is_some()) {
            let spec = schema::BUSHING.field(id);
            let _ = writeln!(o, "    {} {}", spec.name, vec3(m, v, spec.dim));
        }
    }
    o.push_str("}\n");
}

fn channel_name(m: &Model, c: &Channel) -> String {
    let comp = c.component.name();
    match c.target {
        LoadTarget::DefaultWheel => comp.to_string(),
        LoadTarget::Wheel(w) => format!("{}.{comp}", m.wheels[w.index()].name),
        LoadTarget::Marker(mk) => format!("{}.{comp}", m.marker_path(mk)),
    }
}

fn load_set(o: &mut String, m: &Model, set: &LoadSet) {
    o.push('\n');
    let dim = |c: &Channel| {
        if c.component.is_torque() {
            Dim::TORQUE
        } else {
            Dim::FORCE
        }
    };
    match &set.form {
        LoadForm::Table => {
            let cols: Vec<String> = set
                .channels
                .iter()
                .map(|c| format!("{} {}", channel_name(m, c), dim(c).boundary_unit()))
                .collect();
            let _ = writeln!(o, "loads {} table ({}) {{", set.name, cols.join(", "));
            let name_w = set.cases.iter().map(|c| c.name.len()).max().unwrap_or(0);
            let cells: Vec<Vec<String>> = set
                .cases
                .iter()
                .map(|c| {
                    c.values
                        .iter()
                        .zip(&set.channels)
                        .map(|(v, ch)| number(to_boundary(*v, dim(ch))))
                        .collect()
                })
                .collect();
            let widths: Vec<usize> = (0..set.channels.len())
                .map(|k| cells.iter().map(|r| r[k].len()).max().unwrap_or(0))
                .collect();
            for (case, row) in set.cases.iter().zip(&cells) {
                let mut line = format!("    {:<name_w$}", case.name);
                for (cell, w) in row.iter().zip(&widths) {
                    let _ = write!(line, "  {cell:>w$}");
                }
                let _ = writeln!(o, "{}", line.trim_end());
            }
        }
        LoadForm::Sweep { swept } => {
            let _ = writeln!(o, "loads {} sweep {{", set.name);
            for (k, ch) in set.channels.iter().enumerate() {
                let d = dim(ch);
                let u = d.boundary_unit();
                if let Some(sw) = swept.iter().find(|s| s.channel == k) {
                    let pts: Vec<String> = sw
                        .waypoints
                        .iter()
                        .map(|w| format!("{} {u}", number(to_boundary(*w, d))))
                        .collect();
                    let _ = writeln!(
                        o,
                        "    {} {} by {} {u}",
                        channel_name(m, ch),
                        pts.join(" -> "),
                        number(to_boundary(sw.step, d))
                    );
                } else {
                    let v = set.cases.first().map_or(0.0, |c| c.values[k]);
                    let _ = writeln!(
                        o,
                        "    {} {} {u}",
                        channel_name(m, ch),
                        number(to_boundary(v, d))
                    );
                }
            }
        }
    }
    o.push_str("}\n");
}
