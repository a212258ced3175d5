//! Stiffness identification against synthetic truth (thesis chapters 4 and 5):
//! equilibria solved by the statics engine are the measurements, so the
//! answers are known.

use axle::identify::{self, Identified, Measured, Unknown};
use axle::model::{LoadSetId, Model};
use axle::statics::{self, State};
use axle::units::DEG;

fn model(src: &str) -> Model {
    let (_, c) = axle::check::check_str("t.axle", src);
    c.model.expect("the model checks")
}

/// Every case of the model's first load set, solved from design, as measured poses.
fn measured_from_truth(m: &Model) -> Measured {
    let set = LoadSetId(0);
    let eqs = statics::solve_set(m, set).expect("truth solves");
    let steps: Vec<(State, Vec<_>)> = eqs
        .into_iter()
        .enumerate()
        .map(|(c, e)| (e.state, m.point_loads(set, c)))
        .collect();
    Measured::from_states(m, &steps)
}

fn param<'a>(r: &'a Identified, name: &str) -> (&'a Unknown, &'a identify::ParamResult) {
    let i = r
        .unknowns
        .iter()
        .position(|u| u.names.iter().any(|n| n == name))
        .unwrap_or_else(|| panic!("no unknown {name}"));
    (&r.unknowns[i], &r.params[i])
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// Table 4.1: one case of the single bushing gives all six stiffnesses exactly.
#[test]
fn single_bushing_all_six_from_one_case() {
    let m = model(include_str!("../examples/single_bushing.axle"));
    let mut data = measured_from_truth(&m);
    data.steps.truncate(1);
    let u = identify::select_unknowns(&m, &[]).expect("unknowns");
    assert_eq!(u.len(), 6);
    let r = identify::direct::identify(&m, &u, &data, Default::default()).expect("identifies");
    assert_eq!(r.rank, 6);
    for (name, truth) in [
        ("b.k_x", 10000.0),
        ("b.k_y", 10000.0),
        ("b.k_z", 10000.0),
        ("b.kt_x", 10000.0 / DEG),
        ("b.kt_y", 10000.0 / DEG),
        ("b.kt_z", 10000.0 / DEG),
    ] {
        let (_, p) = param(&r, name);
        let v = p
            .value
            .unwrap_or_else(|| panic!("{name} not identified: {:?}", p.notes));
        assert!(rel(v, truth) < 1e-7, "{name}: {v} vs {truth}");
    }
    assert!(r.combinations.is_empty());
}

/// Table 4.2: the slider-crank determines k_x of `bs` only; the other eleven
/// are reported undetermined, with no number.
#[test]
fn slider_crank_only_k_x() {
    let m = model(include_str!("../examples/slider_crank.axle"));
    let data = measured_from_truth(&m);
    let u = identify::select_unknowns(&m, &[]).expect("unknowns");
    let r = identify::direct::identify(&m, &u, &data, Default::default()).expect("identifies");
    assert_eq!(r.rank, 1, "singular values {:?}", r.singular_values);
    let (_, kx) = param(&r, "bs.k_x");
    assert!(rel(kx.value.expect("k_x identified"), 10000.0) < 1e-7);
    for (un, p) in r.unknowns.iter().zip(&r.params) {
        if un.names[0] != "bs.k_x" {
            assert!(
                !p.identifiable && p.value.is_none(),
                "{}: {:?}",
                un.names[0],
                p
            );
            assert!(!p.notes.is_empty());
        }
    }
    // One equation per step (18 coordinates, constraint rank 17).
    assert!(r.notes[0].text().contains("(1 per step"), "{}", r.notes[0]);
}

/// Table 4.3 and eq. 4.55: the four-bar over ten cases. Translational
/// stiffnesses and the in-plane torsion within 0.1 %; the two out-of-plane
/// torsions only as sums, reported so. The example's revolute axes are along
/// global y (the thesis' z), so the in-plane torsion is kt_y here and the sums
/// are kt_x and kt_z (the thesis' Krx, Kry).
#[test]
fn four_bar_out_of_plane_torsions_only_as_sums() {
    let m = model(include_str!("../examples/four_bar.axle"));
    let data = measured_from_truth(&m);
    assert_eq!(data.steps.len(), 10);
    let u = identify::select_unknowns(&m, &[]).expect("unknowns");
    assert_eq!(u.len(), 12);
    let r = identify::direct::identify(&m, &u, &data, Default::default()).expect("identifies");
    assert_eq!(r.rank, 10, "singular values {:?}", r.singular_values);
    assert!(r.notes[0].text().contains("(8 per step"), "{}", r.notes[0]);
    for b in ["b1", "b2"] {
        for f in ["k_x", "k_y", "k_z"] {
            let (_, p) = param(&r, &format!("{b}.{f}"));
            assert!(rel(p.value.expect("translational"), 10000.0) < 1e-3);
        }
        let (_, p) = param(&r, &format!("{b}.kt_y"));
        assert!(rel(p.value.expect("kt_y"), 10000.0 / DEG) < 1e-3);
        for f in ["kt_x", "kt_z"] {
            let (_, p) = param(&r, &format!("{b}.{f}"));
            assert!(p.value.is_none() && !p.identifiable, "{b}.{f}: {p:?}");
        }
    }
    let exprs: Vec<String> = r.combinations.iter().map(|c| c.expression()).collect();
    assert_eq!(exprs, vec!["kt_x(b1) + kt_x(b2)", "kt_z(b1) + kt_z(b2)"]);
    for c in &r.combinations {
        assert!(
            rel(c.value, 20000.0) < 1e-3,
            "{}: {}",
            c.expression(),
            c.value
        );
        assert_eq!(c.unit, "N*mm/deg");
    }
}

fn mcpherson() -> Model {
    model(include_str!("../examples/mcpherson.axle"))
}

/// Landmark measurements of `truth` along its load set `set`, through the
/// whole measuring path: synthetic CSV → reader → pose fits → steps.
fn measured_from_landmarks(truth: &Model, set: &str, sigma: f64, seed: u64) -> Measured {
    let id = truth.load_set_named(set).expect("load set");
    let csv =
        axle::measure::synthetic::landmarks_csv(truth, id, sigma, seed).expect("truth solves");
    let (obs, skipped) = axle::data::landmarks::read(&csv, truth).expect("reads");
    assert!(skipped.is_empty());
    let (poses, issues) = axle::measure::poses::fit_poses(truth, &obs, 0.5);
    assert!(issues.is_empty());
    let loads = identify::measured::loads_of_set(truth, id);
    let steps: Vec<usize> = poses.iter().map(|p| p.step).collect();
    let loads = identify::measured::match_in_order(loads, &steps).expect("counts agree");
    Measured::from_poses(truth, &poses, &loads).expect("measured")
}

/// Toe (deg) of the model's wheel along a load set.
fn toe_along(m: &Model, set: &str) -> Vec<f64> {
    let id = m.load_set_named(set).expect("load set");
    statics::solve_set(m, id)
        .expect("solves")
        .iter()
        .map(|e| axle::kc::wheel_quantities(m, &e.state, &m.wheels[0]).toe_deg)
        .collect()
}

/// Largest toe difference over the lateral and longitudinal sweeps, as a
/// fraction of the truth's toe range on that sweep.
fn toe_mismatch(truth: &Model, other: &Model) -> f64 {
    let mut worst: f64 = 0.0;
    for set in ["lateral", "longitudinal"] {
        let a = toe_along(truth, set);
        let b = toe_along(other, set);
        let range =
            a.iter().cloned().fold(f64::MIN, f64::max) - a.iter().cloned().fold(f64::MAX, f64::min);
        let d = a
            .iter()
            .zip(&b)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max);
        worst = worst.max(d / range);
    }
    worst
}

