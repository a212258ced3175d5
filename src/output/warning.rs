//! Warnings of a solve, worded once: bushings driven beyond the range of
//! projected angles (W1001) and implausible states ([`super::plausibility`]:
//! W1002, W1003). (Redundant constraints are reported once, by the checker's
//! mobility analysis.)

use super::report::{ANGLE_LIMIT_DEG, AngleWarning, BushingReport, CaseReport};
use crate::diagnostic::Diagnostic;
use crate::geom::Vec3;
use crate::model::{Bushing, BushingId, ElementId, Model};
use crate::statics::coords::Layout;
use crate::statics::forces::bushing_state;
use crate::statics::{Equilibrium, State};

/// Every warning of a path's converged cases (`names[k]` names case `k`):
/// the angle warnings, then the implausible states.
pub fn of_path(model: &Model, names: &[String], eqs: &[Equilibrium]) -> Vec<Diagnostic> {
    let mut w = PathWarnings::new(model);
    for e in eqs {
        w.add(&e.state);
    }
    w.finish(names)
}

/// The warnings of a path gathered case by case, for a path whose states
/// are not kept ([`crate::statics::path::Simulator::run_each`]): what each
/// case shows, a few words a case and none for most.
pub struct PathWarnings<'m> {
    model: &'m Model,
    layout: Layout,
    design: State,
    angles: Vec<Vec<AngleWarning>>,
    found: Vec<Vec<super::plausibility::Finding>>,
}

impl<'m> PathWarnings<'m> {
    pub fn new(model: &'m Model) -> PathWarnings<'m> {
        PathWarnings {
            model,
            layout: Layout::new(model),
            design: State::design(model),
            angles: Vec::new(),
            found: Vec::new(),
        }
    }

    /// The next converged case's state.
    pub fn add(&mut self, state: &State) {
        let readings = BushingReading::all_at(self.model, &self.layout, state);
        self.push(state, &readings);
    }

    /// The next converged case, reported as `report`: its bushings read off
    /// the report rather than evaluated again.
    pub fn add_reported(&mut self, state: &State, report: &CaseReport) {
        let readings: Vec<BushingReading> = self
            .model
            .bushings
            .iter()
            .map(|b| match report.bushings.get(&b.name) {
                Some(r) => BushingReading::of_report(r),
                None => BushingReading::of_state(self.model, &self.layout, state, b),
            })
            .collect();
        self.push(state, &readings);
    }

    fn push(&mut self, state: &State, readings: &[BushingReading]) {
        let model = self.model;
        self.angles.push(angle_warnings_of(model, readings));
        let found = super::plausibility::findings(model, &self.design, state, readings);
        self.found.push(found);
    }

    /// The warnings, the cases named by `names`.
    pub fn finish(self, names: &[String]) -> Vec<Diagnostic> {
        let mut out = angles(self.model, names, &self.angles);
        out.extend(super::plausibility::warnings(
            self.model,
            names,
            &self.found,
        ));
        out
    }
}

/// One warning per bushing whose tilts (ax, ay) leave ±15° in some case:
/// the largest angle and the cases where it happens. `per_case[k]` holds the
/// warnings of case `k` named `names[k]`.
pub fn angles(model: &Model, names: &[String], per_case: &[Vec<AngleWarning>]) -> Vec<Diagnostic> {
    // (bushing, worst angle name, worst value, cases) in bushing order.
    let mut worst: std::collections::BTreeMap<ElementId, (&'static str, f64, Vec<&str>)> =
        Default::default();
    for (k, ws) in per_case.iter().enumerate() {
        for w in ws {
            let e = worst.entry(w.bushing).or_insert((w.angle, 0.0, Vec::new()));
            if w.value_deg.abs() > e.1.abs() {
                e.0 = w.angle;
                e.1 = w.value_deg;
            }
            let case = names.get(k).map_or("?", String::as_str);
            if !e.2.contains(&case) {
                e.2.push(case);
            }
        }
    }
    worst
        .into_iter()
        .map(|(id, (angle, value, cases))| {
            let shown: Vec<&str> = cases.iter().take(6).copied().collect();
            let more = if cases.len() > shown.len() { format!(" and {} more", cases.len() - shown.len()) } else { String::new() };
            Diagnostic::warning(
                "W1001",
                format!(
                    "{} tilts beyond ±{ANGLE_LIMIT_DEG}° ({angle} = {value:.2}° at most), where projected angles lose accuracy",
                    model.describe(id)
                ),
            )
            .secondary_opt(model.origins.get(id), "this bushing")
            .note(format!("in case{} {}{more}", if cases.len() == 1 { "" } else { "s" }, shown.join(", ")))
            .hint("check the bushing's orientation (its J axes) and the size of the load")
        })
        .collect()
}

/// What a case's warnings read of one bushing: the size of its translation
/// (mm) and its tilts ax, ay (degrees). Read off the case's report where
/// there is one, so that a path's bushings are evaluated once a case.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BushingReading {
    pub mm: f64,
    pub tilt_deg: [f64; 2],
}

impl BushingReading {
    /// Every bushing's, in the model's order, evaluated at `state`.
    pub fn all_at(model: &Model, layout: &Layout, state: &State) -> Vec<Self> {
        model
            .bushings
            .iter()
            .map(|b| BushingReading::of_state(model, layout, state, b))
            .collect()
    }

    pub fn of_state(model: &Model, layout: &Layout, state: &State, b: &Bushing) -> Self {
        let e = bushing_state(model, layout, state, b);
        BushingReading {
            mm: e.t.norm(),
            tilt_deg: [e.angles.x.to_degrees(), e.angles.y.to_degrees()],
        }
    }

    /// The same numbers from the report (the same bits: the report holds
    /// the translation and the angles in degrees).
    pub fn of_report(r: &BushingReport) -> Self {
        let d = &r.deformation;
        BushingReading {
            mm: Vec3::new(d[0], d[1], d[2]).norm(),
            tilt_deg: [d[3], d[4]],
        }
    }
}

/// The angle warnings of the model's bushings at `state`.
pub fn angle_warnings(model: &Model, state: &State) -> Vec<AngleWarning> {
    let readings = BushingReading::all_at(model, &Layout::new(model), state);
    angle_warnings_of(model, &readings)
}

/// The angle warnings of one case, `readings[k]` of the model's bushing `k`.
pub fn angle_warnings_of(model: &Model, readings: &[BushingReading]) -> Vec<AngleWarning> {
    let mut out = Vec::new();
    for (k, (b, r)) in model.bushings.iter().zip(readings).enumerate() {
        // Only the tilts: ax and ay read the direction of z_I alone, and the
        // projections are exact for a rotation about z_J (az = the angle), so
        // torsion about the bushing's own axis, however large, is no reason
        // to doubt them (docs/language.md, "Deformation").
        for (v, name) in r.tilt_deg.into_iter().zip(["ax", "ay"]) {
            if v.abs() > ANGLE_LIMIT_DEG {
                out.push(AngleWarning {
                    bushing: ElementId::Bushing(BushingId(k as u32)),
                    name: b.name.clone(),
                    angle: name,
                    value_deg: v,
                });
            }
        }
    }
    out
}
