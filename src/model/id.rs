//! Typed indices into the model's arenas (rapier-style handles), so models can be
//! cloned, extended and serialised without references.

use serde::Serialize;

macro_rules! ids {
    ($($name:ident),* $(,)?) => {$(
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize)]
        pub struct $name(pub u32);
        impl $name {
            pub fn index(self) -> usize { self.0 as usize }
        }
    )*};
}

ids!(
    PartId, MarkerId, LandmarkId, JointId, BushingId, SpringId, StopId, FrictionId, WheelId,
    ParamId, LoadSetId
);

/// Any element of a model, for diagnostics and the origin side table.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize)]
pub enum ElementId {
    Part(PartId),
    Marker(MarkerId),
    Landmark(LandmarkId),
    Joint(JointId),
    Bushing(BushingId),
    Spring(SpringId),
    Stop(StopId),
    Friction(FrictionId),
    Wheel(WheelId),
    Param(ParamId),
    LoadSet(LoadSetId),
}
