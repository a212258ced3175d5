//! Model → Adams/Solver dataset (`.adm`), runnable as is with the `.acf` of
//! [`super::acf`]. Layout and statement syntax: `docs/adams.md`.

use super::error::EmitError;
use super::forces;
use super::plan::{PLACEHOLDER_INERTIA, PLACEHOLDER_MASS, Plan};
use super::writer::{MAX_LINE, Stmt, VIEW_NAME, deg, list, num};
use crate::geom::{Mat3, matrix_to_zxz};
use crate::model::*;

/// A written deck and the notes a user should read (never silent about what
/// ADAMS does differently).
#[derive(Debug, Clone, PartialEq)]
pub struct Deck {
    pub text: String,
    pub notes: Vec<String>,
}

fn section(out: &mut String, title: &str) {
    let bar = "-".repeat(72usize.saturating_sub(title.len() + 3));
    out.push_str(&format!("!{bar} {title}\n"));
}

/// REULER of a marker: the angles as written, else extracted from the matrix
/// (theta = 0/180° handled by `matrix_to_zxz`).
fn reuler(mk: &Marker) -> [f64; 3] {
    match &mk.orientation {
        Orientation::Euler(a) => [a[0].value, a[1].value, a[2].value],
        _ => {
            let (p, t, f) = matrix_to_zxz(&mk.rotation);
            [p, t, f]
        }
    }
}

fn marker_stmt(id: u32, part: u32, view: &str, qp: [f64; 3], rot: Option<[f64; 3]>) -> Stmt {
    let mut s = Stmt::new("MARKER", Some(id))
        .named(view)
        .arg("PART", part.to_string());
    s = s.arg("QP", list(&qp));
    if let Some(a) = rot {
        s = s.arg(
            "REULER",
            a.iter().map(|v| deg(*v)).collect::<Vec<_>>().join(", "),
        );
    }
    s
}

