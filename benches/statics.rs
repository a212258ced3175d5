//! Speed of the statics engine on the McPherson benchmark (`docs/performance.md`):
//! the 13-case thesis table 5-1 from a warm start and from design, the 57-step
//! bump sweep (also with strut friction), and scaling with a synthetic model of N McPherson corners on one
//! ground, uncoupled and coupled in a chain (one mechanism: the sparse
//! solver's case); the 500-case random load path of issue 12 and the cost of its
//! `solve --format json` document. Run with `cargo bench --bench statics`.

use axle::model::{Channel, LoadSet, LoadSetId, LoadTarget, Model, PartId, WheelId};
use axle::statics::Problem;
use axle::statics::path::{solve_path, solve_path_from};
use divan::Bencher;

fn main() {
    // Newton iterations per case, printed once so the docs can quote them.
    let (m, set) = mcpherson("thesis_table_5_1");
    let p = Problem::new(&m).expect("problem");
    let cold = solve_path(&p, set).expect("solves");
    let warm = solve_path_from(&p, set, &cold[cold.len() - 1].state).expect("solves");
    let its = |eqs: &[axle::statics::Equilibrium]| {
        eqs.iter()
            .map(|e| e.iterations.to_string())
            .collect::<Vec<_>>()
            .join(" ")
    };
    println!(
        "thesis_table_5_1 iterations per case, from design: {}",
        its(&cold)
    );
    println!(
        "thesis_table_5_1 iterations per case, warm start:  {}",
        its(&warm)
    );
    let lus = |eqs: &[axle::statics::Equilibrium]| {
        eqs.iter()
            .map(|e| e.factorizations.to_string())
            .collect::<Vec<_>>()
            .join(" ")
    };
    println!(
        "thesis_table_5_1 LU factorisations per case, warm start: {}",
        lus(&warm)
    );
    let subs: Vec<String> = warm.iter().map(|e| e.substeps.to_string()).collect();
    println!(
        "thesis_table_5_1 extra load sub-steps per case, warm start: {}",
        subs.join(" ")
    );
    // Newton steps of the N-corner bench, for the cost per step.
    for n in [1, 2, 4, 8] {
        let (m, set) = corners(n);
        let p = Problem::new(&m).expect("problem");
        let start = solve_path(&p, set)
            .expect("solves")
            .pop()
            .expect("cases")
            .state;
        let warm = solve_path_from(&p, set, &start).expect("solves");
        let steps: usize = warm.iter().map(|e| e.iterations).sum();
        let lus: usize = warm.iter().map(|e| e.factorizations).sum();
        println!("corners N = {n}: {steps} Newton steps, {lus} factorisations (warm set)");
    }
    for n in [1, 2, 4, 8] {
        let (m, set) = coupled_corners(n);
        let p = Problem::new(&m).expect("problem");
        let start = solve_path(&p, set)
            .expect("solves")
            .pop()
            .expect("cases")
            .state;
        let warm = solve_path_from(&p, set, &start).expect("solves");
        let steps: usize = warm.iter().map(|e| e.iterations).sum();
        let lus: usize = warm.iter().map(|e| e.factorizations).sum();
        println!("coupled corners N = {n}: {steps} Newton steps, {lus} factorisations (warm set)");
    }
    // The random path's work, and a digest of every result (bit for bit).
    let (m, set) = random_path(500);
    let p = Problem::new(&m).expect("problem");
    let eqs = solve_path(&p, set).expect("solves");
    let steps: usize = eqs.iter().map(|e| e.iterations).sum();
    let lus: usize = eqs.iter().map(|e| e.factorizations).sum();
    // How the cases' work is spread: the median case is one of these kinds.
    let mut kinds = std::collections::BTreeMap::new();
    for e in &eqs {
        *kinds
            .entry((e.iterations, e.factorizations))
            .or_insert(0usize) += 1;
    }
    let kinds: Vec<String> = kinds
        .iter()
        .map(|((s, f), c)| format!("{c} of ({s}, {f})"))
        .collect();
    println!(
        "random_500_path cases by (Newton steps, factorisations): {}",
        kinds.join(", ")
    );
    let mut h = std::collections::hash_map::DefaultHasher::new();
    std::hash::Hash::hash(&format!("{eqs:?}"), &mut h);
    println!(
        "random_500_path: {steps} Newton steps, {lus} factorisations; results digest {:016x}",
        std::hash::Hasher::finish(&h)
    );
    let (median, mean) = case_times(&p, set, &m, 21);
    println!(
        "random_500_path per case, medians of 21 runs: median case {median:.2} µs, mean case {mean:.2} µs"
    );
    // A peer's own loads file timed the same way, for a comparison on the
    // very cases it solved (`AXLE_BENCH_LOADS=…/random_500.csv`, the CSV of
    // `interfaces.md`): the bench's path has the same statistics, not the
    // same cases.
    if let Ok(path) = std::env::var("AXLE_BENCH_LOADS") {
        let text = std::fs::read_to_string(&path).expect("the loads file reads");
        let (m, set) = mcpherson_with_loads(&text, "peer");
        let cases = m.load_sets[set.0 as usize].cases.len();
        let p = Problem::new(&m).expect("problem");
        let (median, mean) = case_times(&p, set, &m, 21);
        println!(
            "{path} ({cases} cases) per case, medians of 21 runs: median case {median:.2} µs, mean case {mean:.2} µs"
        );
    }
    divan::main();
}

