//! Static equilibrium against independent expectations
//! (`tests/data/expected`, computed by a separate implementation of
//! `spec/conventions.md`) and against closed-form results.
//!
//! One test binary in modules (each file in `tests/` is a binary of its own,
//! linked against the whole library).

mod mcpherson;
mod mechanisms;
mod paths;
mod support;
