//! ADAMS decks: snapshots of the decks emitted for every example, the
//! emit → import → emit fixed point, equal equilibria of imported models, an
//! independent strict reading of every emitted deck, REULER extraction, the
//! thesis Annexe F import, and error cases (never a panic).

mod adams_reader;

use axle::check::check_str;
use axle::emit::{Vertical, emit_acf, emit_adm, emit_lcf, emit_lcf_as, emit_lcf_axle, load_set};
use axle::geom::{Mat3, euler_zxz, frame_from_z_x};
use axle::import::import_adm;
use axle::model::{Model, PointLoad};
use axle::statics::{Problem, State, solve};

/// Every example, and `tests/data/adams/coverage.axle`, which holds the
/// statement forms the examples do not (FIXED, JPRIM, preloads and offsets,
/// cubic and rotational-table bushings, a tabulated spring, a linear stop,
/// two wheels, torque loads).
fn examples() -> Vec<(String, Model)> {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut paths: Vec<_> = std::fs::read_dir(dir.join("examples"))
        .expect("examples/")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .collect();
    paths.retain(|p| p.extension().is_some_and(|e| e == "axle"));
    paths.sort();
    paths.push(dir.join("tests/data/adams/coverage.axle"));
    paths
        .iter()
        .map(|p| {
            let text = std::fs::read_to_string(p).expect("readable");
            let name = p
                .file_stem()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_default();
            let (_, checked) = check_str(&format!("{name}.axle"), &text);
            (name, checked.model.expect("examples check clean"))
        })
        .collect()
}

fn adm(m: &Model) -> String {
    emit_adm(m).expect("emits").text
}

fn import(text: &str) -> Model {
    let imp = import_adm("deck.adm", text);
    let errs: Vec<String> = imp
        .problems
        .iter()
        .filter(|d| d.severity == axle::diagnostic::Severity::Error)
        .map(|d| d.message.clone())
        .collect();
    assert!(errs.is_empty(), "{errs:?}");
    imp.model.expect("imports")
}

#[test]
fn emitted_decks_of_every_example() {
    for (name, m) in examples() {
        insta::assert_snapshot!(format!("{name}.adm"), adm(&m));
        let set = load_set(&m, None);
        let acf = set
            .clone()
            .and_then(|s| emit_acf(&m, s, &format!("{name}.adm"), &name));
        insta::assert_snapshot!(
            format!("{name}.acf"),
            acf.unwrap_or_else(|e| format!("error: {e}"))
        );
        let lcf = set.and_then(|s| emit_lcf(&m, s));
        insta::assert_snapshot!(
            format!("{name}.lcf"),
            lcf.unwrap_or_else(|e| format!("error: {e}"))
        );
    }
}

#[test]
fn every_emitted_deck_passes_the_strict_reader() {
    for (name, m) in examples() {
        let text = adm(&m);
        let st = adams_reader::parse(&text).unwrap_or_else(|e| panic!("{name}: {e}"));
        adams_reader::check(&st).unwrap_or_else(|e| panic!("{name}: {e}"));
        let bushings = st.iter().filter(|s| s.name == "BUSHING").count();
        let gforces = st
            .iter()
            .filter(|s| {
                s.name == "GFORCE" && s.values.contains_key("TZ") && s.values["FX"].contains("DX(")
            })
            .count();
        assert_eq!(
            bushings + gforces,
            m.bushings.len(),
            "{name}: one force element per bushing"
        );
    }
}

#[test]
fn emit_import_emit_is_a_fixed_point() {
    // Every example, the front axle's qualified names (`front_left.upright`,
    // its marker `front_left.upright.WC`) among them.
    for (name, m) in examples() {
        let first = adm(&m);
        let again = adm(&import(&first));
        assert_eq!(first, again, "{name}");
    }
}

