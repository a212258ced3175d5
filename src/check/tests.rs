//! The checker turns written values into the model's internal units and frames:
//! ZXZ Euler angles and directions to rotation matrices (including the singular
//! θ = 0° and 180°), rotation matrices back to Euler angles, unit conversions,
//! shorthands and defaults. Expectations are closed forms, not the code under test.

use super::check_str;
use crate::geom::{Mat3, matrix_to_zxz};
use crate::model::{AxisLaw, Model, SpringLaw, StopLaw};
use std::f64::consts::PI;

const DEG: f64 = PI / 180.0;

fn model(body: &str) -> Model {
    // A part must be held: bodies without a bushing get one on `arm.o`.
    let hold = "\nbushing hold {\n    i g.o\n    j arm.o\n    k (1, 1, 1) N/mm\n    kt (1, 1, 1) N*mm/deg\n}\n";
    let body = if body.contains("bushing") {
        body.to_string()
    } else {
        format!("{body}{hold}")
    };
    let text = format!(
        "ground g {{\n    marker o at (0, 0, 0) mm\n    marker s at (0, 0, 400) mm\n}}\n\n{body}"
    );
    let (sources, checked) = check_str("t.axle", &text);
    let errors: Vec<String> = checked
        .problems
        .list
        .iter()
        .filter(|d| d.severity == crate::diagnostic::Severity::Error)
        .map(|d| crate::diagnostic::render::to_string(&sources, d))
        .collect();
    assert!(errors.is_empty(), "{}", errors.join("\n"));
    checked.model.expect("a model")
}

fn rotation(m: &Model, part: &str, marker: &str) -> Mat3 {
    let p = m.part_named(part).expect("part");
    m.marker(m.marker_named(p, marker).expect("marker"))
        .rotation
}

fn close(a: &Mat3, b: &Mat3) -> bool {
    (a - b).abs().max() < 1e-12
}

fn rz(a: f64) -> Mat3 {
    let (s, c) = a.sin_cos();
    Mat3::new(c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0)
}

fn linear_k(law: &AxisLaw) -> (f64, f64) {
    match law {
        AxisLaw::Linear { k, k3 } => (k.value, k3.value),
        AxisLaw::Table(_) => panic!("expected a linear law"),
    }
}

const ARM: &str = "bushing b {\n    i g.o\n    j arm.o\n";

#[test]
fn euler_angles_give_the_closed_form_rotation() {
    let m = model(
        "part arm {\n    marker o at (0, 0, 0) mm\n    marker a at (0, 0, 0) mm euler (30, 0, 20) deg\n    marker b at (0, 0, 0) mm euler (30, 180, 20) deg\n    marker f at (0, 0, 0) mm euler (141.5, 166.7, 53.68) deg\n}\n",
    );
    // θ = 0: a rotation about z by ψ + φ.
    assert!(close(&rotation(&m, "arm", "a"), &rz(50.0 * DEG)));
    // θ = 180°: Rz(ψ) diag(1, -1, -1) Rz(φ) = [[c, s, 0], [s, -c, 0], [0, 0, -1]] of ψ - φ.
    let (s, c) = (10.0 * DEG).sin_cos();
    let flip = Mat3::new(c, s, 0.0, s, -c, 0.0, 0.0, 0.0, -1.0);
    assert!(close(&rotation(&m, "arm", "b"), &flip));
    // Generic: the z axis is (sin ψ sin θ, -cos ψ sin θ, cos θ).
    let r = rotation(&m, "arm", "f");
    let (psi, theta) = (141.5 * DEG, 166.7 * DEG);
    let z = [
        psi.sin() * theta.sin(),
        -psi.cos() * theta.sin(),
        theta.cos(),
    ];
    for k in 0..3 {
        assert!((r[(k, 2)] - z[k]).abs() < 1e-12);
    }
}