/// A path's cases each timed on its own, as Exudyn's script
/// times its cases (`../shared/peers/exudyn`, the median over the cases of
/// one run): per run, the median and the mean case over the path (the first
/// case, from design with a fresh solver, is one of them), and of each the
/// median over `runs` runs. The divan bench's median path over 500 is a
/// mean case; compared with Exudyn's median case it counts the slow cases
/// on one side only.
fn case_times(p: &Problem, set: LoadSetId, m: &Model, runs: usize) -> (f64, f64) {
    let loads = axle::statics::path::set_loads(m, set).expect("loads");
    let start = axle::statics::State::design(m);
    let (mut medians, mut means) = (Vec::new(), Vec::new());
    for _ in 0..runs {
        let mut times: Vec<f64> = Vec::with_capacity(loads.len());
        let mut at = std::time::Instant::now();
        let run = axle::statics::path::Simulator::new().run_each(p, &loads, &start, |_, _| {
            let now = std::time::Instant::now();
            times.push((now - at).as_secs_f64() * 1e6);
            at = now;
            std::ops::ControlFlow::Continue(())
        });
        assert!(run.failure.is_none(), "the path solves");
        means.push(times.iter().sum::<f64>() / times.len() as f64);
        medians.push(median(&mut times));
    }
    (median(&mut medians), median(&mut means))
}

/// The median of `v` (the mean of the middle two for an even length).
fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    let k = v.len() / 2;
    if v.len() % 2 == 1 {
        v[k]
    } else {
        0.5 * (v[k - 1] + v[k])
    }
}

/// The McPherson example and one of its load sets.
fn mcpherson(set: &str) -> (Model, LoadSetId) {
    let (_, c) =
        axle::check::check_str("mcpherson.axle", include_str!("../examples/mcpherson.axle"));
    let m = c.model.expect("the example checks");
    let id = m.load_set_named(set).expect("stdlib set");
    (m, id)
}

/// `n` copies of the McPherson corner on the one ground (elements renamed
/// `name_k`), loaded by table 5-1 at every wheel at once.
fn corners(n: usize) -> (Model, LoadSetId) {
    let (base, set) = mcpherson("thesis_table_5_1");
    let ground = base.ground().expect("ground");
    let mut m = base.clone();
    for k in 1..n {
        let parts: Vec<PartId> = base
            .parts
            .iter()
            .map(|p| {
                if p.ground {
                    return ground;
                }
                let mut q = p.clone();
                q.name = format!("{}_{k}", p.name);
                m.parts.push(q);
                PartId(m.parts.len() as u32 - 1)
            })
            .collect();
        let off = m.markers.len() as u32;
        for mk in &base.markers {
            let mut c = mk.clone();
            c.name = format!("{}_{k}", mk.name);
            c.part = parts[mk.part.index()];
            m.markers.push(c);
        }
        let mid = |id: axle::model::MarkerId| axle::model::MarkerId(id.0 + off);
        for j in &base.joints {
            let mut c = j.clone();
            (c.name, c.i, c.j) = (format!("{}_{k}", j.name), mid(j.i), mid(j.j));
            m.joints.push(c);
        }
        for b in &base.bushings {
            let mut c = b.clone();
            (c.name, c.i, c.j) = (format!("{}_{k}", b.name), mid(b.i), mid(b.j));
            m.bushings.push(c);
        }
        for s in &base.springs {
            let mut c = s.clone();
            (c.name, c.i, c.j) = (format!("{}_{k}", s.name), mid(s.i), mid(s.j));
            m.springs.push(c);
        }
        for w in &base.wheels {
            let mut c = w.clone();
            (c.name, c.part, c.centre, c.contact) = (
                format!("{}_{k}", w.name),
                parts[w.part.index()],
                mid(w.centre),
                mid(w.contact),
            );
            m.wheels.push(c);
        }
    }
    let src = &base.load_sets[set.index()];
    let channels: Vec<Channel> = (0..m.wheels.len())
        .flat_map(|w| {
            src.channels.iter().map(move |c| Channel {
                target: LoadTarget::Wheel(WheelId(w as u32)),
                component: c.component,
            })
        })
        .collect();
    let mut cases = src.cases.clone();
    for c in &mut cases {
        c.values = c.values.repeat(m.wheels.len());
    }
    m.load_sets = vec![LoadSet {
        name: "corners".into(),
        channels,
        cases,
        form: src.form.clone(),
    }];
    (m, LoadSetId(0))
}

