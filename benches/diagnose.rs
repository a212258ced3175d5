//! Speed of `axle diagnose` (`docs/diagnose.md`, "Speed"; target from issue
//! 11: under 10 s on this 2-core machine): the McPherson with a hidden stiffer
//! bushing, rig data along the bump, lateral and longitudinal sweeps up and
//! back (187 steps), the full candidate library. Run with
//! `cargo bench --bench diagnose`; it prints the split between screening and
//! fitting of one run first.

use axle::diagnose::rig::{RigPath, read};
use axle::diagnose::{Options, diagnose};
use axle::measure::synthetic::kc_csv;
use axle::model::Model;
use axle::model::address::Address;
use axle::span::FileId;

fn main() {
    let (m, rig) = case();
    let d = diagnose(&m, &rig, &Options::default()).expect("diagnosis");
    println!(
        "diagnose: {} steps, {} candidates screened, {} fitted; screening {:.2} s, fitting {:.2} s; {} effect(s)",
        rig.iter().map(|p| p.steps.len()).sum::<usize>(),
        d.screened,
        d.fitted,
        d.screen_time.as_secs_f64(),
        d.fit_time.as_secs_f64(),
        d.effects.len()
    );
    divan::main();
}

fn case() -> (Model, Vec<RigPath>) {
    let text = include_str!("../examples/mcpherson.axle");
    let (_, checked) = axle::check::check_str("mcpherson.axle", text);
    let nominal = checked.model.expect("example checks");
    let mut truth = nominal.clone();
    Address::parse(&truth, "B.k_x")
        .expect("address")
        .set(&mut truth, 775.0);
    let rig = ["bump", "lateral", "longitudinal"]
        .iter()
        .enumerate()
        .map(|(k, name)| {
            let set = truth.load_set_named(name).expect("sweep");
            let csv = kc_csv(&truth, set, 0.005, 0.02, 10 + k as u64).expect("solves");
            read(&nominal, FileId(k as u32), name, &csv).expect("reads")
        })
        .collect();
    (nominal, rig)
}

#[divan::bench(sample_count = 3, sample_size = 1)]
fn mcpherson_full_library(b: divan::Bencher) {
    let (m, rig) = case();
    b.bench(|| diagnose(&m, &rig, &Options::default()).expect("diagnosis"));
}
