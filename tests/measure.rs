//! Pose fitting from measured landmarks against the independent McPherson
//! equilibria: landmarks with σ = 0.05 mm noise (seeded) along thesis Table 4.4.

use axle::geom::{Mat3, Vec3};
use axle::measure::poses::fit_poses;
use axle::model::values;
use serde_json::Value;

fn mcpherson() -> axle::model::Model {
    let (_, c) =
        axle::check::check_str("mcpherson.axle", include_str!("../examples/mcpherson.axle"));
    c.model.expect("the example checks")
}

fn mat(v: &Value) -> Mat3 {
    let r: Vec<f64> = v
        .as_array()
        .expect("rows")
        .iter()
        .flat_map(|row| {
            row.as_array()
                .expect("row")
                .iter()
                .map(|x| x.as_f64().expect("number"))
        })
        .collect();
    Mat3::from_row_slice(&r)
}

fn vec3(v: &Value) -> Vec3 {
    let a: Vec<f64> = v
        .as_array()
        .expect("array")
        .iter()
        .map(|x| x.as_f64().expect("number"))
        .collect();
    Vec3::new(a[0], a[1], a[2])
}

#[test]
fn noisy_landmarks_give_poses_within_the_noise() {
    let model = mcpherson();
    let text =
        include_str!("data/expected/mcpherson_thesis_table_4_4_landmarks_sigma0.05_seed1.csv");
    let (obs, skipped) = axle::data::landmarks::read(text, &model).expect("reads");
    assert!(skipped.is_empty());
    let (steps, issues) = fit_poses(&model, &obs, 0.5);
    assert!(
        issues.is_empty(),
        "{:?}",
        issues.iter().map(|i| i.message(&model)).collect::<Vec<_>>()
    );
    let truth: Value = serde_json::from_str(include_str!(
        "data/expected/mcpherson_thesis_table_4_4.json"
    ))
    .expect("json");
    let cases = truth["cases"].as_array().expect("cases");
    assert_eq!(steps.len(), cases.len());
    let mut worst: f64 = 0.0;
    let mut rms_sum = 0.0;
    let mut n = 0.0;
    for (s, case) in steps.iter().zip(cases) {
        for (part, pose) in &s.parts {
            let name = &model.part(*part).name;
            let (r, t) = if model.part(*part).ground {
                (Mat3::identity(), Vec3::zeros())
            } else {
                let p = &case["parts"][name];
                (mat(&p["rotation"]), vec3(&p["position"]))
            };
            // Compare where the pose puts the part's own landmarks (the part frame's
            // origin is far from the part, where rotation noise is magnified).
            for l in model.landmarks.iter().filter(|l| l.part == *part) {
                let x = values(&l.position);
                let err = ((pose.translation + pose.rotation * x) - (t + r * x)).norm();
                worst = worst.max(err);
            }
            rms_sum += pose.rms * pose.rms;
            n += 1.0;
        }
    }
    // Four landmarks with σ = 0.05 mm per coordinate: the fitted positions of the
    // landmarks scatter by about σ·sqrt(6/4) ≈ 0.06 mm; 4σ bounds every one of 17×5 fits.
    eprintln!("worst landmark position error {worst:.4} mm");
    assert!(worst < 0.2, "worst landmark position error {worst} mm");
    // The fit's residual estimates the noise: E[rms²] = 3σ²·(4·3 − 6)/(4·3) per point.
    let rms = (rms_sum / n).sqrt();
    let expect = (3.0f64 * 0.05 * 0.05 * 6.0 / 12.0).sqrt();
    eprintln!("mean fit residual {rms:.4} mm, expected {expect:.4} mm");
    assert!(
        (rms - expect).abs() < 0.3 * expect,
        "mean residual {rms} mm vs {expect} mm expected from σ"
    );
}

#[test]
fn shuffled_and_corrupted_landmarks_are_handled() {
    let model = mcpherson();
    let text =
        include_str!("data/expected/mcpherson_thesis_table_4_4_landmarks_sigma0.05_seed1.csv");
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    // Reverse the order of step 1's upright points and corrupt one of step 2's.
    let up: Vec<usize> = (0..lines.len())
        .filter(|&i| lines[i].starts_with("1,upright,"))
        .collect();
    let rev: Vec<String> = up.iter().rev().map(|&i| lines[i].clone()).collect();
    for (k, &i) in up.iter().enumerate() {
        lines[i] = rev[k].clone();
    }
    let bad = (0..lines.len())
        .find(|&i| lines[i].starts_with("2,front_arm,"))
        .expect("row");
    let f: Vec<&str> = lines[bad].split(',').collect();
    let x: f64 = f[3].parse::<f64>().expect("x") + 6.0;
    lines[bad] = format!("{},{},{},{x},{},{}", f[0], f[1], f[2], f[4], f[5]);
    let text = lines.join("\n");
    let (obs, _) = axle::data::landmarks::read(&text, &model).expect("reads");
    let (steps, issues) = fit_poses(&model, &obs, 0.5);
    assert_eq!(
        issues.len(),
        1,
        "{:?}",
        issues.iter().map(|i| i.message(&model)).collect::<Vec<_>>()
    );
    assert!(
        issues[0]
            .message(&model)
            .contains(&format!("line {}", bad + 1))
    );
    let front = model.part_named("front_arm").expect("part");
    let up = model.part_named("upright").expect("part");
    assert_eq!(
        steps[1].parts[&front].residuals.len(),
        3,
        "fitted from the three good points"
    );
    assert!(steps[0].parts[&up].rms < 0.15);
}

#[test]
fn synthetic_landmarks_without_noise_fit_the_truth_exactly() {
    let model = mcpherson();
    let set = model.load_set_named("thesis_table_5_1").expect("set");
    let csv = axle::measure::synthetic::landmarks_csv(&model, set, 0.0, 1).expect("solves");
    let (obs, _) = axle::data::landmarks::read(&csv, &model).expect("reads");
    let (steps, issues) = fit_poses(&model, &obs, 0.5);
    assert!(issues.is_empty());
    let eqs = axle::statics::solve_set(&model, set).expect("solves");
    for (s, eq) in steps.iter().zip(&eqs) {
        for (part, pose) in &s.parts {
            let (t, r) = eq.state.part_pose(*part);
            assert!((pose.rotation - r).abs().max() < 1e-9);
            assert!((pose.translation - t).norm() < 1e-6);
        }
    }
}
