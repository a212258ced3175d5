//! The kinds of cause a diagnosis can name (`interfaces.md`, `diagnose
//! --format json`: `kind`).

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Kind {
    Stiffness,
    JointLocation,
    BumpStop,
    ReboundStop,
    NonlinearBushing,
    Preload,
    SpringFreeLength,
    PartCompliance,
    Friction,
    /// The model already explains the data within its noise.
    None,
}

impl Kind {
    /// Every kind of cause (not `None`), in the order of the library.
    pub const CAUSES: [Kind; 9] = [
        Kind::Stiffness,
        Kind::JointLocation,
        Kind::BumpStop,
        Kind::ReboundStop,
        Kind::NonlinearBushing,
        Kind::Preload,
        Kind::SpringFreeLength,
        Kind::PartCompliance,
        Kind::Friction,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Kind::Stiffness => "stiffness",
            Kind::JointLocation => "joint_location",
            Kind::BumpStop => "bump_stop",
            Kind::ReboundStop => "rebound_stop",
            Kind::NonlinearBushing => "nonlinear_bushing",
            Kind::Preload => "preload",
            Kind::SpringFreeLength => "spring_free_length",
            Kind::PartCompliance => "part_compliance",
            Kind::Friction => "friction",
            Kind::None => "none",
        }
    }

    pub fn parse(s: &str) -> Option<Kind> {
        Kind::CAUSES.into_iter().find(|k| k.name() == s)
    }
}
