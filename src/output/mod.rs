//! What `solve` and `kc` print: the one place numbers are formatted ([`number`]),
//! the terminal tables, the K&C CSV, and the SVG plots. Every function returns
//! a `String`; `cli/` decides where it goes.

pub mod columns;
pub mod diagnose_html;
pub mod diagnose_json;
pub mod diagnose_table;
pub mod json;
pub mod kc_table;
pub mod number;
pub mod parts_csv;
pub mod plausibility;
pub mod plot;
pub mod report;
pub mod solve_json;
pub mod solve_table;
pub mod warning;
