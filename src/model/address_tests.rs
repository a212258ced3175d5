//! Addresses: every field of a model reads, writes and names itself.

use super::*;
use crate::model::schema::FieldId;

fn model() -> Model {
    let src = "param kz = 1000 N/mm\nparam zt = 100 mm\nground g {\n    marker o at (0, 0, 0) mm\n    marker s at (0, 0, 200) mm\n}\npart p {\n    marker o at (0, 0, 0) mm\n    marker t at (0 mm, 0 mm, zt)\n    landmark m1 at (1, 2, 3) mm\n}\nbushing b {\n    i g.o\n    j p.o\n    k (1000 N/mm, 2000 N/mm, kz)\n    kt (1, 2, 3) N*mm/deg\n    k3 (0, 0, 2) N/mm^3\n    offset (0, 0, 1.5) mm\n}\nbushing r {\n    i g.s\n    j p.t\n    k_radial 500 N/mm\n    k_axial 50 N/mm\n    kt (1, 1, 1) N*mm/deg\n}\nspring s {\n    i g.o\n    j p.t\n    k 30 N/mm\n    free_length 290 mm\n}\nstop bump compression {\n    i g.s\n    j p.t\n    contact_length 90 mm\n    poly [500 N/mm, 20 N/mm^2]\n}\n";
    let (_, c) = crate::check::check_str("t.axle", src);
    c.model.unwrap_or_else(|| panic!("{:?}", c.problems))
}

#[test]
fn addresses_resolve_read_and_write() {
    let mut m = model();
    let a = Address::parse(&m, "b.k_y").expect("bushing field");
    assert_eq!(a.get(&m), 2000.0);
    a.set(&mut m, 2500.0);
    assert_eq!(a.get(&m), 2500.0);
    assert_eq!(a.name(&m), "b.k_y");
    let kt = Address::parse(&m, "b.kt_z").expect("rotational");
    assert!((kt.get(&m) - 3.0 / crate::units::DEG).abs() < 1e-9);
    assert_eq!(kt.unit(&m), "N*mm/deg");
    let l0 = Address::parse(&m, "s.free_length").expect("spring");
    assert_eq!(l0.get(&m), 290.0);
    assert_eq!(l0.dim(&m), Dim::LENGTH);
    let k3 = Address::parse(&m, "b.k3_z").expect("cubic");
    assert_eq!((k3.get(&m), k3.dim(&m)), (2.0, Dim::new(-3, 1, 0)));
    let off = Address::parse(&m, "b.offset_z").expect("offset");
    assert_eq!(off.get(&m), 1.5);
    let c2 = Address::parse(&m, "bump.poly_2").expect("stop coefficient");
    assert_eq!((c2.get(&m), c2.dim(&m)), (20.0, Dim::new(-2, 1, 0)));
    assert_eq!(
        Address::parse(&m, "bump.k").expect("degree 1").get(&m),
        500.0
    );
    let cl = Address::parse(&m, "bump.contact_length").expect("contact");
    cl.set(&mut m, 95.0);
    assert_eq!(m.stops[0].contact_length.value, 95.0);
    let lm = Address::parse(&m, "p.m1.y").expect("landmark");
    assert_eq!((lm.get(&m), lm.name(&m)), (2.0, "p.m1.y".to_string()));
}

#[test]
fn an_axisymmetric_radial_law_is_one_number() {
    let mut m = model();
    let x = Address::parse(&m, "r.k_x").expect("x");
    let y = Address::parse(&m, "r.k_y").expect("y");
    let radial = Address::parse(&m, "r.k_radial").expect("radial");
    assert_eq!(x.canonical(&m), y.canonical(&m));
    assert_eq!(radial, x);
    y.set(&mut m, 700.0);
    assert_eq!((x.get(&m), y.get(&m)), (700.0, 700.0));
    assert_eq!(
        Address::parse(&m, "r.k_axial").expect("axial").get(&m),
        50.0
    );
    // A general bushing has no radial law to name.
    assert!(matches!(
        Address::parse(&m, "b.k_radial"),
        Err(AddressError::UnknownField { .. })
    ));
}

#[test]
fn a_bound_field_sets_its_parameter_and_reports_the_binding() {
    let mut m = model();
    let a = Address::parse(&m, "b.k_z").expect("bound field");
    let kz = m.param_named("kz");
    assert_eq!(a.binding(&m), kz);
    assert_eq!(Address::parse(&m, "b.k_x").expect("free").binding(&m), None);
    a.set(&mut m, 1500.0);
    assert_eq!(m.params[0].value, 1500.0);
    assert_eq!(Address::parse(&m, "kz").expect("param").get(&m), 1500.0);
}