fn ab_unknowns(m: &Model) -> Vec<Unknown> {
    let names: Vec<String> = ["A", "B"]
        .iter()
        .flat_map(|b| ["k_x", "k_y", "k_z", "kt_x", "kt_y", "kt_z"].map(|f| format!("{b}.{f}")))
        .collect();
    identify::select_unknowns(m, &names).expect("unknowns")
}

fn with_all(m: &Model, u: &[Unknown], boundary_value: f64) -> Model {
    let mut w = m.clone();
    for x in u {
        x.set(&mut w, axle::units::from_boundary(boundary_value, x.dim));
    }
    w
}

/// Tables 5.2 and 5.3, figure 5.9: bushings A and B of the McPherson from both
/// of the thesis' initial guesses. Both runs converge, k_x of both arms (the
/// stiffnesses along the arms) comes out right, and both identified models
/// reproduce the reference toe under lateral and longitudinal force.
#[test]
fn mcpherson_iterative_from_both_initial_guesses() {
    let truth = mcpherson();
    let data = measured_from_landmarks(&truth, "thesis_table_5_1", 0.0, 1);
    let u = ab_unknowns(&truth);
    for start in [10000.0, 500.0] {
        let init = with_all(&truth, &u, start);
        let u0 = ab_unknowns(&init);
        let r = identify::iterative::identify(&init, &u0, &data, Default::default())
            .unwrap_or_else(|e| panic!("start {start}: {e}"));
        eprintln!("start {start}: {} iterations", r.iterations);
        for (un, p) in r.unknowns.iter().zip(&r.params) {
            eprintln!(
                "  {} {:?} {}",
                un.label(),
                p.value.map(|v| axle::units::to_boundary(v, un.dim)),
                p.identifiable
            );
        }
        let (_, ax) = param(&r, "A.k_x");
        let (_, bx) = param(&r, "B.k_x");
        assert!(rel(ax.value.expect("A.k_x"), 13875.0) < 0.05, "{ax:?}");
        assert!(rel(bx.value.expect("B.k_x"), 310.0) < 0.05, "{bx:?}");
        let identified = r.apply(&init);
        let before = toe_mismatch(&truth, &init);
        let after = toe_mismatch(&truth, &identified);
        eprintln!("toe mismatch {before} -> {after}");
        assert!(
            after < 0.05,
            "start {start}: toe mismatch {after} of the range (initial {before})"
        );
    }
}

/// Least squares on the McPherson: the stiffnesses of bushings A and B (10
/// unknowns with the radial pairs tied, the thesis' question) from σ = 0.05 mm
/// landmarks along Table 5-1 (chassis landmarks included, so the poses are
/// registered and least squares re-estimates the registration), started 30 %
/// off the truth (a nominal model to refine; free length 5 mm off). What it
/// calls identifiable carries a real 95 % interval; the rest has no value.
///
/// Coverage over four seeds: each identified interval is a 95 % one, so over
/// the ~18 intervals of the four fits the number of misses is about
/// Binomial(18, 0.05) (the intervals of one fit are correlated, which spreads
/// the count but not its mean of 0.9): P(≥ 4) = 1.1 %. At most 3 misses are
/// allowed. (Measured: 0 of 18; before least squares froze the directions
/// the data hardly see, 2 of 18, both in seed 1: A.kt_x 13488 [11591, 15695]
/// against 11000, B.k_x 306.6 [303.9, 309.4] against 310.)
/// The truth with every unknown moved off: stiffnesses 30 % high, lengths
/// 5 mm long (the starting guess of the least-squares tests).
fn started_off(truth: &Model, unknowns: &[Unknown]) -> Model {
    let mut init = truth.clone();
    for u in unknowns {
        let v = if u.is_stiffness() {
            u.initial * 1.3
        } else {
            u.initial + 5.0
        };
        u.set(&mut init, v);
    }
    init
}

