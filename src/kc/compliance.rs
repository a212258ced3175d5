//! Compliance events of a K&C rig (`docs/kc.md`, "Compliance events"): a
//! load path that sweeps one horizontal load at a wheel with its vertical
//! load held: a lateral force or a braking force at the contact point, a
//! traction force at the wheel centre, or an aligning torque about the
//! vertical. Per wheel, the slopes at the step where that load is nearest
//! zero: compliance steer (toe), compliance camber and the wheel centre's
//! displacement along the load. An axle's two wheels loaded together are
//! loaded **in phase** (the same global direction, as in a turn or under
//! braking) or **opposed**; the slope of each wheel is taken along the path,
//! so it includes what the other wheel's load does through the rack, the bar
//! or a twist beam, and the two phases differ by exactly that coupling.
//!
//! Each wheel's load is counted in its own frame so that a symmetric axle
//! gives the same number on both sides: lateral force and aligning torque
//! positive **outboard** (`s fy`, `s mz`, with `s = +1` for a left wheel and
//! `-1` for a right one: a positive aligning torque turns the wheel's front
//! outboard, toward toe-out), longitudinal forces positive forward.

use super::axle::{reference, wheel_pairs};
use super::wheel::KcRow;
use crate::model::{Model, WheelId};

/// The load a compliance event sweeps at a wheel.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Input {
    /// `fy` at the contact point (cornering force).
    Lateral,
    /// `fx` at the contact point (brake force).
    Braking,
    /// `fx` at the wheel centre (drive force through the hub).
    Traction,
    /// `mz` at the contact point (the tyre's aligning torque).
    AligningTorque,
}

impl Input {
    pub const ALL: [Input; 4] = [
        Input::Lateral,
        Input::Braking,
        Input::Traction,
        Input::AligningTorque,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Input::Lateral => "lateral",
            Input::Braking => "braking",
            Input::Traction => "traction",
            Input::AligningTorque => "aligning_torque",
        }
    }

    /// The words of the table and plots.
    pub fn title(self) -> &'static str {
        match self {
            Input::Lateral => "lateral force at the contact point",
            Input::Braking => "longitudinal force at the contact point (braking)",
            Input::Traction => "longitudinal force at the wheel centre (traction)",
            Input::AligningTorque => "aligning torque at the contact point",
        }
    }

    /// The unit of the load the slopes are per: kN, or N·m for a torque.
    pub fn per(self) -> &'static str {
        match self {
            Input::AligningTorque => "N*m",
            _ => "kN",
        }
    }

    /// The global component of the row's loads the input is (N, or N·mm).
    pub fn global(self, r: &KcRow) -> f64 {
        match self {
            Input::Lateral => r.force[1],
            Input::Braking => r.force[0],
            Input::Traction => r.centre_force[0],
            Input::AligningTorque => r.torque[2],
        }
    }

    /// The row's load in its wheel's own frame (N or N·mm): the global
    /// component, negated on a right wheel for a lateral force or a torque.
    pub fn own(self, r: &KcRow) -> f64 {
        if self.mirrored() {
            side(r) * self.global(r)
        } else {
            self.global(r)
        }
    }

    /// Whether the wheel's own frame flips the global sign on a right wheel
    /// (lateral and yaw loads do; longitudinal ones do not).
    fn mirrored(self) -> bool {
        matches!(self, Input::Lateral | Input::AligningTorque)
    }
}

/// A load (N or N·mm) in the slopes' unit (kN or N·m): the same factor.
const TO_SLOPE_UNIT: f64 = 1e-3;

/// How an axle's two wheels are loaded in an event.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Phase {
    /// Both loads in the same global direction.
    InPhase,
    /// Loads in opposite global directions (both outboard, or both inboard,
    /// for a lateral force).
    Opposed,
}

impl Phase {
    pub fn name(self) -> &'static str {
        match self {
            Phase::InPhase => "in_phase",
            Phase::Opposed => "opposed",
        }
    }
}

