//! Speed of a whole car (`examples/vehicle.axle`: McPherson front axle with
//! anti-roll bar and steering rack, five-link rear corners; issue 13's
//! targets: one case under 0.3 ms, a K&C sweep of 100 steps under 30 ms).
//! Run with `cargo bench --bench vehicle`; the model's size and the Newton
//! work are printed once so the figures can be read per step.

use axle::model::{
    Channel, Component, JointKind, LoadCase, LoadForm, LoadSet, LoadSetId, LoadTarget, Model,
    WheelId,
};
use axle::statics::path::{set_loads, simulate, solve_case};
use axle::statics::{Problem, State};
use divan::Bencher;

fn main() {
    let m = vehicle();
    let p = Problem::new(&m).expect("problem");
    let moving = m.moving_parts().count();
    let equations: usize = m
        .joints
        .iter()
        .map(|j| match j.kind {
            JointKind::Spherical => 3,
            JointKind::Universal | JointKind::Cylindrical => 4,
            JointKind::Revolute | JointKind::Translational => 5,
            JointKind::Fixed => 6,
            JointKind::Inline => 2,
            JointKind::Inplane => 1,
        })
        .sum();
    println!(
        "vehicle: {moving} moving parts, {} joints ({} constraint equations, {} redundant), {} bushings, {} springs, {} wheels: {} unknowns",
        m.joints.len(),
        equations,
        p.redundant.len(),
        m.bushings.len(),
        m.springs.len(),
        m.wheels.len(),
        6 * moving + equations - p.redundant.len()
    );
    let design = State::design(&m);
    let (curb, laden) = (case(&m, 0), case(&m, 1));
    let e = solve_case(&p, &curb, &design).expect("solves");
    println!(
        "curb from design: {} Newton steps, {} factorisations, {} sub-steps",
        e.iterations, e.factorizations, e.substeps
    );
    let w = solve_case(&p, &laden, &e.state).expect("solves");
    println!(
        "laden from curb: {} Newton steps, {} factorisations",
        w.iterations, w.factorizations
    );
    let m35 = vehicle_35();
    let p35 = Problem::new(&m35).expect("problem");
    let c35 = solve_case(&p35, &case(&m35, 0), &State::design(&m35)).expect("solves");
    let w35 = solve_case(&p35, &case(&m35, 1), &c35.state).expect("solves");
    println!(
        "car of {} parts: curb from design {} Newton steps, {} factorisations; laden from curb {}, {}",
        m35.moving_parts().count(),
        c35.iterations,
        c35.factorizations,
        w35.iterations,
        w35.factorizations
    );
    let (m100, set) = with_sweep_100(&m);
    let p100 = Problem::new(&m100).expect("problem");
    let eqs = axle::statics::path::solve_path(&p100, set).expect("solves");
    let steps: usize = eqs.iter().map(|e| e.iterations).sum();
    let lus: usize = eqs.iter().map(|e| e.factorizations).sum();
    println!(
        "front bump in 100 steps: {steps} Newton steps, {lus} factorisations ({:.2} steps a case)",
        steps as f64 / eqs.len() as f64
    );
    divan::main();
}

fn vehicle() -> Model {
    let (_, c) = axle::check::check_str("vehicle.axle", include_str!("../examples/vehicle.axle"));
    c.model.expect("the example checks")
}

/// The car of 35 moving parts issue 13 names: the example with a rear
/// anti-roll bar and four braked hubs (`vehicle_35.axle`, spliced in as
/// `tests/vehicle.rs` does, where it is checked against the example).
fn vehicle_35() -> Model {
    let car = include_str!("../examples/vehicle.axle");
    let more = include_str!("vehicle_35.axle");
    let text = car.replace("ground chassis {\n}\n", "").replace(
        "\ndefault loads vehicle",
        &format!("\n{more}\ndefault loads vehicle"),
    );
    let (_, c) = axle::check::check_str("vehicle_35.axle", &text);
    c.model.expect("the car of 35 parts checks")
}

