//! Readers of measured and tabulated data files (`interfaces.md`, "Measured data
//! files"): comma-separated text with a header row and `#` comment lines, and
//! IGES files from a measuring arm (`iges`). Each reader is a pure function of
//! the text; `cli/` reads the file.

pub mod csv_error;
pub mod iges;
pub mod landmarks;
pub mod loads;
pub mod table;

pub use csv_error::CsvError;
