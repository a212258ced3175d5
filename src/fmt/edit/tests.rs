//! Edits against hand-written expectations: only the changed numbers move, in
//! the unit they were written in; everything else stays byte for byte.

use super::*;
use crate::units::Dim;

/// A bushing on a slider, written with comments in odd places, a parameter,
/// vectors, and units other than the internal ones.
const SRC: &str = "\
// top comment
model edits   // trailing

param k_ax = 1.37 kN/mm unknown [100 N/mm, 5 kN/mm] // the axial rate

ground chassis {
    marker B at (0.2947, 0.3651, 0.2461) m // metres on purpose
    marker S at (0, 0, 0) mm
}

part arm {
    // the arm's end
    marker B at (294.7, 365.1, 246.1) mm euler (0, 0, 0) deg
    marker S at (0, 0, 0) mm
}

bushing B {
    i chassis.B   // chassis side
    j arm.B
    k (310, 2400,   // odd line break
       180) N/mm
    kt_radial 4500 N*mm/deg
    kt_axial 1.6 N*m/deg
    k3 (0, 0, 0) N/mm^3
}

spring s {
    i chassis.S
    j arm.B
    k k_ax
    free_length 600 mm
}
";

fn checked(text: &str) -> Model {
    let (_, c) = crate::check::check_str("edits.axle", text);
    c.model.unwrap_or_else(|| panic!("{:#?}", c.problems.list))
}

fn edit(old: &Model, new: &Model) -> Result<Edited, EditError> {
    let req = Request {
        tool: "test",
        reasons: &[],
    };
    edit_source(FileId(0), "edits.axle", SRC, old, new, &req)
}

/// The lines of `b` that differ from `a`'s (same line count assumed).
fn changed_lines(a: &str, b: &str) -> Vec<(String, String)> {
    a.lines()
        .zip(b.lines())
        .filter(|(x, y)| x != y)
        .map(|(x, y)| (x.to_string(), y.to_string()))
        .collect()
}

#[test]
fn an_unchanged_model_gives_back_the_same_bytes() {
    let m = checked(SRC);
    assert_eq!(edit(&m, &m).unwrap().text, SRC);
}

#[test]
fn changed_values_are_rewritten_in_their_own_units_and_nothing_else_moves() {
    let old = checked(SRC);
    let mut new = old.clone();
    // 2500 N/mm on the bushing's y axis; the kt axial law 2 N*m/deg.
    let AxisLaw::Linear { k, .. } = &mut new.bushings[0].translational[1] else {
        panic!()
    };
    k.value = 2500.0;
    let kt = 2.0 * Dim::ROT_STIFFNESS.boundary_factor() * 1000.0;
    let AxisLaw::Linear { k, .. } = &mut new.bushings[0].rotational[2] else {
        panic!()
    };
    k.value = kt;
    // The parameter: 1.5 kN/mm, written back in kN/mm on its own line.
    new.set_param(ParamId(0), 1500.0);
    // The chassis marker 10 mm up: written back in metres.
    new.markers[0].position[2].value += 10.0;
    let out = edit(&old, &new).unwrap();
    assert_eq!(
        changed_lines(SRC, &out.text),
        [
            (
                "param k_ax = 1.37 kN/mm unknown [100 N/mm, 5 kN/mm] // the axial rate",
                "param k_ax = 1.5 kN/mm unknown [100 N/mm, 5 kN/mm] // the axial rate"
            ),
            (
                "    marker B at (0.2947, 0.3651, 0.2461) m // metres on purpose",
                "    marker B at (0.2947, 0.3651, 0.2561) m // metres on purpose"
            ),
            (
                "    k (310, 2400,   // odd line break",
                "    k (310, 2500,   // odd line break"
            ),
            ("    kt_axial 1.6 N*m/deg", "    kt_axial 2 N*m/deg"),
        ]
        .map(|(a, b)| (a.to_string(), b.to_string()))
    );
    assert_eq!(out.changes.len(), 4);
}

