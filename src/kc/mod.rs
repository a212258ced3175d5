//! Kinematics-and-compliance stages built on the statics engine: the wheel
//! quantities of a solved state and K&C tables ([`wheel`]), ride-height trim
//! ([`trim`]), and the wheel-centre heights an `.lcf` in height mode carries
//! ([`heights`]). The statics engine knows none of them.

pub mod heights;
pub mod trim;
pub mod wheel;

pub use wheel::{KcRow, WheelQuantities, kc_rows, wheel_quantities};
