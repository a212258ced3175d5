//! The IGES reader (thesis Annexe B): a file written by hand per the standard,
//! files written from synthetic landmarks that must pose-fit exactly like the
//! same numbers in CSV, diagnostics of malformed files, and no panic on
//! mutated files.

mod common;
use axle::data::iges::{self, Geometry, Iges};
use axle::diagnostic::render;
use axle::geom::Vec3;
use axle::measure::poses::fit_poses;
use axle::source::SourceMap;
use common::{axle, landmark_files};
use proptest::prelude::*;

const HAND: &str = include_str!("data/iges/hand.igs");

fn mcpherson() -> axle::model::Model {
    let (_, c) =
        axle::check::check_str("mcpherson.axle", include_str!("../examples/mcpherson.axle"));
    c.model.expect("the example checks")
}

fn close(a: Vec3, b: Vec3) -> bool {
    (a - b).norm() < 1e-12
}

#[test]
fn the_hand_written_file_gives_its_points_lines_planes_and_names() {
    let f: Iges = iges::parse(HAND).expect("the fixture reads");
    assert_eq!(
        f.global.product, "G-Pad, v1.00",
        "a Hollerith string holding a comma"
    );
    assert_eq!((f.global.units_flag, f.global.to_mm), (2, 1.0));
    assert!(f.warnings.is_empty());
    assert_eq!(f.entities.len(), 10, "every directory entry is kept");
    let points: Vec<(&str, i64, Vec3)> = f
        .points()
        .map(|(e, p)| (e.name().expect("named"), e.subscript, p))
        .collect();
    let expect = [
        ("UPRIGHT", 1, Vec3::new(62.0, 749.0, 234.0)),
        ("UPRIGHT", 2, Vec3::new(-48.0, 694.0, 209.0)), // 6.94E2, 2.09D2
        ("upright.m3", 3, Vec3::new(5.0, -0.001, 10.0)), // Name property; 0.5E1, -1.E-3
        // (10, 0, 0) through the matrix: 90° about z, then (1, 2, 3).
        ("UPRIGHT", 4, Vec3::new(1.0, 12.0, 3.0)),
        ("HUB", 1, Vec3::new(1.0, 2.0, 3.0)),
    ];
    assert_eq!(points.len(), expect.len());
    for (got, want) in points.iter().zip(&expect) {
        assert_eq!((got.0, got.1), (want.0, want.1));
        assert!(close(got.2, want.2), "{} {}: {}", got.0, got.1, got.2);
    }
    let by = |label: &str| f.entities.iter().find(|e| e.label == label).expect(label);
    match &by("AXE1").geometry {
        Some(Geometry::Line { from, to }) => {
            assert!(close(*from, Vec3::zeros()) && close(*to, Vec3::new(0.0, 0.0, 100.0)))
        }
        g => panic!("line expected, got {g:?}"),
    }
    // 2 z = 10: the unit normal (0, 0, 1) at offset 5.
    match &by("PL1").geometry {
        Some(Geometry::Plane { normal, offset }) => {
            assert!(close(*normal, Vec3::z()) && (offset - 5.0).abs() < 1e-12)
        }
        g => panic!("plane expected, got {g:?}"),
    }
    let sphere = by("S1");
    assert_eq!((sphere.kind, sphere.geometry.clone()), (158, None));
}

/// The thesis' own sample (Annexe B, `methods.md` §10.4), its Global section as
/// printed: the points, line and plane with the values the thesis lists.
#[test]
fn the_thesis_annexe_b_sample_reads() {
    let text = include_str!("data/iges/annexe_b.igs");
    let f = iges::parse(text).expect("the thesis sample reads");
    assert_eq!(f.global.product, "Convertisseur G-Tech ");
    assert_eq!(
        (f.global.units_flag, f.global.units_name.as_str()),
        (2, "MM")
    );
    let names: Vec<&str> = f.points().map(|(e, _)| e.name().expect("named")).collect();
    assert_eq!(names, ["Pt1", "Pt2"]);
    let (_, pt1) = f.points().next().expect("Pt1");
    assert!(close(
        pt1,
        Vec3::new(17.7197143876002, -160.229593209037, -6.73288989141572)
    ));
    let line = f.entities.iter().find(|e| e.label == "Dr1").expect("Dr1");
    assert_eq!(
        line.geometry,
        Some(Geometry::Line {
            from: Vec3::new(0.647563703122529, -358.153098982009, -16.8623597185424),
            to: Vec3::new(0.647563703122504, 0.11386049782746, -17.5135153407048),
        })
    );
    let plane = f.entities.iter().find(|e| e.label == "Pl1").expect("Pl1");
    match plane.geometry {
        Some(Geometry::Plane { normal, offset }) => {
            assert!((normal - Vec3::z()).norm() < 1e-15);
            assert!((offset + 2.97322844289585).abs() < 1e-12);
        }
        ref g => panic!("plane expected, got {g:?}"),
    }
    // The arc (100) and its matrix (124) are kept, not decoded.
    let kinds: Vec<i64> = f.entities.iter().map(|e| e.kind).collect();
    assert_eq!(kinds, [116, 116, 110, 108, 124, 100]);
}

