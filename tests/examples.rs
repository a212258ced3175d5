//! Every example and stdlib module checks clean, is a formatter fixed point, and
//! prints back (model → source) to a model that prints the same.

use axle::check::check_str;
use axle::diagnostic::render;

/// Warnings an example is written to show (benchmarks.md: the slider-crank's
/// constraint set contains a redundancy to detect).
const EXPECTED_WARNINGS: &[(&str, &str)] = &[("slider_crank.axle", "W0601")];

fn check_clean(path: &std::path::Path) -> (String, axle::model::Model) {
    let text = std::fs::read_to_string(path).expect("readable");
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let (sources, checked) = check_str(&name, &text);
    let rendered: String = checked
        .problems
        .list
        .iter()
        .map(|d| render::to_string(&sources, d))
        .collect();
    let codes: Vec<&str> = checked.problems.list.iter().map(|d| d.code).collect();
    let expected: Vec<&str> = EXPECTED_WARNINGS
        .iter()
        .filter(|(f, _)| *f == name)
        .map(|(_, c)| *c)
        .collect();
    assert_eq!(codes, expected, "{name} diagnostics:\n{rendered}");
    (text, checked.model.expect("no errors means a model"))
}

fn each(dir: &str, f: impl Fn(&std::path::Path)) {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(dir);
    let mut paths: Vec<_> = std::fs::read_dir(&root)
        .expect("directory exists")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "axle"))
        .collect();
    paths.sort();
    assert!(!paths.is_empty(), "no .axle files in {dir}");
    for p in paths {
        f(&p);
    }
}

#[test]
fn examples_and_stdlib_check_clean() {
    each("examples", |p| {
        check_clean(p);
    });
    each("stdlib", |p| {
        check_clean(p);
    });
}

#[test]
fn examples_and_stdlib_are_formatter_fixed_points() {
    for dir in ["examples", "stdlib"] {
        each(dir, |p| {
            let text = std::fs::read_to_string(p).expect("readable");
            let formatted = axle::fmt::format_source(axle::span::FileId(0), &text).expect("parses");
            assert_eq!(
                formatted,
                text,
                "{} is not in canonical format (run `axle fmt`)",
                p.display()
            );
        });
    }
}

#[test]
fn printed_models_check_and_print_the_same() {
    each("examples", |p| {
        let (_, model) = check_clean(p);
        let printed = axle::fmt::print_model(&model);
        let (sources, again) = check_str("printed.axle", &printed);
        let rendered: String = again
            .problems
            .list
            .iter()
            .map(|d| render::to_string(&sources, d))
            .collect();
        let again = again.model.unwrap_or_else(|| {
            panic!(
                "{}: printed model does not check:\n{rendered}\n{printed}",
                p.display()
            )
        });
        assert_eq!(axle::fmt::print_model(&again), printed, "{}", p.display());
        // Same elements and the same numbers (to printing precision).
        assert_eq!(again.markers.len(), model.markers.len());
        assert_eq!(again.bushings.len(), model.bushings.len());
        for (a, b) in again.markers.iter().zip(&model.markers) {
            assert!((a.origin() - b.origin()).norm() < 1e-9);
            assert!(
                (a.rotation - b.rotation).abs().max() < 1e-9,
                "{} {}",
                p.display(),
                a.name
            );
        }
        for (a, b) in again.load_sets.iter().zip(&model.load_sets) {
            assert_eq!(a.cases.len(), b.cases.len());
            for (x, y) in a.cases.iter().zip(&b.cases) {
                assert_eq!(x.name, y.name);
                for (u, v) in x.values.iter().zip(&y.values) {
                    assert!((u - v).abs() < 1e-9);
                }
            }
        }
    });
}

// ---------------------------------------------------------------------------
// The benchmark examples carry exactly the numbers of spec/benchmarks.md. The
// expected values below are copied from that page (ISO 8855 frame, mm, deg,
// N/mm, N·mm/deg), not read from the examples.
// ---------------------------------------------------------------------------

use axle::model::{AxisLaw, AxisLaws, Component, JointKind, LoadTarget, Model, SpringLaw};

const DEG: f64 = std::f64::consts::PI / 180.0;

fn example(name: &str) -> Model {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("examples")
        .join(name);
    check_clean(&path).1
}

fn marker<'a>(m: &'a Model, path: &str) -> &'a axle::model::Marker {
    let (part, name) = path.split_once('.').expect("part.marker");
    let p = m.part_named(part).unwrap_or_else(|| panic!("part {part}"));
    m.marker(
        m.marker_named(p, name)
            .unwrap_or_else(|| panic!("marker {path}")),
    )
}