#[test]
fn rotations_give_back_euler_angles_including_the_singular_ones() {
    // θ = 0 and 180°: only ψ ± φ is defined; it goes to ψ, with φ = 0.
    let (psi, theta, phi) = matrix_to_zxz(&rz(50.0 * DEG));
    assert!((psi - 50.0 * DEG).abs() < 1e-12 && theta == 0.0 && phi == 0.0);
    let (s, c) = (10.0 * DEG).sin_cos();
    let flip = Mat3::new(c, s, 0.0, s, -c, 0.0, 0.0, 0.0, -1.0);
    let (psi, theta, phi) = matrix_to_zxz(&flip);
    assert!((psi - 10.0 * DEG).abs() < 1e-12);
    assert!((theta - PI).abs() < 1e-12 && phi == 0.0);
    // Generic angles from the McPherson's strut mount come back unchanged.
    let m = model(
        "part arm {\n    marker o at (0, 0, 0) mm\n    marker f at (0, 0, 0) mm euler (141.5, 166.7, 53.68) deg\n}\n",
    );
    let (psi, theta, phi) = matrix_to_zxz(&rotation(&m, "arm", "f"));
    assert!((psi / DEG - 141.5).abs() < 1e-9);
    assert!((theta / DEG - 166.7).abs() < 1e-9);
    assert!((phi / DEG - 53.68).abs() < 1e-9);
}

#[test]
fn directions_give_orthonormal_frames() {
    let m = model(
        "part arm {\n    marker o at (0, 0, 0) mm\n    marker t at (0, 0, 0) mm z (2, 0, 0) x (1, 5, 0)\n}\n",
    );
    // z along +x; the hint (1, 5, 0) made perpendicular to z is +y; y = z × x = +z.
    let want = Mat3::new(0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0);
    assert!(close(&rotation(&m, "arm", "t"), &want));
}

#[test]
fn units_convert_to_internal_units() {
    let m = model(&format!(
        "part arm {{\n    marker o at (0.1, 2 cm, 0.3 m) mm\n}}\n\n{ARM}    k_radial 13.875 kN/mm\n    k_axial 1370000 N/m\n    kt_radial 11000 N*mm/deg\n    kt_axial 4 N*m/deg\n    k3 (0, 0, 2) N/mm^3\n    angle_offset (0, 0, 2) deg\n}}\n"
    ));
    let p = m.part_named("arm").expect("arm");
    let o = m.marker(m.marker_named(p, "o").expect("o")).origin();
    assert!((o - crate::geom::Vec3::new(0.1, 20.0, 300.0)).norm() < 1e-12);
    let b = &m.bushings[0];
    // Radial sets x and y, axial sets z.
    assert_eq!(linear_k(&b.translational[0]), (13875.0, 0.0));
    assert_eq!(linear_k(&b.translational[1]), (13875.0, 0.0));
    let (kz, k3z) = linear_k(&b.translational[2]);
    assert!((kz - 1370.0).abs() < 1e-9 && (k3z - 2.0).abs() < 1e-12);
    // N·mm/deg → N·mm/rad: × 180/π (thesis Annexe F: 10000 N·mm/deg = 5.729577951e5).
    let (kt, _) = linear_k(&b.rotational[0]);
    assert!((kt - 11000.0 * 180.0 / PI).abs() < 1e-6);
    let (ktz, _) = linear_k(&b.rotational[2]);
    assert!((ktz - 4000.0 * 180.0 / PI).abs() < 1e-6);
    assert!((b.angle_offset[2].value - 2.0 * DEG).abs() < 1e-15);
}

#[test]
fn offsets_preloads_and_one_sided_laws_are_kept() {
    let m = model(&format!(
        "part arm {{\n    marker o at (0, 0, 0) mm\n    marker s at (0, 0, 250) mm\n}}\n\n{ARM}    k (1, 2, 3) N/mm\n    kt (4, 5, 6) N*mm/deg\n    offset (0, 0, 1.5) mm\n    preload (0, 0, 100) N\n    torque_preload (0, 0, 1000) N*mm\n}}\n\nspring coil {{\n    i g.s\n    j arm.o\n    k 30 N/mm\n    preload 4800 N\n}}\n\nstop bump compression {{\n    i g.s\n    j arm.s\n    contact_length 140 mm\n    law table (mm, kN) [(0, 0), (10, 0.5), (20, 2)]\n}}\n\nstop droop rebound {{\n    i g.o\n    j arm.s\n    contact_length 300 mm\n    poly [500 N/mm, 20 N/mm^2]\n}}\n"
    ));
    let b = &m.bushings[0];
    assert_eq!(b.offset[2].value, 1.5);
    assert_eq!(b.preload[2].value, 100.0);
    assert_eq!(b.torque_preload[2].value, 1000.0);
    // A spring with a preload and no free length: the preload acts at the design length (400 mm).
    match &m.springs[0].law {
        SpringLaw::Linear {
            k,
            free_length,
            preload,
        } => {
            assert_eq!((k.value, preload.value), (30.0, 4800.0));
            assert!((free_length.value - 400.0).abs() < 1e-12);
        }
        SpringLaw::Table(_) => panic!("linear spring"),
    }
    // kN converted in the table; penetration from contact on.
    match &m.stops[0].law {
        StopLaw::Table(t) => assert_eq!(t.points, vec![(0.0, 0.0), (10.0, 500.0), (20.0, 2000.0)]),
        StopLaw::Polynomial(_) => panic!("table stop"),
    }
    match &m.stops[1].law {
        StopLaw::Polynomial(c) => {
            assert_eq!(
                c.iter().map(|v| v.value).collect::<Vec<_>>(),
                vec![500.0, 20.0]
            )
        }
        StopLaw::Table(_) => panic!("polynomial stop"),
    }
    assert_eq!(m.stops[0].kind, crate::model::StopKind::Compression);
    assert_eq!(m.stops[1].kind, crate::model::StopKind::Rebound);
}