pub fn emit_adm(m: &Model) -> Result<Deck, EmitError> {
    let plan = Plan::new(m)?;
    let mut o = String::new();
    let mut notes = Vec::new();
    // The first line of a dataset is its title.
    o.push_str(&format!("axle model: {}\n", m.name));
    section(&mut o, "SYSTEM UNITS");
    o.push_str("! Angles are radians unless written with the D suffix (degrees).\n");
    Stmt::new("UNITS", None)
        .arg("FORCE", "NEWTON")
        .arg("MASS", "KILOGRAM")
        .arg("LENGTH", "MILLIMETER")
        .arg("TIME", "SECOND")
        .write(&mut o);
    section(&mut o, "PARTS");
    o.push_str(&format!(
        "! Part frames coincide with the global frame; markers carry global coordinates.\n! Moving parts carry a placeholder mass ({} kg) and inertia ({} kg*mm**2):\n! statics ignore them and no gravity is defined.\n",
        num(PLACEHOLDER_MASS),
        num(PLACEHOLDER_INERTIA)
    ));
    for (pi, part) in m.parts.iter().enumerate() {
        let pid = plan.part[pi];
        let mut s = Stmt::new("PART", Some(pid)).named(&part.name);
        if part.ground {
            s = s.flag("GROUND");
        } else {
            s = s
                .arg("MASS", num(PLACEHOLDER_MASS))
                .arg("CM", plan.cm[pi].unwrap_or(0).to_string())
                .arg("IP", list(&[PLACEHOLDER_INERTIA; 3]));
        }
        s.write(&mut o);
        for (k, mk) in m
            .markers
            .iter()
            .enumerate()
            .filter(|(_, k)| k.part.index() == pi)
        {
            let p = mk.origin();
            if !(p.iter().all(|v| v.is_finite()) && mk.rotation.iter().all(|v| v.is_finite())) {
                return Err(EmitError::NotFinite {
                    element: format!("marker `{}`", m.marker_path(MarkerId(k as u32))),
                    what: "its position or orientation".into(),
                });
            }
            let rot = reuler(mk);
            let rot = (rot != [0.0; 3]).then_some(rot);
            marker_stmt(
                plan.marker[k],
                pid,
                &m.marker_path(MarkerId(k as u32)),
                [p.x, p.y, p.z],
                rot,
            )
            .write(&mut o);
        }
        for a in plan.aux.iter().filter(|a| a.part.index() == pi) {
            let view = format!("{}.{}", part.name, a.name);
            if a.floating {
                Stmt::new("MARKER", Some(a.id))
                    .named(&view)
                    .arg("PART", pid.to_string())
                    .flag("FLOATING")
                    .write(&mut o);
            } else {
                let rot = a.rotation.map(|r: Mat3| {
                    let (p, t, f) = matrix_to_zxz(&r);
                    [p, t, f]
                });
                let rot = rot.filter(|r| *r != [0.0; 3]);
                marker_stmt(
                    a.id,
                    pid,
                    &view,
                    [a.position.x, a.position.y, a.position.z],
                    rot,
                )
                .write(&mut o);
            }
        }
    }
    section(&mut o, "CONSTRAINTS");
    let (mut jid, mut pid) = (0, 0);
    for (_, j) in m.active_joints() {
        let (kw, id) = match j.kind {
            JointKind::Inline | JointKind::Inplane => {
                pid += 1;
                ("JPRIM", pid)
            }
            _ => {
                jid += 1;
                ("JOINT", jid)
            }
        };
        let flag = match j.kind {
            JointKind::Spherical => "SPHERICAL",
            // UNIVERSAL keeps z_I perpendicular to z_J (the cross axes), which is
            // the axle convention; HOOKE uses the shaft axes instead (docs/adams.md).
            JointKind::Universal => "UNIVERSAL",
            JointKind::Revolute => "REVOLUTE",
            JointKind::Cylindrical => "CYLINDRICAL",
            JointKind::Translational => "TRANSLATIONAL",
            JointKind::Fixed => "FIXED",
            JointKind::Inline => "INLINE",
            JointKind::Inplane => "INPLANE",
        };
        Stmt::new(kw, Some(id))
            .named(&j.name)
            .flag(flag)
            .arg("I", plan.marker(j.i).to_string())
            .arg("J", plan.marker(j.j).to_string())
            .write(&mut o);
    }
    section(&mut o, "FORCES");
    let (mut sf, mut sd) = (0, 0);
    for k in 0..m.bushings.len() {
        forces::bushing(&mut o, m, &plan, k)?;
    }
    for k in 0..m.springs.len() {
        forces::spring(&mut o, m, &plan, k, &mut sf, &mut sd)?;
    }
    for k in 0..m.stops.len() {
        forces::stop(&mut o, m, &plan, k, &mut sf)?;
    }
    for k in 0..m.frictions.len() {
        forces::friction(&mut o, m, &plan, k)?;
    }
    if !m.frictions.is_empty() {
        notes.push("frictions are written as GFORCEs: the stick spring capped at the slip limit about the design offset; ADAMS statics keeps no slip history, so the deck has no hysteresis along a path that turns back (docs/adams.md)".into());
    }
    if plan.spring_splines.iter().chain(&plan.stop_splines).any(Option::is_some)
        || plan.bushings.iter().any(|b| matches!(b, super::plan::BushingForm::General { splines, .. } if splines.iter().any(Option::is_some)))
    {
        notes.push("tables are written as SPLINEs evaluated with AKISPL (Akima): ADAMS matches axle at the table points and outside them, and may differ slightly between points".into());
    }
    if !m.landmarks.is_empty() {
        notes.push(format!(
            "{} landmarks are measurement points, not mechanics: they are not written",
            m.landmarks.len()
        ));
    }
    loads(&mut o, m, &plan);
    requests(&mut o, m, &plan);
    section(&mut o, "ANALYSIS SETTINGS");
    Stmt::new("OUTPUT", None).flag("REQSAVE").write(&mut o);
    Stmt::new("RESULTS", None).flag("XRF").write(&mut o);
    o.push_str("END\n");
    if let Some(note) = long_view_names(&o) {
        notes.push(note);
    }
    Ok(Deck { text: o, notes })
}

/// The note for `adams_view_name` comments past the 80 columns of the
/// dataset format: a statement is wrapped to fit, but a comment cannot be
/// continued, so a long element name (an instance's, a long part name)
/// leaves its line longer, and a reader that cuts lines at 80 columns cuts
/// the name. The deck is still written whole.
fn long_view_names(deck: &str) -> Option<String> {
    let long: Vec<&str> = deck
        .lines()
        .filter(|l| l.len() > MAX_LINE && l.starts_with(VIEW_NAME))
        .collect();
    let longest = long.iter().max_by_key(|l| l.len())?;
    let name = longest[VIEW_NAME.len()..].trim_matches('\'');
    Some(format!(
        "{} adams_view_name comments are longer than the 80 columns of the dataset format (the longest, of `{name}`, {} characters): a reader that cuts lines at 80 columns cuts these names; shorter part and element names avoid it",
        long.len(),
        longest.len()
    ))
}

fn loads(o: &mut String, m: &Model, plan: &Plan) {
    if plan.loads.is_empty() {
        return;
    }
    section(o, "LOADS");
    o.push_str("! Load components in global axes; their values are VARIABLEs that the .acf\n! sets for each load case (0 here: the design configuration).\n");
    for g in &plan.loads {
        let path = m.marker_path(g.marker);
        for (grp, keys, stmt, names) in [
            (g.vforce, ["FX", "FY", "FZ"], "VFORCE", ["fx", "fy", "fz"]),
            (g.vtorque, ["TX", "TY", "TZ"], "VTORQUE", ["mx", "my", "mz"]),
        ] {
            let Some((id, vars)) = grp else { continue };
            for (v, n) in vars.iter().zip(names) {
                Stmt::new("VARIABLE", Some(*v))
                    .named(&format!("{path}.{n}"))
                    .expr("FUNCTION", "0")
                    .write(o);
            }
            let mut s = Stmt::new(stmt, Some(id))
                .named(&format!(
                    "{path}.{}",
                    if stmt == "VFORCE" { "force" } else { "torque" }
                ))
                .arg("I", plan.marker(g.marker).to_string())
                .arg("JFLOAT", g.float.to_string())
                .arg("RM", plan.global.to_string());
            for (k, v) in keys.iter().zip(vars) {
                s = s.expr(k, format!("VARVAL({v})"));
            }
            s.write(o);
        }
    }
}

