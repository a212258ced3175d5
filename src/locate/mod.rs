//! Joint localisation from part motion (thesis chapter 3): centres and axes of
//! joints and bushings from the measured poses of the parts they connect.

pub mod correct;
pub mod linear;
pub mod motion;
pub mod nonlinear;
pub mod plan;
pub mod preflight;
pub mod rack;
pub mod report;
pub mod simplex;
