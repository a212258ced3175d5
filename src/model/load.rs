//! Load cases: named sets written as tables (independent cases) or as load paths
//! (sweeps), both solved in order, each step starting from the previous state.

use super::id::{MarkerId, WheelId};
use crate::geom::Vec3;

/// Where a load channel acts.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum LoadTarget {
    /// At a wheel's contact marker.
    Wheel(WheelId),
    /// At the only wheel of whichever model uses the set (stdlib sets are written
    /// this way); resolved by the checker when the model has its wheels.
    DefaultWheel,
    /// At a marker's origin.
    Marker(MarkerId),
}

/// One component of a force/torque (global axes).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Component {
    Fx,
    Fy,
    Fz,
    Mx,
    My,
    Mz,
}

impl Component {
    pub const ALL: [Component; 6] = [
        Component::Fx,
        Component::Fy,
        Component::Fz,
        Component::Mx,
        Component::My,
        Component::Mz,
    ];

    pub fn name(self) -> &'static str {
        ["fx", "fy", "fz", "mx", "my", "mz"][self as usize]
    }

    pub fn from_name(s: &str) -> Option<Component> {
        Self::ALL.into_iter().find(|c| c.name() == s)
    }

    pub fn is_torque(self) -> bool {
        (self as usize) >= 3
    }
}

/// A column of a load set: a target and a component.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Channel {
    pub target: LoadTarget,
    pub component: Component,
}

/// One load case: a value per channel of its set, internal units (N, N·mm).
#[derive(Debug, Clone, PartialEq)]
pub struct LoadCase {
    pub name: String,
    pub values: Vec<f64>,
}

/// How a set was written, kept so that it prints back the same way.
#[derive(Debug, Clone, PartialEq)]
pub enum LoadForm {
    Table,
    /// A sweep: constant channels plus one or more channels, each through
    /// its waypoints by its step, all moving in lockstep (the same number of
    /// cases); the first swept channel is the one plots are drawn against.
    Sweep {
        swept: Vec<SweptChannel>,
    },
}

/// One swept channel of a sweep: its index in the set's channels, its
/// waypoints and step (internal units).
#[derive(Debug, Clone, PartialEq)]
pub struct SweptChannel {
    pub channel: usize,
    pub waypoints: Vec<f64>,
    pub step: f64,
}

#[derive(Debug, Clone, PartialEq)]
pub struct LoadSet {
    pub name: String,
    pub channels: Vec<Channel>,
    pub cases: Vec<LoadCase>,
    pub form: LoadForm,
}

/// A force and torque (global, N and N·mm) applied at a marker's origin.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointLoad {
    pub marker: MarkerId,
    pub force: Vec3,
    pub torque: Vec3,
}