fn requests(o: &mut String, m: &Model, plan: &Plan) {
    section(o, "OUTPUT REQUESTS");
    let g = plan.global;
    let mut id = 0;
    let mut next = || {
        id += 1;
        id
    };
    for (w, spin) in m.wheels.iter().zip(&plan.spin) {
        let (c, k) = (plan.marker(w.centre), plan.marker(w.contact));
        for (mk, what) in [(c, "centre"), (k, "contact")] {
            Stmt::new("REQUEST", Some(next()))
                .named(&format!("wheel.{}.{what}", w.name))
                .flag("DISPLACEMENT")
                .arg("I", mk.to_string())
                .arg("J", g.to_string())
                .comment(&format!("wheel {} {what} X Y Z PSI THETA PHI", w.name))
                .write(o);
        }
        // Toe and camber from the spin axis s = (spin - centre) / |spin - centre|
        // (conventions.md): toe-in positive, camber positive top outboard.
        let right = m.marker(w.centre).origin().y < 0.0;
        let (dx, dy, dz) = (
            format!("DX({spin},{c})"),
            format!("DY({spin},{c})"),
            format!("DZ({spin},{c})"),
        );
        let toe = if right {
            format!("ATAN2({dx}, -{dy})*RTOD")
        } else {
            format!("ATAN2({dx}, {dy})*RTOD")
        };
        let camber = format!("ASIN(-{dz}/DM({spin},{c}))*RTOD");
        Stmt::new("REQUEST", Some(next()))
            .named(&format!("wheel.{}.angles", w.name))
            .comment(&format!("wheel {} F2 toe deg F3 camber deg", w.name))
            .expr("F2", toe)
            .expr("F3", camber)
            .write(o);
    }
    for (k, b) in m.bushings.iter().enumerate() {
        let (i, j) = (plan.marker(b.i), plan.marker(b.j));
        let mut s = Stmt::new("REQUEST", Some(next()))
            .named(&format!("{}.deformation", b.name))
            .comment(&format!(
                "bushing {} deformation in J axes mm and deg",
                b.name
            ));
        for (f, e) in ["F2", "F3", "F4"].iter().zip(["DX", "DY", "DZ"]) {
            s = s.expr(f, format!("{e}({i},{j},{j})"));
        }
        for (f, e) in ["F6", "F7", "F8"].iter().zip(["AX", "AY", "AZ"]) {
            s = s.expr(f, format!("{e}({i},{j})*RTOD"));
        }
        s.write(o);
        let (func, fid) = match plan.bushings[k] {
            super::plan::BushingForm::Linear { id } => ("BUSH", id),
            super::plan::BushingForm::General { id, .. } => ("GFORCE", id),
        };
        let mut s = Stmt::new("REQUEST", Some(next()))
            .named(&format!("{}.force", b.name))
            .comment(&format!(
                "bushing {} force and torque on I in J axes N and N*mm",
                b.name
            ));
        for c in [2, 3, 4, 6, 7, 8] {
            s = s.expr(&format!("F{c}"), format!("{func}({fid},0,{c},{j})"));
        }
        s.write(o);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A part whose name leaves its view-name comment past column 80 gets a
    /// note naming it; the example's names do not.
    #[test]
    fn view_names_past_80_columns_are_noted() {
        let source = include_str!("../../examples/single_bushing.axle");
        let (_, c) = crate::check::check_str("single_bushing.axle", source);
        let deck = emit_adm(&c.model.expect("the example checks")).expect("emits");
        assert!(
            deck.notes.iter().all(|n| !n.contains("80 columns")),
            "{:?}",
            deck.notes
        );
        let long = "a_trailing_arm_named_at_great_length_by_an_engineer_who_likes_words";
        let renamed = source.replace("arm", long);
        let (_, c) = crate::check::check_str("long.axle", &renamed);
        let deck = emit_adm(&c.model.expect("the renamed example checks")).expect("emits");
        let note = deck
            .notes
            .iter()
            .find(|n| n.contains("80 columns"))
            .expect("a note on the long names");
        // Every long line is a view-name comment, and every one is counted.
        let count: usize = note.split(' ').next().unwrap().parse().unwrap();
        let lines = deck.text.lines().filter(|l| l.len() > MAX_LINE).count();
        assert_eq!(count, lines, "{note}");
        assert!(note.contains(long), "{note}");
    }
}
