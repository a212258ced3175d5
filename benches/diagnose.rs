//! Speed of `axle diagnose` (`docs/diagnose.md`, "Speed"; target from issue
//! 11: under 10 s on this 2-core machine): the McPherson with a hidden stiffer
//! bushing, rig data along the bump, lateral and longitudinal sweeps up and
//! back (187 steps), the full candidate library; and the same with landmarks.
//! Run with
//! `cargo bench --bench diagnose`; it prints the split between screening and
//! fitting of one run first.

use axle::diagnose::rig::{RigPath, read};
use axle::diagnose::{Options, diagnose};
use axle::measure::synthetic::kc_csv;
use axle::model::Model;
use axle::model::address::Address;
use axle::span::FileId;

fn main() {
    for (what, (m, rig)) in [("K&C", case()), ("K&C and landmarks", with_landmarks())] {
        let d = diagnose(&m, &rig, &Options::default()).expect("diagnosis");
        println!(
            "diagnose ({what}): {} steps, {} candidates screened, {} fitted; screening {:.2} s, fitting {:.2} s; {} effect(s)",
            rig.iter().map(|p| p.steps.len()).sum::<usize>(),
            d.screened,
            d.fitted,
            d.screen_time.as_secs_f64(),
            d.fit_time.as_secs_f64(),
            d.effects.len()
        );
    }
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
        .flat_map(|(k, name)| {
            let set = truth.load_set_named(name).expect("sweep");
            let csv = kc_csv(&truth, set, 0.005, 0.02, 10 + k as u64).expect("solves");
            read(&nominal, FileId(k as u32), name, &csv).expect("reads")
        })
        .collect();
    (nominal, rig)
}

/// The same rig with a landmark file per sweep (σ = 0.05 mm, every step):
/// 16 moving landmarks add 48 residuals to each step's 5.
fn with_landmarks() -> (Model, Vec<RigPath>) {
    use axle::diagnose::landmarks::attach;
    use axle::measure::inputs::{LandmarkFile, LandmarkFormat, Remarks};
    let (nominal, mut rig) = case();
    let mut truth = nominal.clone();
    Address::parse(&truth, "B.k_x")
        .expect("address")
        .set(&mut truth, 775.0);
    let mut sources = axle::source::SourceMap::new();
    let files: Vec<LandmarkFile> = ["bump", "lateral", "longitudinal"]
        .iter()
        .enumerate()
        .map(|(k, name)| {
            let set = truth.load_set_named(name).expect("sweep");
            let csv = axle::measure::synthetic::landmarks_csv(&truth, set, 0.05, 20 + k as u64)
                .expect("solves");
            LandmarkFile {
                id: sources.add(format!("{name}.csv"), csv),
                format: LandmarkFormat::Csv,
            }
        })
        .collect();
    attach(
        &sources,
        &nominal,
        &mut rig,
        &files,
        &mut Remarks::default(),
    )
    .expect("joins");
    (nominal, rig)
}

#[divan::bench(sample_count = 3, sample_size = 1)]
fn mcpherson_full_library(b: divan::Bencher) {
    let (m, rig) = case();
    b.bench(|| diagnose(&m, &rig, &Options::default()).expect("diagnosis"));
}

#[divan::bench(sample_count = 3, sample_size = 1)]
fn mcpherson_full_library_with_landmarks(b: divan::Bencher) {
    let (m, rig) = with_landmarks();
    b.bench(|| diagnose(&m, &rig, &Options::default()).expect("diagnosis"));
}