#[test]
fn points_move_on_one_part_or_both_keeping_bindings() {
    let mut m = model();
    // The bushing point `r.z` moves g.s and p.t; p.t's z is written as `zt`.
    let both = Address::parse(&m, "r.z").expect("bushing point");
    both.set(&mut m, 120.0);
    let zt = m.param_named("zt").expect("zt");
    assert_eq!(m.params[zt.index()].value, 120.0, "the binding is kept");
    let gs = m.marker_named(m.part_named("g").unwrap(), "s").unwrap();
    assert_eq!(m.marker(gs).position[2].value, 120.0);
    // `g.r.x`: the bushing's marker on part g only.
    let one = Address::parse(&m, "g.r.x").expect("point on one part");
    assert_eq!(one.element, ElementId::Marker(gs));
    one.set(&mut m, 4.0);
    let pt = m.marker_named(m.part_named("p").unwrap(), "t").unwrap();
    assert_eq!(
        (
            m.marker(gs).position[0].value,
            m.marker(pt).position[0].value
        ),
        (4.0, 0.0)
    );
}

#[test]
fn every_address_of_a_model_round_trips_through_its_name() {
    let m = model();
    let all = Address::all(&m);
    // 2 params, 4 markers x 3, 1 landmark x 3, bushing b (k 3, kt 3, k3 3,
    // kt3 3, offsets/preloads 12, point 3 = 27), bushing r (radial once: 2 + 3
    // + 2 + 3 + 12 + 3 = 25), spring 3, stop 1 + 2.
    assert_eq!(all.len(), 2 + 12 + 3 + 27 + 25 + 3 + 3, "{all:?}");
    for a in all {
        let name = a.name(&m);
        assert_eq!(Address::parse(&m, &name), Ok(a), "{name}");
        assert!(a.get(&m).is_finite(), "{name}");
    }
    assert!(Address::all(&m).iter().any(|a| a.field == FieldId::Kt3));
}

#[test]
fn unknown_names_say_what_exists() {
    let m = model();
    match Address::parse(&m, "nope.k") {
        Err(AddressError::UnknownElement { name, candidates }) => {
            assert_eq!(name, "nope");
            assert!(candidates.contains(&"bump".to_string()));
        }
        other => panic!("{other:?}"),
    }
    match Address::parse(&m, "b.k_w") {
        Err(AddressError::UnknownField { fields, .. }) => {
            assert!(fields.contains(&"k_x".to_string()));
            assert!(fields.contains(&"torque_preload_z".to_string()));
        }
        other => panic!("{other:?}"),
    }
    let d = Address::parse(&m, "s.free_lenght")
        .unwrap_err()
        .to_diagnostic("--trim", "s.free_lenght");
    assert_eq!(d.code, "E0803");
    assert_eq!(d.hint.as_deref(), Some("did you mean `free_length`?"));
}

/// The front axle's qualified names (issue 13): every number of an instance
/// is addressed by its qualified name (`front_right.B.k_x`,
/// `front_left.upright.WC.x`, `chassis.front_left.B.y`) and round-trips.
#[test]
fn every_address_of_the_front_axle_round_trips_with_qualified_names() {
    let (_, c) = crate::check::check_str(
        "front_axle.axle",
        include_str!("../../examples/front_axle.axle"),
    );
    let m = c.model.expect("checks");
    let all = Address::all(&m);
    assert!(all.len() > 300, "{}", all.len());
    for a in &all {
        let name = a.name(&m);
        assert_eq!(Address::parse(&m, &name), Ok(*a), "{name}");
    }
    for name in [
        "front_right.B.k_x",
        "front_left.upright.WC.x",
        "chassis.front_left.B.y",
        "bar.torsion.kt_y",
    ] {
        let a = Address::parse(&m, name).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(a.name(&m), name);
    }
    assert_eq!(
        Address::parse(&m, "front_right.B.k_x").map(|a| a.get(&m)),
        Ok(310.0)
    );
    // A misspelt marker of a qualified part names the part.
    match Address::parse(&m, "front_left.upright.WX.x") {
        Err(AddressError::UnknownPoint { part, .. }) => assert_eq!(part, "front_left.upright"),
        other => panic!("{other:?}"),
    }
}
