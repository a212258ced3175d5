//! K&C rows as the K&C CSV of `interfaces.md` (the required columns in the
//! order of the rig files, then the optional ones, then travel and half-track
//! change), as a terminal table, and as JSON.

use super::columns::{Cell, Col, col, render};
use super::number::{csv as num, fixed, round_json};
use crate::kc::{AxleMetrics, ComplianceMetrics, Input, KcRow, Motion, SteeringMetrics};
use serde_json::{Value, json};

/// The header of the K&C CSV.
pub const CSV_COLUMNS: [&str; 16] = [
    "step",
    "fx",
    "fy",
    "fz",
    "wc_x",
    "wc_y",
    "wc_z",
    "toe_deg",
    "camber_deg",
    "loadcase",
    "mx",
    "my",
    "mz",
    "wheel",
    "travel_mm",
    "half_track_change_mm",
];

/// The K&C CSV: header row, one line per row.
pub fn csv(rows: &[KcRow]) -> String {
    let mut out = CSV_COLUMNS.join(",") + "\n";
    for r in rows {
        let q = &r.quantities;
        let f: Vec<String> = [
            r.step.to_string(),
            num(r.force[0]),
            num(r.force[1]),
            num(r.force[2]),
            num(q.center[0]),
            num(q.center[1]),
            num(q.center[2]),
            num(q.toe_deg),
            num(q.camber_deg),
            r.loadcase.clone(),
            num(r.torque[0]),
            num(r.torque[1]),
            num(r.torque[2]),
            r.wheel.clone(),
            num(q.travel_mm),
            num(q.half_track_change_mm),
        ]
        .into();
        out += &(f.join(",") + "\n");
    }
    out
}

const COLS: [Col; 11] = [
    col("step", "", 0),
    col("case", "", 0),
    col("fx", "N", 0),
    col("fy", "N", 0),
    col("fz", "N", 0),
    col("travel", "mm", 3),
    col("wc_x", "mm", 3),
    col("wc_y", "mm", 3),
    col("toe", "deg", 4),
    col("camber", "deg", 4),
    col("d_track", "mm", 3),
];

/// One table per wheel, rows in path order.
pub fn table(rows: &[KcRow]) -> String {
    let mut wheels: Vec<&str> = Vec::new();
    for r in rows {
        if !wheels.contains(&r.wheel.as_str()) {
            wheels.push(&r.wheel);
        }
    }
    let mut out = String::new();
    for w in wheels {
        out += &format!("wheel {w} (toe-in +, camber top-out +, d_track = half-track change)\n");
        let cells: Vec<Vec<Cell>> = rows
            .iter()
            .filter(|r| r.wheel == w)
            .map(|r| {
                let q = &r.quantities;
                vec![
                    Cell::Num(r.step as f64),
                    Cell::Text(r.loadcase.clone()),
                    Cell::Num(r.force[0]),
                    Cell::Num(r.force[1]),
                    Cell::Num(r.force[2]),
                    Cell::Num(q.travel_mm),
                    Cell::Num(q.center[0]),
                    Cell::Num(q.center[1]),
                    Cell::Num(q.toe_deg),
                    Cell::Num(q.camber_deg),
                    Cell::Num(q.half_track_change_mm),
                ]
            })
            .collect();
        out += &render(&COLS, &cells, "  ");
    }
    out
}

/// The rows as JSON objects with the CSV's column names.
pub fn json_rows(rows: &[KcRow]) -> Value {
    let mut v = Value::Array(
        rows.iter()
            .map(|r| {
                let q = &r.quantities;
                json!({
                    "step": r.step, "loadcase": r.loadcase, "wheel": r.wheel,
                    "fx": r.force[0], "fy": r.force[1], "fz": r.force[2],
                    "mx": r.torque[0], "my": r.torque[1], "mz": r.torque[2],
                    "wc_x": q.center[0], "wc_y": q.center[1], "wc_z": q.center[2],
                    "toe_deg": q.toe_deg, "camber_deg": q.camber_deg,
                    "travel_mm": q.travel_mm, "half_track_mm": q.half_track_mm,
                    "half_track_change_mm": q.half_track_change_mm,
                })
            })
            .collect(),
    );
    round_json(&mut v);
    v
}

const PARALLEL_COLS: [Col; 4] = [
    col("wheel", "", 0),
    col("bump steer", "deg/mm", 5),
    col("bump camber", "deg/mm", 5),
    col("wheel rate", "N/mm", 2),
];

const OPPOSED_COLS: [Col; 3] = [
    col("wheel", "", 0),
    col("roll steer", "deg/deg", 4),
    col("roll camber", "deg/deg", 4),
];