/// Solves every case of every load set of `a`, and the same loads (mapped by
/// marker path) on `b`, each case from the previous state; part poses agree.
fn same_equilibria(name: &str, a: &Model, b: &Model) {
    let (pa, pb) = (Problem::new(a).expect("a"), Problem::new(b).expect("b"));
    for set in 0..a.load_sets.len() {
        let id = axle::model::LoadSetId(set as u32);
        let (mut sa, mut sb) = (State::design(a), State::design(b));
        for case in 0..a.load_sets[set].cases.len() {
            let la = a.point_loads(id, case);
            let lb: Vec<PointLoad> = la
                .iter()
                .map(|l| {
                    let mk = a.marker(l.marker);
                    let part = b.part_named(&a.part(mk.part).name).expect("same parts");
                    PointLoad {
                        marker: b.marker_named(part, &mk.name).expect("same markers"),
                        ..*l
                    }
                })
                .collect();
            // A case the original cannot solve (the tour model under the McPherson
            // sets' largest loads) must fail on the imported model too.
            match (solve(&pa, &la, &sa), solve(&pb, &lb, &sb)) {
                (Ok(ea), Ok(eb)) => (sa, sb) = (ea.state, eb.state),
                (Err(_), Err(_)) => break,
                (ra, rb) => panic!(
                    "{name} set {} case {case}: {:?} vs {:?}",
                    a.load_sets[set].name,
                    ra.err(),
                    rb.err()
                ),
            }
            for (k, p) in a.parts.iter().enumerate() {
                let (xa, ra) = sa.part_pose(axle::model::PartId(k as u32));
                let (xb, rb) = sb.part_pose(b.part_named(&p.name).expect("part"));
                let err = (xa - xb).norm().max((ra - rb).abs().max() * 1000.0);
                assert!(
                    err < 1e-6,
                    "{name} set {} case {case} part {}: {err:e} mm",
                    a.load_sets[set].name,
                    p.name
                );
            }
        }
    }
}

#[test]
fn imported_models_reach_the_same_equilibria() {
    for (name, m) in examples() {
        let back = import(&adm(&m));
        same_equilibria(&name, &m, &back);
    }
}

/// The data rows of a loadcase file.
fn lcf_rows(text: &str) -> Vec<Vec<f64>> {
    text.lines()
        .skip_while(|l| !l.starts_with("{ whl_z_l"))
        .skip(1)
        .map(|l| {
            l.split_whitespace()
                .filter_map(|x| x.parse().ok())
                .collect()
        })
        .collect()
}

/// A car's `.lcf` is one axle's (`--axle`): the front axle of the car under
/// its front bump is the front axle example's file under the same wheel
/// loads (the rear wheels' static loads are not in it), and a force at a
/// wheel centre (traction) is the `drive` column.
#[test]
fn an_lcf_of_a_car_is_one_axles_and_traction_is_the_drive_column() {
    let all = examples();
    let get = |n: &str| all.iter().find(|(x, _)| x == n).map(|(_, m)| m).expect(n);
    let (car, axle) = (get("vehicle"), get("front_axle"));
    let front = emit_lcf_axle(
        car,
        load_set(car, Some("front_bump")).expect("set"),
        &Vertical::Force,
        Some("front_right.wheel"),
    )
    .expect("the front axle's file");
    assert!(front.contains("$ left wheel: front_left.wheel\n$ right wheel: front_right.wheel\n"));
    let alone = emit_lcf(axle, load_set(axle, Some("parallel_bump")).expect("set")).expect("lcf");
    assert_eq!(lcf_rows(&front), lcf_rows(&alone));
    assert_eq!(lcf_rows(&front).len(), 57);
    let rear = emit_lcf_axle(
        car,
        load_set(car, Some("vehicle")).expect("set"),
        &Vertical::Force,
        Some("rear_left.wheel"),
    )
    .expect("the rear axle's file");
    // braking: 2500 N on each rear wheel, 1500 N of brake force (rearward +).
    let braking = &lcf_rows(&rear)[3];
    assert_eq!(
        (braking[0], braking[1], braking[10], braking[11]),
        (2500.0, 2500.0, 1500.0, 1500.0)
    );
    // A misspelt wheel gets its did-you-mean.
    let e = emit_lcf_axle(
        car,
        load_set(car, Some("vehicle")).expect("set"),
        &Vertical::Force,
        Some("rear_rigth.wheel"),
    )
    .expect_err("no such wheel");
    assert!(
        e.to_string().ends_with("did you mean `rear_right.wheel`?"),
        "{e}"
    );
    // Without --axle the car is refused, naming the way out.
    let e = emit_lcf(car, load_set(car, Some("vehicle")).expect("set")).expect_err("four wheels");
    assert!(e.to_string().contains("--axle"), "{e}");
    let traction =
        emit_lcf(axle, load_set(axle, Some("traction_opposed")).expect("set")).expect("lcf");
    // Case 2: +500 N forward at the left centre, -500 N at the right.
    let row = &lcf_rows(&traction)[1];
    assert_eq!(
        (row[12], row[13], row[10], row[11]),
        (500.0, -500.0, 0.0, 0.0)
    );
}

