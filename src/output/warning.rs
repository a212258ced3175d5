//! Warnings of a solve, worded once: bushings driven beyond the range of
//! projected angles (W1001) and implausible states ([`super::plausibility`]:
//! W1002, W1003). (Redundant constraints are reported once, by the checker's
//! mobility analysis.)

use super::report::{ANGLE_LIMIT_DEG, AngleWarning, angle_warnings_in};
use crate::diagnostic::Diagnostic;
use crate::model::{ElementId, Model};
use crate::statics::coords::Layout;
use crate::statics::{Equilibrium, State};

/// Every warning of a path's converged cases (`names[k]` names case `k`):
/// the angle warnings, then the implausible states.
pub fn of_path(model: &Model, names: &[String], eqs: &[Equilibrium]) -> Vec<Diagnostic> {
    let (layout, design) = (Layout::new(model), State::design(model));
    let angles_per_case: Vec<_> = eqs
        .iter()
        .map(|e| angle_warnings_in(model, &layout, &e.state))
        .collect();
    let found: Vec<_> = eqs
        .iter()
        .map(|e| super::plausibility::findings(model, &layout, &design, &e.state))
        .collect();
    let mut out = angles(model, names, &angles_per_case);
    out.extend(super::plausibility::warnings(model, names, &found));
    out
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
