//! Axle K&C metrics of a load path on a pair of wheels (`docs/kc.md`): for
//! parallel travel (both wheels' vertical loads moving together) the bump
//! steer, bump camber and wheel rate of each wheel and the kinematic roll
//! centre; for opposed travel (roll) the roll stiffness and each wheel's
//! roll steer and roll camber. Every metric is a slope at the step nearest
//! the design position, by a difference of its neighbours on the path.
//!
//! Signs follow ISO 8855 and `conventions.md`: x forward, y left, z up; toe-in
//! and camber top-out positive (per wheel); the body's roll angle φ is
//! right-handed about x, positive when the body's left side rises relative
//! to the wheels (the left wheel drops, the right one rises).

use super::wheel::{KcRow, WheelQuantities};
use crate::geom::Vec3;
use crate::model::{Model, WheelId};

/// How the two wheels of an axle move along a load path.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Motion {
    /// Both vertical loads rise and fall together (parallel wheel travel).
    Parallel,
    /// One vertical load rises as the other falls (opposed travel, roll).
    Opposed,
}

impl Motion {
    pub fn name(self) -> &'static str {
        match self {
            Motion::Parallel => "parallel",
            Motion::Opposed => "opposed",
        }
    }
}

/// One wheel's slopes at the reference step. Parallel travel: per mm of the
/// wheel's own travel (and N/mm of its vertical load); opposed travel: per
/// degree of body roll.
#[derive(Debug, Clone, PartialEq)]
pub struct WheelSlopes {
    pub wheel: String,
    /// d toe / d travel (deg/mm) or d toe / d φ (deg/deg).
    pub toe: f64,
    /// d camber / d travel (deg/mm) or d camber / d φ (deg/deg).
    pub camber: f64,
    /// d fz / d travel (N/mm), parallel travel only.
    pub rate: Option<f64>,
}

/// The metrics of one axle (a left and a right wheel) along one load path.
#[derive(Debug, Clone, PartialEq)]
pub struct AxleMetrics {
    pub motion: Motion,
    /// 1-based step of the path the slopes are taken at, and its case.
    pub step: usize,
    pub loadcase: String,
    /// Left wheel, then right.
    pub wheels: [WheelSlopes; 2],
    /// Kinematic roll centre `(y, z)`, mm (parallel travel; `None` when the
    /// two contact paths are parallel: the roll centre is at infinity).
    pub roll_centre: Option<[f64; 2]>,
    /// Roll stiffness `-dMx/dφ`, N·m/deg (opposed travel).
    pub roll_stiffness: Option<f64>,
    /// The roll stiffness of the model without some force elements (the
    /// anti-roll bar: `axle kc --without`), and their names; set by the caller.
    pub roll_stiffness_without: Option<(f64, Vec<String>)>,
}

/// The wheel pairs of a model ([`Model::wheel_pairs`]: each left wheel with
/// the right wheel nearest its mirror image).
pub fn wheel_pairs(model: &Model) -> Vec<(WheelId, WheelId)> {
    model.wheel_pairs()
}

/// The body's roll relative to an axle's wheels (deg): right-handed about x,
/// positive when the left wheel drops and the right one rises, from the
/// wheel centres' travel and their lateral distance.
pub fn roll_angle(left: &WheelQuantities, right: &WheelQuantities) -> f64 {
    (right.travel_mm - left.travel_mm)
        .atan2(left.center[1] - right.center[1])
        .to_degrees()
}

/// Whether the two wheels' vertical loads move together or against each other
/// along the set; `None` when one of them does not move.
fn motion(fl: &[f64], fr: &[f64]) -> Option<Motion> {
    let (l0, r0) = (*fl.first()?, *fr.first()?);
    let varies = |f: &[f64], f0: f64| f.iter().any(|v| (v - f0).abs() > 1e-9);
    if !varies(fl, l0) || !varies(fr, r0) {
        return None;
    }
    let s: f64 = fl.iter().zip(fr).map(|(l, r)| (l - l0) * (r - r0)).sum();
    match s {
        s if s > 0.0 => Some(Motion::Parallel),
        s if s < 0.0 => Some(Motion::Opposed),
        _ => None,
    }
}

