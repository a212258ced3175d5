//! The landmark file of `locate` and `identify` (`interfaces.md`, "Landmarks"):
//! columns `step, part, landmark, x, y, z` (global mm). Points of a part may come
//! in any order; they are matched to the declared landmarks later
//! ([`crate::measure::poses`]), so a wrong landmark name is not an error here.
//! A row naming an unknown part is reported and left out, not fatal.

use super::CsvError;
use super::table::{self, Field};
use crate::diagnostic::suggest::did_you_mean;
use crate::geom::Vec3;
use crate::measure::poses::Observation;
use crate::model::Model;

const REQUIRED: [&str; 6] = ["step", "part", "landmark", "x", "y", "z"];

/// A row that was read but left out, with the reason.
#[derive(Debug, Clone, PartialEq)]
pub struct Skipped {
    pub line: usize,
    pub start: usize,
    pub end: usize,
    pub message: String,
}

fn number(f: &Field, column: &str) -> Result<f64, CsvError> {
    match f.text.parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        _ => Err(CsvError::new(
            "E0705",
            format!("`{}` is not a number (column `{column}`)", f.text),
            (f.start, f.end),
            "not a number",
        )),
    }
}

/// Reads landmark observations; rows on parts the model does not have are skipped.
pub fn read(text: &str, model: &Model) -> Result<(Vec<Observation>, Vec<Skipped>), CsvError> {
    let t = table::parse(text)?;
    let mut cols = [0usize; 6];
    for (k, name) in REQUIRED.iter().enumerate() {
        cols[k] = t.column(name).ok_or_else(|| {
            CsvError::new(
                "E0703",
                format!("the landmark file has no column `{name}`"),
                (t.header.start, t.header.end),
                "header row",
            )
            .with_hint(Some(
                "a landmark file has the columns step, part, landmark, x, y, z".into(),
            ))
        })?;
    }
    let mut obs = Vec::new();
    let mut skipped = Vec::new();
    for row in &t.rows {
        if row.fields.len() != t.names.len() {
            return Err(CsvError::new(
                "E0704",
                format!(
                    "line {} has {} fields but the header has {} columns",
                    row.line,
                    row.fields.len(),
                    t.names.len()
                ),
                (row.start, row.end),
                "this row",
            ));
        }
        let f = |k: usize| &row.fields[cols[k]];
        let step: usize = f(0).text.parse().map_err(|_| {
            CsvError::new(
                "E0705",
                format!(
                    "`{}` is not a step number (a whole number 0 or more)",
                    f(0).text
                ),
                (f(0).start, f(0).end),
                "not a step",
            )
        })?;
        let part_name = f(1).text;
        let position = Vec3::new(number(f(3), "x")?, number(f(4), "y")?, number(f(5), "z")?);
        match model.part_named(part_name) {
            Some(part) => obs.push(Observation {
                step,
                part,
                label: f(2).text.to_string(),
                position,
                line: row.line,
            }),
            None => {
                let hint = did_you_mean(part_name, model.parts.iter().map(|p| p.name.as_str()));
                skipped.push(Skipped {
                    line: row.line,
                    start: f(1).start,
                    end: f(1).end,
                    message: format!(
                        "the model has no part `{part_name}`; the point was left out{}",
                        hint.map(|h| format!(" ({h})")).unwrap_or_default()
                    ),
                });
            }
        }
    }
    Ok((obs, skipped))
}

/// Landmark observations of one measured state from an IGES file: every
/// point named `<part>.<landmark>` (Name property or label), or labelled with
/// the part's name alone (the landmark then is its subscript, since a label
/// has 8 characters). Part names match case-insensitively when unambiguous,
/// as measuring software often writes labels in capitals. A point that names
/// no part is reported and left out, like a CSV row.
pub fn from_iges(
    iges: &super::iges::Iges,
    step: usize,
    text: &str,
    model: &Model,
) -> (Vec<Observation>, Vec<Skipped>) {
    let mut obs = Vec::new();
    let mut skipped = Vec::new();
    let line_of = |at: usize| text[..at.min(text.len())].matches('\n').count() + 1;
    for (e, position) in iges.points() {
        let (part_name, label) = match e.name().map(|n| n.split_once('.').unwrap_or((n, ""))) {
            Some((part, "")) => (part, e.subscript.to_string()),
            Some((part, lm)) => (part, lm.to_string()),
            None => ("", String::new()),
        };
        let part = model.part_named(part_name).or_else(|| {
            let mut same = model
                .parts
                .iter()
                .enumerate()
                .filter(|(_, p)| p.name.eq_ignore_ascii_case(part_name));
            match (same.next(), same.next()) {
                (Some((i, _)), None) => Some(crate::model::PartId(i as u32)),
                _ => None,
            }
        });
        let line = line_of(e.data_start);
        match part {
            Some(part) => obs.push(Observation {
                step,
                part,
                label,
                position,
                line,
            }),
            None => {
                let hint = did_you_mean(part_name, model.parts.iter().map(|p| p.name.as_str()));
                let shown = e.name().unwrap_or("(no name)");
                skipped.push(Skipped {
                    line: line_of(e.label_span.0),
                    start: e.label_span.0,
                    end: e.label_span.1,
                    message: format!(
                        "point D {} `{shown}` names no part of the model (IGES points are named `<part>.<landmark>`, or labelled with the part); it was left out{}",
                        e.de,
                        hint.map(|h| format!(" ({h})")).unwrap_or_default()
                    ),
                });
            }
        }
    }
    (obs, skipped)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn model() -> Model {
        let (_, c) =
            crate::check::check_str("m.axle", include_str!("../../examples/mcpherson.axle"));
        c.model.expect("example checks")
    }

    #[test]
    fn reads_rows_and_skips_unknown_parts() {
        let m = model();
        let text =
            "# landmarks\nstep,part,landmark,x,y,z\n1,upright,m1,62,749,234\n1, uprigt ,m2,1,2,3\n";
        let (obs, skipped) = read(text, &m).expect("reads");
        assert_eq!(obs.len(), 1);
        assert_eq!(obs[0].line, 3);
        assert_eq!(obs[0].position, Vec3::new(62.0, 749.0, 234.0));
        assert_eq!(skipped.len(), 1);
        assert_eq!(skipped[0].line, 4);
        assert!(
            skipped[0].message.contains("did you mean `upright`?"),
            "{}",
            skipped[0].message
        );
        assert_eq!(&text[skipped[0].start..skipped[0].end], "uprigt");
    }

    #[test]
    fn bad_numbers_and_missing_columns_are_located() {
        let m = model();
        let text = "step,part,landmark,x,y,z\n1,upright,m1,62,7x9,234\n";
        let e = read(text, &m).unwrap_err();
        assert_eq!(e.code, "E0705");
        assert_eq!(&text[e.start..e.end], "7x9");
        let e = read("step,part,x,y,z\n", &m).unwrap_err();
        assert_eq!(e.code, "E0703");
        assert!(e.message.contains("landmark"));
    }
}