/// [`corners`] with corner `k`'s front arm held to corner `k + 1`'s by a soft
/// bushing (100 N/mm, 1e5 N·mm/rad): one mechanism of `30 N` coordinates and
/// `17 N` multipliers whose Newton matrix does not split into blocks.
fn coupled_corners(n: usize) -> (Model, LoadSetId) {
    use axle::model::{AxisLaw, AxisLaws, MarkerId};
    let (mut m, set) = corners(n);
    let per = m.markers.len() / n;
    let arm = m.part_named("front_arm").expect("part");
    let b = m.markers[..per]
        .iter()
        .position(|mk| mk.part == arm && mk.name == "B")
        .expect("front_arm.B");
    let soft = |k: f64| AxisLaws::from_three([0; 3].map(|_| AxisLaw::linear(k)), false);
    let template = m.bushings[0].clone();
    for k in 0..n.saturating_sub(1) {
        let mut c = template.clone();
        c.name = format!("link_{k}");
        c.i = MarkerId((k * per + b) as u32);
        c.j = MarkerId(((k + 1) * per + b) as u32);
        c.translational = soft(100.0);
        c.rotational = soft(1e5);
        m.bushings.push(c);
    }
    (m, set)
}

/// The 13 cases of table 5-1, starting from the last case's equilibrium (the
/// situation of an identification loop re-solving the same set).
#[divan::bench]
fn table_5_1_warm(b: Bencher) {
    let (m, set) = mcpherson("thesis_table_5_1");
    let p = Problem::new(&m).expect("problem");
    let start = solve_path(&p, set)
        .expect("solves")
        .pop()
        .expect("cases")
        .state;
    b.bench_local(|| solve_path_from(&p, set, &start).expect("solves"));
}

/// The 13 cases from the design configuration, Problem compiled each time (what `axle solve` does).
#[divan::bench]
fn table_5_1_cold_with_compile(b: Bencher) {
    let (m, set) = mcpherson("thesis_table_5_1");
    b.bench_local(|| {
        let p = Problem::new(&m).expect("problem");
        solve_path(&p, set).expect("solves")
    });
}

/// The 57-step bump sweep from design.
#[divan::bench]
fn bump_sweep(b: Bencher) {
    let (m, set) = mcpherson("bump");
    let p = Problem::new(&m).expect("problem");
    b.bench_local(|| solve_path(&p, set).expect("solves"));
}

/// The same sweep on the McPherson with strut friction (kf 1000 N/mm, Ff
/// 150 N): the cost of the history (issue 10: at most twice `bump_sweep`).
#[divan::bench]
fn bump_sweep_with_friction(b: Bencher) {
    let (_, c) = axle::check::check_str(
        "mcpherson_friction.axle",
        include_str!("../examples/mcpherson_friction.axle"),
    );
    let m = c.model.expect("the example checks");
    let set = m.load_set_named("bump").expect("stdlib set");
    let p = Problem::new(&m).expect("problem");
    b.bench_local(|| solve_path(&p, set).expect("solves"));
}

/// Table 5-1 at every corner of an N-corner model, warm start.
#[divan::bench(args = [1, 2, 4, 8])]
fn corners_table_5_1_warm(b: Bencher, n: usize) {
    let (m, set) = corners(n);
    let p = Problem::new(&m).expect("problem");
    let start = solve_path(&p, set)
        .expect("solves")
        .pop()
        .expect("cases")
        .state;
    b.bench_local(|| solve_path_from(&p, set, &start).expect("solves"));
}

/// Table 5-1 at every corner of the coupled N-corner model, warm start.
#[divan::bench(args = [1, 2, 4, 8])]
fn coupled_corners_table_5_1_warm(b: Bencher, n: usize) {
    let (m, set) = coupled_corners(n);
    let p = Problem::new(&m).expect("problem");
    let start = solve_path(&p, set)
        .expect("solves")
        .pop()
        .expect("cases")
        .state;
    b.bench_local(|| solve_path_from(&p, set, &start).expect("solves"));
}

