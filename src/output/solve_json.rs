//! The documents of `solve --format json` and `kc --format json`
//! (`interfaces.md`), written directly with [`Json`]: keys in the sorted
//! order serde_json's maps give, every float rounded once as it is printed.
//! The tests check the bytes against the `serde_json::Value` tree these
//! documents were built from before (serialised reports, `round_json`).

use super::json::{Json, Template};
use super::report::{ByName, CaseReport, FailedCase};
use crate::kc::axle::WheelSlopes;
use crate::kc::compliance::WheelCompliance;
use crate::kc::steer::WheelSteer;
use crate::kc::{
    AxleMetrics, ComplianceMetrics, Input, KcRow, Motion, SteeringMetrics, WheelQuantities,
};
use serde_json::Value;

fn wheel(w: &mut Json, q: &WheelQuantities) {
    w.begin_object();
    w.key("camber_deg").num(q.camber_deg);
    w.key("center").nums(&q.center);
    w.key("half_track_mm").num(q.half_track_mm);
    w.key("spin_axis").nums(&q.spin_axis);
    w.key("toe_deg").num(q.toe_deg);
    w.key("travel_mm").num(q.travel_mm);
    w.end_object();
}

/// One case of `solve` (the fields of [`CaseReport`], sorted).
fn case(w: &mut Json, c: &CaseReport) {
    w.begin_object();
    w.key("bushings").begin_object();
    for (name, b) in &c.bushings {
        w.key(name).begin_object();
        w.key("deformation").nums(&b.deformation);
        w.key("force").nums(&b.force);
        w.end_object();
    }
    w.end_object();
    w.key("converged").bool(c.converged);
    if !c.frictions.is_empty() {
        w.key("frictions").begin_object();
        for (name, f) in &c.frictions {
            w.key(name).begin_object();
            w.key("force").num(f.force);
            w.key("slide").num(f.slide);
            w.key("slip_offset").num(f.slip_offset);
            w.key("state").str(f.state);
            w.end_object();
        }
        w.end_object();
    }
    w.key("iterations").int(c.iterations as u64);
    w.key("joints").begin_object();
    for (name, j) in &c.joints {
        w.key(name).begin_object();
        w.key("force").nums(&j.force);
        w.key("point").nums(&j.point);
        w.key("torque").nums(&j.torque);
        w.end_object();
    }
    w.end_object();
    w.key("loads").begin_array();
    for l in &c.loads {
        w.begin_object();
        w.key("force").nums(&l.force);
        w.key("marker").str(&l.marker);
        w.key("torque").nums(&l.torque);
        w.end_object();
    }
    w.end_array();
    w.key("name").str(&c.name);
    w.key("parts").begin_object();
    for (name, p) in &c.parts {
        w.key(name).begin_object();
        w.key("displacement").nums(&p.displacement);
        w.key("position").nums(&p.position);
        w.key("rotation").begin_array();
        for row in &p.rotation {
            w.nums(row);
        }
        w.end_array();
        w.end_object();
    }
    w.end_object();
    w.key("springs").begin_object();
    for (name, s) in &c.springs {
        w.key(name).begin_object();
        w.key("force").num(s.force);
        w.key("length").num(s.length);
        w.end_object();
    }
    w.end_object();
    w.key("step").int(c.step as u64);
    w.key("substeps").int(c.substeps as u64);
    w.key("wheels").begin_object();
    for (name, q) in &c.wheels {
        w.key(name);
        wheel(w, q);
    }
    w.end_object();
    w.end_object();
}

/// What a case's layout depends on besides its values: how many elements of
/// each kind and loads it has, and which names (by address: the reports of
/// one `Reporter` share them; equal names elsewhere only cost a recording).
fn shape(c: &CaseReport, out: &mut Vec<usize>) {
    fn names<T>(out: &mut Vec<usize>, m: &ByName<T>) {
        out.push(m.len());
        out.extend(m.iter().map(|(k, _)| k.as_ptr() as usize));
    }
    out.clear();
    names(out, &c.bushings);
    names(out, &c.frictions);
    names(out, &c.joints);
    names(out, &c.parts);
    names(out, &c.springs);
    names(out, &c.wheels);
    out.push(c.loads.len());
}

