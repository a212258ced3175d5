//! Kinematics-and-compliance stages built on the statics engine: the wheel
//! quantities of a solved state and K&C tables ([`wheel`]), the metrics of
//! an axle's pair of wheels along a path ([`axle`]), compliance steer
//! and camber under horizontal wheel loads ([`compliance`]), the steering geometry
//! of a path that drives a rack ([`steer`]), ride-height trim
//! ([`trim`]), a model without some force elements for the metrics "without
//! the bar" ([`without`]), and the wheel-centre heights an `.lcf` in height mode carries
//! ([`heights`]). The statics engine knows none of them.

pub mod axle;
pub mod compliance;
pub mod heights;
pub mod steer;
pub mod trim;
pub mod wheel;
pub mod without;

pub use axle::{AxleMetrics, Motion, axle_metrics};
pub use compliance::{ComplianceMetrics, Input, Phase, compliance_metrics};
pub use steer::{Rack, SteeringMetrics, driven_rack, rack_travel, steering_metrics};
pub use wheel::{KcRow, WheelQuantities, kc_rows, wheel_quantities, wheel_quantities_from};