#[test]
fn mcpherson_lsq_intervals_cover_the_truth() {
    let truth = mcpherson();
    let u_truth = ab_unknowns(&truth);
    let init = started_off(&truth, &u_truth);
    let u0 = ab_unknowns(&init);
    let (mut intervals, mut misses) = (0, 0);
    for seed in 1..=4u64 {
        let data = measured_from_landmarks(&truth, "thesis_table_5_1", 0.05, seed);
        let r = identify::lsq::identify(&init, &u0, &data, Default::default()).expect("lsq");
        eprintln!(
            "seed {seed}: {} iterations, sigma0 {:?}",
            r.iterations, r.sigma0
        );
        assert!(
            r.sigma0.expect("sigma0") < 1.3,
            "the fit did not reach the noise level"
        );
        let mut identified = 0;
        for ((un, p), tu) in r.unknowns.iter().zip(&r.params).zip(&u_truth) {
            let b = |v: f64| axle::units::to_boundary(v, un.dim);
            let covers = p
                .interval
                .map(|(lo, hi)| lo <= tu.initial && tu.initial <= hi);
            eprintln!(
                "  {} truth {} value {:?} interval {:?} {}",
                un.label(),
                b(tu.initial),
                p.value.map(b),
                p.interval.map(|(a, c)| (b(a), b(c))),
                match covers {
                    Some(true) => "covers",
                    Some(false) => "MISSES",
                    None => "",
                }
            );
            match covers {
                Some(c) => {
                    identified += 1;
                    intervals += 1;
                    misses += usize::from(!c);
                }
                None => assert!(p.value.is_none() && !p.identifiable),
            }
        }
        assert!(identified >= 4, "seed {seed}: only {identified} identified");
        let (_, ax) = param(&r, "A.k_x");
        let (_, bx) = param(&r, "B.k_x");
        assert!(ax.identifiable && bx.identifiable);
    }
    eprintln!("{misses} of {intervals} 95 % intervals miss the truth");
    assert!(
        misses <= 3,
        "{misses} of {intervals} 95 % intervals miss the truth"
    );
}

/// Every McPherson unknown at once (A, B, F with radial pairs tied, spring k
/// and free length: 16, plus the 6 registration variables), 30 % high and 5 mm
/// long. Directions the data hardly see are frozen, so the fit converges by
/// its own rule (no GN step of more than 0.02 standard errors) instead of
/// drifting along them to the iteration cap, and what it calls identified
/// covers the truth. Misses over the 4 seeds are about Binomial(~29, 0.05):
/// P(≥ 5) = 4 %; at most 4 are allowed. (Before the freezing, seed 1 ran 100
/// iterations without converging and F.k_x 1187 [1133, 1243] missed 1285.)
#[test]
fn mcpherson_lsq_all_sixteen_unknowns_converge_and_cover() {
    let truth = mcpherson();
    let u_truth = identify::select_unknowns(&truth, &[]).expect("unknowns");
    assert_eq!(u_truth.len(), 16);
    let init = started_off(&truth, &u_truth);
    let u0 = identify::select_unknowns(&init, &[]).expect("unknowns");
    let (mut intervals, mut misses) = (0, 0);
    for seed in 1..=4u64 {
        let data = measured_from_landmarks(&truth, "thesis_table_5_1", 0.05, seed);
        let opts = identify::lsq::LsqOptions::default();
        let r = identify::lsq::identify(&init, &u0, &data, opts).expect("lsq");
        eprintln!(
            "seed {seed}: {} iterations, sigma0 {:?}",
            r.iterations, r.sigma0
        );
        assert!(r.iterations < opts.max_iterations, "{:?}", r.notes);
        // The weak directions are data: a `Frozen` note with the threshold used.
        assert!(
            !r.notes
                .iter()
                .any(|n| matches!(n, identify::FitNote::NotConverged { .. }))
        );
        assert!(
            r.notes.iter().any(|n| matches!(n,
                identify::FitNote::Frozen { count, below } if *count > 0 && *below == opts.freeze_below)),
            "{:?}",
            r.notes
        );
        assert!(r.notes.iter().any(|n| n.text().contains("not searched")));
        assert!(r.sigma0.expect("sigma0") < 1.3);
        for ((un, p), tu) in r.unknowns.iter().zip(&r.params).zip(&u_truth) {
            let b = |v: f64| axle::units::to_boundary(v, un.dim);
            let Some((lo, hi)) = p.interval else {
                assert!(p.value.is_none() && !p.identifiable);
                continue;
            };
            let covers = lo <= tu.initial && tu.initial <= hi;
            eprintln!(
                "  {} truth {} value {:?} interval [{}, {}] {}",
                un.label(),
                b(tu.initial),
                p.value.map(b),
                b(lo),
                b(hi),
                if covers { "covers" } else { "MISSES" }
            );
            intervals += 1;
            misses += usize::from(!covers);
        }
        // The well-determined ones are always among the identified.
        for name in ["A.k_x", "B.k_x", "F.k_x", "spring.k", "spring.free_length"] {
            assert!(param(&r, name).1.identifiable, "seed {seed}: {name}");
        }
    }
    eprintln!("{misses} of {intervals} 95 % intervals miss the truth");
    assert!(
        misses <= 4,
        "{misses} of {intervals} 95 % intervals miss the truth"
    );
}

/// The McPherson with bushing A written per axis (so k_x and k_y may differ).
fn mcpherson_general_a(k_x: f64) -> Model {
    let src = include_str!("../examples/mcpherson.axle").replace(
        "    k_radial 13875 N/mm\n    k_axial 1370 N/mm\n    kt_radial 11000 N*mm/deg\n    kt_axial 4000 N*mm/deg",
        &format!("    k ({k_x}, 13875, 1370) N/mm\n    kt (11000, 11000, 4000) N*mm/deg"),
    );
    model(&src)
}

