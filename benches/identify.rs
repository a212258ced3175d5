//! Speed of stiffness identification on the McPherson benchmark
//! (`docs/performance.md`, "Identification"; targets from issue 6): the
//! direct method over the 17 steps of thesis Table 4.4, the iterative method
//! to tolerance 0.01 over Table 5-1 from the thesis' all-10000 start (Table
//! 5.2), and least squares over every bushing stiffness and the spring's k and
//! free length. Data are synthetic, from the truth model (the example).
//! Run with `cargo bench --bench identify`.

use axle::identify::{self, Measured, Unknown};
use axle::model::{LoadSetId, Model};
use axle::statics::{self, State};
use divan::Bencher;

fn main() {
    // Iteration counts and unknown counts, printed once so the docs can quote them.
    let (m, data) = direct_case();
    let u = identify::select_unknowns(&m, &[]).expect("unknowns");
    let r = identify::direct::identify(&m, &u, &data, Default::default()).expect("direct");
    println!(
        "direct: {} steps, {} unknowns, rank {}",
        data.steps.len(),
        u.len(),
        r.rank
    );
    let (init, u, data) = iterative_case();
    let r = identify::iterative::identify(&init, &u, &data, Default::default()).expect("iter");
    println!(
        "iterative: {} steps, {} unknowns, {} iterations",
        data.steps.len(),
        u.len(),
        r.iterations
    );
    // Newton iterations of one pass (13 warm-started solves) early and late:
    // the iterative method's cost is 22 passes of the statics engine.
    let pass = |a: &[f64], b: &[f64]| {
        let (mut ma, mut mb) = (init.clone(), init.clone());
        for ((x, va), vb) in u.iter().zip(a).zip(b) {
            x.set(&mut ma, *va);
            x.set(&mut mb, *vb);
        }
        let (pa, pb) = (
            statics::Problem::new(&ma).expect("problem"),
            statics::Problem::new(&mb).expect("problem"),
        );
        let loads = || data.steps.iter().map(|s| &s.loads);
        let design = State::design(&ma);
        let a = statics::path::simulate(&pa, loads(), &design)
            .into_result()
            .expect("solves");
        let guesses: Vec<State> = a.into_iter().map(|e| e.state).collect();
        let b = statics::path::Simulator::new()
            .run(&pb, loads(), &design, &guesses)
            .into_result()
            .expect("solves");
        b.iter().map(|e| e.iterations).sum::<usize>()
    };
    let h = &r.history;
    println!(
        "iterative: Newton iterations per pass of 13 warm solves: pass 2 {}, pass {} {}",
        pass(&h[1].values, &h[2].values),
        h.len() - 1,
        pass(&h[h.len() - 2].values, &h[h.len() - 1].values)
    );
    let (init, u, data) = lsq_case();
    let r = identify::lsq::identify(&init, &u, &data, Default::default()).expect("lsq");
    let ok = r.params.iter().filter(|p| p.identifiable).count();
    println!(
        "lsq: {} steps, {} unknowns, {} LM iterations, sigma0 {:.3}, {} identifiable",
        data.steps.len(),
        u.len(),
        r.iterations,
        r.sigma0.unwrap_or(f64::NAN),
        ok
    );
    for (un, p) in u.iter().zip(&r.params) {
        if let (Some(v), Some((lo, hi))) = (p.value, p.interval) {
            let b = |x: f64| axle::units::to_boundary(x, un.dim);
            println!("  {} {:.5} [{:.5}, {:.5}]", un.label(), b(v), b(lo), b(hi));
        }
    }
    divan::main();
}

fn mcpherson() -> Model {
    let (_, c) =
        axle::check::check_str("mcpherson.axle", include_str!("../examples/mcpherson.axle"));
    c.model.expect("the example checks")
}

fn set(m: &Model, name: &str) -> LoadSetId {
    m.load_set_named(name).expect("stdlib set")
}