#[test]
fn iges_points_become_landmark_observations_of_their_parts() {
    let m = mcpherson();
    let f = iges::parse(HAND).expect("reads");
    let (obs, skipped) = axle::data::landmarks::from_iges(&f, 3, HAND, &m);
    let labels: Vec<&str> = obs.iter().map(|o| o.label.as_str()).collect();
    assert_eq!(
        labels,
        ["1", "2", "m3", "4"],
        "the label names the part in capitals; the subscript stands for the landmark"
    );
    assert!(obs.iter().all(|o| o.step == 3));
    assert_eq!(obs[0].line, 27, "the point's parameter record");
    assert_eq!(skipped.len(), 1);
    assert_eq!(&HAND[skipped[0].start..skipped[0].end], "HUB");
    assert_eq!(skipped[0].line, 26, "its label, on D 20");
    assert!(
        skipped[0]
            .message
            .contains("point D 19 `HUB` names no part")
    );
}

/// Builds a file from its Start and Global lines and entities
/// `(type, form, label, subscript, transform pointer, parameter lines)`.
type Spec<'a> = (i64, i64, &'a str, i64, i64, &'a [&'a str]);

fn file(s: &[&str], g: &[&str], entities: &[Spec]) -> String {
    let mut out = Vec::new();
    for (k, l) in s.iter().enumerate() {
        out.push(format!("{l:<72}S{:>7}", k + 1));
    }
    for (k, l) in g.iter().enumerate() {
        out.push(format!("{l:<72}G{:>7}", k + 1));
    }
    let (mut d, mut p) = (Vec::new(), Vec::new());
    for (i, (t, form, label, sub, tr, lines)) in entities.iter().enumerate() {
        let seq = 2 * i + 1;
        let first = p.len() + 1;
        for l in lines.iter() {
            p.push(format!("{l:<64}{seq:>8}P{:>7}", p.len() + 1));
        }
        d.push(format!(
            "{t:>8}{first:>8}{:>8}{:>8}{:>8}{:>8}{tr:>8}{:>8}{:>8}D{seq:>7}",
            0, 0, 0, 0, 0, "00000000"
        ));
        d.push(format!(
            "{t:>8}{:>8}{:>8}{:>8}{form:>8}{:>8}{:>8}{label:>8}{sub:>8}D{:>7}",
            0,
            0,
            lines.len(),
            "",
            "",
            seq + 1
        ));
    }
    let t = format!(
        "S{:>7}G{:>7}D{:>7}P{:>7}",
        s.len(),
        g.len(),
        d.len(),
        p.len()
    );
    out.extend(d);
    out.extend(p);
    out.push(format!("{t:<72}T{:>7}", 1));
    out.join("\n") + "\n"
}

#[test]
fn declared_delimiters_and_inches_are_honoured() {
    // `/` separates parameters and `#` ends records; a string holds both.
    let text = file(
        &["inches"],
        &["1H//1H#/7HA/B#C,D/5Hx.igs/////////1.0/1/4HINCH#"],
        &[
            (116, 0, "", 0, 0, &["116/1.0/-2.5D0/0.5/0/0/1/3#"]),
            (406, 15, "", 0, 0, &["406/1/7Htie,r#d#"]),
        ],
    );
    let f = iges::parse(&text).expect("reads");
    assert_eq!((f.global.param_delim, f.global.record_delim), (b'/', b'#'));
    assert_eq!(f.global.product, "A/B#C,D");
    assert_eq!(f.global.to_mm, 25.4);
    let (e, p) = f.points().next().expect("a point");
    assert!(close(p, Vec3::new(25.4, -63.5, 12.7)), "{p}");
    assert_eq!(e.name(), Some("tie,r#d"));
    // A Global section without a units flag means inches, and says so.
    let text = file(&["x"], &[",,;"], &[(116, 0, "P", 0, 0, &["116,1.,0.,0.;"])]);
    let f = iges::parse(&text).expect("reads");
    assert_eq!(f.global.to_mm, 25.4);
    assert_eq!(f.warnings.len(), 1);
    assert!(f.warnings[0].message.contains("inches"));
}