fn assert_at(m: &Model, path: &str, at: [f64; 3]) {
    let o = marker(m, path).origin();
    for k in 0..3 {
        assert!((o[k] - at[k]).abs() < 1e-9, "{path}: {o:?} vs {at:?}");
    }
}

fn assert_euler(m: &Model, path: &str, e: [f64; 3]) {
    let r = marker(m, path).rotation;
    let want = axle::geom::euler_zxz(e[0] * DEG, e[1] * DEG, e[2] * DEG);
    assert!((r - want).abs().max() < 1e-12, "{path} orientation");
}

fn linear(laws: &AxisLaws) -> [f64; 3] {
    laws.to_three().map(|l| match l {
        AxisLaw::Linear { k, k3 } => {
            assert_eq!(k3.value, 0.0);
            k.value
        }
        AxisLaw::Table(_) => panic!("a linear law"),
    })
}

/// A bushing's parts, k (N/mm) and kt (N·mm/deg).
fn assert_bushing(m: &Model, name: &str, i: &str, j: &str, k: [f64; 3], kt: [f64; 3]) {
    let b = m.bushings.iter().find(|b| b.name == name).expect(name);
    assert_eq!(m.marker_path(b.i), i, "{name}.i");
    assert_eq!(m.marker_path(b.j), j, "{name}.j");
    assert_eq!(linear(&b.translational), k, "{name}.k");
    let kt_deg = linear(&b.rotational).map(|v| v * DEG);
    for a in 0..3 {
        assert!((kt_deg[a] - kt[a]).abs() < 1e-9, "{name}.kt {kt_deg:?}");
    }
}

fn assert_joint(m: &Model, name: &str, kind: JointKind, i: &str, j: &str) {
    let jt = m.joints.iter().find(|x| x.name == name).expect(name);
    assert_eq!(jt.kind, kind, "{name}");
    assert_eq!(m.marker_path(jt.i), i, "{name}.i");
    assert_eq!(m.marker_path(jt.j), j, "{name}.j");
}

/// The cases of a load set as rows of (fx, fy, fz) at the wheel.
fn wheel_rows(m: &Model, set: &str) -> Vec<[f64; 3]> {
    let s = &m.load_sets[m.load_set_named(set).expect(set).index()];
    s.cases
        .iter()
        .map(|c| {
            let mut row = [0.0; 3];
            for (ch, v) in s.channels.iter().zip(&c.values) {
                assert!(
                    matches!(ch.target, LoadTarget::Wheel(_)),
                    "{set}: wheel loads"
                );
                match ch.component {
                    Component::Fx => row[0] = *v,
                    Component::Fy => row[1] = *v,
                    Component::Fz => row[2] = *v,
                    _ => panic!("{set}: forces only"),
                }
            }
            row
        })
        .collect()
}

