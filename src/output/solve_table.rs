//! `solve --format table`: one block per case, for an engineer at a terminal:
//! the loads applied, the wheels (what the K&C rig measures), then the
//! bushings (where the compliance comes from), springs, frictions, the joint
//! reactions (ball-joint loads are design loads) and the part displacements.

use super::columns::{Cell, Col, col, render};
use crate::output::report::{CaseReport, FailedCase};

const WHEEL: [Col; 8] = [
    col("wheel", "", 0),
    col("wc_x", "mm", 3),
    col("wc_y", "mm", 3),
    col("wc_z", "mm", 3),
    col("travel", "mm", 3),
    col("toe", "deg", 4),
    col("camber", "deg", 4),
    col("half_track", "mm", 3),
];

const BUSHING: [Col; 13] = [
    col("bushing", "", 0),
    col("tx", "mm", 4),
    col("ty", "mm", 4),
    col("tz", "mm", 4),
    col("ax", "deg", 4),
    col("ay", "deg", 4),
    col("az", "deg", 4),
    col("Fx", "N", 1),
    col("Fy", "N", 1),
    col("Fz", "N", 1),
    col("Tx", "N*mm", 0),
    col("Ty", "N*mm", 0),
    col("Tz", "N*mm", 0),
];

const SPRING: [Col; 3] = [
    col("spring", "", 0),
    col("length", "mm", 3),
    col("force", "N", 1),
];

const FRICTION: [Col; 5] = [
    col("friction", "", 0),
    col("slide", "mm", 4),
    col("force", "N", 2),
    col("slip_offset", "mm", 4),
    col("state", "", 0),
];

const LOAD: [Col; 7] = [
    col("load at", "", 0),
    col("Fx", "N", 1),
    col("Fy", "N", 1),
    col("Fz", "N", 1),
    col("Mx", "N*mm", 0),
    col("My", "N*mm", 0),
    col("Mz", "N*mm", 0),
];

const JOINT: [Col; 7] = [
    col("joint", "", 0),
    col("Fx", "N", 1),
    col("Fy", "N", 1),
    col("Fz", "N", 1),
    col("Tx", "N*mm", 0),
    col("Ty", "N*mm", 0),
    col("Tz", "N*mm", 0),
];

const PART: [Col; 5] = [
    col("part", "", 0),
    col("dx", "mm", 3),
    col("dy", "mm", 3),
    col("dz", "mm", 3),
    col("rotation", "deg", 4),
];

fn text(s: &str) -> Cell {
    Cell::Text(s.to_string())
}

/// The table of one case.
pub fn case(c: &CaseReport) -> String {
    let sub = if c.substeps > 0 {
        format!(", {} load sub-steps", c.substeps)
    } else {
        String::new()
    };
    let mut out = format!(
        "case {} (step {}): converged in {} Newton iterations{sub}\n",
        c.name, c.step, c.iterations
    );
    if !c.loads.is_empty() {
        let rows: Vec<Vec<Cell>> = c
            .loads
            .iter()
            .map(|l| {
                let mut r = vec![text(&l.marker)];
                r.extend(l.force.map(Cell::Num));
                r.extend(l.torque.map(Cell::Num));
                r
            })
            .collect();
        out += "\n";
        out += &render(&LOAD, &rows, "  ");
        out += "  (applied at the marker, global axes)\n";
    }
    if !c.wheels.is_empty() {
        let rows: Vec<Vec<Cell>> = c
            .wheels
            .iter()
            .map(|(n, q)| {
                let mut r = vec![text(n)];
                r.extend(q.center.map(Cell::Num));
                r.extend([q.travel_mm, q.toe_deg, q.camber_deg, q.half_track_mm].map(Cell::Num));
                r
            })
            .collect();
        out += "\n";
        out += &render(&WHEEL, &rows, "  ");
    }
    if !c.bushings.is_empty() {
        let rows: Vec<Vec<Cell>> = c
            .bushings
            .iter()
            .map(|(n, b)| {
                let mut r = vec![text(n)];
                r.extend(b.deformation.map(Cell::Num));
                r.extend(b.force.map(Cell::Num));
                r
            })
            .collect();
        out += "\n";
        out += &render(&BUSHING, &rows, "  ");
        out += "  (deformation of I from J and force on I, J axes; angles are projected)\n";
    }
    if !c.springs.is_empty() {
        let rows: Vec<Vec<Cell>> = c
            .springs
            .iter()
            .map(|(n, s)| vec![text(n), Cell::Num(s.length), Cell::Num(s.force)])
            .collect();
        out += "\n";
        out += &render(&SPRING, &rows, "  ");
        out += "  (force: tension +)\n";
    }
    if !c.frictions.is_empty() {
        let rows: Vec<Vec<Cell>> = c
            .frictions
            .iter()
            .map(|(n, f)| {
                vec![
                    text(n),
                    Cell::Num(f.slide),
                    Cell::Num(f.force),
                    Cell::Num(f.slip_offset),
                    text(f.state),
                ]
            })
            .collect();
        out += "\n";
        out += &render(&FRICTION, &rows, "  ");
        out += "  (slide of I along z_J and force on I; a rotation friction: deg and N*mm)\n";
    }
    if !c.joints.is_empty() {
        let rows: Vec<Vec<Cell>> = c
            .joints
            .iter()
            .map(|(n, j)| {
                let mut r = vec![text(n)];
                r.extend(j.force.map(Cell::Num));
                r.extend(j.torque.map(Cell::Num));
                r
            })
            .collect();
        out += "\n";
        out += &render(&JOINT, &rows, "  ");
        out += "  (reaction on I at its marker, global axes; J carries the opposite)\n";
    }
    if !c.parts.is_empty() {
        let rows: Vec<Vec<Cell>> = c
            .parts
            .iter()
            .map(|(n, p)| {
                let r = &p.rotation;
                let cos = ((r[0][0] + r[1][1] + r[2][2] - 1.0) / 2.0).clamp(-1.0, 1.0);
                let mut row = vec![text(n)];
                row.extend(p.displacement.map(Cell::Num));
                row.push(Cell::Num(cos.acos().to_degrees()));
                row
            })
            .collect();
        out += "\n";
        out += &render(&PART, &rows, "  ");
        out += "  (displacement of the part's marker centroid from design, and rotation angle)\n";
    }
    out
}

/// The tables of all cases, separated by blank lines; a path that stopped
/// ends with the line of the case it stopped at and the names of the cases
/// after it (`not_solved`), which were not tried: each starts from the
/// previous case's equilibrium, which the failed case lacks.
pub fn cases(
    model: &str,
    set: &str,
    cases: &[CaseReport],
    failed: Option<&FailedCase>,
    not_solved: &[(String, usize)],
) -> String {
    let n = cases.len();
    let mut out = match failed {
        None => format!(
            "model {model}, load set {set}: {n} case{}\n",
            if n == 1 { "" } else { "s" }
        ),
        Some(f) => format!(
            "model {model}, load set {set}: {n} case{} converged, stopped at case {} (step {})\n",
            if n == 1 { "" } else { "s" },
            f.name,
            f.step
        ),
    };
    for c in cases {
        out += "\n";
        out += &case(c);
    }
    if let Some(f) = failed {
        out += "\n";
        out += &f.line();
    }
    if !not_solved.is_empty() {
        let names: Vec<&str> = not_solved.iter().map(|(n, _)| n.as_str()).collect();
        out += &format!(
            "not solved: {} (the path stops at the first case that fails)\n",
            names.join(", ")
        );
    }
    out
}