/// A wheel's toe and camber slopes and, when the metric has one, a third.
fn slope_row(wheel: &str, toe: f64, camber: f64, third: Option<f64>) -> Vec<Cell> {
    let mut row = vec![
        Cell::Text(wheel.to_string()),
        Cell::Num(toe),
        Cell::Num(camber),
    ];
    row.extend(third.map(Cell::Num));
    row
}

/// The axle metrics (`docs/kc.md`): one block per wheel pair.
pub fn axle_table(axles: &[AxleMetrics]) -> String {
    let mut out = String::new();
    for a in axles {
        let [l, r] = &a.wheels;
        let what = match a.motion {
            Motion::Parallel => "parallel travel",
            Motion::Opposed => "opposed travel (roll)",
        };
        out += &format!(
            "\naxle {} / {}: {what}, slopes at step {} ({})\n",
            l.wheel, r.wheel, a.step, a.loadcase
        );
        let cols: &[Col] = match a.motion {
            Motion::Parallel => {
                out += &match a.roll_centre {
                    Some([y, z]) => format!(
                        "  roll centre (kinematic): height {} mm, y {} mm\n",
                        fixed(z, 1, 0),
                        fixed(y, 1, 0)
                    ),
                    None => {
                        "  roll centre (kinematic): at infinity (the contact paths are parallel)\n"
                            .into()
                    }
                };
                &PARALLEL_COLS
            }
            Motion::Opposed => {
                if let Some(k) = a.roll_stiffness {
                    out += &format!("  roll stiffness: {} N*m/deg\n", fixed(k, 1, 0));
                }
                if let Some((k, names)) = &a.roll_stiffness_without {
                    out += &format!(
                        "  roll stiffness without {}: {} N*m/deg\n",
                        names.join(", "),
                        fixed(*k, 1, 0)
                    );
                }
                &OPPOSED_COLS
            }
        };
        // A wheel rate only for parallel travel (the columns say which).
        let rows: Vec<Vec<Cell>> = a
            .wheels
            .iter()
            .map(|w| slope_row(&w.wheel, w.toe, w.camber, w.rate))
            .collect();
        out += &render(cols, &rows, "  ");
    }
    out
}

const STEER_COLS: [Col; 6] = [
    col("wheel", "", 0),
    col("caster", "deg", 3),
    col("kingpin incl.", "deg", 3),
    col("scrub radius", "mm", 2),
    col("trail", "mm", 2),
    col("steer/travel", "deg/mm", 5),
];

/// The steering geometry of a path that drives a rack (`docs/kc.md`).
pub fn steering_table(s: &SteeringMetrics) -> String {
    let mut out = format!(
        "\nsteering by rack `{}`: axis at step {} ({}), rack travel {} mm\n",
        s.rack,
        s.step,
        s.loadcase,
        fixed(s.travel_mm, 3, 0)
    );
    let rows: Vec<Vec<Cell>> = s
        .wheels
        .iter()
        .map(|w| {
            vec![
                Cell::Text(w.wheel.clone()),
                Cell::Num(w.caster_deg),
                Cell::Num(w.kpi_deg),
                Cell::Num(w.scrub_mm),
                Cell::Num(w.trail_mm),
                Cell::Num(w.steer_per_travel),
            ]
        })
        .collect();
    out += &render(&STEER_COLS, &rows, "  ");
    out
}

/// The compliance events (`docs/kc.md`): one block per wheel or axle pair
/// loaded, slopes per unit of each wheel's own load (outboard or forward
/// positive).
pub fn compliance_table(events: &[ComplianceMetrics]) -> String {
    let mut out = String::new();
    for e in events {
        let phase = match e.phase {
            Some(p) => format!(", {}", p.name().replace('_', " ")),
            None => String::new(),
        };
        let sign = match e.input {
            Input::Lateral => "outboard positive",
            Input::AligningTorque => "turning the front outboard positive",
            Input::Braking | Input::Traction => "forward positive",
        };
        out += &format!(
            "\ncompliance: {}{phase}, slopes at step {} ({}), per {} of each wheel's load ({sign})\n",
            e.input.title(),
            e.step,
            e.loadcase,
            e.input.per(),
        );
        let per = match e.input {
            Input::AligningTorque => "deg/N*m",
            _ => "deg/kN",
        };
        let along = match e.input {
            Input::Lateral => "centre outboard",
            _ => "centre forward",
        };
        let mut cols = vec![
            col("wheel", "", 0),
            col("compliance steer", per, 5),
            col("compliance camber", per, 5),
        ];
        if e.input != Input::AligningTorque {
            cols.push(col(along, "mm/kN", 4));
        }
        let rows: Vec<Vec<Cell>> = e
            .wheels
            .iter()
            .map(|w| slope_row(&w.wheel, w.toe, w.camber, w.centre))
            .collect();
        out += &render(&cols, &rows, "  ");
    }
    out
}
