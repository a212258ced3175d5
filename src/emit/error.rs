//! Why a model cannot be written as an ADAMS deck. Every variant names the
//! element, so the user knows what to change; nothing is approximated silently.

use crate::diagnostic::Diagnostic;
use crate::model::{ElementId, Model, WheelId};
use std::fmt;

#[derive(Debug, Clone, PartialEq)]
pub enum EmitError {
    /// A value is NaN or infinite.
    NotFinite { element: String, what: String },
    /// A table has fewer than the 4 points an ADAMS SPLINE needs, or x not increasing.
    BadTable { element: String, detail: String },
    /// A load channel aims at no single wheel/marker.
    UnresolvedLoad { set: String, channel: String },
    /// A load channel cannot be written in an Adams/Car loadcase file.
    NotAWheelLoad { set: String, channel: String },
    /// Two wheels on the same side of the car (an `.lcf` has one left and one right column).
    WheelSide { wheel: String, other: String },
    /// `--axle` names no wheel of the model.
    UnknownWheel { name: String, known: Vec<String> },
    /// The named load set does not exist.
    UnknownLoadSet { name: String, known: Vec<String> },
    /// The model has no load set to write.
    NoLoadSet,
    /// The model has no ground part.
    NoGround,
    /// A case of the set has no equilibrium (wheel-centre heights need one).
    NotSolved {
        set: String,
        case: String,
        detail: String,
    },
}

impl fmt::Display for EmitError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            EmitError::NotFinite { element, what } => {
                write!(f, "{element}: {what} is not a finite number")
            }
            EmitError::BadTable { element, detail } => {
                write!(
                    f,
                    "{element}: its table cannot be an ADAMS SPLINE: {detail}"
                )
            }
            EmitError::UnresolvedLoad { set, channel } => write!(
                f,
                "load set `{set}`: channel `{channel}` aims at the model's only wheel, but the model has none or several"
            ),
            EmitError::NotAWheelLoad { set, channel } => write!(
                f,
                "load set `{set}`: channel `{channel}` is not a wheel load, and an Adams/Car loadcase file only has wheel columns"
            ),
            EmitError::WheelSide { wheel, other } => write!(
                f,
                "wheels `{other}` and `{wheel}` are on the same side; an Adams/Car loadcase file has one left and one right wheel (give `--axle {other}` to write the file of its axle)"
            ),
            EmitError::UnknownWheel { name, known } => {
                write!(
                    f,
                    "--axle `{name}`: the model has no wheel of that name (its wheels: {})",
                    known.join(", ")
                )?;
                match crate::diagnostic::suggest::did_you_mean(
                    name,
                    known.iter().map(String::as_str),
                ) {
                    Some(h) => write!(f, "; {h}"),
                    None => Ok(()),
                }
            }
            EmitError::UnknownLoadSet { name, known } => write!(
                f,
                "no load set `{name}` (known: {})",
                if known.is_empty() {
                    "none".to_string()
                } else {
                    known.join(", ")
                }
            ),
            EmitError::NoLoadSet => write!(f, "the model has no load set to write"),
            EmitError::NoGround => write!(f, "the model has no ground part"),
            EmitError::NotSolved { set, case, detail } => write!(
                f,
                "load set `{set}`, case `{case}`: no equilibrium for the wheel-centre heights: {detail}"
            ),
        }
    }
}

impl std::error::Error for EmitError {}

impl EmitError {
    /// The model elements responsible, for source labels: a load set, or the
    /// two wheels on one side.
    fn elements(&self, m: &Model) -> Vec<ElementId> {
        let wheel = |n: &str| {
            m.wheels
                .iter()
                .position(|w| w.name == n)
                .map(|k| ElementId::Wheel(WheelId(k as u32)))
        };
        match self {
            EmitError::UnresolvedLoad { set, .. } | EmitError::NotAWheelLoad { set, .. } => m
                .load_set_named(set)
                .map(ElementId::LoadSet)
                .into_iter()
                .collect(),
            EmitError::WheelSide { wheel: w, other } => {
                wheel(w).into_iter().chain(wheel(other)).collect()
            }
            _ => Vec::new(),
        }
    }

    /// The error as a diagnostic (E0910) labelled at the elements' source lines
    /// when the model was read from a file.
    pub fn to_diagnostic(&self, m: &Model) -> Diagnostic {
        let mut d = Diagnostic::error("E0910", format!("cannot write the ADAMS deck: {self}"));
        let mut first = true;
        for e in self.elements(m) {
            if let Some(span) = m.origins.get(e) {
                let what = m.describe(e);
                d = if first {
                    d.primary(span, format!("{what} is the cause"))
                } else {
                    d.secondary(span, format!("{what} is involved"))
                };
                first = false;
            }
        }
        d
    }
}