#[test]
fn unknown_parameters_keep_their_bounds_and_bind_elements() {
    let m = model(&format!(
        "param k_arm = 2 kN/mm unknown [500 N/mm, _]\n\npart arm {{\n    marker o at (0, 0, 0) mm\n}}\n\n{ARM}    k (k_arm, k_arm, 100 N/mm)\n    kt (4, 5, 6) N*mm/deg\n}}\n"
    ));
    let p = &m.params[0];
    assert_eq!(p.value, 2000.0);
    let b = p.unknown.expect("unknown");
    assert_eq!((b.lower, b.upper), (Some(500.0), None));
    match &m.bushings[0].translational[0] {
        AxisLaw::Linear { k, .. } => assert_eq!(k.param.map(|id| id.index()), Some(0)),
        AxisLaw::Table(_) => panic!("linear"),
    }
}

/// The E0105 diagnostics of `text`: (message, notes).
fn unknown_properties(text: &str) -> Vec<(String, Vec<String>)> {
    let (_, checked) = check_str("t.axle", text);
    checked
        .problems
        .list
        .iter()
        .filter(|d| d.code == "E0105")
        .map(|d| (d.message.clone(), d.notes.clone()))
        .collect()
}

/// A spring, stop or friction accepts exactly the keys of its kind's schema,
/// so a field added to the schema needs no second list in the checker: every
/// schema key is accepted, and the note of an unknown key lists the schema's.
#[test]
fn springs_stops_and_frictions_accept_exactly_their_schema_keys() {
    use crate::model::schema;
    use crate::syntax::ast::ElementKw;
    let head = "ground g {\n    marker o at (0, 0, 0) mm\n    marker s at (0, 0, 400) mm\n}\n\npart arm {\n    marker o at (0, 0, 0) mm\n}\n\njoint r revolute {\n    i g.o\n    j arm.o\n}\n\n";
    for (kw, decl, s) in [
        (ElementKw::Spring, "spring e {", &schema::SPRING),
        (ElementKw::Stop, "stop e compression {", &schema::STOP),
        (ElementKw::Friction, "friction e {", &schema::FRICTION),
    ] {
        let keys = s.keys();
        assert_eq!(super::properties(kw), keys, "{}", s.keyword);
        for key in &keys {
            let text = format!("{head}{decl}\n    {key} 1 mm\n}}\n");
            assert_eq!(unknown_properties(&text), vec![], "{} {key}", s.keyword);
        }
        let text = format!("{head}{decl}\n    no_such_key 1 mm\n}}\n");
        let found = unknown_properties(&text);
        assert_eq!(found.len(), 1, "{}", s.keyword);
        let note = format!("{} properties: {}", s.keyword, keys.join(", "));
        assert!(
            found[0].1.contains(&note),
            "{}: {:?}",
            s.keyword,
            found[0].1
        );
    }
    // The lists the diagnostics have always shown.
    assert_eq!(
        schema::SPRING.keys(),
        ["i", "j", "k", "free_length", "preload", "law"]
    );
    assert_eq!(
        schema::STOP.keys(),
        ["i", "j", "contact_length", "k", "poly", "law"]
    );
    assert_eq!(schema::FRICTION.keys(), ["joint", "kf", "limit", "motion"]);
}