/// `.lcf` in `wheel_center_height` mode: each row's whl_z is the wheel-centre z
/// of that case's equilibrium (solved in order, as `axle solve` does), so the
/// McPherson wheel rises with its vertical load and sits at its design height
/// when the load is the one the spring carries at design.
#[test]
fn lcf_height_mode_writes_the_solved_wheel_centre_heights() {
    let (_, m) = examples()
        .into_iter()
        .find(|(n, _)| n == "mcpherson")
        .expect("mcpherson");
    let set = load_set(&m, Some("thesis_table_5_1")).expect("set");
    let h = axle::kc::heights::centre_heights(&m, set).expect("solves");
    let text = emit_lcf_as(&m, set, &Vertical::CentreHeight(h.clone())).expect("lcf");
    assert!(
        text.contains("VERTICAL_MODE  =  'wheel_center_height'"),
        "{text}"
    );
    let rows = lcf_rows(&text);
    assert_eq!(rows.len(), 13);
    // Independently: the same set solved case by case from the previous state.
    let p = Problem::new(&m).expect("problem");
    let mut st = State::design(&m);
    let wc = m.marker(m.wheels[0].centre);
    for (k, row) in rows.iter().enumerate() {
        st = solve(&p, &m.point_loads(set, k), &st).expect("case").state;
        let (x, r) = st.part_pose(wc.part);
        let z = (x + r * wc.origin()).z;
        assert!((row[0] - z).abs() < 1e-6, "case {k}: {} vs {z}", row[0]);
        // The half axle's missing right side is its mirror image, not a
        // request for a 0 mm wheel-centre height.
        assert_eq!(row[1], row[0], "right wheel mirrored");
    }
    // c1..c5: fz 1500..7500 N, strictly rising centre; lateral rows keep fy.
    assert!(
        rows[..5].windows(2).all(|w| w[1][0] > w[0][0] + 10.0),
        "{rows:?}"
    );
    assert_eq!(rows[5][2], -4000.0);
    assert_eq!(rows[5][3], 4000.0, "mirrored lateral force");
    assert!(text.contains("VERTICAL_MODE_FOR_SETUP  =  'wheel_center_height'"));
    assert!(text.contains("$ right wheel: none in the model; its columns mirror the left wheel's"));
}