#[test]
fn mcpherson_has_the_numbers_of_benchmarks_md() {
    let m = example("mcpherson.axle");
    assert_eq!(m.part(m.ground().expect("ground")).name, "chassis");
    let moving: Vec<&str> = m.moving_parts().map(|p| m.part(p).name.as_str()).collect();
    assert_eq!(
        moving,
        ["front_arm", "rear_arm", "tie_rod", "strut", "upright"]
    );
    // Hardpoints, with every marker written at the point on both of its parts.
    let points: &[(&[&str], [f64; 3])] = &[
        (&["chassis.B", "front_arm.B"], [294.7, 365.1, 246.1]),
        (&["chassis.A", "rear_arm.A"], [-61.1, 383.5, 186.2]),
        (&["chassis.L3", "tie_rod.L3"], [73.7, 353.4, 228.3]),
        (&["chassis.F", "strut.F"], [-73.7, 594.7, 762.6]),
        (&["strut.L5", "upright.L5"], [-63.1, 617.8, 635.1]),
        (&["tie_rod.L6", "upright.L6"], [135.3, 694.6, 207.4]),
        (&["rear_arm.L7", "upright.L7"], [-5.87, 679.9, 164.8]),
        (&["front_arm.L8", "upright.L8"], [25.5, 691.2, 233.0]),
        (&["upright.WC"], [0.0, 787.0, 305.0]),
        (&["upright.CP"], [0.0, 787.0, 0.0]),
    ];
    for (paths, at) in points {
        for p in *paths {
            assert_at(&m, p, *at);
        }
    }
    let eulers: &[(&[&str], [f64; 3])] = &[
        (&["chassis.B", "front_arm.B"], [309.5, 90.22, 181.7]),
        (&["chassis.A", "rear_arm.A"], [259.58, 90.24, 4.11]),
        (&["chassis.F", "strut.F"], [141.5, 166.7, 53.68]),
        (&["strut.L5", "upright.L5"], [151.16, 168.1, 0.0]),
        (&["upright.WC"], [179.74, 90.69, 0.0]),
    ];
    for (paths, e) in eulers {
        for p in *paths {
            assert_euler(&m, p, *e);
        }
    }
    // Universal L3: J (chassis) z = global z; I (tie rod) z = normalize((L6 - L3) × z).
    let zj = marker(&m, "chassis.L3").rotation.column(2).into_owned();
    assert!((zj - axle::geom::Vec3::z()).norm() < 1e-12);
    let l6_l3 = axle::geom::Vec3::new(135.3 - 73.7, 694.6 - 353.4, 207.4 - 228.3);
    let zi_want = l6_l3.cross(&axle::geom::Vec3::z()).normalize();
    let zi = marker(&m, "tie_rod.L3").rotation.column(2).into_owned();
    assert!((zi - zi_want).norm() < 1e-12, "{zi:?} vs {zi_want:?}");
    assert_bushing(
        &m,
        "B",
        "chassis.B",
        "front_arm.B",
        [310.0, 2400.0, 180.0],
        [4500.0, 1100.0, 1600.0],
    );
    assert_bushing(
        &m,
        "A",
        "chassis.A",
        "rear_arm.A",
        [13875.0, 13875.0, 1370.0],
        [11000.0, 11000.0, 4000.0],
    );
    assert_bushing(
        &m,
        "F",
        "strut.F",
        "chassis.F",
        [1285.0, 1285.0, 647.0],
        [5500.0, 5500.0, 1000.0],
    );
    assert_eq!(m.bushings.len(), 3);
    assert_joint(&m, "L3", JointKind::Universal, "tie_rod.L3", "chassis.L3");
    assert_joint(&m, "L5", JointKind::Cylindrical, "strut.L5", "upright.L5");
    assert_joint(&m, "L6", JointKind::Spherical, "tie_rod.L6", "upright.L6");
    assert_joint(&m, "L7", JointKind::Spherical, "rear_arm.L7", "upright.L7");
    assert_joint(&m, "L8", JointKind::Spherical, "front_arm.L8", "upright.L8");
    assert_eq!(m.joints.len(), 5);
    // Spring chassis.F → upright.L5, 30 N/mm, L0 = 290 mm, 130.0 mm long at design.
    assert_eq!(m.springs.len(), 1);
    let s = &m.springs[0];
    assert_eq!(
        (m.marker_path(s.i).as_str(), m.marker_path(s.j).as_str()),
        ("chassis.F", "upright.L5")
    );
    match &s.law {
        SpringLaw::Linear {
            k,
            free_length,
            preload,
        } => {
            assert_eq!(
                (k.value, free_length.value, preload.value),
                (30.0, 290.0, 0.0)
            );
        }
        SpringLaw::Table(_) => panic!("linear spring"),
    }
    let length = (m.marker(s.i).origin() - m.marker(s.j).origin()).norm();
    assert!((length - 130.0).abs() < 0.05, "spring length {length}");
    assert!(
        m.stops.is_empty(),
        "no bump or rebound stops in the nominal model"
    );
    // Wheel `left` on the upright: toe +0.26° (toe-in), camber +0.69° at design (conventions.md).
    assert_eq!(m.wheels.len(), 1);
    let w = &m.wheels[0];
    assert_eq!(w.name, "left");
    assert_eq!(m.part(w.part).name, "upright");
    assert_eq!(
        (
            m.marker_path(w.centre).as_str(),
            m.marker_path(w.contact).as_str()
        ),
        ("upright.WC", "upright.CP")
    );
    let sp = m.marker(w.centre).rotation.column(2).into_owned();
    let camber = (-sp.z).asin() / DEG;
    let h = sp.cross(&axle::geom::Vec3::z()).normalize(); // left wheel
    let toe = -h.y.atan2(h.x) / DEG;
    assert!((camber - 0.69).abs() < 0.005, "camber {camber}");
    assert!((toe - 0.26).abs() < 0.005, "toe {toe}");
    // Landmarks m1..m4 of each measured part, in order; the strut carries none.
    let landmarks: &[(&str, [[f64; 3]; 4])] = &[
        (
            "chassis",
            [
                [310.0, 330.0, 270.0],
                [-80.0, 350.0, 205.0],
                [60.0, 320.0, 300.0],
                [-95.0, 560.0, 790.0],
            ],
        ),
        (
            "front_arm",
            [
                [256.9, 432.9, 249.7],
                [177.6, 492.8, 229.7],
                [127.6, 594.2, 229.3],
                [53.7, 638.1, 244.8],
            ],
        ),
        (
            "rear_arm",
            [
                [-59.9, 450.2, 174.5],
                [-23.9, 512.2, 185.8],
                [-29.6, 596.2, 183.0],
                [3.2, 641.1, 162.4],
            ],
        ),
        (
            "tie_rod",
            [
                [91.5, 406.9, 229.9],
                [91.7, 487.0, 211.2],
                [124.2, 565.8, 208.1],
                [116.7, 642.0, 217.7],
            ],
        ),
        (
            "upright",
            [
                [62.0, 749.0, 234.0],
                [-48.0, 758.0, 209.0],
                [35.0, 732.0, 426.0],
                [-81.0, 746.0, 363.0],
            ],
        ),
    ];
    for (part, pts) in landmarks {
        let p = m.part_named(part).expect(part);
        let got: Vec<(String, [f64; 3])> = m
            .landmarks
            .iter()
            .filter(|l| l.part == p)
            .map(|l| (l.name.clone(), l.position.map(|v| v.value)))
            .collect();
        let want: Vec<(String, [f64; 3])> = pts
            .iter()
            .enumerate()
            .map(|(n, x)| (format!("m{}", n + 1), *x))
            .collect();
        assert_eq!(got, want, "landmarks of {part}");
    }
    let strut = m.part_named("strut").expect("strut");
    assert!(m.landmarks.iter().all(|l| l.part != strut));
}