#[test]
fn an_axisymmetric_rate_written_once_is_rewritten_once() {
    let old = checked(SRC);
    let mut new = old.clone();
    // x and y are one stored radial law (a split is unrepresentable).
    let AxisLaw::Linear { k, .. } = &mut new.bushings[0].rotational[1] else {
        panic!()
    };
    k.value *= 2.0;
    assert_eq!(new.bushings[0].rotational[0], new.bushings[0].rotational[1]);
    let out = edit(&old, &new).unwrap();
    assert!(
        out.text.contains("    kt_radial 9000 N*mm/deg\n"),
        "{}",
        out.text
    );
}

#[test]
fn a_field_not_written_reprints_its_element_keeping_the_comments_inside() {
    let old = checked(SRC);
    let mut new = old.clone();
    // The spring's preload was not written: the block is printed again.
    let SpringLaw::Linear { preload, .. } = &mut new.springs[0].law else {
        panic!()
    };
    preload.value = 50.0;
    let out = edit(&old, &new).unwrap();
    assert!(
        out.text.contains(
            "spring s {\n    i chassis.S\n    j arm.B\n    k k_ax\n    free_length 600 mm\n    preload 50 N\n}\n"
        ),
        "{}",
        out.text
    );
    assert_eq!(
        out.changes,
        [Change::Reprinted {
            element: ElementId::Spring(SpringId(0))
        }]
    );
    // A marker whose frame changes form is restated on its line, comment kept above.
    let mut new = old.clone();
    let (z, x) = (
        crate::geom::Vec3::new(1.0, 0.0, 0.0),
        crate::geom::Vec3::new(0.0, 1.0, 0.0),
    );
    new.markers[2].rotation = crate::geom::frame_from_z_x(z, Some(x)).unwrap();
    new.markers[2].orientation = Orientation::Directions { z, x: Some(x) };
    let out = edit(&old, &new).unwrap();
    assert!(
        out.text.contains("    // the arm's end\n    marker B at (294.7, 365.1, 246.1) mm z (1, 0, 0) x (0, 1, 0)\n"),
        "{}",
        out.text
    );
}

#[test]
fn new_elements_are_appended_with_the_reason_and_markers_go_into_their_part() {
    let old = checked(SRC);
    let mut new = old.clone();
    let mut mk = new.markers[3].clone();
    mk.name = "T".into();
    new.markers.push(mk);
    new.stops.push(Stop {
        name: "bump".into(),
        kind: StopKind::Compression,
        i: MarkerId(0),
        j: MarkerId(4),
        contact_length: Val::lit(40.0),
        law: StopLaw::Polynomial(vec![Val::lit(500.0)]),
    });
    let req = Request {
        tool: "diagnose",
        reasons: &[(
            ElementId::Stop(StopId(0)),
            "the bump curve stiffens after 40 mm".into(),
        )],
    };
    let out = edit_source(FileId(0), "edits.axle", SRC, &old, &new, &req).unwrap();
    let expected_tail = "\n// added by diagnose: the bump curve stiffens after 40 mm\nstop bump compression {\n    i chassis.B\n    j arm.T\n    contact_length 40 mm\n    k 500 N/mm\n}\n";
    assert!(
        out.text.ends_with(&format!("}}\n{expected_tail}")),
        "{}",
        out.text
    );
    assert!(
        out.text.contains("    marker S at (0, 0, 0) mm\n    // added by diagnose\n    marker T at (0, 0, 0) mm\n}"),
        "{}",
        out.text
    );
}

#[test]
fn removing_an_element_is_refused_with_a_diagnostic() {
    let old = checked(SRC);
    let mut new = old.clone();
    new.springs.clear();
    let d = edit(&old, &new).unwrap_err().to_diagnostic();
    assert_eq!(d.code, "E1201");
}

#[test]
fn refusals_render_with_the_place_in_the_file() {
    let (sources, c) = crate::check::check_str("edits.axle", SRC);
    let old = c.model.expect("checks");
    // (kt_radial asked to hold two values is unrepresentable since the
    // radial law is stored once.)
    let mut removed = old.clone();
    removed.springs.clear();
    let unsupported = edit(&old, &removed).unwrap_err().to_diagnostic();
    let text: String = [unsupported]
        .iter()
        .map(|d| crate::diagnostic::render::to_string(&sources, d))
        .collect();
    insta::assert_snapshot!(text);
}