fn failed_case(w: &mut Json, f: &FailedCase) {
    w.begin_object();
    w.key("code").str(f.code);
    w.key("converged").bool(f.converged);
    w.key("elements").begin_array();
    for e in &f.elements {
        w.str(e);
    }
    w.end_array();
    w.key("error").str(&f.error);
    w.key("name").str(&f.name);
    w.key("step").int(f.step as u64);
    w.end_object();
}

/// `solve --format json`: the converged cases, then the failing one, and the
/// trim ([`SolveDocument`] in one piece).
pub fn solve(
    model: &str,
    load_set: &str,
    cases: &[CaseReport],
    failed: Option<&FailedCase>,
    not_solved: Option<&[(String, usize)]>,
    trim: Option<&Value>,
) -> String {
    let mut doc = SolveDocument::new();
    for c in cases {
        doc.case(c);
    }
    doc.end(load_set, model, failed, not_solved, trim)
}

/// The document of `solve --format json` made case by case, for a caller
/// that writes it out as the path is solved ([`Self::drain`] between cases)
/// rather than holding every case's report and the whole text.
pub struct SolveDocument {
    w: Json,
    /// The shape of the case at hand, and the last case's with its layout.
    this: Vec<usize>,
    last: Option<(Vec<usize>, Template)>,
}

impl Default for SolveDocument {
    fn default() -> Self {
        SolveDocument::new()
    }
}

impl SolveDocument {
    /// The document up to its first case.
    pub fn new() -> SolveDocument {
        SolveDocument::with_capacity(0)
    }

    /// As [`Self::new`], its text growing into `bytes` before it reallocates.
    pub fn with_capacity(bytes: usize) -> SolveDocument {
        let mut w = Json::with_capacity(bytes);
        w.begin_object();
        w.key("cases").begin_array();
        SolveDocument {
            w,
            this: Vec::new(),
            last: None,
        }
    }

    /// The next converged case.
    pub fn case(&mut self, c: &CaseReport) {
        // The cases of a path name the same elements (shared names, see
        // `report::Reporter`): the first of each shape is written and its
        // layout recorded, the others only format their values into it.
        shape(c, &mut self.this);
        let replayed = match &mut self.last {
            Some((was, layout)) if *was == self.this => self.w.replay(layout, |w| case(w, c)),
            _ => false,
        };
        if !replayed {
            let layout = self.w.record(|w| case(w, c));
            self.last = Some((self.this.clone(), layout));
        }
    }

    /// The failing case if any, and the rest of the document: the text not
    /// yet drained, to its final newline.
    pub fn end(
        mut self,
        load_set: &str,
        model: &str,
        failed: Option<&FailedCase>,
        not_solved: Option<&[(String, usize)]>,
        trim: Option<&Value>,
    ) -> String {
        let w = &mut self.w;
        if let Some(f) = failed {
            failed_case(w, f);
        }
        w.end_array();
        w.key("load_set").str(load_set);
        w.key("model").str(model);
        if let Some(rest) = not_solved {
            w.key("not_solved").begin_array();
            for (name, step) in rest {
                w.begin_object();
                w.key("name").str(name);
                w.key("step").int(*step as u64);
                w.end_object();
            }
            w.end_array();
        }
        if let Some(t) = trim {
            w.key("trim").value(t);
        }
        w.end_object();
        self.w.finish()
    }

    /// The bytes made since the last call, handed to `sink` (see
    /// [`Json::drain`]).
    pub fn drain<R>(&mut self, sink: impl FnOnce(&[u8]) -> R) -> R {
        self.w.drain(sink)
    }

    /// How many bytes [`Self::drain`] would hand over.
    pub fn pending(&self) -> usize {
        self.w.pending()
    }
}