/// Thesis §5.4: the real arm's bushing A had about half its nominal k_x (7300
/// against 13875 N/mm). From a nominal model, all three methods find it.
#[test]
fn half_k_x_of_bushing_a_found_by_all_three_methods() {
    let truth = mcpherson_general_a(7300.0);
    let nominal = mcpherson_general_a(13875.0);
    let names: Vec<String> = ["A.k_x", "A.k_y", "A.k_z", "B.k_x", "B.k_y"]
        .map(String::from)
        .to_vec();
    let u = identify::select_unknowns(&nominal, &names).expect("unknowns");
    // Direct: every part pose (the strut's too) from the truth along Table 4.4.
    let set = truth.load_set_named("thesis_table_4_4").expect("set");
    let eqs = statics::solve_set(&truth, set).expect("solves");
    let steps: Vec<(State, Vec<_>)> = eqs
        .into_iter()
        .enumerate()
        .map(|(c, e)| (e.state, truth.point_loads(set, c)))
        .collect();
    let all_parts = Measured::from_states(&truth, &steps);
    let r =
        identify::direct::identify(&nominal, &u, &all_parts, Default::default()).expect("direct");
    let (_, p) = param(&r, "A.k_x");
    assert!(
        rel(p.value.expect("direct finds A.k_x"), 7300.0) < 0.01,
        "direct {p:?}"
    );
    // Iterative and least squares from landmarks (no strut pose) along Table 5-1.
    let data = measured_from_landmarks(&truth, "thesis_table_5_1", 0.0, 3);
    let r =
        identify::iterative::identify(&nominal, &u, &data, Default::default()).expect("iterative");
    let (_, p) = param(&r, "A.k_x");
    assert!(
        p.identifiable && rel(p.value.expect("value"), 7300.0) < 0.05,
        "iterative {p:?}"
    );
    let noisy = measured_from_landmarks(&truth, "thesis_table_5_1", 0.05, 3);
    let r = identify::lsq::identify(&nominal, &u, &noisy, Default::default()).expect("lsq");
    let (_, p) = param(&r, "A.k_x");
    let (lo, hi) = p.interval.expect("lsq identifies A.k_x");
    assert!(lo <= 7300.0 && 7300.0 <= hi && hi < 13875.0, "lsq {p:?}");
}

/// The polylines of an SVG with more than two points (legend samples have
/// two), as (stroke colour, pixel points), in document order.
fn polylines(svg: &str) -> Vec<(String, Vec<(f64, f64)>)> {
    let attr = |tag: &str, name: &str| -> Option<String> {
        let i = tag.find(&format!(" {name}=\""))? + name.len() + 3;
        Some(tag[i..i + tag[i..].find('"')?].to_string())
    };
    svg.split("<polyline")
        .skip(1)
        .filter_map(|t| {
            let tag = &t[..t.find("/>")?];
            let pts: Vec<(f64, f64)> = attr(tag, "points")?
                .split_whitespace()
                .filter_map(|p| {
                    let (x, y) = p.split_once(',')?;
                    Some((x.parse().ok()?, y.parse().ok()?))
                })
                .collect();
            if pts.len() > 2 {
                Some((attr(tag, "stroke")?, pts))
            } else {
                None
            }
        })
        .collect()
}

/// `axle identify --report DIR` (figure 5.9): from landmarks of the truth
/// along Table 5-1 and a model whose bushings A and B all start at the
/// thesis' 10000, the iterative method's report has one plot per swept load
/// direction with the measured, initial and identified curves, and on every
/// panel the identified curve lies far closer to the measured one than the
/// initial curve does (compared in the SVG's own pixel coordinates).
#[test]
fn cli_report_plots_measured_initial_and_identified_curves() {
    let truth = mcpherson();
    let id = truth.load_set_named("thesis_table_5_1").expect("set");
    let csv = axle::measure::synthetic::landmarks_csv(&truth, id, 0.0, 1).expect("solves");
    let dir = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("identify_report");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("tmp dir");
    let lm = dir.join("landmarks.csv");
    std::fs::write(&lm, csv).expect("write landmarks");
    let out_model = dir.join("identified.axle");
    let report = dir.join("report");
    let mut args: Vec<String> = [
        "identify",
        "examples/mcpherson.axle",
        "--landmarks",
        lm.to_str().expect("utf-8"),
        "--method",
        "iterative",
        "--initial",
        "10000",
        "--format",
        "json",
        "-o",
        out_model.to_str().expect("utf-8"),
        "--report",
        report.to_str().expect("utf-8"),
        "--unknown",
    ]
    .map(String::from)
    .to_vec();
    args.extend(ab_unknowns(&truth).iter().flat_map(|u| u.names.clone()));
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_axle"))
        .args(&args)
        .output()
        .expect("runs");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
    assert_eq!(json["method"], "iterative");
    let ax = &json["parameters"]["A.k_x"];
    assert_eq!(ax["initial"], 10000.0);
    assert!(rel(ax["value"].as_f64().expect("A.k_x value"), 13875.0) < 0.05);
    // -o writes the identified model, which checks and carries the value.
    let written = model(&std::fs::read_to_string(&out_model).expect("-o written"));
    let u = identify::select_unknowns(&written, &["A.k_x".to_string()]).expect("A.k_x");
    assert!(rel(axle::units::to_boundary(u[0].initial, u[0].dim), 13875.0) < 0.05);

    let mut files: Vec<String> = std::fs::read_dir(&report)
        .expect("report dir")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect();
    files.sort();
    assert_eq!(
        files,
        [
            "toe_camber_lateral.svg",
            "toe_camber_longitudinal.svg",
            "toe_camber_vertical.svg"
        ]
    );
    // One note per plot with the RMS toe / camber differences (deg) to the
    // measured curve: "... initial T / C deg, identified T / C deg".
    let notes: Vec<&str> = json["notes"]
        .as_array()
        .expect("notes")
        .iter()
        .filter_map(|n| n.as_str().filter(|s| s.starts_with("report ")))
        .collect();
    assert_eq!(notes.len(), 3, "{notes:?}");
    for n in &notes {
        let rms = |key: &str| -> [f64; 2] {
            let tail = &n[n.find(key).expect(key) + key.len()..];
            let mut w = tail.split_whitespace();
            let t = w.next().expect("toe").parse().expect("number");
            assert_eq!(w.next(), Some("/"));
            let c = w.next().expect("camber").trim_end_matches(',');
            [t, c.parse().expect("number")]
        };
        let (init, ident) = (rms("initial "), rms("identified "));
        eprintln!("{n}");
        // Noise-free data: the identified model is within 0.02 deg everywhere,
        // and at least ten times closer than the all-10000 start.
        for k in 0..2 {
            assert!(ident[k] < 0.02 && ident[k] < 0.1 * init[k], "{n}");
        }
    }
    // Colours of the three series, as plot.rs draws them.
    let (measured, initial, identified) = ("#005AB4", "#C83C14", "#1E8C3C");
    for f in &files {
        let svg = std::fs::read_to_string(report.join(f)).expect("svg");
        for label in ["measured", "initial model", "identified model", "Toe angle"] {
            assert!(svg.contains(label), "{f}: no {label}");
        }
        let lines = polylines(&svg);
        // Two panels (toe, camber), each measured, initial, identified.
        let colours: Vec<&str> = lines.iter().map(|(c, _)| c.as_str()).collect();
        assert_eq!(
            colours,
            [measured, initial, identified, measured, initial, identified],
            "{f}"
        );
        // Five steps per direction of Table 5-1 (the 4500 N vertical step in each).
        for (_, pts) in &lines {
            assert_eq!(pts.len(), 5, "{f}");
        }
        for panel in lines.chunks(3) {
            let dist = |k: usize| -> f64 {
                panel[0]
                    .1
                    .iter()
                    .zip(&panel[k].1)
                    .map(|(a, b)| {
                        assert_eq!(a.0, b.0, "same x (load) for every series");
                        (a.1 - b.1).abs()
                    })
                    .fold(0.0, f64::max)
            };
            let (d_init, d_ident) = (dist(1), dist(2));
            eprintln!("{f}: largest pixel distance initial {d_init}, identified {d_ident}");
            assert!(
                d_ident < 0.1 * d_init,
                "{f}: identified {d_ident} px vs initial {d_init} px"
            );
        }
    }
}