/// The deck's wheel-angle REQUESTs report axle's toe and camber: their F2/F3
/// expressions, evaluated with the marker positions of each solved case (the
/// spin-axis marker moving with its part), equal `kc::wheel_quantities`, on a
/// left wheel (McPherson) and on both sides (coverage model), to 1e-6 deg
/// (the spin marker is written to 12 significant digits).
#[test]
fn wheel_angle_requests_evaluate_to_axle_toe_and_camber() {
    use axle::import::expr;
    for (name, m) in examples()
        .into_iter()
        .filter(|(n, _)| n == "mcpherson" || n == "coverage")
    {
        let st = adams_reader::parse(&adm(&m)).expect("reads");
        let part_of_view = |id: u32| -> (axle::model::PartId, axle::geom::Vec3) {
            let mk = st
                .iter()
                .find(|s| s.name == "MARKER" && s.id == Some(id))
                .expect("marker");
            let pid = mk.ints("PART")[0];
            let part = st
                .iter()
                .find(|s| s.name == "PART" && s.id == Some(pid))
                .expect("part");
            let q = mk.nums("QP");
            (
                m.part_named(part.view.as_deref().unwrap_or(""))
                    .expect("named"),
                axle::geom::Vec3::new(q[0], q[1], q[2]),
            )
        };
        let set = load_set(&m, None).expect("set");
        let p = Problem::new(&m).expect("problem");
        let mut state = State::design(&m);
        for case in 0..m.load_sets[set.index()].cases.len() {
            state = solve(&p, &m.point_loads(set, case), &state)
                .expect("case")
                .state;
            let at = |id: u32| {
                let (part, q) = part_of_view(id);
                let (x, r) = state.part_pose(part);
                x + r * q
            };
            for w in &m.wheels {
                let req = st
                    .iter()
                    .find(|s| s.view.as_deref() == Some(&format!("wheel.{}.angles", w.name)))
                    .expect("angles request");
                let eval = |key: &str| {
                    // DX/DY/DZ/DM(a,b) of the solved positions, then ADAMS arithmetic.
                    let mut e = req.values[key].clone();
                    while let Some(k) = ["DX(", "DY(", "DZ(", "DM("]
                        .iter()
                        .filter_map(|p| e.find(p))
                        .min()
                        .map(|k| k + 1)
                    {
                        let end = k + e[k..].find(')').expect(")");
                        let ids: Vec<u32> = e[k + 2..end]
                            .split(',')
                            .map(|x| x.trim().parse().expect("id"))
                            .collect();
                        let d = at(ids[0]) - at(ids[1]);
                        let v = match &e[k..=k] {
                            "X" => d.x,
                            "Y" => d.y,
                            "Z" => d.z,
                            _ => d.norm(),
                        };
                        e = format!("{}({v:e}){}", &e[..k - 1], &e[end + 1..]);
                    }
                    let (sp, vars) = (Default::default(), Default::default());
                    let c = expr::Ctx {
                        measure: None,
                        x: 0.0,
                        splines: &sp,
                        variables: &vars,
                    };
                    expr::eval(&expr::parse(&e).expect("parses"), &c, 0).expect("evaluates")
                };
                let q = axle::kc::wheel_quantities(&m, &state, w);
                let (toe, camber) = (eval("F2"), eval("F3"));
                assert!(
                    (toe - q.toe_deg).abs() < 1e-6,
                    "{name} {} case {case}: toe {toe} vs {}",
                    w.name,
                    q.toe_deg
                );
                assert!(
                    (camber - q.camber_deg).abs() < 1e-6,
                    "{name} {} case {case}: camber {camber} vs {}",
                    w.name,
                    q.camber_deg
                );
            }
        }
    }
}

#[test]
fn reuler_reproduces_marker_axes_including_singular_angles() {
    // Markers written by directions whose ZXZ angles are known, including
    // theta = 0 and 180° where only psi ± phi is defined.
    let cases: [(f64, f64, f64); 6] = [
        (30.0, 0.0, 20.0),
        (30.0, 180.0, 20.0),
        (-90.0, 180.0, 0.0),
        (10.0, 20.0, 30.0),
        (141.5, 166.7, 53.68),
        (0.0, 90.0, 0.0),
    ];
    let mut src = String::from(
        "model r\nground g {\n    marker o at (0, 0, 0) mm\n}\npart p {\n    marker o at (0, 0, 0) mm\n",
    );
    let mut rots = Vec::new();
    for (k, (p, t, f)) in cases.iter().enumerate() {
        let r = euler_zxz(p.to_radians(), t.to_radians(), f.to_radians());
        let (z, x) = (r.column(2), r.column(0));
        src += &format!(
            "    marker m{k} at (1, 2, 3) mm z ({}, {}, {}) x ({}, {}, {})\n",
            z[0], z[1], z[2], x[0], x[1], x[2]
        );
        rots.push(frame_from_z_x(z.into(), Some(x.into())).expect("frame"));
    }
    src += "}\nbushing b {\n    i p.o\n    j g.o\n    k (1, 1, 1) N/mm\n    kt (1, 1, 1) N*mm/deg\n}\n";
    let (_, checked) = check_str("r.axle", &src);
    let m = checked.model.expect("checks");
    let st = adams_reader::parse(&adm(&m)).expect("reads");
    for (k, r) in rots.iter().enumerate() {
        let mk = st
            .iter()
            .find(|s| s.view.as_deref() == Some(&format!("p.m{k}")))
            .expect("marker");
        let a = mk.nums("REULER");
        let back: Mat3 = euler_zxz(a[0].to_radians(), a[1].to_radians(), a[2].to_radians());
        assert!((back - r).abs().max() < 1e-9, "case {k}: {a:?}");
        if cases[k].1 == 0.0 || cases[k].1 == 180.0 {
            assert_eq!(a[2], 0.0, "singular case {k}: phi is set to 0");
        }
    }
}