/// Whether the wheel's rows hold every load but the vertical one: the
/// horizontal forces and the torques at the contact point, and any force at
/// the wheel centre.
fn only_fz_moves(rows: &[&KcRow]) -> bool {
    let Some(first) = rows.first() else {
        return true;
    };
    let held = |a: &KcRow| {
        let same = |x: f64, y: f64| (x - y).abs() <= 1e-9 * (1.0 + y.abs());
        same(a.force[0], first.force[0])
            && same(a.force[1], first.force[1])
            && (0..3).all(|c| same(a.torque[c], first.torque[c]))
            && (0..3).all(|c| same(a.centre_force[c], first.centre_force[c]))
    };
    rows.iter().all(|r| held(r))
}

/// The reference step and the two steps whose difference gives a slope
/// there. The reference is nearest x = 0 (a path may pass there several
/// times, up and back: the first passage with a neighbour on each side that
/// x runs through monotonically, else the first passage); the slope is from
/// those neighbours, or from the step and its one neighbour.
pub(crate) fn reference(x: &[f64]) -> Option<(usize, usize, usize)> {
    let n = x.len();
    let min = x.iter().fold(f64::INFINITY, |m, v| m.min(v.abs()));
    let scale = x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let near = |k: &usize| x[*k].abs() <= min + 1e-9 * scale;
    let central = |k: &usize| *k > 0 && k + 1 < n && (x[k + 1] - x[*k]) * (x[*k] - x[k - 1]) > 0.0;
    let k = (0..n)
        .filter(near)
        .find(central)
        .or_else(|| (0..n).find(near))?;
    let (a, b) = if central(&k) {
        (k - 1, k + 1)
    } else if k + 1 < n {
        (k, k + 1)
    } else if k > 0 {
        (k - 1, k)
    } else {
        return None;
    };
    (x[b] != x[a]).then_some((k, a, b))
}

/// The axle metrics of a path's K&C rows ([`super::kc_rows`]: a row per
/// solved case and wheel, with the roll angle of the wheel's axle), one per
/// wheel pair whose loads move in parallel or opposed. A path cut short
/// gives the metrics of its solved part.
pub fn axle_metrics(model: &Model, rows: &[KcRow]) -> Vec<AxleMetrics> {
    let nw = model.wheels.len();
    if nw == 0 || !rows.len().is_multiple_of(nw) {
        return Vec::new();
    }
    let n = rows.len() / nw;
    let mut out = Vec::new();
    for (l, r) in wheel_pairs(model) {
        // Rows are case by case, the wheels of a case in declaration order.
        let of =
            |w: WheelId| -> Vec<&KcRow> { (0..n).map(|k| &rows[k * nw + w.index()]).collect() };
        let (rl, rr) = (of(l), of(r));
        let fz = |rs: &[&KcRow]| -> Vec<f64> { rs.iter().map(|r| r.force[2]).collect() };
        let (fl, fr) = (fz(&rl), fz(&rr));
        // A path that also moves a wheel's horizontal loads or torques (a
        // table of manoeuvres: curb, turn, braking) is no wheel travel: its
        // differences mix the loads.
        if !only_fz_moves(&rl) || !only_fz_moves(&rr) {
            continue;
        }
        let Some(mo) = motion(&fl, &fr) else {
            continue;
        };
        let (ql, qr): (Vec<WheelQuantities>, Vec<WheelQuantities>) =
            (0..n).map(|k| (rl[k].quantities, rr[k].quantities)).unzip();
        let contact = |q: &WheelQuantities| Vec3::from(q.contact);
        let roll: Vec<f64> = (0..n)
            .map(|k| rl[k].roll_deg.unwrap_or_else(|| roll_angle(&ql[k], &qr[k])))
            .collect();
        let driver: Vec<f64> = match mo {
            Motion::Parallel => (0..n)
                .map(|k| 0.5 * (ql[k].travel_mm + qr[k].travel_mm))
                .collect(),
            Motion::Opposed => roll.clone(),
        };
        let Some((k, a, b)) = reference(&driver) else {
            continue;
        };
        let slopes = |q: &[WheelQuantities], f: &[f64], name: &str| {
            let dx = match mo {
                Motion::Parallel => q[b].travel_mm - q[a].travel_mm,
                Motion::Opposed => roll[b] - roll[a],
            };
            WheelSlopes {
                wheel: name.to_string(),
                toe: (q[b].toe_deg - q[a].toe_deg) / dx,
                camber: (q[b].camber_deg - q[a].camber_deg) / dx,
                rate: (mo == Motion::Parallel).then(|| (f[b] - f[a]) / dx),
            }
        };
        let roll_centre = match mo {
            Motion::Parallel => roll_centre(
                contact(&ql[k]),
                contact(&ql[b]) - contact(&ql[a]),
                contact(&qr[k]),
                contact(&qr[b]) - contact(&qr[a]),
            ),
            Motion::Opposed => None,
        };
        // Mx of the vertical wheel loads about the x axis (contact points), N·mm.
        let mx = |j: usize| ql[j].contact[1] * fl[j] + qr[j].contact[1] * fr[j];
        let roll_stiffness = match mo {
            Motion::Opposed => Some(-(mx(b) - mx(a)) / (roll[b] - roll[a]) / 1000.0),
            Motion::Parallel => None,
        };
        out.push(AxleMetrics {
            motion: mo,
            step: rl[k].step,
            loadcase: rl[k].loadcase.clone(),
            wheels: [
                slopes(&ql, &fl, &rl[k].wheel),
                slopes(&qr, &fr, &rr[k].wheel),
            ],
            roll_centre,
            roll_stiffness,
            roll_stiffness_without: None,
        });
    }
    out
}

