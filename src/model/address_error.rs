//! Why a name does not address a number of the model, and the one diagnostic
//! (E0803, with did-you-mean) every command that takes an address reports.

use crate::diagnostic::Diagnostic;
use crate::diagnostic::suggest::did_you_mean;

/// Why a name does not address a number of the model.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum AddressError {
    /// No parameter, element, part or marker has this name; `candidates` are
    /// the names that exist at that place.
    UnknownElement {
        name: String,
        candidates: Vec<String>,
    },
    /// The part exists but has no such point (marker, landmark, or joint or
    /// bushing with a marker on it).
    UnknownPoint {
        part: String,
        name: String,
        candidates: Vec<String>,
    },
    /// The element exists but has no such field; `fields` are those it has.
    UnknownField {
        element: String,
        field: String,
        fields: Vec<String>,
    },
    /// The field exists but its law is a table, not a number.
    NotLinear(String),
}

impl std::fmt::Display for AddressError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            AddressError::UnknownElement { name, .. } => {
                write!(f, "no parameter or element is called `{name}`")
            }
            AddressError::UnknownPoint { part, name, .. } => write!(
                f,
                "part `{part}` has no marker, landmark, joint or bushing `{name}`"
            ),
            AddressError::UnknownField {
                element,
                field,
                fields,
            } => write!(
                f,
                "`{element}` has no field `{field}` (it has {})",
                fields.join(", ")
            ),
            AddressError::NotLinear(n) => {
                write!(f, "`{n}` is a table law, not a single number")
            }
        }
    }
}

/// The address grammar in one line, for notes.
pub const GRAMMAR: &str = "an address is a declared `param`, `<element>.<field>` \
(`B.k_x`, `B.k3_z`, `B.offset_y`, `spring.free_length`, `bump.contact_length`, \
`bump.poly_2`, `L5_friction.kf`), `<joint or bushing>.x|y|z` (both markers), or \
`<part>.<marker>.x|y|z` (see docs/language.md, \"Addresses\")";

impl AddressError {
    /// The diagnostic for `option name` (e.g. `--trim spring.free_lenght`),
    /// worded here once for every command that takes an address.
    pub fn to_diagnostic(&self, option: &str, name: &str) -> Diagnostic {
        let d = Diagnostic::error("E0803", format!("{option} `{name}`: {self}"));
        let hint = match self {
            AddressError::UnknownElement { name, candidates }
            | AddressError::UnknownPoint {
                name, candidates, ..
            } => did_you_mean(name, candidates.iter().map(String::as_str)),
            AddressError::UnknownField { field, fields, .. } => {
                did_you_mean(field, fields.iter().map(String::as_str))
            }
            AddressError::NotLinear(_) => {
                Some("a table law has no single number to change; give it a linear law (optionally with a cubic term)".into())
            }
        };
        let d = match hint {
            Some(h) => d.hint(h),
            None => d,
        };
        match self {
            AddressError::UnknownElement { .. } => d.note(GRAMMAR),
            _ => d,
        }
    }
}