/// Like [`measured_from_landmarks`] without the ground's landmarks: the poses
/// are measured in the model frame, with no registration. (With the chassis
/// landmarks, one registration pose fitted from all steps adds an error common
/// to every step that the least-squares noise model does not contain, and the
/// stiffness intervals come out too narrow: A.k_x missed its 95 % interval for
/// 2 of 3 seeds here, against 0 of 6 without registration.)
fn measured_in_model_frame(truth: &Model, set: &str, sigma: f64, seed: u64) -> Measured {
    let id = truth.load_set_named(set).expect("load set");
    let csv =
        axle::measure::synthetic::landmarks_csv(truth, id, sigma, seed).expect("truth solves");
    let ground = &truth.part(truth.ground().expect("ground")).name;
    let csv: String = csv
        .lines()
        .filter(|l| l.split(',').nth(1) != Some(ground.as_str()))
        .map(|l| format!("{l}\n"))
        .collect();
    let (obs, _) = axle::data::landmarks::read(&csv, truth).expect("reads");
    let (poses, issues) = axle::measure::poses::fit_poses(truth, &obs, 0.5);
    assert!(issues.is_empty());
    let steps: Vec<usize> = poses.iter().map(|p| p.step).collect();
    let loads = identify::measured::loads_of_set(truth, id);
    let loads = identify::measured::match_in_order(loads, &steps).expect("counts agree");
    Measured::from_poses(truth, &poses, &loads).expect("measured")
}

/// Geometry and stiffness at once (beyond the thesis, its named next step):
/// the truth's ball joint L7 sits 2 mm higher than the model says. Least
/// squares over L7.z and the arms' k_x from σ = 0.05 mm landmarks finds the
/// height within a fraction of a millimetre and every value within its 95 %
/// interval.
#[test]
fn lsq_joint_coordinate_and_stiffnesses_together() {
    let nominal = mcpherson();
    let names: Vec<String> = ["L7.z", "A.k_x", "B.k_x"].map(String::from).to_vec();
    let u = identify::select_unknowns(&nominal, &names).expect("unknowns");
    let z0 = u[0].initial;
    let mut truth = nominal.clone();
    u[0].set(&mut truth, z0 + 2.0);
    let data = measured_in_model_frame(&truth, "thesis_table_5_1", 0.05, 5);
    let r = identify::lsq::identify(&nominal, &u, &data, Default::default()).expect("lsq");
    eprintln!("{} iterations, sigma0 {:?}", r.iterations, r.sigma0);
    for (name, expected) in [("L7.z", z0 + 2.0), ("A.k_x", 13875.0), ("B.k_x", 310.0)] {
        let (_, p) = param(&r, name);
        let (lo, hi) = p
            .interval
            .unwrap_or_else(|| panic!("{name} not identified: {p:?}"));
        eprintln!("{name}: {:?} [{lo}, {hi}] truth {expected}", p.value);
        assert!(lo <= expected && expected <= hi, "{name}: {p:?}");
    }
    let (_, z) = param(&r, "L7.z");
    let (lo, hi) = z.interval.expect("interval");
    // Resolved to a fraction of the 2 mm offset, and away from the model's value.
    assert!(hi - lo < 0.2 && lo > z0 + 1.5, "L7.z interval [{lo}, {hi}]");
}

