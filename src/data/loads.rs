//! The loads file of `solve --loads` (`interfaces.md`, "Loads"): columns
//! `step, fx, fy, fz` and optional `mx, my, mz, wheel, loadcase`, wheel loads
//! in N and N·mm at the wheel's contact marker. Other columns are ignored, so a
//! K&C file can be replayed as loads. Rows sharing a step are one load case
//! (one row per wheel); cases keep the order in which their steps first appear.

use super::CsvError;
use super::table::{self, Field, Row};
use crate::diagnostic::suggest::did_you_mean;
use crate::model::{Channel, Component, LoadCase, LoadForm, LoadSet, LoadTarget, Model, WheelId};
use crate::units::Dim;
use std::collections::{HashMap, HashSet};

const REQUIRED: [&str; 4] = ["step", "fx", "fy", "fz"];
const COLUMNS_HINT: &str =
    "a loads file has the columns step, fx, fy, fz and optionally mx, my, mz, wheel, loadcase";

/// A row read: step, case name, wheel, and component values.
type LoadRow = (u64, String, WheelId, Vec<(Component, f64)>);

/// Reads a loads file into a load set named `name` for `model`.
pub fn read(text: &str, name: &str, model: &Model) -> Result<LoadSet, CsvError> {
    let t = table::parse(text)?;
    for col in REQUIRED {
        if t.column(col).is_none() {
            return Err(CsvError::new(
                "E0703",
                format!("the loads file has no column `{col}`"),
                (t.header.start, t.header.end),
                "header row",
            )
            .with_hint(Some(COLUMNS_HINT.to_string())));
        }
    }
    let comps: Vec<(Component, usize)> = Component::ALL
        .into_iter()
        .filter_map(|c| t.column(c.name()).map(|i| (c, i)))
        .collect();
    let wheel_col = t.column("wheel");
    let case_col = t.column("loadcase");
    let step_col = t.column("step").unwrap_or(0);

    let mut rows: Vec<LoadRow> = Vec::new();
    // Each (step, wheel) read so far: a set, not a scan of the rows, so that
    // a long measured series reads in time linear in its rows.
    let mut seen: HashSet<(u64, WheelId)> = HashSet::with_capacity(t.rows.len());
    for row in &t.rows {
        if row.fields.len() != t.names.len() {
            let end = (row.end, row.end);
            return Err(CsvError::new(
                "E0704",
                format!(
                    "line {} has {} fields but the header has {} columns",
                    row.line,
                    row.fields.len(),
                    t.names.len()
                ),
                (row.start, row.end.max(end.0)),
                "this row",
            ));
        }
        let sf = &row.fields[step_col];
        let step: u64 = sf.text.parse().map_err(|_| {
            CsvError::new(
                "E0705",
                format!(
                    "`{}` is not a step number (a whole number 0 or more)",
                    sf.text
                ),
                (sf.start, sf.end),
                "in column `step`",
            )
        })?;
        let mut values = Vec::with_capacity(comps.len());
        for &(c, i) in &comps {
            values.push((c, number(&row.fields[i], c.name())?));
        }
        let wheel = wheel_of(model, wheel_col.map(|i| &row.fields[i]), row)?;
        let case = case_col
            .map(|i| row.fields[i].text)
            .filter(|s| !s.is_empty())
            .map_or_else(|| format!("step_{step}"), str::to_string);
        if !seen.insert((step, wheel)) {
            return Err(CsvError::new(
                "E0706",
                format!(
                    "step {step} loads wheel `{}` twice",
                    model.wheels[wheel.index()].name
                ),
                (sf.start, sf.end),
                "a second row for this step and wheel",
            ));
        }
        rows.push((step, case, wheel, values));
    }
    if rows.is_empty() {
        return Err(CsvError::new(
            "E0701",
            "the loads file has a header but no data rows",
            (t.header.start, t.header.end),
            "only a header",
        ));
    }

    let mut wheels: Vec<WheelId> = Vec::new();
    for r in &rows {
        if !wheels.contains(&r.2) {
            wheels.push(r.2);
        }
    }
    let channels: Vec<Channel> = wheels
        .iter()
        .flat_map(|&w| {
            comps.iter().map(move |&(c, _)| Channel {
                target: LoadTarget::Wheel(w),
                component: c,
            })
        })
        .collect();
    // Each step's case, in the order the steps first appear.
    let mut case_of: HashMap<u64, usize> = HashMap::with_capacity(rows.len());
    let mut cases: Vec<LoadCase> = Vec::new();
    for (step, case, wheel, values) in rows {
        let k = *case_of.entry(step).or_insert_with(|| {
            cases.push(LoadCase {
                name: case,
                values: vec![0.0; channels.len()],
            });
            cases.len() - 1
        });
        for (c, v) in values {
            if let Some(ch) = channels
                .iter()
                .position(|ch| ch.target == LoadTarget::Wheel(wheel) && ch.component == c)
            {
                cases[k].values[ch] = v;
            }
        }
    }
    Ok(LoadSet {
        name: name.to_string(),
        channels,
        cases,
        form: LoadForm::Table,
    })
}