/// Table 4.4's 17 steps with every part pose known (the strut has no
/// landmarks; chapter 4 needs every pose).
fn direct_case() -> (Model, Measured) {
    let m = mcpherson();
    let s = set(&m, "thesis_table_4_4");
    let steps: Vec<(State, Vec<_>)> = statics::solve_set(&m, s)
        .expect("solves")
        .into_iter()
        .enumerate()
        .map(|(c, e)| (e.state, m.point_loads(s, c)))
        .collect();
    let data = Measured::from_states(&m, &steps);
    (m, data)
}

/// Landmarks of the truth along Table 5-1 (noise `sigma`, mm), through the
/// whole measuring path: CSV, reader, pose fits.
fn landmarks(truth: &Model, sigma: f64) -> Measured {
    let s = set(truth, "thesis_table_5_1");
    let csv = axle::measure::synthetic::landmarks_csv(truth, s, sigma, 1).expect("solves");
    let (obs, _) = axle::data::landmarks::read(&csv, truth).expect("reads");
    let (poses, _) = axle::measure::poses::fit_poses(truth, &obs, 0.5);
    let steps: Vec<usize> = poses.iter().map(|p| p.step).collect();
    let loads =
        identify::measured::match_in_order(identify::measured::loads_of_set(truth, s), &steps)
            .expect("counts agree");
    Measured::from_poses(truth, &poses, &loads).expect("measured")
}

fn named(m: &Model, bushings: &[&str]) -> Vec<Unknown> {
    let names: Vec<String> = bushings
        .iter()
        .flat_map(|b| ["k_x", "k_y", "k_z", "kt_x", "kt_y", "kt_z"].map(|f| format!("{b}.{f}")))
        .collect();
    identify::select_unknowns(m, &names).expect("unknowns")
}

/// Table 5.2: bushings A and B, every stiffness started at 10000.
fn iterative_case() -> (Model, Vec<Unknown>, Measured) {
    let truth = mcpherson();
    let data = landmarks(&truth, 0.0);
    let mut init = truth.clone();
    for u in named(&truth, &["A", "B"]) {
        u.set(&mut init, axle::units::from_boundary(10000.0, u.dim));
    }
    let u = named(&init, &["A", "B"]);
    (init, u, data)
}

/// Every bushing stiffness (A, B, F; axisymmetric radial pairs tied) and the
/// spring's k and free length, started 30 % high and 5 mm long, from
/// σ = 0.05 mm landmarks.
fn lsq_case() -> (Model, Vec<Unknown>, Measured) {
    let truth = mcpherson();
    let data = landmarks(&truth, 0.05);
    let mut init = truth.clone();
    for u in identify::select_unknowns(&truth, &[]).expect("unknowns") {
        let v = if u.is_stiffness() {
            u.initial * 1.3
        } else {
            u.initial + 5.0
        };
        u.set(&mut init, v);
    }
    let u = identify::select_unknowns(&init, &[]).expect("unknowns");
    (init, u, data)
}

/// Direct method, 17 steps, every default unknown (target: under 1 ms).
#[divan::bench]
fn direct_table_4_4(b: Bencher) {
    let (m, data) = direct_case();
    let u = identify::select_unknowns(&m, &[]).expect("unknowns");
    b.bench_local(|| identify::direct::identify(&m, &u, &data, Default::default()).expect("ok"));
}

/// Iterative method to tolerance 0.01 (target: under 20 ms).
#[divan::bench(sample_count = 20)]
fn iterative_table_5_2(b: Bencher) {
    let (init, u, data) = iterative_case();
    b.bench_local(|| {
        identify::iterative::identify(&init, &u, &data, Default::default()).expect("ok")
    });
}

/// Least squares over every stiffness and the spring (target: under 200 ms).
#[divan::bench(sample_count = 5)]
fn lsq_all_stiffnesses_and_spring(b: Bencher) {
    let (init, u, data) = lsq_case();
    b.bench_local(|| identify::lsq::identify(&init, &u, &data, Default::default()).expect("ok"));
}
