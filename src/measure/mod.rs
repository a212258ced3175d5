//! Measurements on an assembled axle: landmark matching and rigid pose fitting
//! (thesis chapter 2), the inputs of joint localisation and identification.

pub mod inputs;
pub mod matching;
pub mod pose_fit;
pub mod poses;
pub mod synthetic;