/// A finite number within what any suspension sees (`check`'s E0214 limits:
/// 10 MN, 10 MN·m); an empty field counts as 0 only in the optional torque
/// columns.
fn number(f: &Field, column: &str) -> Result<f64, CsvError> {
    let torque = matches!(column, "mx" | "my" | "mz");
    if f.text.is_empty() && torque {
        return Ok(0.0);
    }
    let (dim, unit) = if torque {
        (Dim::TORQUE, "N*mm")
    } else {
        (Dim::FORCE, "N")
    };
    match f.text.parse::<f64>() {
        Ok(v) if v.is_finite() => match crate::check::plausible_limit(dim) {
            Some((limit, shown)) if v.abs() > limit => Err(CsvError::new(
                "E0214",
                format!(
                    "{v:e} {unit} in column `{column}` is beyond any suspension (more than {shown})"
                ),
                (f.start, f.end),
                "this value",
            )
            .with_hint(Some("check the unit and the exponent".into()))),
            _ => Ok(v),
        },
        _ => Err(CsvError::new(
            "E0705",
            format!("`{}` is not a number", f.text),
            (f.start, f.end),
            format!("in column `{column}`"),
        )),
    }
}

/// The wheel a row loads (or measures): the named one, or the model's only wheel.
pub(crate) fn wheel_of(
    model: &Model,
    field: Option<&Field>,
    row: &Row,
) -> Result<WheelId, CsvError> {
    let names = || model.wheels.iter().map(|w| w.name.as_str());
    match field.filter(|f| !f.text.is_empty()) {
        Some(f) => match model.wheels.iter().position(|w| w.name == f.text) {
            Some(i) => Ok(WheelId(i as u32)),
            None => Err(CsvError::new(
                "E0707",
                format!("the model has no wheel `{}`", f.text),
                (f.start, f.end),
                "unknown wheel",
            )
            .with_hint(did_you_mean(f.text, names()).or_else(|| {
                Some(format!(
                    "the model's wheels: {}",
                    names().collect::<Vec<_>>().join(", ")
                ))
            }))),
        },
        None => match model.wheels.len() {
            1 => Ok(WheelId(0)),
            0 => Err(CsvError::new(
                "E0708",
                "the model has no wheel to apply these loads to",
                (row.start, row.end),
                "wheel loads",
            )
            .with_hint(Some("declare a `wheel` in the model".into()))),
            _ => Err(CsvError::new(
                "E0708",
                "the model has several wheels, so each row must name one",
                (row.start, row.end),
                "which wheel?",
            )
            .with_hint(Some(format!(
                "add a `wheel` column with one of: {}",
                names().collect::<Vec<_>>().join(", ")
            )))),
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn model() -> Model {
        let text = std::fs::read_to_string(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/examples/mcpherson.axle"
        ))
        .expect("example");
        let (_, c) = crate::check::check_str("mcpherson.axle", &text);
        c.model.expect("checks")
    }

    #[test]
    fn rows_become_cases_at_the_only_wheel() {
        let m = model();
        let text =
            "# rig run 3\nstep, fx, fy, fz, loadcase\n1, 0, 0, 1500, c1\n2, 100, -200, 3000,\n";
        let set = read(text, "run3", &m).expect("reads");
        assert_eq!(set.cases.len(), 2);
        assert_eq!(set.cases[0].name, "c1");
        assert_eq!(set.cases[1].name, "step_2");
        assert_eq!(set.channels.len(), 3);
        assert_eq!(set.cases[1].values, vec![100.0, -200.0, 3000.0]);
        assert!(
            set.channels
                .iter()
                .all(|c| c.target == LoadTarget::Wheel(WheelId(0)))
        );
    }

    #[test]
    fn torques_and_extra_columns() {
        let m = model();
        let text = "step,fx,fy,fz,mx,my,mz,wheel,wc_x\n1,0,0,1,5,,7,left,3.5\n";
        let set = read(text, "s", &m).expect("reads");
        assert_eq!(set.cases[0].values, vec![0.0, 0.0, 1.0, 5.0, 0.0, 7.0]);
    }

    #[test]
    fn errors_point_at_the_field() {
        let m = model();
        let text = "step,fx,fy,fz\n1,0,0,1500\n2,0,x1,3000\n";
        let e = read(text, "s", &m).unwrap_err();
        assert_eq!(e.code, "E0705");
        assert_eq!(&text[e.start..e.end], "x1");
        let e = read("step,fx,fz\n1,0,1\n", "s", &m).unwrap_err();
        assert!(e.message.contains("`fy`"), "{}", e.message);
        let e = read("step,fx,fy,fz,wheel\n1,0,0,1,lef\n", "s", &m).unwrap_err();
        assert_eq!(e.hint.as_deref(), Some("did you mean `left`?"));
        let e = read("step,fx,fy,fz\n1,0,0\n", "s", &m).unwrap_err();
        assert_eq!(e.code, "E0704");
        assert_eq!(read("step,fx,fy,fz\n", "s", &m).unwrap_err().code, "E0701");
        assert_eq!(
            read("step,fx,fy,fz\n1,0,0,1\n1,0,0,2\n", "s", &m)
                .unwrap_err()
                .code,
            "E0706"
        );
        assert_eq!(
            read("step,fx,fy,fz\n1.5,0,0,1\n", "s", &m)
                .unwrap_err()
                .code,
            "E0705"
        );
        assert_eq!(
            read("step,fx,fy,fz\n1,0,0,inf\n", "s", &m)
                .unwrap_err()
                .code,
            "E0705"
        );
    }
}