#[test]
fn thesis_annexe_f_deck_becomes_an_axle_file() {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/adams/annexe_f.adm"
    ))
    .expect("data");
    let imp = import_adm("annexe_f.adm", &text);
    let src = imp.source.expect("imports");
    for want in [
        "model model_exemple11",
        "ground ground {",
        "part PART_2 {",
        "marker MARKER_8 at (0, 0, 0) mm euler (28.18678543, 33.22594022, 350.8538915) deg",
        "marker MARKER_13 at (-300, 0, 0) mm",
        "marker cm at (-150,",
        "joint JOINT_1 cylindrical {",
        "i PART_2.MARKER_7",
        "j ground.MARKER_8",
        "k_radial 100 N/mm",
        "kt_radial 9999.9999",
    ] {
        assert!(src.contains(want), "missing `{want}` in\n{src}");
    }
    // Skipped statements are reported with their lines, never silently.
    let msgs: Vec<&str> = imp.problems.iter().map(|d| d.message.as_str()).collect();
    assert!(
        msgs.iter().any(|m| m.starts_with("line 41: GRAPHICS/2")),
        "{msgs:?}"
    );
    assert!(msgs.iter().any(|m| m.contains("damping")), "{msgs:?}");
    assert!(msgs.iter().any(|m| m.contains("TIME")), "{msgs:?}");
    // FY = 1000 sin(0.15 pi) at TIME = 0.
    assert!(src.contains("453.99049974"), "{src}");
}

