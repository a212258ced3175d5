//! The direct documents against the serde_json tree they replace.
use super::*;
use crate::kc::kc_rows;
use crate::model::{LoadSetId, Model};
use crate::output::number::round_exact;
use crate::output::report::Reporter;
use crate::statics::{Problem, State, compliance, path::run_set};
use serde_json::json;

/// The rounding of the tree before the direct writer: every float printed
/// and parsed back (`round_exact`), noise flushed to 0.
fn round_tree(v: &mut Value) {
    match v {
        Value::Number(n) if n.is_f64() => {
            let x = n.as_f64().unwrap_or(f64::NAN);
            let r = if x.abs() < crate::output::number::ZERO {
                0.0
            } else {
                round_exact(x)
            };
            if let Some(r) = serde_json::Number::from_f64(r) {
                *n = r;
            }
        }
        Value::Array(a) => a.iter_mut().for_each(round_tree),
        Value::Object(o) => o.values_mut().for_each(round_tree),
        _ => {}
    }
}

fn model(name: &str, text: &str) -> Model {
    let (_, c) = crate::check::check_str(name, text);
    c.model.expect("the example checks")
}

/// The random McPherson path of issue 12 (fz 2000-7000 N, fx and fy within
/// ±2500 N, steps of at most 1500 N), from a fixed xorshift seed, as a loads CSV.
fn random_loads(n: usize) -> String {
    let mut s = 0x2545_F491_4F6C_DD1Du64;
    let mut uniform = || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s >> 11) as f64 / (1u64 << 53) as f64
    };
    let (lo, hi) = ([-2500.0, -2500.0, 2000.0], [2500.0, 2500.0, 7000.0]);
    let mut x = [0.0, 0.0, 3000.0];
    let mut out = String::from("step,fx,fy,fz\n");
    for k in 0..n {
        let d = [0; 3].map(|_| 2.0 * uniform() - 1.0);
        let len = d.iter().map(|v| v * v).sum::<f64>().sqrt().max(1e-9);
        // at most 1500 N per step, less after the clamp into the box
        let r = 1500.0 * uniform();
        for i in 0..3 {
            let v = (x[i] + r * d[i] / len).clamp(lo[i], hi[i]);
            x[i] = (v * 10.0).round() / 10.0;
        }
        out += &format!("{},{},{},{}\n", k + 1, x[0], x[1], x[2]);
    }
    out
}

/// `solve`'s document both ways (the reports by one `Reporter`, as
/// `axle solve` makes them: the writer replays the cases' layout).
fn both_solve(m: &Model, set: LoadSetId) -> (String, String) {
    let p = Problem::new(m).expect("problem");
    let run = run_set(&p, set, &State::design(m));
    let ls = &m.load_sets[set.index()];
    let reporter = Reporter::new(m);
    let reports: Vec<CaseReport> = run
        .steps
        .iter()
        .zip(&ls.cases)
        .enumerate()
        .map(|(k, (eq, c))| reporter.case(&c.name, k + 1, eq))
        .collect();
    let failed = run.failure.as_ref().map(|e| {
        let name = &ls.cases[e.case].name;
        FailedCase::new(m, name, e.case + 1, &e.error)
    });
    let trim = json!({"param": "spring.k", "value": 12.345678901234, "iterations": 3});
    let mut v = json!({ "model": m.name, "load_set": ls.name, "cases": reports });
    if let (Some(f), Some(cases)) = (&failed, v["cases"].as_array_mut()) {
        cases.push(json!(f));
    }
    v["trim"] = trim.clone();
    round_tree(&mut v);
    // Written out after every case, as `axle solve` writes a long path
    // in pieces: the layouts replayed across the pieces.
    let mut doc = SolveDocument::new();
    let mut direct = Vec::new();
    for r in &reports {
        doc.case(r);
        doc.drain(|b| direct.extend_from_slice(b));
    }
    let tail = doc.end(&ls.name, &m.name, failed.as_ref(), None, Some(&trim));
    direct.extend_from_slice(tail.as_bytes());
    let whole = solve(
        &m.name,
        &ls.name,
        &reports,
        failed.as_ref(),
        None,
        Some(&trim),
    );
    assert_eq!(
        String::from_utf8_lossy(&direct),
        whole,
        "in pieces and whole"
    );
    (whole, format!("{v:#}\n"))
}