/// One wheel's slopes per unit of its own load (outboard or forward
/// positive, in kN, or N·m for a torque).
#[derive(Debug, Clone, PartialEq)]
pub struct WheelCompliance {
    pub wheel: String,
    /// d toe / d load (toe-in positive): deg/kN or deg/(N·m).
    pub toe: f64,
    /// d camber / d load (top outboard positive): deg/kN or deg/(N·m).
    pub camber: f64,
    /// The wheel centre's displacement along the load (outboard for a
    /// lateral force, forward for a longitudinal one), mm/kN; none for a
    /// torque.
    pub centre: Option<f64>,
}

/// A compliance event on one wheel, or on an axle's pair of wheels loaded
/// together.
#[derive(Debug, Clone, PartialEq)]
pub struct ComplianceMetrics {
    pub input: Input,
    /// `None` for a wheel loaded alone.
    pub phase: Option<Phase>,
    /// 1-based step of the slopes, and its case.
    pub step: usize,
    pub loadcase: String,
    /// Left wheel first for a pair.
    pub wheels: Vec<WheelCompliance>,
}

/// Loads below this are rig noise, not a swept input (N, N·mm).
const STILL: f64 = 1e-9;

fn varies(v: &[f64]) -> bool {
    v.iter()
        .any(|x| (x - v[0]).abs() > STILL * (1.0 + v[0].abs()))
}

/// `+1` for a left wheel, `-1` for a right one: the side of its centre, as
/// toe is signed (`super::wheel_quantities`).
fn side(r: &KcRow) -> f64 {
    if r.quantities.center[1] < 0.0 {
        -1.0
    } else {
        1.0
    }
}

/// The input a wheel's rows sweep: exactly one of the four varies and the
/// vertical load is held; `None` otherwise (no event, or a mixed one whose
/// slopes would confound two loads).
fn swept_input(rows: &[&KcRow]) -> Option<Input> {
    let fz: Vec<f64> = rows.iter().map(|r| r.force[2]).collect();
    if rows.len() < 2 || varies(&fz) {
        return None;
    }
    let moving: Vec<Input> = Input::ALL
        .into_iter()
        .filter(|i| varies(&rows.iter().map(|r| i.global(r)).collect::<Vec<_>>()))
        .collect();
    match moving.as_slice() {
        [one] => Some(*one),
        _ => None,
    }
}

/// The slopes of one wheel's rows at steps `a`, `b` (the reference's
/// neighbours), per unit of the wheel's own load; `None` when its load is
/// the same at both (a second wheel that does not move in step there).
fn slopes(input: Input, rows: &[&KcRow], a: usize, b: usize) -> Option<WheelCompliance> {
    let load = |k: usize| input.own(rows[k]) * TO_SLOPE_UNIT;
    let dl = load(b) - load(a);
    if dl == 0.0 || !dl.is_finite() {
        return None;
    }
    let q = |k: usize| &rows[k].quantities;
    let centre = match input {
        // Outboard: +y on the left, -y on the right.
        Input::Lateral => Some(side(rows[a]) * (q(b).center[1] - q(a).center[1]) / dl),
        Input::Braking | Input::Traction => Some((q(b).center[0] - q(a).center[0]) / dl),
        Input::AligningTorque => None,
    };
    Some(WheelCompliance {
        wheel: rows[0].wheel.clone(),
        toe: (q(b).toe_deg - q(a).toe_deg) / dl,
        camber: (q(b).camber_deg - q(a).camber_deg) / dl,
        centre,
    })
}

