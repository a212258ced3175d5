//! Hover: what a name means (from the partial model) and what a value is worth
//! in internal units (from the syntax tree). Positions are global at design.

use super::document::Document;
use super::navigate::symbol_at;
use crate::check::Symbol;
use crate::model::*;
use crate::units::{DEG, Dim};
use lsp_types::{Hover, HoverContents, MarkupContent, MarkupKind, Position};

pub fn hover(doc: &Document, p: Position) -> Option<Hover> {
    let a = doc.analysis.as_ref()?;
    let (span, text) = match symbol_at(doc, p) {
        Some((span, Symbol::Element(id))) => (span, element(doc, &a.model, id)?),
        Some((span, Symbol::Module(file))) => (
            span,
            format!(
                "**module** `{}` (stdlib, read-only)",
                doc.sources.name(file.file)
            ),
        ),
        None => super::hover_value::value(doc, &a.ast, doc.offset(p))?,
    };
    Some(Hover {
        contents: HoverContents::Markup(MarkupContent {
            kind: MarkupKind::Markdown,
            value: text,
        }),
        range: Some(doc.range(span)),
    })
}

fn element(doc: &Document, m: &Model, id: ElementId) -> Option<String> {
    Some(match id {
        ElementId::Part(p) => part(m, p),
        ElementId::Marker(k) => marker(m, k),
        ElementId::Landmark(l) => {
            let l = m.landmarks.get(l.index())?;
            format!(
                "**landmark** `{}.{}` (measured point)\n\nat {} mm, global",
                m.part(l.part).name,
                l.name,
                vec3(&values(&l.position))
            )
        }
        ElementId::Param(k) => param(doc, m, k),
        ElementId::Bushing(b) => bushing(m, m.bushings.get(b.index())?),
        ElementId::Joint(j) => {
            let j = m.joints.get(j.index())?;
            format!(
                "**{} joint** `{}`\n\n- I `{}`\n- J `{}`",
                j.kind.keyword(),
                j.name,
                m.marker_path(j.i),
                m.marker_path(j.j)
            )
        }
        ElementId::Spring(s) => {
            let s = m.springs.get(s.index())?;
            format!(
                "**spring** `{}`\n\n- I `{}`\n- J `{}`\n- length at design {:.2} mm",
                s.name,
                m.marker_path(s.i),
                m.marker_path(s.j),
                distance(m, s.i, s.j)
            )
        }
        ElementId::Stop(s) => {
            let s = m.stops.get(s.index())?;
            format!(
                "**stop** `{}`\n\n- I `{}`\n- J `{}`\n- contact length {} mm, length at design {:.2} mm",
                s.name,
                m.marker_path(s.i),
                m.marker_path(s.j),
                num(s.contact_length.value),
                distance(m, s.i, s.j)
            )
        }
        ElementId::Wheel(w) => {
            let w = m.wheels.get(w.index())?;
            format!(
                "**wheel** `{}` on `{}`\n\n- centre `{}` at {} mm\n- contact `{}` at {} mm",
                w.name,
                m.part(w.part).name,
                m.marker_path(w.centre),
                vec3(&m.marker(w.centre).origin()),
                m.marker_path(w.contact),
                vec3(&m.marker(w.contact).origin())
            )
        }
        ElementId::Friction(f) => {
            let f = m.frictions.get(f.index())?;
            format!(
                "**friction** `{}` on joint `{}`",
                f.name,
                m.joints.get(f.joint.index())?.name
            )
        }
        ElementId::LoadSet(s) => load_set(m, m.load_sets.get(s.index())?),
    })
}

/// Every element with a marker on the part.
fn connections(m: &Model, on: impl Fn(MarkerId) -> bool) -> Vec<String> {
    let mut out = Vec::new();
    for (k, j) in m.joints.iter().enumerate() {
        if on(j.i) || on(j.j) {
            out.push(m.describe(ElementId::Joint(JointId(k as u32))));
        }
    }
    for (k, b) in m.bushings.iter().enumerate() {
        if on(b.i) || on(b.j) {
            out.push(m.describe(ElementId::Bushing(BushingId(k as u32))));
        }
    }
    for (k, s) in m.springs.iter().enumerate() {
        if on(s.i) || on(s.j) {
            out.push(m.describe(ElementId::Spring(SpringId(k as u32))));
        }
    }
    for (k, s) in m.stops.iter().enumerate() {
        if on(s.i) || on(s.j) {
            out.push(m.describe(ElementId::Stop(StopId(k as u32))));
        }
    }
    for (k, w) in m.wheels.iter().enumerate() {
        if on(w.centre) || on(w.contact) {
            out.push(m.describe(ElementId::Wheel(WheelId(k as u32))));
        }
    }
    out
}

