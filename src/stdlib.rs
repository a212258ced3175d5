//! axle source shipped with the compiler (`stdlib/`), embedded so that `import`
//! needs no file system.

/// `(module name, source text)` for every stdlib module.
pub const MODULES: &[(&str, &str)] = &[
    (
        "mcpherson_loads",
        include_str!("../stdlib/mcpherson_loads.axle"),
    ),
    (
        "mcpherson_corner",
        include_str!("../stdlib/mcpherson_corner.axle"),
    ),
    (
        "anti_roll_bar",
        include_str!("../stdlib/anti_roll_bar.axle"),
    ),
    (
        "steering_rack",
        include_str!("../stdlib/steering_rack.axle"),
    ),
    (
        "double_wishbone_corner",
        include_str!("../stdlib/double_wishbone_corner.axle"),
    ),
    (
        "multilink_corner",
        include_str!("../stdlib/multilink_corner.axle"),
    ),
    (
        "twist_beam_axle",
        include_str!("../stdlib/twist_beam_axle.axle"),
    ),
];

pub fn module(name: &str) -> Option<&'static str> {
    MODULES.iter().find(|(n, _)| *n == name).map(|(_, t)| *t)
}

/// The name a module's file is shown under in diagnostics.
pub fn file_name(module: &str) -> String {
    format!("stdlib/{module}.axle")
}
