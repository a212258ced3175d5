//! `axle diagnose` finds an effect hidden in synthetic rig data: a truth model
//! (a shipped model plus one hidden effect of realistic size) solved along the
//! bump, lateral and longitudinal sweeps (each up and back) with seeded noise
//! (angles σ = 0.005°, positions σ = 0.02 mm); the diagnosis of the nominal
//! model must name the kind and element, recover the parameters within their
//! intervals, and cut the held-out RMS error of the affected channels by at
//! least half. The data say nothing of the answer except through the test's
//! assertions.

use axle::diagnose::rig::{RigPath, read};
use axle::diagnose::{Diagnosis, Kind, Options, diagnose, words};
use axle::measure::synthetic::kc_csv;
use axle::model::Model;
use axle::model::address::Address;
use axle::span::FileId;

fn model(text: &str) -> Model {
    let (_, checked) = axle::check::check_str("m.axle", text);
    checked.model.expect("the example checks")
}

fn mcpherson() -> Model {
    model(include_str!("../examples/mcpherson.axle"))
}

/// Rig data of `truth` along the three sweeps, as the nominal model reads them.
fn rig(nominal: &Model, truth: &Model, seed: u64) -> Vec<RigPath> {
    ["bump", "lateral", "longitudinal"]
        .iter()
        .enumerate()
        .map(|(k, name)| {
            let set = truth.load_set_named(name).expect("sweep");
            let csv = kc_csv(truth, set, 0.005, 0.02, seed * 10 + k as u64).expect("truth solves");
            read(nominal, FileId(k as u32), name, &csv).expect("rig data read")
        })
        .collect()
}

fn set(m: &mut Model, address: &str, value: f64) {
    let a = Address::parse(m, address).expect("address");
    a.set(m, value);
}

fn show(d: &Diagnosis) {
    eprintln!("baseline held-out rms {:?}", d.baseline.rms_held_out);
    for h in d.hypotheses.iter().take(8) {
        eprintln!(
            "  {:>10.1} {} {} {} {}",
            h.score,
            h.kind.name(),
            h.element_name,
            h.detail,
            words::claim(h)
        );
    }
    for e in &d.effects {
        eprintln!("EFFECT {}", words::sentence(e, &d.noise));
    }
    eprintln!("screened {} fitted {}", d.screened, d.fitted);
}

#[test]
fn a_stiffer_bushing_is_found() {
    let nominal = mcpherson();
    let mut truth = nominal.clone();
    set(&mut truth, "B.k_x", 775.0);
    let r = rig(&nominal, &truth, 1);
    let d = diagnose(&nominal, &r, &Options::default()).expect("diagnosis");
    show(&d);
    let e = &d.effects[0].hypothesis;
    assert_eq!((e.kind, e.element_name.as_str()), (Kind::Stiffness, "B"));
}
