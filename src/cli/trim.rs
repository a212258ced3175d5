//! `solve --trim PARAM [--trim-case CASE] [--trim-marker PART.MARKER]`: resolve
//! the names, trim, set the trimmed value in the model, and say what was done.

use super::Exit;
use super::input::Loaded;
use super::solve::TrimArgs;
use crate::diagnostic::Diagnostic;
use crate::diagnostic::suggest::did_you_mean;
use crate::kc::trim::trim;
use crate::model::address::Address;
use crate::model::{LoadSetId, MarkerId};
use crate::output::number::round;
use crate::units::to_boundary;
use serde_json::{Value, json};

/// What a trim did: one line for people, one JSON object for scripts.
pub struct TrimReport {
    pub line: String,
    pub json: Value,
}

fn address(loaded: &Loaded, name: &str) -> Result<Address, Diagnostic> {
    Address::parse(&loaded.model, name).map_err(|e| e.to_diagnostic("--trim", name))
}

fn marker(loaded: &Loaded, name: Option<&str>) -> Result<MarkerId, Diagnostic> {
    let m = &loaded.model;
    let Some(name) = name else {
        return match m.wheels.as_slice() {
            [w] => Ok(w.centre),
            _ => Err(Diagnostic::error("E0804", "name the marker to trim with --trim-marker PART.MARKER")
                .note("without it the trim uses the wheel centre, and the model has not exactly one wheel")),
        };
    };
    let unknown = |what: String, hint: Option<String>| {
        let d = Diagnostic::error("E0804", what);
        match hint {
            Some(h) => d.hint(h),
            None => d,
        }
    };
    let Some((part, mk)) = name.split_once('.') else {
        return Err(unknown(
            format!("`{name}` is not a marker; write PART.MARKER"),
            None,
        ));
    };
    let Some(p) = m.part_named(part) else {
        return Err(unknown(
            format!("the model has no part `{part}`"),
            did_you_mean(part, m.parts.iter().map(|p| p.name.as_str())),
        ));
    };
    m.marker_named(p, mk).ok_or_else(|| {
        let on_part = m
            .markers
            .iter()
            .filter(|x| x.part == p)
            .map(|x| x.name.as_str());
        unknown(
            format!("part `{part}` has no marker `{mk}`"),
            did_you_mean(mk, on_part),
        )
    })
}

/// Trims and sets the parameter in `loaded.model`; prints the trimmed value on stderr.
pub fn run(loaded: &mut Loaded, set: LoadSetId, args: &TrimArgs) -> Result<TrimReport, Exit> {
    let resolved = (|| -> Result<(Address, usize, MarkerId), Diagnostic> {
        let a = address(loaded, &args.param)?;
        let ls = &loaded.model.load_sets[set.index()];
        let case = match &args.case {
            None => 0,
            Some(c) => ls.cases.iter().position(|x| &x.name == c).ok_or_else(|| {
                let d =
                    Diagnostic::error("E0805", format!("load set `{}` has no case `{c}`", ls.name));
                match did_you_mean(c, ls.cases.iter().map(|x| x.name.as_str())) {
                    Some(h) => d.hint(h),
                    None => d,
                }
            })?,
        };
        Ok((a, case, marker(loaded, args.marker.as_deref())?))
    })();
    let (a, case, mk) = resolved.map_err(|d| {
        loaded.report(&[d]);
        Exit::Input
    })?;
    let m = &loaded.model;
    let loads = m.point_loads(set, case);
    let t = trim(m, a, &loads, mk).map_err(|e| {
        loaded.report(&[e.to_diagnostic(m)]);
        Exit::Input
    })?;
    let (dim, name) = (a.dim(m), a.name(m));
    let unit = dim.boundary_unit();
    let (value, initial) = (to_boundary(t.value, dim), to_boundary(t.initial, dim));
    let case_name = m.load_sets[set.index()]
        .cases
        .get(case)
        .map_or(String::new(), |c| c.name.clone());
    let marker_name = m.marker_path(mk);
    let line = format!(
        "trim: {name} = {} {unit} (was {} {unit}): {marker_name} at its design z = {:.6} mm in case {case_name} ({} equilibria)",
        round(value),
        round(initial),
        t.target_z,
        t.evaluations
    );
    eprintln!("{line}");
    let json = json!({
        "parameter": name, "value": value, "initial": initial, "unit": unit,
        "case": case_name, "marker": marker_name, "target_z": t.target_z, "z": t.z,
        "evaluations": t.evaluations,
    });
    a.set(&mut loaded.model, t.value);
    Ok(TrimReport { line, json })
}