/// One K&C row with the CSV's column names.
fn kc_row(w: &mut Json, r: &KcRow) {
    let q = &r.quantities;
    w.begin_object();
    w.key("camber_deg").num(q.camber_deg);
    w.key("fx").num(r.force[0]);
    w.key("fy").num(r.force[1]);
    w.key("fz").num(r.force[2]);
    w.key("half_track_change_mm").num(q.half_track_change_mm);
    w.key("half_track_mm").num(q.half_track_mm);
    w.key("loadcase").str(&r.loadcase);
    w.key("mx").num(r.torque[0]);
    w.key("my").num(r.torque[1]);
    w.key("mz").num(r.torque[2]);
    w.key("step").int(r.step as u64);
    w.key("toe_deg").num(q.toe_deg);
    w.key("travel_mm").num(q.travel_mm);
    w.key("wc_x").num(q.center[0]);
    w.key("wc_y").num(q.center[1]);
    w.key("wc_z").num(q.center[2]);
    w.key("wheel").str(&r.wheel);
    w.end_object();
}

/// One axle's metrics (keys sorted; `docs/kc.md`).
fn axle(w: &mut Json, a: &AxleMetrics) {
    w.begin_object();
    w.key("left").str(&a.wheels[0].wheel);
    w.key("loadcase").str(&a.loadcase);
    w.key("motion").str(a.motion.name());
    w.key("right").str(&a.wheels[1].wheel);
    match a.motion {
        Motion::Parallel => {
            w.key("roll_centre_mm");
            match a.roll_centre {
                Some(rc) => w.nums(&rc),
                None => w.value(&Value::Null),
            }
        }
        Motion::Opposed => {
            if let Some(k) = a.roll_stiffness {
                w.key("roll_stiffness_nm_per_deg").num(k);
            }
            if let Some((k, names)) = &a.roll_stiffness_without {
                w.key("roll_stiffness_without").begin_object();
                w.key("elements").begin_array();
                for n in names {
                    w.str(n);
                }
                w.end_array();
                w.key("nm_per_deg").num(*k);
                w.end_object();
            }
        }
    }
    w.key("step").int(a.step as u64);
    w.key("wheels").begin_object();
    let mut sorted: Vec<&WheelSlopes> = a.wheels.iter().collect();
    sorted.sort_by(|x, y| x.wheel.cmp(&y.wheel));
    for s in sorted {
        w.key(&s.wheel).begin_object();
        match a.motion {
            Motion::Parallel => {
                w.key("bump_camber_deg_per_mm").num(s.camber);
                w.key("bump_steer_deg_per_mm").num(s.toe);
                if let Some(k) = s.rate {
                    w.key("wheel_rate_n_per_mm").num(k);
                }
            }
            Motion::Opposed => {
                w.key("roll_camber_deg_per_deg").num(s.camber);
                w.key("roll_steer_deg_per_deg").num(s.toe);
            }
        }
        w.end_object();
    }
    w.end_object();
    w.end_object();
}

/// The metrics of a K&C path beside its rows (`docs/kc.md`): an axle's
/// parallel or opposed travel, compliance events, a steering rack's geometry.
#[derive(Debug, Clone, Default)]
pub struct PathMetrics<'a> {
    pub axles: &'a [AxleMetrics],
    pub events: &'a [ComplianceMetrics],
    pub steering: Option<&'a SteeringMetrics>,
}