#[test]
fn stdlib_load_sets_have_the_numbers_of_benchmarks_md() {
    // The McPherson imports the stdlib sets, resolved to its wheel.
    let m = example("mcpherson.axle");
    let fz = |v: f64| [0.0, 0.0, v];
    let mut t44: Vec<[f64; 3]> = [1500.0, 3000.0, 4500.0, 6000.0, 7500.0].map(fz).to_vec();
    let pairs = [
        (4500.0, -1000.0),
        (4500.0, 1000.0),
        (3000.0, -1000.0),
        (3000.0, 1000.0),
        (6000.0, -1000.0),
        (6000.0, 1000.0),
    ];
    t44.extend(pairs.iter().map(|&(z, y)| [0.0, y, z]));
    t44.extend(pairs.iter().map(|&(z, x)| [x, 0.0, z]));
    assert_eq!(wheel_rows(&m, "thesis_table_4_4"), t44);
    let mut t51: Vec<[f64; 3]> = [1500.0, 3000.0, 4500.0, 6000.0, 7500.0].map(fz).to_vec();
    let side = [-4000.0, -2000.0, 2000.0, 4000.0];
    t51.extend(side.iter().map(|&y| [0.0, y, 4500.0]));
    t51.extend(side.iter().map(|&x| [x, 0.0, 4500.0]));
    assert_eq!(wheel_rows(&m, "thesis_table_5_1"), t51);
    // Sweeps in 250 N steps: bump fz 1000 → 8000 → 1000; lateral/longitudinal at
    // fz 4500 through 0 → 4000 → -4000 → 0.
    let path = |points: &[f64]| -> Vec<f64> {
        let mut v = vec![points[0]];
        for w in points.windows(2) {
            let n = ((w[1] - w[0]).abs() / 250.0).round() as i32;
            for k in 1..=n {
                v.push(w[0] + (w[1] - w[0]).signum() * 250.0 * k as f64);
            }
        }
        v
    };
    let bump: Vec<[f64; 3]> = path(&[1000.0, 8000.0, 1000.0])
        .into_iter()
        .map(fz)
        .collect();
    assert_eq!(bump.len(), 57);
    assert_eq!(wheel_rows(&m, "bump"), bump);
    let sweep = path(&[0.0, 4000.0, -4000.0, 0.0]);
    assert_eq!(sweep.len(), 65);
    let lateral: Vec<[f64; 3]> = sweep.iter().map(|&y| [0.0, y, 4500.0]).collect();
    let longitudinal: Vec<[f64; 3]> = sweep.iter().map(|&x| [x, 0.0, 4500.0]).collect();
    assert_eq!(wheel_rows(&m, "lateral"), lateral);
    assert_eq!(wheel_rows(&m, "longitudinal"), longitudinal);
}