fn part(m: &Model, p: PartId) -> String {
    let part = m.part(p);
    let mut s = format!(
        "**{}** `{}`\n\nmarkers (global, mm):",
        if part.ground { "ground" } else { "part" },
        part.name
    );
    for mk in m.markers.iter().filter(|k| k.part == p) {
        s.push_str(&format!("\n- `{}` at {}", mk.name, vec3(&mk.origin())));
    }
    let conn = connections(m, |k| m.marker(k).part == p);
    if !conn.is_empty() {
        s.push_str("\n\nconnected by:");
        for c in conn {
            s.push_str(&format!("\n- {c}"));
        }
    }
    s
}

fn marker(m: &Model, k: MarkerId) -> String {
    let mk = m.marker(k);
    let r = &mk.rotation;
    let axis = |c: usize| vec3(&r.column(c).into_owned());
    let mut s = format!(
        "**marker** `{}`\n\nat {} mm (global, design)\n\n- x axis {}\n- y axis {}\n- z axis {}",
        m.marker_path(k),
        vec3(&mk.origin()),
        axis(0),
        axis(1),
        axis(2)
    );
    let conn = connections(m, |x| x == k);
    if !conn.is_empty() {
        s.push_str(&format!("\n\nused by {}", conn.join(", ")));
    }
    s
}

fn param(doc: &Document, m: &Model, k: ParamId) -> String {
    let p = &m.params[k.index()];
    let mut s = format!("**param** `{}` = {}", p.name, quantity(p.value, p.dim));
    if let Some(b) = &p.unknown {
        let bound = |v: Option<f64>| v.map_or("open".to_string(), |v| quantity(v, p.dim));
        s.push_str(&format!(
            "\n\nunknown in [{}, {}]",
            bound(b.lower),
            bound(b.upper)
        ));
    }
    let uses = super::hover_value::fields_using(doc, k);
    if !uses.is_empty() {
        s.push_str("\n\nbound to:");
        for u in uses {
            s.push_str(&format!("\n- `{u}`"));
        }
    }
    s
}

fn bushing(m: &Model, b: &Bushing) -> String {
    let mut s = format!(
        "**bushing** `{}`\n\n- I `{}`\n- J `{}`\n\n| axis | translational (N/mm) | rotational (N·mm/deg) |\n|---|---|---|",
        b.name,
        m.marker_path(b.i),
        m.marker_path(b.j)
    );
    for (k, axis) in ["x", "y", "z"].iter().enumerate() {
        s.push_str(&format!(
            "\n| {axis} | {} | {} |",
            law(&b.translational[k], 1.0),
            law(&b.rotational[k], DEG)
        ));
    }
    s
}

/// A law's stiffness: `k` (and `k3`), or a table's point count; `scale` takes
/// internal units (per rad) to those shown (per deg).
fn law(l: &AxisLaw, scale: f64) -> String {
    match l {
        AxisLaw::Linear { k, k3 } if k3.value == 0.0 => num(k.value * scale),
        AxisLaw::Linear { k, k3 } => format!("{} + k3 {}", num(k.value * scale), num(k3.value)),
        AxisLaw::Table(t) => format!("table of {} points", t.points.len()),
    }
}

fn load_set(m: &Model, s: &LoadSet) -> String {
    let channel = |c: &Channel| match c.target {
        LoadTarget::Wheel(w) => format!("{}.{}", m.wheels[w.index()].name, c.component.name()),
        LoadTarget::DefaultWheel => c.component.name().to_string(),
        LoadTarget::Marker(k) => format!("{}.{}", m.marker_path(k), c.component.name()),
    };
    let mut out = format!(
        "**loads** `{}`: {} cases\n\n| case |",
        s.name,
        s.cases.len()
    );
    for c in &s.channels {
        out.push_str(&format!(" {} |", channel(c)));
    }
    out.push_str(&format!("\n|---|{}", "---|".repeat(s.channels.len())));
    const SHOWN: usize = 12;
    for case in s.cases.iter().take(SHOWN) {
        out.push_str(&format!("\n| {} |", case.name));
        for v in &case.values {
            out.push_str(&format!(" {} |", num(*v)));
        }
    }
    if s.cases.len() > SHOWN {
        out.push_str(&format!("\n\n… and {} more", s.cases.len() - SHOWN));
    }
    out.push_str("\n\nforces in N, torques in N·mm");
    out
}

fn distance(m: &Model, i: MarkerId, j: MarkerId) -> f64 {
    (m.marker(i).origin() - m.marker(j).origin()).norm()
}

/// A value of a dimension in its boundary unit, with the internal value when
/// they differ (angles: rad).
pub(super) fn quantity(internal: f64, dim: Dim) -> String {
    let unit = dim.boundary_unit();
    let shown = crate::units::to_boundary(internal, dim);
    if dim.angle == 0 {
        format!("{} {unit}", num(shown)).trim_end().to_string()
    } else {
        format!(
            "{} {unit} ({} {} internal)",
            num(shown),
            num(internal),
            unit.replace("deg", "rad")
        )
    }
}

pub(super) fn num(v: f64) -> String {
    let s = format!("{v:.6}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" { "0".into() } else { s.to_string() }
}

fn vec3(v: &crate::geom::Vec3) -> String {
    format!("({}, {}, {})", num(v[0]), num(v[1]), num(v[2]))
}
