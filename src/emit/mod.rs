//! ADAMS decks from a checked model: the Adams/Solver dataset (`.adm`), its
//! command file (`.acf`) and the Adams/Car loadcase file (`.lcf`). Pure
//! functions `&Model → String`; the CLI writes the files. Mapping, units and
//! what is verified: `docs/adams.md`.

pub mod acf;
pub mod adm;
pub mod error;
pub mod forces;
pub mod lcf;
pub mod plan;
pub mod writer;

pub use acf::emit_acf;
pub use adm::{Deck, emit_adm};
pub use error::EmitError;
pub use lcf::{Vertical, emit_lcf, emit_lcf_as, emit_lcf_axle};

use crate::model::{LoadSetId, Model};

/// The load set named `name`, else the model's default set, else its first set.
pub fn load_set(m: &Model, name: Option<&str>) -> Result<LoadSetId, EmitError> {
    match name {
        Some(n) => m
            .load_set_named(n)
            .ok_or_else(|| EmitError::UnknownLoadSet {
                name: n.to_string(),
                known: m.load_sets.iter().map(|s| s.name.clone()).collect(),
            }),
        None => m
            .default_load_set
            .or_else(|| (!m.load_sets.is_empty()).then_some(LoadSetId(0)))
            .ok_or(EmitError::NoLoadSet),
    }
}