#[test]
fn small_benchmarks_have_the_numbers_of_benchmarks_md() {
    let e = [10000.0; 3];
    // 1. Single bushing: b from ground to arm at the origin, tip at (300, 0, 0), cases c1..c3.
    let m = example("single_bushing.axle");
    assert_bushing(&m, "b", "ground.b", "arm.b", e, e);
    assert_at(&m, "ground.b", [0.0; 3]);
    assert_at(&m, "arm.b", [0.0; 3]);
    assert_euler(&m, "arm.b", [0.0; 3]);
    assert_at(&m, "arm.tip", [300.0, 0.0, 0.0]);
    let set = &m.load_sets[0];
    let rows: Vec<(&str, Vec<f64>)> = set
        .cases
        .iter()
        .map(|c| (c.name.as_str(), c.values.clone()))
        .collect();
    assert_eq!(
        rows,
        [
            ("c1", vec![100.0, 200.0, -300.0, 1000.0, -2000.0, 500.0]),
            ("c2", vec![-400.0, 50.0, 250.0, -3000.0, 1500.0, 2500.0]),
            ("c3", vec![0.0, 0.0, 1000.0, 0.0, 0.0, 0.0]),
        ]
    );
    let comps: Vec<&str> = set.channels.iter().map(|c| c.component.name()).collect();
    assert_eq!(comps, ["fx", "fy", "fz", "mx", "my", "mz"]);
    // 2. Four-bar: links, bushings b1 b2, revolutes along global y, ten cases within 1000 N, 10000 N·mm.
    let m = example("four_bar.axle");
    assert_bushing(&m, "b1", "ground.b1", "link1.b1", e, e);
    assert_bushing(&m, "b2", "ground.b2", "link2.b2", e, e);
    assert_at(&m, "link1.b1", [0.0, 0.0, 0.0]);
    assert_at(&m, "link2.b2", [250.0, 0.0, 0.0]);
    assert_joint(&m, "r1", JointKind::Revolute, "link1.r1", "coupler.r1");
    assert_joint(&m, "r2", JointKind::Revolute, "link2.r2", "coupler.r2");
    for p in ["link1.r1", "coupler.r1", "link2.r2", "coupler.r2"] {
        let z = marker(&m, p).rotation.column(2).into_owned();
        assert!(
            (z - axle::geom::Vec3::y()).norm() < 1e-12,
            "{p} axis along global y"
        );
    }
    assert_at(&m, "coupler.r1", [0.0, 0.0, 450.0]);
    assert_at(&m, "coupler.r2", [250.0, 0.0, 450.0]);
    assert_at(&m, "coupler.mid", [125.0, 0.0, 450.0]);
    let set = &m.load_sets[0];
    assert_eq!(set.cases.len(), 10);
    for c in &set.cases {
        let f = (c.values[0].powi(2) + c.values[1].powi(2) + c.values[2].powi(2)).sqrt();
        let t = (c.values[3].powi(2) + c.values[4].powi(2) + c.values[5].powi(2)).sqrt();
        assert!(f <= 1000.0 + 1e-9 && t <= 10000.0 + 1e-9, "{}", c.name);
    }
    // 3. Slider-crank: crank pin (50, 86.6025, 0), slider pin (50 + sqrt(300² - 86.6025²), 0, 0).
    let m = example("slider_crank.axle");
    let xs = 50.0 + (300.0f64.powi(2) - 86.6025f64.powi(2)).sqrt();
    assert!((xs - 337.2).abs() < 0.05);
    assert_joint(
        &m,
        "crank_pivot",
        JointKind::Revolute,
        "crank.pivot",
        "ground.crank_pivot",
    );
    assert_joint(
        &m,
        "crank_pin",
        JointKind::Spherical,
        "rod.crank_pin",
        "crank.pin",
    );
    assert_joint(
        &m,
        "slider_pin",
        JointKind::Revolute,
        "rod.slider_pin",
        "slider.pin",
    );
    assert_joint(
        &m,
        "slide",
        JointKind::Translational,
        "slider.slide",
        "ground.slide",
    );
    assert_at(&m, "crank.pin", [50.0, 86.6025, 0.0]);
    for p in ["rod.slider_pin", "slider.pin", "slider.bs", "ground.bs"] {
        assert_at(&m, p, [xs, 0.0, 0.0]);
    }
    let slide = marker(&m, "ground.slide").rotation.column(2).into_owned();
    assert!(
        (slide - axle::geom::Vec3::x()).norm() < 1e-12,
        "slide along global x"
    );
    assert_bushing(&m, "bs", "ground.bs", "slider.bs", e, e);
    for c in &m.load_sets[0].cases {
        let f = (c.values[0].powi(2) + c.values[1].powi(2)).sqrt();
        assert!(
            f <= 500.0 + 1e-9 && c.values[2] == 0.0,
            "{}: in the x-y plane, up to 500 N",
            c.name
        );
    }
}