/// Case `k` of the example's `vehicle` table (curb, laden, ...) as point loads.
fn case(m: &Model, k: usize) -> Vec<axle::model::PointLoad> {
    let set = m.load_set_named("vehicle").expect("the vehicle set");
    set_loads(m, set).expect("loads").swap_remove(k)
}

/// The car with a K&C sweep of 100 steps added: both front wheels' fz
/// 1000 -> 8000 -> 1140 N in 140 N steps, the rear wheels at their curb
/// 3500 N (parallel travel of the front axle, as `front_bump` in finer steps).
fn with_sweep_100(base: &Model) -> (Model, LoadSetId) {
    let mut m = base.clone();
    let channels: Vec<Channel> = (0..m.wheels.len())
        .map(|w| Channel {
            target: LoadTarget::Wheel(WheelId(w as u32)),
            component: Component::Fz,
        })
        .collect();
    let cases = (0..100)
        .map(|k| {
            let f = 1000.0 + 140.0 * (if k <= 50 { k } else { 100 - k }) as f64;
            LoadCase {
                name: format!("bump_{:03}", k + 1),
                values: m
                    .wheels
                    .iter()
                    .map(|w| {
                        if w.name.starts_with("front_") {
                            f
                        } else {
                            3500.0
                        }
                    })
                    .collect(),
            }
        })
        .collect();
    m.load_sets.push(LoadSet {
        name: "bump_100".into(),
        channels,
        cases,
        form: LoadForm::Table,
    });
    let id = LoadSetId(m.load_sets.len() as u32 - 1);
    (m, id)
}

/// The example (27 moving parts) or the car of 35 parts.
fn car(parts: usize) -> Model {
    if parts == 35 { vehicle_35() } else { vehicle() }
}

/// The curb case from the design configuration (`Problem` compiled once),
/// on the example and on the car of 35 parts.
#[divan::bench(args = [27, 35])]
fn one_case_from_design(b: Bencher, parts: usize) {
    let m = car(parts);
    let p = Problem::new(&m).expect("problem");
    let (curb, design) = (case(&m, 0), State::design(&m));
    b.bench_local(|| solve_case(&p, &curb, &design).expect("solves"));
}

/// The laden case from the curb equilibrium: one step of a path.
#[divan::bench(args = [27, 35])]
fn one_case_warm(b: Bencher, parts: usize) {
    let m = car(parts);
    let p = Problem::new(&m).expect("problem");
    let start = solve_case(&p, &case(&m, 0), &State::design(&m))
        .expect("solves")
        .state;
    let laden = case(&m, 1);
    b.bench_local(|| solve_case(&p, &laden, &start).expect("solves"));
}

/// The 100-step front bump from design: the path alone, on the example and
/// on the car of 35 parts.
#[divan::bench(sample_count = 30, args = [27, 35])]
fn kc_sweep_100_steps_solve(b: Bencher, parts: usize) {
    let (m, set) = with_sweep_100(&car(parts));
    let p = Problem::new(&m).expect("problem");
    let cases = set_loads(&m, set).expect("loads");
    let design = State::design(&m);
    b.bench_local(|| simulate(&p, &cases, &design).into_result().expect("solves"));
}

/// The same sweep as `axle kc` does it: compile, solve, the K&C rows of
/// every wheel and the axle metrics.
#[divan::bench(sample_count = 30)]
fn kc_sweep_100_steps_with_metrics(b: Bencher) {
    let (m, set) = with_sweep_100(&vehicle());
    b.bench_local(|| {
        let p = Problem::new(&m).expect("problem");
        let eqs = axle::statics::path::solve_path(&p, set).expect("solves");
        let states: Vec<_> = eqs.iter().map(|e| &e.state).collect();
        let rows = axle::kc::kc_rows(&m, set, &states);
        axle::kc::axle_metrics(&m, &rows)
    });
}