/// The compliance events of a path's K&C rows ([`super::kc_rows`], a row
/// per case and wheel): one per axle pair whose wheels sweep the same
/// input, and one per other wheel that sweeps one, in wheel order.
pub fn compliance_metrics(model: &Model, rows: &[KcRow]) -> Vec<ComplianceMetrics> {
    let nw = model.wheels.len();
    if nw == 0 || !rows.len().is_multiple_of(nw) {
        return Vec::new();
    }
    let n = rows.len() / nw;
    let of = |w: usize| -> Vec<&KcRow> { (0..n).map(|k| &rows[k * nw + w]).collect() };
    let inputs: Vec<Option<Input>> = (0..nw).map(|w| swept_input(&of(w))).collect();
    // Each event's wheels: the pairs first, then wheels left alone.
    let mut groups: Vec<(Input, Vec<usize>)> = Vec::new();
    let mut grouped = vec![false; nw];
    for (WheelId(l), WheelId(r)) in wheel_pairs(model) {
        let (l, r) = (l as usize, r as usize);
        if let (Some(il), Some(ir)) = (inputs[l], inputs[r])
            && il == ir
        {
            groups.push((il, vec![l, r]));
            grouped[l] = true;
            grouped[r] = true;
        }
    }
    for w in 0..nw {
        if let (Some(i), false) = (inputs[w], grouped[w]) {
            groups.push((i, vec![w]));
        }
    }
    groups.sort_by_key(|(_, ws)| ws[0]);
    let mut out = Vec::new();
    for (input, wheels) in groups {
        let first = of(wheels[0]);
        let driver: Vec<f64> = first.iter().map(|r| input.global(r)).collect();
        let Some((k, a, b)) = reference(&driver) else {
            continue;
        };
        // A second wheel whose load stands still at the reference is left
        // out: the event is then the first wheel's alone.
        let slopes: Vec<WheelCompliance> = wheels
            .iter()
            .filter_map(|&w| slopes(input, &of(w), a, b))
            .collect();
        let phase = (slopes.len() == 2).then(|| {
            let other: Vec<f64> = of(wheels[1]).iter().map(|r| input.global(r)).collect();
            let s: f64 = driver
                .iter()
                .zip(&other)
                .map(|(x, y)| (x - driver[0]) * (y - other[0]))
                .sum();
            if s >= 0.0 {
                Phase::InPhase
            } else {
                Phase::Opposed
            }
        });
        out.push(ComplianceMetrics {
            input,
            phase,
            step: first[k].step,
            loadcase: first[k].loadcase.clone(),
            wheels: slopes,
        });
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kc::WheelQuantities;

    /// A row of wheel `wheel` at `step` with lateral force `fy` and a toe
    /// that follows it (0.1 deg/kN), centre at `y`.
    fn row(step: usize, wheel: &str, y: f64, fy: f64) -> KcRow {
        KcRow {
            step,
            loadcase: format!("c{step}"),
            wheel: wheel.to_string(),
            force: [0.0, fy, 4500.0],
            torque: [0.0; 3],
            centre_force: [0.0; 3],
            quantities: WheelQuantities {
                center: [0.0, y, 300.0],
                spin_axis: [0.0, y.signum(), 0.0],
                toe_deg: 1e-4 * fy * y.signum(),
                camber_deg: 0.0,
                travel_mm: 0.0,
                half_track_mm: y.abs(),
                half_track_change_mm: 0.0,
                contact: [0.0, y, 0.0],
            },
            roll_deg: None,
            rack_mm: None,
        }
    }

    #[test]
    fn a_second_wheel_standing_still_at_the_reference_is_left_out() {
        let left = [-1000.0, 0.0, 1000.0].map(|f| row(0, "l", 750.0, f));
        // The right wheel's load rises and falls elsewhere, but not across
        // the reference's neighbours.
        let right = [500.0, 500.0, 500.0].map(|f| row(0, "r", -750.0, f));
        let (l, r): (Vec<&KcRow>, Vec<&KcRow>) = (left.iter().collect(), right.iter().collect());
        assert!(slopes(Input::Lateral, &r, 0, 2).is_none());
        let s = slopes(Input::Lateral, &l, 0, 2).expect("the left wheel's");
        // Toe per kN of outboard force: 1e-4 deg/N.
        assert!((s.toe - 0.1).abs() < 1e-12, "{s:?}");
        assert_eq!(s.centre, Some(0.0));
    }

    #[test]
    fn a_right_wheels_lateral_load_and_torque_count_outboard() {
        let r = row(1, "r", -750.0, -2000.0);
        assert_eq!(Input::Lateral.own(&r), 2000.0);
        assert_eq!(Input::Braking.own(&r), 0.0);
        let l = row(1, "l", 750.0, -2000.0);
        assert_eq!(Input::Lateral.own(&l), -2000.0);
    }
}