/// `kc --format json`: the axle metrics (when the path moves a wheel pair), rows, the wheel-centre compliances (mm/kN, sorted by
/// wheel, whose names are unique), the iterations per step, the failing step.
pub fn kc(
    model: &str,
    sweep: &str,
    rows: &[KcRow],
    compliance: &[(String, [[f64; 3]; 3])],
    metrics: &PathMetrics,
    iterations: &[usize],
    failed: Option<&FailedCase>,
) -> String {
    let &PathMetrics {
        axles,
        events,
        steering,
    } = metrics;
    let mut w = Json::new();
    w.begin_object();
    if !axles.is_empty() {
        w.key("axles").begin_array();
        for a in axles {
            axle(&mut w, a);
        }
        w.end_array();
    }
    if !events.is_empty() {
        w.key("compliance_events").begin_array();
        for e in events {
            compliance_event(&mut w, e);
        }
        w.end_array();
    }
    w.key("compliance_mm_per_kn").begin_object();
    let mut sorted: Vec<&(String, [[f64; 3]; 3])> = compliance.iter().collect();
    sorted.sort_by(|a, b| a.0.cmp(&b.0));
    for (name, m) in sorted {
        w.key(name).begin_array();
        for row in m {
            w.nums(row);
        }
        w.end_array();
    }
    w.end_object();
    if let Some(f) = failed {
        w.key("failed");
        failed_case(&mut w, f);
    }
    w.key("iterations").begin_array();
    for &i in iterations {
        w.int(i as u64);
    }
    w.end_array();
    w.key("model").str(model);
    w.key("rows").begin_array();
    for r in rows {
        kc_row(&mut w, r);
    }
    w.end_array();
    if let Some(s) = steering {
        w.key("steering");
        steering_metrics(&mut w, s, rows);
    }
    w.key("sweep").str(sweep);
    w.end_object();
    w.finish()
}

/// A compliance event (`docs/kc.md`): the input, the phase of an axle's
/// pair, the reference step and per wheel the slopes per kN (per N·m of
/// an aligning torque) of the wheel's own load.
fn compliance_event(w: &mut Json, e: &ComplianceMetrics) {
    let per = match e.input {
        Input::AligningTorque => "nm",
        _ => "kn",
    };
    w.begin_object();
    w.key("input").str(e.input.name());
    w.key("loadcase").str(&e.loadcase);
    if let Some(p) = e.phase {
        w.key("phase").str(p.name());
    }
    w.key("step").int(e.step as u64);
    w.key("wheels").begin_object();
    let mut sorted: Vec<&WheelCompliance> = e.wheels.iter().collect();
    sorted.sort_by(|x, y| x.wheel.cmp(&y.wheel));
    for c in sorted {
        w.key(&c.wheel).begin_object();
        w.key(&format!("camber_deg_per_{per}")).num(c.camber);
        if let Some(d) = c.centre {
            w.key("centre_mm_per_kn").num(d);
        }
        w.key(&format!("toe_deg_per_{per}")).num(c.toe);
        w.end_object();
    }
    w.end_object();
    w.end_object();
}

/// The steering geometry of a path that drives a rack (`docs/kc.md`), and
/// the rack's travel at every step.
fn steering_metrics(w: &mut Json, s: &SteeringMetrics, rows: &[KcRow]) {
    w.begin_object();
    w.key("loadcase").str(&s.loadcase);
    w.key("rack").str(&s.rack);
    w.key("rack_travel_mm").begin_array();
    let mut step = 0;
    for r in rows {
        if r.step != step {
            step = r.step;
            w.num(r.rack_mm.unwrap_or(f64::NAN));
        }
    }
    w.end_array();
    w.key("step").int(s.step as u64);
    w.key("travel_mm").num(s.travel_mm);
    w.key("wheels").begin_object();
    let mut sorted: Vec<&WheelSteer> = s.wheels.iter().collect();
    sorted.sort_by(|x, y| x.wheel.cmp(&y.wheel));
    for ws in sorted {
        w.key(&ws.wheel).begin_object();
        w.key("axis_direction").nums(&ws.axis_direction);
        w.key("axis_ground_point_mm").nums(&ws.axis_point);
        w.key("caster_deg").num(ws.caster_deg);
        w.key("kingpin_inclination_deg").num(ws.kpi_deg);
        w.key("mechanical_trail_mm").num(ws.trail_mm);
        w.key("scrub_radius_mm").num(ws.scrub_mm);
        w.key("steer_deg_per_mm").num(ws.steer_per_travel);
        w.end_object();
    }
    w.end_object();
    w.end_object();
}

#[cfg(test)]
#[path = "solve_json_tests.rs"]
mod tests;
