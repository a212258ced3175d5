//! axle: a model language and compiler for car suspensions.
//!
//! One pipeline, one model:
//! 1. source text → syntax tree with spans ([`syntax::parse`]);
//! 2. syntax tree → checked [`model::Model`] ([`check::check_file`]): names resolved,
//!    units checked and converted to internal units (mm, N, rad), mobility analysed;
//! 3. backends read the model: [`statics`] (equilibrium, K&C), the printer
//!    ([`fmt`]), the ADAMS decks ([`emit`]); [`import`] reads ADAMS datasets back.
//!
//! [`lsp`] serves editors (`axle lsp`) from the same stages; it works on partial
//! results ([`check::analyse`]) so a file with errors still has names and hovers.
//!
//! Only `main.rs`, `cli/` and `lsp/` (stdio, and read-only copies of the stdlib
//! for editors to open) touch the filesystem.
//!
//! Lints (enforced by `.ci/run`): the library never panics on user data
//! through `unwrap`/`expect` (a fact the code proves locally may use them with
//! an `allow` saying why) and never prints: it returns diagnostics and text;
//! only `cli/`, the diagnostic renderer and the editor server's stdio write.
#![deny(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::print_stdout,
    clippy::print_stderr
)]

// pest's derive names `::alloc` when pest is built without `std` (see
// Cargo.toml and `syntax::depth`).
extern crate alloc;

pub mod check;
pub mod cli;
pub mod data;
pub mod diagnose;
pub mod diagnostic;
pub mod edit;
pub mod emit;
pub mod fmt;
pub mod geom;
pub mod identify;
pub mod import;
pub mod kc;
pub mod locate;
pub mod lsp;
pub mod measure;
pub mod model;
pub mod output;
pub mod source;
pub mod span;
pub mod statics;
pub mod stdlib;
pub mod syntax;
pub mod units;