/// The public decks of `reference/adams-examples/` (copied into tests/data,
/// provenance in tests/data/adams/README.md) are read statement by statement;
/// what axle cannot hold is reported with its line, never dropped silently.
#[test]
fn public_adams_decks_are_read_with_every_skip_reported() {
    let read = |f: &str| {
        let path = format!("{}/tests/data/adams/{f}", env!("CARGO_MANIFEST_DIR"));
        let text = std::fs::read_to_string(path).expect("data");
        let imp = import_adm(f, &text);
        let msgs: Vec<String> = imp.problems.iter().map(|d| d.message.clone()).collect();
        (imp, msgs)
    };
    // Chrono's HOOKE pendulum (METER units): the deck is read in full, the
    // HOOKE becomes a universal on its cross axes, gravity and requests are
    // reported; the pendulum hangs free without gravity, which the checker
    // says, and the draft source is kept for the user to fix.
    let (imp, msgs) = read("chrono_universal.adm");
    let has = |m: &[String], s: &str| m.iter().any(|x| x.contains(s));
    assert!(has(&msgs, "line 41: JOINT/1: HOOKE"), "{msgs:?}");
    assert!(has(&msgs, "line 45: ACCGRAV/"), "{msgs:?}");
    assert!(has(&msgs, "REQUESTs at lines 49, 50"), "{msgs:?}");
    assert!(has(&msgs, "part `part_2` can move"), "{msgs:?}");
    let draft = imp.draft.expect("draft");
    // QP = 0, 2, 0 m is 2000 mm; the cross axes are x_I = X and y_J = Z.
    assert!(draft.contains("marker m201 at (0, 2000, 0) mm"), "{draft}");
    assert!(
        draft.contains("marker m102_hooke_i at (0, 0, 0) mm z (1, 0, 0) x (0, -1, 0)"),
        "{draft}"
    );
    assert!(
        draft.contains("marker m202_hooke_j at (0, 0, 0) mm z (0, 0, 1) x (0, -1, 0)"),
        "{draft}"
    );
    assert!(
        draft.contains(
            "joint joint_1 universal {\n    i ground.m102_hooke_i\n    j part_2.m202_hooke_j"
        ),
        "{draft}"
    );
    // Chrono spring excerpts: continued FUNCTION lines, a multi-line VARIABLE
    // and a one-line backslash REQUEST all read; the excerpt lacks its
    // markers and repeats SFORCE/1, each named with its line.
    let (imp, msgs) = read("chrono_springs.adm");
    assert!(imp.model.is_none());
    assert!(!has(&msgs, "unexpected"), "{msgs:?}");
    assert!(
        has(
            &msgs,
            "line 26: SFORCE/1: I = 204: MARKER/204 is not defined"
        ),
        "{msgs:?}"
    );
    assert!(
        has(
            &msgs,
            "line 44: SFORCE/1: SFORCE/1 is already defined at line 26"
        ),
        "{msgs:?}"
    );
    assert!(
        has(&msgs, "line 44: SFORCE/1: a rotational SFORCE"),
        "{msgs:?}"
    );
    assert!(
        has(
            &msgs,
            "line 52: JOINT/1: I = 102: MARKER/102 is not defined"
        ),
        "{msgs:?}"
    );
    assert!(has(&msgs, "REQUESTs at lines 19, 56"), "{msgs:?}");
}

/// The thesis' Annexe I bushing (methods.md §10.3): one SPLINE per direction
/// holding the restoring force on I (`Y = -K X`, torsional X in radians) and a
/// GFORCE `FX = AKISPL(DX(I,J,J), 0, id)`. Imported, the arm deflects by the
/// thesis' equivalent stiffnesses: 14 052.52 N/mm along x (70 262.6 N at
/// 5 mm) and 63 314 N·mm per 15° about z.
#[test]
fn thesis_annexe_i_spline_bushing_imports_with_its_stiffness() {
    let text = include_str!("data/adams/annexe_i_bushing.adm");
    let imp = import_adm("annexe_i_bushing.adm", text);
    let src = imp.source.clone().expect("imports");
    assert!(src.starts_with("model annexe_i_bushing"), "{src}");
    assert!(
        src.contains(
            "k_x table (mm, N) [(-10, -140525), (-5, -70262.6), (0, 0), (5, 70262.6), (10, 140525)]"
        ),
        "{src}"
    );
    let m = imp.model.expect("model");
    let arm = m.part_named("arm").expect("arm");
    let i = m.marker_named(arm, "I_ref").expect("I");
    let p = Problem::new(&m).expect("problem");
    let load = |force: [f64; 3], torque: [f64; 3]| {
        let l = PointLoad {
            marker: i,
            force: force.into(),
            torque: torque.into(),
        };
        solve(&p, &[l], &State::design(&m))
            .expect("solves")
            .state
            .part_pose(arm)
    };
    // 1405.252 N on the 14 052.52 N/mm segment: 0.1 mm.
    let (x, _) = load([1405.252, 0.0, 0.0], [0.0; 3]);
    assert!((x.x - 0.1).abs() < 1e-9 && x.y.abs() < 1e-9, "{x:?}");
    // 6331.4 N*mm about z on 63 314 N*mm per 0.261799 rad: 0.0261799 rad.
    let (_, r) = load([0.0; 3], [0.0, 0.0, 6331.4]);
    let az = r[(1, 0)].atan2(r[(0, 0)]);
    assert!((az - 0.0261799).abs() < 1e-9, "{az}");
}

