//! The words of every parameter note are the line the table prints under the
//! parameter and the JSON's `note`, and are the sentences the methods wrote
//! before the notes became data.

use super::{to_json, to_table};
use crate::identify::notes::{AxisFit, AxisRegression, OutsideBounds};
use crate::identify::{Identified, Method, ParamNote, ParamResult, Unknown};

fn unknown() -> Unknown {
    let (_, c) = crate::check::check_str(
        "single_bushing.axle",
        include_str!("../../examples/single_bushing.axle"),
    );
    let m = c.model.expect("the example checks");
    let u = crate::identify::select_unknowns(&m, &["b.k_x".into()]).expect("b.k_x");
    u[0].clone()
}

fn result(method: Method, u: &Unknown, p: ParamResult) -> Identified {
    Identified {
        method,
        unknowns: vec![u.clone()],
        params: vec![p],
        combinations: Vec::new(),
        rank: 0,
        singular_values: Vec::new(),
        iterations: 1,
        history: Vec::new(),
        correlation: None,
        sigma0: None,
        notes: Vec::new(),
    }
}

fn param(u: &Unknown, value: Option<f64>, notes: Vec<ParamNote>) -> ParamResult {
    ParamResult {
        initial: u.initial,
        value,
        interval: None,
        identifiable: false,
        notes,
        bound: None,
    }
}

fn axis(name: &str, r: f64, offset: f64, unit: &'static str) -> AxisRegression {
    AxisRegression {
        name: name.into(),
        fit: Some(AxisFit { r, offset, unit }),
    }
}

/// The lines of the table indented under the parameter's row.
fn table_notes(r: &Identified) -> Vec<String> {
    to_table(r)
        .lines()
        .filter_map(|l| l.strip_prefix("    "))
        .map(str::to_string)
        .collect()
}

#[test]
fn each_param_note_is_worded_once_for_table_and_json() {
    let u = unknown();
    let cases: Vec<(ParamNote, &str)> = vec![
        (
            ParamNote::OnlyCombined {
                with: vec!["A.k_x".into(), "B.k_x".into()],
            },
            "not determined on its own: only combinations with A.k_x, B.k_x are (see determined combinations)",
        ),
        (
            ParamNote::NotDeformed,
            "not determined: the measured equilibria do not deform the element this way (zero column)",
        ),
        (
            ParamNote::NoEffect,
            "not determined: it does not affect the measured equilibria",
        ),
        (ParamNote::NotFinite, "the solution is not a finite number"),
        (
            ParamNote::NotPositive { value: -12.3456 },
            "determined by the equations but came out -12.35 (not positive): the data do not support a stiffness here",
        ),
        (
            ParamNote::Imprecise {
                half_width_percent: 73.6,
            },
            "determined by the equations but not by the data's precision (95 % half-width 74 % of the value)",
        ),
        (
            ParamNote::Regression {
                axes: vec![
                    axis("b.k_x", 0.99951, -2e-5, "mm"),
                    AxisRegression {
                        name: "b.k_y".into(),
                        fit: None,
                    },
                ],
                kept_below: None,
            },
            "b.k_x: r = 1.000, offset 0.0000 mm; b.k_y: no deformation or force spread to correlate",
        ),
        (
            ParamNote::Regression {
                axes: vec![axis("b.kt_x", 0.5, 1.23456, "deg")],
                kept_below: Some(0.75),
            },
            "kept its value: correlation below 0.75 (b.kt_x: r = 0.500, offset 1.2346 deg)",
        ),
        (
            ParamNote::HeldAtBound {
                upper: true,
                value: 12000.0,
                unit: "N/mm".into(),
            },
            "at its upper bound 12000 N/mm: the data pull it beyond the declared bounds, so it is held there and has no interval (the others' intervals assume it exact)",
        ),
        (
            ParamNote::HeldAtBound {
                upper: false,
                value: 0.1234567,
                unit: "mm".into(),
            },
            "at its lower bound 0.123457 mm: the data pull it beyond the declared bounds, so it is held there and has no interval (the others' intervals assume it exact)",
        ),
        (
            ParamNote::NotObserved,
            "not identifiable: it does not affect the observations",
        ),
        (
            ParamNote::WideInterval {
                relative_half_width: 2.5,
                fitted: 310.0,
            },
            "not identifiable from these data: its 95 % interval spans a factor 3.50 (fitted 3.1000e2)",
        ),
        (
            ParamNote::OutsideBounds(OutsideBounds {
                unknown: "b.k_x".into(),
                value: 20000.0,
                unit: "N/mm".into(),
                lower: Some(100.0),
                upper: None,
            }),
            "b.k_x = 20000 N/mm lies outside its declared bounds [100, open]",
        ),
    ];
    for (note, words) in cases {
        assert_eq!(note.words(), words);
        let r = result(Method::Lsq, &u, param(&u, None, vec![note]));
        assert_eq!(table_notes(&r), vec![words.to_string()]);
        assert_eq!(to_json(&r)["parameters"]["b.k_x"]["note"], words);
    }
    // No note: no line, and a JSON null.
    let r = result(Method::Lsq, &u, param(&u, Some(u.initial), vec![]));
    assert!(table_notes(&r).is_empty());
    assert!(to_json(&r)["parameters"]["b.k_x"]["note"].is_null());
}

/// A value outside its bounds from a method that does not enforce them: the
/// bounds note comes first in the parameter's line, and the fit's warning
/// repeats it.
#[test]
fn outside_bounds_leads_the_parameter_note_and_warns_the_fit() {
    use crate::units::from_boundary;
    let mut u = unknown();
    u.bounds.lower = Some(from_boundary(100.0, u.dim));
    u.bounds.upper = Some(from_boundary(15000.0, u.dim));
    let regression = ParamNote::Regression {
        axes: vec![axis("b.k_x", 0.99, 0.0, "mm")],
        kept_below: None,
    };
    let p = param(&u, Some(from_boundary(20000.0, u.dim)), vec![regression]);
    let mut r = result(Method::Iterative, &u, p);
    crate::identify::flag_outside_bounds(&mut r);
    let bounds = "b.k_x = 20000 N/mm lies outside its declared bounds [100, 15000]";
    assert_eq!(
        table_notes(&r),
        vec![format!("{bounds}; b.k_x: r = 0.990, offset 0.0000 mm")]
    );
    let warning = format!(
        "warning: {bounds}; the iterative method does not enforce bounds (least squares does), and -o keeps the model's value"
    );
    assert!(to_table(&r).contains(&format!("note: {warning}\n")));
    assert_eq!(to_json(&r)["notes"][0], warning.as_str());
}