/// The table a user reads, with the iteration history (snapshot): three
/// stiffnesses from 10000 on noise-free landmarks along Table 5-1.
#[test]
fn cli_iterative_table_with_history_snapshot() {
    let truth = mcpherson();
    let id = truth.load_set_named("thesis_table_5_1").expect("set");
    let csv = axle::measure::synthetic::landmarks_csv(&truth, id, 0.0, 1).expect("solves");
    let dir = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("identify_table");
    std::fs::create_dir_all(&dir).expect("tmp dir");
    let lm = dir.join("landmarks.csv");
    std::fs::write(&lm, csv).expect("write landmarks");
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_axle"))
        .args(["identify", "examples/mcpherson.axle", "--landmarks"])
        .arg(&lm)
        .args(["--method", "iterative", "--initial", "10000"])
        .args(["--unknown", "A.k_x", "A.k_z", "B.k_x"])
        .output()
        .expect("runs");
    assert!(out.status.success());
    insta::assert_snapshot!(String::from_utf8_lossy(&out.stdout));
}

/// K&C channels join the landmarks in least squares, weighted by their noise:
/// toe, camber (σ 0.01 deg) and wheel centre (σ 0.05 mm) of the truth, with
/// that noise, added to the σ = 0.05 mm landmarks. More data of the same
/// quality: every interval narrows and still covers the truth.
#[test]
fn lsq_kc_channels_narrow_the_intervals() {
    let truth = mcpherson();
    let set = truth.load_set_named("thesis_table_5_1").expect("set");
    let eqs = statics::solve_set(&truth, set).expect("solves");
    let mut noise = axle::measure::synthetic::Noise::new(11);
    let kc: Vec<(usize, identify::KcObservation)> = eqs
        .iter()
        .enumerate()
        .map(|(k, e)| {
            let q = axle::kc::wheel_quantities(&truth, &e.state, &truth.wheels[0]);
            let c = q.center.map(|v| v + 0.05 * noise.normal());
            let obs = identify::KcObservation {
                wheel: axle::model::WheelId(0),
                toe_deg: q.toe_deg + 0.01 * noise.normal(),
                camber_deg: q.camber_deg + 0.01 * noise.normal(),
                wc: axle::geom::Vec3::new(c[0], c[1], c[2]),
            };
            (k + 1, obs)
        })
        .collect();
    let plain = measured_in_model_frame(&truth, "thesis_table_5_1", 0.05, 12);
    let mut with_kc = plain.clone();
    identify::measured::attach_kc(&mut with_kc, &kc);
    assert!(with_kc.steps.iter().all(|s| s.kc.len() == 1));
    let names: Vec<String> = ["A.k_x", "A.kt_z", "B.k_x"].map(String::from).to_vec();
    let u = identify::select_unknowns(&truth, &names).expect("unknowns");
    let mut init = truth.clone();
    for x in &u {
        x.set(&mut init, x.initial * 1.3);
    }
    let u0 = identify::select_unknowns(&init, &names).expect("unknowns");
    let a = identify::lsq::identify(&init, &u0, &plain, Default::default()).expect("lsq");
    let b = identify::lsq::identify(&init, &u0, &with_kc, Default::default()).expect("lsq");
    assert!(
        b.notes[0]
            .text()
            .contains(&format!("{} independent", 6 * 4 * 13 + 5 * 13))
    );
    for (x, truth_x) in u0.iter().zip(&u) {
        let name = &x.names[0];
        let (_, pa) = param(&a, name);
        let (_, pb) = param(&b, name);
        let (la, ha) = pa.interval.expect("landmarks alone identify it");
        let (lb, hb) = pb.interval.expect("with K&C");
        eprintln!(
            "{name}: truth {} landmarks [{la}, {ha}], with K&C [{lb}, {hb}]",
            truth_x.initial
        );
        assert!(hb / lb < ha / la, "{name} did not narrow");
        assert!(
            lb <= truth_x.initial && truth_x.initial <= hb,
            "{name}: {pb:?}"
        );
    }
}

/// Every wheel's K&C channels (issue 13): one K&C CSV of the front axle has
/// a row per wheel and step (its `wheel` column); each row is compared with
/// its own wheel, so the right corner's bushing B, started 30 % off, is found
/// from the landmarks and both wheels' channels.
#[test]
fn lsq_on_the_front_axle_compares_each_wheel_with_its_own_kc_rows() {
    let truth = model(include_str!("../examples/front_axle.axle"));
    let set = truth.load_set_named("mirrored").expect("set");
    let eqs = statics::solve_set(&truth, set).expect("solves");
    let states: Vec<_> = eqs.iter().map(|e| &e.state).collect();
    let csv = axle::output::kc_table::csv(&axle::kc::kc_rows(&truth, set, &states));
    let kc = identify::measured::kc_channels(&truth, &csv).expect("reads");
    assert_eq!(kc.len(), 2 * 3, "a row per wheel and step");
    // Without a `wheel` column the rows of a two-wheel model are ambiguous.
    let bare = "step,fx,fy,fz,wc_x,wc_y,wc_z,toe_deg,camber_deg\n1,0,0,4500,0,787,305,0.3,0.5\n";
    let e = identify::measured::kc_channels(&truth, bare).expect_err("which wheel?");
    assert_eq!(e.code, "E0708", "{e:?}");
    let right = truth
        .wheels
        .iter()
        .position(|w| w.name == "front_right.wheel");
    assert!(
        kc.iter()
            .any(|(_, o)| Some(o.wheel.index()) == right && o.wc.y < -700.0)
    );
    let plain = measured_in_model_frame(&truth, "mirrored", 0.05, 21);
    let mut with_kc = plain.clone();
    identify::measured::attach_kc(&mut with_kc, &kc);
    assert!(with_kc.steps.iter().all(|s| s.kc.len() == 2));
    let names = vec!["front_right.B.k_x".to_string()];
    let u = identify::select_unknowns(&truth, &names).expect("unknowns");
    let mut init = truth.clone();
    for x in &u {
        x.set(&mut init, x.initial * 1.3);
    }
    let u0 = identify::select_unknowns(&init, &names).expect("unknowns");
    let r = identify::lsq::identify(&init, &u0, &with_kc, Default::default()).expect("lsq");
    // 8 measured parts x 6 x 3 steps, and 5 channels x 2 wheels x 3 steps.
    assert!(
        r.notes[0]
            .text()
            .contains(&format!("{} independent", 6 * 8 * 3 + 5 * 2 * 3)),
        "{}",
        r.notes[0].text()
    );
    let (_, p) = param(&r, "front_right.B.k_x");
    let (lo, hi) = p.interval.expect("identified");
    eprintln!("front_right.B.k_x: truth {} [{lo}, {hi}]", u[0].initial);
    assert!(lo <= u[0].initial && u[0].initial <= hi, "{p:?}");
    assert!(rel(p.value.expect("a value"), u[0].initial) < 0.05, "{p:?}");

    // The report plots every wheel: its own file per wheel, and the right
    // wheel, whose bushing was 30 % off, is where the identification shows.
    let curves = identify::report::curves(&init, &r.apply(&init), &with_kc).expect("curves");
    let files: Vec<&str> = curves.iter().map(|c| c.file.as_str()).collect();
    assert_eq!(
        files,
        [
            "toe_camber_front_left_wheel_vertical",
            "toe_camber_front_right_wheel_vertical"
        ]
    );
    for c in &curves {
        assert_eq!(c.measured.len(), 3, "{}", c.file);
        assert!(c.measured.iter().all(|m| m.wheel == c.wheel));
        let (before, after) = (c.rms(&c.initial, false), c.rms(&c.identified, false));
        eprintln!(
            "{}: toe RMS initial {before:e}, identified {after:e} deg",
            c.wheel
        );
        // Measured = the truth's own K&C rows: the identified model is
        // within the 5 % of its stiffness of them.
        assert!(
            after < 0.2 * before || after < 1e-6,
            "{}: {before} -> {after}",
            c.wheel
        );
    }
    let right = &curves[1];
    assert!(
        right.rms(&right.initial, false) > 1e-4,
        "the start differs from the truth at the right wheel"
    );
}