#[test]
fn a_malformed_line_gets_a_diagnostic_with_its_line() {
    let imp = import_adm(
        "bad.adm",
        "title\nPART/1, GROUND\nMARKER/2, PART = 1, QP = 1, 2, oops3\nJOINT 3, I = 2\n",
    );
    let msgs: Vec<&str> = imp.problems.iter().map(|d| d.message.as_str()).collect();
    assert!(msgs.iter().any(|m| m.starts_with("line 4:")), "{msgs:?}");
    assert!(imp.source.is_none());
}

#[test]
fn elements_adams_cannot_hold_are_errors_naming_them() {
    let m = examples()
        .into_iter()
        .find(|(n, _)| n == "four_bar")
        .expect("four_bar")
        .1;
    let e = emit_lcf(&m, load_set(&m, None).expect("set")).expect_err("no wheels");
    assert!(e.to_string().contains("coupler.mid.fx"), "{e}");
    let e = load_set(&m, Some("nope")).expect_err("unknown");
    assert!(e.to_string().contains("nope"), "{e}");
}

mod no_panics {
    use proptest::prelude::*;

    proptest! {
        #![proptest_config(ProptestConfig { cases: 96, ..ProptestConfig::default() })]
        #[test]
        fn mutated_decks_never_panic(cut in 0usize..4000, len in 0usize..40, junk in "[ -~\n]{0,12}") {
            let text = include_str!("data/adams/annexe_f.adm");
            let (a, b) = (cut.min(text.len()), (cut + len).min(text.len()));
            if text.is_char_boundary(a) && text.is_char_boundary(b) {
                let mutated = format!("{}{}{}", &text[..a], junk, &text[b..]);
                let _ = axle::import::import_adm("m.adm", &mutated);
            }
        }
    }
}

#[test]
fn cli_emit_and_import_exit_codes() {
    let bin = env!("CARGO_BIN_EXE_axle");
    let dir = std::env::temp_dir().join(format!("axle_adams_{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("tmp");
    let ex = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/mcpherson.axle");
    let out = dir.join("m.adm");
    let st = std::process::Command::new(bin)
        .args(["emit", "adm", ex, "-o"])
        .arg(&out)
        .output()
        .expect("runs");
    assert_eq!(st.status.code(), Some(0));
    // The deck drops the measurement points, and says so on stderr.
    assert!(String::from_utf8_lossy(&st.stderr).contains("20 landmarks are measurement points"));
    let st = std::process::Command::new(bin)
        .args(["import", "adm"])
        .arg(&out)
        .arg("-o")
        .arg(dir.join("m.axle"))
        .output()
        .expect("runs");
    assert_eq!(st.status.code(), Some(0));
    assert!(String::from_utf8_lossy(&st.stderr).contains("W0902"));
    let bad = dir.join("bad.adm");
    std::fs::write(&bad, "t\nPART 1\n").expect("write");
    let o = std::process::Command::new(bin)
        .args(["import", "adm"])
        .arg(&bad)
        .output()
        .expect("runs");
    assert_eq!(o.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&o.stderr).contains("line 2"));
    // An element ADAMS/Car cannot hold is labelled at its line in the axle file.
    let fb = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/four_bar.axle");
    let o = std::process::Command::new(bin)
        .args(["emit", "lcf", fb])
        .output()
        .expect("runs");
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1));
    assert!(
        err.contains("error[E0910]") && err.contains("four_bar.axle:61:7"),
        "{err}"
    );
    // A deck that reads but does not check: the draft source is kept.
    let deck = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/adams/chrono_universal.adm"
    );
    let draft = dir.join("u.axle");
    let o = std::process::Command::new(bin)
        .args(["import", "adm", deck, "-o"])
        .arg(&draft)
        .output()
        .expect("runs");
    assert_eq!(o.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&o.stderr).contains("was written to"));
    let text = std::fs::read_to_string(&draft).expect("draft written");
    assert!(text.contains("part part_2 {"), "{text}");
    // Captured, so the test prints no stray diagnostic.
    let o = std::process::Command::new(bin)
        .args(["emit", "lcf", "/nonexistent.axle"])
        .output()
        .expect("runs");
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("E0003"));
}