/// Where the lines through each contact point normal to its path (in the yz
/// plane) meet: each passes through its wheel's instant centre, so they meet
/// at the kinematic roll centre. `(y, z)`, mm; `None` for parallel lines.
fn roll_centre(pl: Vec3, vl: Vec3, pr: Vec3, vr: Vec3) -> Option<[f64; 2]> {
    // Normals (dz, -dy); solve pl + s nl = pr + u nr.
    let (nl, nr) = ([vl.z, -vl.y], [vr.z, -vr.y]);
    let det = nl[0] * (-nr[1]) - (-nr[0]) * nl[1];
    let scale = (nl[0].hypot(nl[1])) * (nr[0].hypot(nr[1]));
    // Also catches a NaN determinant (a path that did not move).
    if det.is_nan() || det.abs() <= 1e-12 * scale {
        return None;
    }
    let (dy, dz) = (pr.y - pl.y, pr.z - pl.z);
    let s = (dy * (-nr[1]) - (-nr[0]) * dz) / det;
    Some([pl.y + s * nl[0], pl.z + s * nl[1]])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_normals_of_two_symmetric_paths_meet_on_the_centreline() {
        // Contact points at y = ±750 moving outward by 0.1 mm per mm of rise:
        // the normals meet at height 0.1 * 750 = 75 mm.
        let rc = roll_centre(
            Vec3::new(0.0, 750.0, 0.0),
            Vec3::new(0.0, 0.1, 1.0),
            Vec3::new(0.0, -750.0, 0.0),
            Vec3::new(0.0, -0.1, 1.0),
        )
        .expect("they meet");
        assert!(rc[0].abs() < 1e-12 && (rc[1] - 75.0).abs() < 1e-9, "{rc:?}");
        // Vertical paths: parallel normals, no roll centre.
        let v = Vec3::new(0.0, 0.0, 1.0);
        assert!(
            roll_centre(
                Vec3::new(0.0, 750.0, 0.0),
                v,
                Vec3::new(0.0, -750.0, 0.0),
                v
            )
            .is_none()
        );
    }

    #[test]
    fn the_reference_is_the_step_nearest_zero_between_its_neighbours() {
        assert_eq!(reference(&[-2.0, -1.0, 0.1, 1.0, 2.0]), Some((2, 1, 3)));
        // A turning point at the reference: the step and the next one.
        assert_eq!(reference(&[1.0, 0.0, 1.0]), Some((1, 1, 2)));
        assert_eq!(reference(&[0.0, 1.0, 2.0]), Some((0, 0, 1)));
        // Up and back through zero: the first passage with a neighbour each side.
        assert_eq!(reference(&[0.0, 1.0, 0.0, -1.0, 0.0]), Some((2, 1, 3)));
        assert_eq!(reference(&[1.0]), None);
    }
}