/// The McPherson example with bushing A's radial stiffness written as the
/// parameter `kA`, declared by `declaration`.
fn mcpherson_with_k_a(declaration: &str) -> Model {
    let src = include_str!("../examples/mcpherson.axle");
    let declared = src
        .replacen(
            "import mcpherson_loads\n",
            &format!("import mcpherson_loads\n{declaration}\n"),
            1,
        )
        .replace("k_radial 13875 N/mm", "k_radial kA");
    assert_ne!(declared, src);
    model(&declared)
}

/// Unknowns the file marks: with no `--unknown`, a parameter declared
/// `unknown` is the one thing identified (not the default set), and least
/// squares finds the truth's value for it. Here A's radial stiffness is a
/// parameter started at the thesis' 10000.
#[test]
fn parameter_marked_unknown_in_the_file_is_identified() {
    let m = mcpherson_with_k_a("param kA = 10000 N/mm unknown");
    let u = identify::select_unknowns(&m, &[]).expect("unknowns");
    assert_eq!(u.len(), 1);
    assert_eq!(u[0].label(), "kA");
    let data = measured_in_model_frame(&mcpherson(), "thesis_table_5_1", 0.05, 13);
    let r = identify::lsq::identify(&m, &u, &data, Default::default()).expect("lsq");
    let (_, p) = param(&r, "kA");
    let (lo, hi) = p.interval.expect("identified");
    eprintln!("kA: {:?} [{lo}, {hi}]", p.value);
    assert!(lo <= 13875.0 && 13875.0 <= hi && hi / lo < 1.1, "{p:?}");
}

/// Honest intervals with the chassis measured: the landmark poses are
/// registered to the model frame through one ground pose fitted from every
/// step, an error common to all steps. Least squares re-estimates that
/// registration (six nuisance variables, observed by the ground's landmarks)
/// with the unknowns, so its uncertainty is in their intervals. Over 8 seeds
/// of σ = 0.05 mm noise, count how often each 95 % interval covers the truth.
///
/// With honest intervals a miss is a Bernoulli event of probability 0.05; the
/// misses of one parameter over 8 independent seeds are Binomial(8, 0.05):
/// P(≥ 2) = 1 − 0.95⁸ − 8·0.05·0.95⁷ = 0.057, P(≥ 3) = 0.0058. The test allows
/// at most 2 misses per parameter, so an honest method fails it with
/// probability below 1 % per parameter; before the registration was
/// estimated A.k_x missed in 2 of 3 seeds (an interval too narrow by a factor
/// of about 3 misses in most seeds). The seeds are fixed, so the test is
/// deterministic; the bound says it is not tuned to luck.
#[test]
fn lsq_intervals_cover_the_truth_with_the_chassis_registration() {
    let truth = mcpherson();
    let names: Vec<String> = ["A.k_x", "B.k_x", "spring.k"].map(String::from).to_vec();
    let u_truth = identify::select_unknowns(&truth, &names).expect("unknowns");
    let mut init = truth.clone();
    for x in &u_truth {
        x.set(&mut init, x.initial * 1.2);
    }
    let u0 = identify::select_unknowns(&init, &names).expect("unknowns");
    let mut misses = vec![0usize; names.len()];
    let mut misses_fixed = vec![0usize; names.len()];
    for seed in 1..=8u64 {
        let data = measured_from_landmarks(&truth, "thesis_table_5_1", 0.05, seed);
        assert!(data.steps.iter().all(|s| s.ground.is_some()));
        let r = identify::lsq::identify(&init, &u0, &data, Default::default()).expect("lsq");
        assert!(
            r.notes.iter().any(|n| n.text().contains("registration")),
            "{:?}",
            r.notes
        );
        // The same data with the registration taken as exact (the old noise model).
        let mut fixed = data.clone();
        for s in &mut fixed.steps {
            s.ground = None;
        }
        let f = identify::lsq::identify(&init, &u0, &fixed, Default::default()).expect("lsq");
        for (k, t) in u_truth.iter().enumerate() {
            let (lo, hi) = r.params[k].interval.expect("identified");
            let (flo, fhi) = f.params[k].interval.expect("identified");
            let covers = lo <= t.initial && t.initial <= hi;
            if !covers {
                misses[k] += 1;
            }
            if !(flo <= t.initial && t.initial <= fhi) {
                misses_fixed[k] += 1;
            }
            eprintln!(
                "seed {seed} {}: truth {:.6e} joint [{lo:.6e}, {hi:.6e}] {} fixed-registration [{flo:.6e}, {fhi:.6e}]",
                names[k],
                t.initial,
                if covers { "covers" } else { "MISSES" }
            );
        }
    }
    eprintln!("misses of 8: joint {misses:?}, registration fixed {misses_fixed:?}");
    for (k, n) in names.iter().enumerate() {
        assert!(misses[k] <= 2, "{n}: {} misses of 8", misses[k]);
    }
    // All 24 intervals: Binomial(24, 0.05), P(≥ 4) = 3 %.
    let total: usize = misses.iter().sum();
    assert!(total <= 3, "{total} of 24 intervals miss the truth");
    // The check has power: the same data with the registration taken as
    // exact (the noise model before) miss far more often (measured 6 of 24).
    let fixed: usize = misses_fixed.iter().sum();
    assert!(
        fixed > 3,
        "with the registration fixed only {fixed} of 24 miss"
    );
}