/// The random McPherson path of issue 12 (wheel loads at the contact point:
/// fz 2000-7000 N, fx and fy within ±2500 N, a random walk with steps of at
/// most 1500 N, fixed xorshift seed) added to the model as a load set.
fn random_path(n: usize) -> (Model, LoadSetId) {
    let mut s = 0x2545_F491_4F6C_DD1Du64;
    let mut uniform = || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s >> 11) as f64 / (1u64 << 53) as f64
    };
    let (lo, hi) = ([-2500.0, -2500.0, 2000.0], [2500.0, 2500.0, 7000.0]);
    let mut x = [0.0f64, 0.0, 3000.0];
    let mut csv = String::from("step,fx,fy,fz\n");
    for k in 0..n {
        let d = [0; 3].map(|_| 2.0 * uniform() - 1.0);
        let len = d.iter().map(|v| v * v).sum::<f64>().sqrt().max(1e-9);
        let r = 1500.0 * uniform();
        for i in 0..3 {
            let v = (x[i] + r * d[i] / len).clamp(lo[i], hi[i]);
            x[i] = (v * 10.0).round() / 10.0;
        }
        csv += &format!("{},{},{},{}\n", k + 1, x[0], x[1], x[2]);
    }
    mcpherson_with_loads(&csv, "random")
}

/// The McPherson example with the loads CSV `csv` (`interfaces.md`) as its
/// load set `name`.
fn mcpherson_with_loads(csv: &str, name: &str) -> (Model, LoadSetId) {
    let (mut m, _) = mcpherson("thesis_table_5_1");
    let set = axle::data::loads::read(csv, name, &m).expect("loads csv");
    m.load_sets.push(set);
    let id = LoadSetId(m.load_sets.len() as u32 - 1);
    (m, id)
}

/// The 500-case random path from design, `Problem` compiled once (divide by
/// 500 for the cost per case).
#[divan::bench(sample_count = 30)]
fn random_500_path(b: Bencher) {
    let (m, set) = random_path(500);
    let p = Problem::new(&m).expect("problem");
    b.bench_local(|| solve_path(&p, set).expect("solves"));
}

/// `solve --format json` of the 500 solved cases: the per-case reports and
/// the document (divide by 500 for the cost per case).
#[divan::bench(sample_count = 30)]
fn random_500_json(b: Bencher) {
    let (m, set) = random_path(500);
    let p = Problem::new(&m).expect("problem");
    let eqs = solve_path(&p, set).expect("solves");
    let ls = &m.load_sets[set.index()];
    b.bench_local(|| {
        let reporter = axle::output::report::Reporter::new(&m);
        let reports: Vec<_> = eqs
            .iter()
            .zip(&ls.cases)
            .enumerate()
            .map(|(k, (eq, c))| reporter.case(&c.name, k + 1, eq))
            .collect();
        axle::output::solve_json::solve(&m.name, &ls.name, &reports, None, None, None)
    });
}

/// 16 independent paths (table 5-1 scaled by 0.65..1.0, from design), the
/// shape of a multi-start or candidate batch.
fn batch_jobs() -> (Problem, Vec<axle::statics::batch::PathJob>) {
    let (m, set) = mcpherson("thesis_table_5_1");
    let base = axle::statics::path::set_loads(&m, set).expect("loads");
    let design = axle::statics::State::design(&m);
    let jobs = (0..16)
        .map(|k| {
            let s = 0.65 + 0.35 * k as f64 / 15.0;
            let cases = base
                .iter()
                .map(|c| {
                    c.iter()
                        .map(|l| axle::model::PointLoad {
                            force: l.force * s,
                            torque: l.torque * s,
                            ..*l
                        })
                        .collect()
                })
                .collect();
            axle::statics::batch::PathJob {
                cases,
                start: design.clone(),
            }
        })
        .collect();
    (Problem::new(&m).expect("problem"), jobs)
}

/// The 16 paths on all cores (`statics::batch::paths`).
#[divan::bench(sample_count = 50)]
fn batch_16_paths_parallel(b: Bencher) {
    let (p, jobs) = batch_jobs();
    b.bench_local(|| axle::statics::batch::paths(&p, &jobs));
}

/// The same 16 paths one after the other on one thread.
#[divan::bench(sample_count = 50)]
fn batch_16_paths_serial(b: Bencher) {
    let (p, jobs) = batch_jobs();
    b.bench_local(|| {
        axle::statics::batch::map_serial(&jobs, |sim, j| sim.run(&p, &j.cases, &j.start, &[]))
    });
}
