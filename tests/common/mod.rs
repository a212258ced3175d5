//! What the command-line tests share: running the built binary and writing
//! scratch input files. Each test file that needs them says `mod common;`.
#![allow(dead_code)] // not every test file uses every helper

use std::process::Command;

/// Runs the built `axle` in the crate root; returns (exit code, stdout,
/// stderr). A panic is never an acceptable outcome, whatever the input.
pub fn axle(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_axle"))
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("the binary runs");
    let (stdout, stderr) = (
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    );
    assert!(!stderr.contains("panicked"), "{stderr}");
    (out.status.code().unwrap_or(-1), stdout, stderr)
}

/// Writes `text` to a file of the test target's scratch folder; returns its path.
pub fn scratch(name: &str, text: &str) -> String {
    let p = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(name);
    std::fs::write(&p, text).expect("scratch file");
    p.to_string_lossy().into_owned()
}

/// Synthetic landmarks of `model` along load set `set` (σ, seed), written
/// once as a CSV file and once as IGES files, one per step: `<stem>.csv`
/// and `<stem>_NN.igs`. Returns (CSV path, IGES paths in step order).
pub fn landmark_files(
    model: &axle::model::Model,
    set: axle::model::LoadSetId,
    sigma: f64,
    seed: u64,
    stem: &str,
) -> (String, Vec<String>) {
    use axle::measure::synthetic::{landmarks_csv, landmarks_iges};
    let csv = scratch(
        &format!("{stem}.csv"),
        &landmarks_csv(model, set, sigma, seed).expect("solves"),
    );
    let iges = landmarks_iges(model, set, sigma, seed)
        .expect("solves")
        .iter()
        .enumerate()
        .map(|(k, text)| scratch(&format!("{stem}_{:02}.igs", k + 1), text))
        .collect();
    (csv, iges)
}

/// A model from source that must check clean.
pub fn checked(name: &str, text: &str) -> axle::model::Model {
    let (_, c) = axle::check::check_str(name, text);
    assert!(!c.problems.has_errors(), "{:?}", c.problems);
    c.model.expect("checks clean")
}

/// A file of the repository (`examples/front_axle.axle`), checked.
pub fn example(file: &str) -> axle::model::Model {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(file);
    checked(file, &std::fs::read_to_string(&path).expect("readable"))
}

/// A load set of the model solved along its path, from design.
pub fn solve(m: &axle::model::Model, set: &str) -> Vec<axle::statics::Equilibrium> {
    let id = m.load_set_named(set).expect("the set exists");
    axle::statics::solve_set(m, id).expect("solves")
}

/// Case by case, how far each solve may have stopped from its exact
/// equilibrium (`statics::stopping_error`): part name -> (mm, rad).
pub fn stopping(
    m: &axle::model::Model,
    eqs: &[axle::statics::Equilibrium],
) -> Vec<std::collections::HashMap<String, (f64, f64)>> {
    let problem = axle::statics::Problem::new(m).expect("compiles");
    eqs.iter()
        .map(|e| {
            axle::statics::stopping_error(&problem, e)
                .expect("a regular equilibrium")
                .iter()
                .map(|s| (m.part(s.part).name.clone(), (s.distance, s.angle)))
                .collect()
        })
        .collect()
}

/// Two solves of the same mechanism agree when each part's poses differ by
/// no more than the two solves' stopping errors together: `d` the origins'
/// distance (mm), `r` the rotations' difference `‖R_a - R_b‖` (Frobenius,
/// at most `√2` times the angle between them). Returns the difference's
/// share of what is allowed (at most 1 when they agree).
pub fn share_of_stopping(d: f64, r: f64, a: (f64, f64), b: (f64, f64)) -> f64 {
    (d / (a.0 + b.0)).max(r / (2f64.sqrt() * (a.1 + b.1)))
}

/// Where the point `at` (global at design) of a part is in a solved state,
/// and the part's rotation.
pub fn pose_at(
    m: &axle::model::Model,
    e: &axle::statics::Equilibrium,
    part: &str,
    at: &axle::geom::Vec3,
) -> (axle::geom::Vec3, axle::geom::Mat3) {
    let p = m.part_named(part).unwrap_or_else(|| panic!("part {part}"));
    let (t, r) = e.state.part_pose(p);
    (t + r * at, r)
}

/// A part's reference point at design (`statics::coords::reference_points`),
/// where `stopping` bounds its distance.
pub fn reference(m: &axle::model::Model, part: &str) -> axle::geom::Vec3 {
    let p = m.part_named(part).unwrap_or_else(|| panic!("part {part}"));
    axle::statics::coords::reference_points(m)[p.index()]
}

/// A part's stopping error `(mm, rad)` at its reference point `from`,
/// moved to the point `to` of the part (both at design): the rotation's
/// error moves `to` by at most its angle times the lever.
pub fn stopping_at(stop: (f64, f64), from: &axle::geom::Vec3, to: &axle::geom::Vec3) -> (f64, f64) {
    (stop.0 + stop.1 * (to - from).norm(), stop.1)
}