/// Declared bounds (`unknown [lo, hi]`) against a truth outside them: the
/// truth's A radial stiffness is 13875 N/mm, the file bounds it to [5000,
/// 12000]. Least squares holds it at 12000 and says so (no interval, not
/// called identified); with bounds [5000, 20000] it finds the truth as if
/// unbounded. Direct and iterative, which do not enforce bounds, find the
/// truth and warn that it lies outside the bounds.
#[test]
fn truth_outside_the_declared_bounds_is_reported() {
    let m = mcpherson_with_k_a("param kA = 10000 N/mm unknown [5000 N/mm, 12000 N/mm]");
    let truth = mcpherson();
    // Least squares over kA and B.k_x from σ = 0.05 mm landmarks.
    let names: Vec<String> = ["kA", "B.k_x"].map(String::from).to_vec();
    let u = identify::select_unknowns(&m, &names).expect("unknowns");
    assert_eq!(u[0].bounds.upper, Some(12000.0));
    let data = measured_from_landmarks(&truth, "thesis_table_5_1", 0.05, 21);
    let r = identify::lsq::identify(&m, &u, &data, Default::default()).expect("lsq");
    let (_, ka) = param(&r, "kA");
    eprintln!("lsq kA: {ka:?}");
    assert_eq!(ka.bound, Some(identify::BoundIssue::AtUpper));
    assert_eq!(ka.value, Some(12000.0));
    assert!(!ka.identifiable && ka.interval.is_none());
    let (_, bx) = param(&r, "B.k_x");
    assert!(bx.bound.is_none() && bx.value.is_some());
    // The same with bounds that contain the truth: they change nothing.
    let wide = mcpherson_with_k_a("param kA = 10000 N/mm unknown [5000 N/mm, 20000 N/mm]");
    let uw = identify::select_unknowns(&wide, &names).expect("unknowns");
    let w = identify::lsq::identify(&wide, &uw, &data, Default::default()).expect("lsq");
    let (_, kw) = param(&w, "kA");
    let (lo, hi) = kw.interval.expect("identified inside its bounds");
    assert!(
        kw.bound.is_none() && lo <= 13875.0 && 13875.0 <= hi,
        "{kw:?}"
    );
    let table = axle::cli::identify::to_table(&r);
    assert!(table.contains("AT upper BOUND"), "{table}");
    insta::assert_snapshot!("lsq_table_at_bound", table);
    let json = axle::cli::identify::to_json(&r);
    assert_eq!(
        json["parameters"]["kA"]["bound"], "AT upper BOUND",
        "{json}"
    );
    // Direct: every part pose of the truth along Table 4.4; the field name
    // A.k_x carries the bounds of the parameter it is written as.
    let names: Vec<String> = ["A.k_x", "A.k_y", "B.k_x"].map(String::from).to_vec();
    let u = identify::select_unknowns(&m, &names).expect("unknowns");
    assert_eq!(u[0].bounds.upper, Some(12000.0));
    let set = truth.load_set_named("thesis_table_4_4").expect("set");
    let eqs = statics::solve_set(&truth, set).expect("solves");
    let steps: Vec<(State, Vec<_>)> = eqs
        .into_iter()
        .enumerate()
        .map(|(c, e)| (e.state, truth.point_loads(set, c)))
        .collect();
    let all_parts = Measured::from_states(&truth, &steps);
    let r = identify::direct::identify(&m, &u, &all_parts, Default::default()).expect("direct");
    let (_, p) = param(&r, "A.k_x");
    eprintln!("direct A.k_x: {p:?}");
    assert!(rel(p.value.expect("value"), 13875.0) < 0.01);
    assert_eq!(p.bound, Some(identify::BoundIssue::AboveUpper));
    assert!(
        r.notes
            .iter()
            .any(|n| n.text().contains("outside its declared bounds"))
    );
    // Iterative from noise-free landmarks along Table 5-1.
    let data = measured_from_landmarks(&truth, "thesis_table_5_1", 0.0, 3);
    let r = identify::iterative::identify(&m, &u, &data, Default::default()).expect("iterative");
    let (_, p) = param(&r, "A.k_x");
    eprintln!("iterative A.k_x: {p:?}");
    assert!(rel(p.value.expect("value"), 13875.0) < 0.05);
    assert_eq!(p.bound, Some(identify::BoundIssue::AboveUpper));
    assert!(
        axle::cli::identify::to_table(&r).contains("OUTSIDE bounds (above)"),
        "{}",
        axle::cli::identify::to_table(&r)
    );
}