#[test]
fn synthetic_iges_steps_fit_the_same_poses_as_the_csv() {
    let m = mcpherson();
    let set = m.load_set_named("thesis_table_4_4").expect("set");
    let csv = axle::measure::synthetic::landmarks_csv(&m, set, 0.05, 1).expect("solves");
    let files = axle::measure::synthetic::landmarks_iges(&m, set, 0.05, 1).expect("solves");
    let (from_csv, skipped) = axle::data::landmarks::read(&csv, &m).expect("reads");
    assert!(skipped.is_empty());
    let mut from_iges = Vec::new();
    for (k, text) in files.iter().enumerate() {
        let f = iges::parse(text).unwrap_or_else(|e| panic!("step {}: {e:?}", k + 1));
        // Part names longer than a label (`front_arm`) come from the Name property.
        assert!(f.entities.iter().any(|e| e.kind == 406));
        let (obs, skipped) = axle::data::landmarks::from_iges(&f, k + 1, text, &m);
        assert!(skipped.is_empty(), "{:?}", skipped);
        from_iges.extend(obs);
    }
    assert_eq!(from_iges.len(), from_csv.len());
    for (a, b) in from_iges.iter().zip(&from_csv) {
        assert_eq!((a.step, a.part, &a.label), (b.step, b.part, &b.label));
        assert_eq!(
            a.position, b.position,
            "the written numbers read back exactly"
        );
    }
    let (pi, ii) = fit_poses(&m, &from_iges, 0.5);
    let (pc, ic) = fit_poses(&m, &from_csv, 0.5);
    assert!(ii.is_empty() && ic.is_empty());
    assert_eq!(pi.len(), files.len());
    assert_eq!(pi, pc);
}

fn diagnose(name: &str, text: &str) -> String {
    let e = iges::parse(text).expect_err("malformed");
    let mut sources = SourceMap::new();
    let id = sources.add(name.to_string(), text.to_string());
    render::to_string(&sources, &e.to_diagnostic(id))
}

/// Replaces columns `col..col+new.len()` (1-based) of line `line` (1-based).
fn edit(text: &str, line: usize, col: usize, new: &str) -> String {
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    lines[line - 1].replace_range(col - 1..col - 1 + new.len(), new);
    lines.join("\n") + "\n"
}

#[test]
fn malformed_files_are_reported_with_file_line_and_record() {
    // Line 9 is D 3; line 27 is P 1, line 29 P 3, line 32 P 6.
    let cases = [
        ("bad_section_letter", edit(HAND, 9, 73, "X")),
        ("bad_parameter_pointer", edit(HAND, 9, 9, "      99")),
        ("bad_property_pointer", edit(HAND, 29, 27, "8")),
        ("bad_number", edit(HAND, 27, 5, "6r")),
        ("bad_back_pointer", edit(HAND, 27, 72, "3")),
        ("not_a_rotation", edit(HAND, 32, 5, "2.")),
        (
            "truncated",
            HAND.lines().take(30).collect::<Vec<_>>().join("\n") + "\n",
        ),
        (
            "line_cut_short",
            HAND.replacen(
                "116,62.,749.,234.,0;                                                   1P      1",
                "116,62.,749.,234.,0;",
                1,
            ),
        ),
        ("sequence_gap", edit(HAND, 12, 74, "      9")),
    ];
    for (name, text) in cases {
        let shown = diagnose(&format!("{name}.igs"), &text);
        insta::assert_snapshot!(format!("iges_{name}"), shown);
    }
}