#[test]
fn solve_documents_are_the_trees_bytes_on_every_example() {
    let examples = [
        (
            "mcpherson.axle",
            include_str!("../../examples/mcpherson.axle"),
        ),
        (
            "mcpherson_friction.axle",
            include_str!("../../examples/mcpherson_friction.axle"),
        ),
        (
            "four_bar.axle",
            include_str!("../../examples/four_bar.axle"),
        ),
        (
            "slider_crank.axle",
            include_str!("../../examples/slider_crank.axle"),
        ),
        (
            "single_bushing.axle",
            include_str!("../../examples/single_bushing.axle"),
        ),
        ("tour.axle", include_str!("../../examples/tour.axle")),
    ];
    let mut documents = 0;
    for (name, text) in examples {
        let m = model(name, text);
        for k in 0..m.load_sets.len() {
            let (direct, tree) = both_solve(&m, LoadSetId(k as u32));
            assert_eq!(direct, tree, "{name}, set {}", m.load_sets[k].name);
            documents += 1;
        }
    }
    assert!(documents >= 6, "{documents} documents compared");
}

#[test]
fn solve_document_of_a_500_case_random_path_is_the_trees_bytes() {
    let mut m = model(
        "mcpherson.axle",
        include_str!("../../examples/mcpherson.axle"),
    );
    let set = crate::data::loads::read(&random_loads(500), "random_500", &m).expect("csv");
    assert_eq!(set.cases.len(), 500);
    m.load_sets.push(set);
    let (direct, tree) = both_solve(&m, LoadSetId(m.load_sets.len() as u32 - 1));
    assert!(direct.len() > 1_000_000, "{} bytes", direct.len());
    assert_eq!(direct, tree);
}

#[test]
fn kc_document_is_the_trees_bytes() {
    let m = model(
        "mcpherson.axle",
        include_str!("../../examples/mcpherson.axle"),
    );
    let set = m.load_set_named("thesis_table_5_1").expect("set");
    let p = Problem::new(&m).expect("problem");
    let eqs = run_set(&p, set, &State::design(&m))
        .into_result()
        .expect("solves");
    let states: Vec<&State> = eqs.iter().map(|e| &e.state).collect();
    let rows = kc_rows(&m, set, &states);
    let c = compliance(&p, &eqs[0], m.wheels[0].centre).expect("compliance");
    let comp = vec![(
        m.wheels[0].name.clone(),
        [0, 1, 2].map(|i| [0, 1, 2].map(|j| c[i][j] * 1000.0)),
    )];
    let iterations: Vec<usize> = eqs.iter().map(|e| e.iterations).collect();
    let ls = &m.load_sets[set.index()];
    let failed = FailedCase {
        name: "x".into(),
        step: 14,
        converged: false,
        code: "E1001",
        error: "no \"equilibrium\"".into(),
        elements: vec!["bushing A".into()],
    };
    for f in [None, Some(&failed)] {
        let cm: serde_json::Map<String, Value> =
            comp.iter().map(|(w, m)| (w.clone(), json!(m))).collect();
        let mut v = json!({
            "model": m.name, "sweep": ls.name, "rows": crate::output::kc_table::json_rows(&rows),
            "compliance_mm_per_kn": cm, "iterations": iterations,
        });
        if let Some(f) = f {
            v["failed"] = json!(f);
        }
        round_tree(&mut v);
        let direct = kc(
            &m.name,
            &ls.name,
            &rows,
            &comp,
            &PathMetrics::default(),
            &iterations,
            f,
        );
        assert_eq!(direct, format!("{v:#}\n"));
    }
}