#[test]
fn accented_comments_in_utf8_or_latin1_keep_their_columns() {
    let utf8 = HAND.replacen("Measuring", "Méasuring", 1);
    let e = iges::parse(&utf8).expect_err("IGES is ASCII");
    assert_eq!(&utf8[e.start..e.end], "é");
    let f = iges::parse(&iges::ascii_columns(utf8.as_bytes())).expect("one `?` per character");
    assert_eq!(f.entities.len(), 10);
    let mut latin1 = HAND.as_bytes().to_vec();
    latin1[1] = 0xE9;
    let text = iges::ascii_columns(&latin1);
    assert!(text.starts_with("M?asuring"));
    assert!(iges::parse(&text).is_ok());
}

fn floor_char(s: &str, i: usize) -> usize {
    let mut i = i % (s.len() + 1);
    while !s.is_char_boundary(i) {
        i -= 1;
    }
    i
}

const NOISE: &[&str] = &[
    "", " ", ",", ";", "H", "1H", "9H", "D", "E", "-", ".", "0", "7", "116", "406", "\n", "é", "P",
    "G", "T", "99999999", "1.5D2",
];

proptest! {
    #![proptest_config(ProptestConfig::with_cases(400))]
    #[test]
    fn mutated_files_never_panic(
        edits in prop::collection::vec((any::<usize>(), 0usize..6, prop::sample::select(NOISE)), 1..6),
        cut in prop::option::of(any::<usize>()),
    ) {
        let mut s = HAND.to_string();
        for (at, del, ins) in edits {
            let a = floor_char(&s, at);
            let b = floor_char(&s, (a + del).min(s.len()));
            s.replace_range(a..b.max(a), ins);
        }
        if let Some(c) = cut {
            let c = floor_char(&s, c);
            s.truncate(c);
        }
        if let Err(e) = iges::parse(&s) {
            prop_assert!(e.start <= e.end && e.end <= s.len());
            prop_assert!(s.is_char_boundary(e.start) && s.is_char_boundary(e.end));
            let mut sources = SourceMap::new();
            let id = sources.add("m.igs", s.clone());
            let _ = render::to_string(&sources, &e.to_diagnostic(id));
        }
    }
}

/// `axle identify` takes the measured states as IGES files (one per load
/// case, as the thesis' measuring arm saved them) and identifies exactly what
/// it identifies from the same numbers in CSV; the truth is the example itself,
/// so the interval covers the nominal stiffness.
#[test]
fn identify_reads_iges_files_like_the_csv() {
    let m = mcpherson();
    let set = m.load_set_named("thesis_table_5_1").expect("set");
    let (csv, files) = landmark_files(&m, set, 0.05, 3, "identify_t51");
    let run = |landmarks: &[String]| {
        let mut args = vec![
            "identify",
            "examples/mcpherson.axle",
            "--loadcases",
            "thesis_table_5_1",
            "--method",
            "lsq",
            "--unknown",
            "A.k_x",
            "--format",
            "json",
            "--landmarks",
        ];
        args.extend(landmarks.iter().map(String::as_str));
        let (code, stdout, stderr) = axle(&args);
        assert_eq!(code, 0, "{stderr}");
        let v: serde_json::Value = serde_json::from_str(&stdout).expect("one JSON document");
        v
    };
    let (from_csv, from_iges) = (run(&[csv]), run(&files));
    assert_eq!(from_iges["rank"], from_csv["rank"]);
    let (a, b) = (
        from_iges["parameters"].as_object().expect("parameters"),
        from_csv["parameters"].as_object().expect("parameters"),
    );
    assert_eq!(a.keys().collect::<Vec<_>>(), b.keys().collect::<Vec<_>>());
    for (name, p) in a {
        assert_eq!(p["identifiable"], b[name]["identifiable"], "{name}");
        match (p["value"].as_f64(), b[name]["value"].as_f64()) {
            (Some(x), Some(y)) => assert!((x - y).abs() <= 1e-9 * y.abs(), "{name}: {x} vs {y}"),
            (x, y) => assert_eq!(x, y, "{name}"),
        }
    }
    let interval = a["A.k_x"]["interval"].as_array().expect("an interval");
    let (lo, hi) = (
        interval[0].as_f64().expect("lo"),
        interval[1].as_f64().expect("hi"),
    );
    assert!(lo < 13875.0 && 13875.0 < hi, "A.k_x in [{lo}, {hi}]");
}
