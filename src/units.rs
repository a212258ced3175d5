//! Physical dimensions and unit suffixes; converts boundary units to internal units.
//!
//! Internal units are mm, N, rad (and kg, s). At every boundary (language, files,
//! command line) lengths are mm, forces N, angles deg, so that a rotational
//! stiffness written `4000 N*mm/deg` is stored as N·mm/rad. See
//! `spec/conventions.md`, "Units".

use std::fmt;

/// Exponents of the base dimensions length, force, angle, mass and time.
///
/// Angle is kept as a dimension of its own (unlike SI) so that a torque written
/// where a rotational stiffness is expected is caught.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct Dim {
    pub length: i8,
    pub force: i8,
    pub angle: i8,
    pub mass: i8,
    pub time: i8,
}

impl Dim {
    pub const NONE: Dim = Dim::new(0, 0, 0);
    pub const LENGTH: Dim = Dim::new(1, 0, 0);
    pub const FORCE: Dim = Dim::new(0, 1, 0);
    pub const ANGLE: Dim = Dim::new(0, 0, 1);
    pub const TORQUE: Dim = Dim::new(1, 1, 0);
    pub const STIFFNESS: Dim = Dim::new(-1, 1, 0);
    pub const ROT_STIFFNESS: Dim = Dim::new(1, 1, -1);
    pub const MASS: Dim = Dim {
        length: 0,
        force: 0,
        angle: 0,
        mass: 1,
        time: 0,
    };

    pub const fn new(length: i8, force: i8, angle: i8) -> Dim {
        Dim {
            length,
            force,
            angle,
            mass: 0,
            time: 0,
        }
    }

    // Saturating: absurd powers written by a user (`mm^100*mm^100`) must give a
    // wrong-dimension diagnostic, not an overflow panic.
    pub fn mul(self, o: Dim) -> Dim {
        Dim {
            length: self.length.saturating_add(o.length),
            force: self.force.saturating_add(o.force),
            angle: self.angle.saturating_add(o.angle),
            mass: self.mass.saturating_add(o.mass),
            time: self.time.saturating_add(o.time),
        }
    }

    pub fn div(self, o: Dim) -> Dim {
        self.mul(o.powi(-1))
    }

    pub fn powi(self, n: i8) -> Dim {
        Dim {
            length: self.length.saturating_mul(n),
            force: self.force.saturating_mul(n),
            angle: self.angle.saturating_mul(n),
            mass: self.mass.saturating_mul(n),
            time: self.time.saturating_mul(n),
        }
    }

    /// The boundary unit of this dimension, as the language writes it (`N*mm/deg`).
    pub fn boundary_unit(self) -> String {
        let mut num = Vec::new();
        let mut den = Vec::new();
        let mut put = |name: &str, e: i8| {
            let (list, e) = if e > 0 {
                (&mut num, e.unsigned_abs())
            } else {
                (&mut den, e.unsigned_abs())
            };
            if e == 1 {
                list.push(name.to_string());
            } else if e > 1 {
                list.push(format!("{name}^{e}"));
            }
        };
        put("N", self.force);
        put("mm", self.length);
        put("deg", self.angle);
        put("kg", self.mass);
        put("s", self.time);
        let n = if num.is_empty() {
            "1".to_string()
        } else {
            num.join("*")
        };
        match den.len() {
            0 => {
                if num.is_empty() {
                    String::new()
                } else {
                    n
                }
            }
            _ => format!("{n}/{}", den.join("/")),
        }
    }

    /// Factor from the boundary unit of this dimension to internal units.
    pub fn boundary_factor(self) -> f64 {
        DEG.powi(self.angle as i32)
    }

    /// A word for the quantity, used in diagnostics ("a length", "a stiffness").
    pub fn describe(self) -> String {
        let known: &[(Dim, &str)] = &[
            (Dim::NONE, "a plain number"),
            (Dim::LENGTH, "a length"),
            (Dim::FORCE, "a force"),
            (Dim::ANGLE, "an angle"),
            (Dim::TORQUE, "a torque"),
            (Dim::STIFFNESS, "a translational stiffness"),
            (Dim::ROT_STIFFNESS, "a rotational stiffness"),
            (Dim::MASS, "a mass"),
        ];
        for (d, w) in known {
            if *d == self {
                return format!("{w} (`{}`)", self.boundary_unit()).replace(" (``)", "");
            }
        }
        format!("`{}`", self.boundary_unit())
    }
}

impl fmt::Display for Dim {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.describe())
    }
}

/// One degree in radians.
pub const DEG: f64 = std::f64::consts::PI / 180.0;

/// A unit: its dimension and the factor that converts a value to internal units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Unit {
    pub dim: Dim,
    pub factor: f64,
}

impl Unit {
    pub const ONE: Unit = Unit {
        dim: Dim::NONE,
        factor: 1.0,
    };

    pub fn mul(self, o: Unit) -> Unit {
        Unit {
            dim: self.dim.mul(o.dim),
            factor: self.factor * o.factor,
        }
    }

    pub fn div(self, o: Unit) -> Unit {
        Unit {
            dim: self.dim.div(o.dim),
            factor: self.factor / o.factor,
        }
    }

    pub fn powi(self, n: i8) -> Unit {
        Unit {
            dim: self.dim.powi(n),
            factor: self.factor.powi(n as i32),
        }
    }
}

/// The base unit names the language knows, with their meaning.
pub const UNIT_NAMES: &[(&str, Unit)] = &[
    (
        "mm",
        Unit {
            dim: Dim::LENGTH,
            factor: 1.0,
        },
    ),
    (
        "cm",
        Unit {
            dim: Dim::LENGTH,
            factor: 10.0,
        },
    ),
    (
        "m",
        Unit {
            dim: Dim::LENGTH,
            factor: 1000.0,
        },
    ),
    (
        "N",
        Unit {
            dim: Dim::FORCE,
            factor: 1.0,
        },
    ),
    (
        "kN",
        Unit {
            dim: Dim::FORCE,
            factor: 1000.0,
        },
    ),
    (
        "deg",
        Unit {
            dim: Dim::ANGLE,
            factor: DEG,
        },
    ),
    (
        "rad",
        Unit {
            dim: Dim::ANGLE,
            factor: 1.0,
        },
    ),
    (
        "kg",
        Unit {
            dim: Dim::MASS,
            factor: 1.0,
        },
    ),
    (
        "s",
        Unit {
            dim: Dim {
                length: 0,
                force: 0,
                angle: 0,
                mass: 0,
                time: 1,
            },
            factor: 1.0,
        },
    ),
];

/// Looks up a base unit name (`mm`, `N`, `deg`, ...).
pub fn base_unit(name: &str) -> Option<Unit> {
    UNIT_NAMES.iter().find(|(n, _)| *n == name).map(|(_, u)| *u)
}

/// Parses a compound unit such as `N*mm/deg` or `N/mm^3`.
///
/// `*` and `/` associate left to right (`N/mm/deg` is N per mm per deg), and a
/// factor may carry an integer power. Returns the offending piece on error.
pub fn parse_unit(text: &str) -> Result<Unit, String> {
    let mut unit = Unit::ONE;
    let mut op = '*';
    let mut rest = text.trim();
    loop {
        let end = rest.find(['*', '/']).unwrap_or(rest.len());
        let piece = rest[..end].trim();
        let (name, power) = match piece.split_once('^') {
            Some((n, p)) => (
                n.trim(),
                p.trim().parse::<i8>().map_err(|_| piece.to_string())?,
            ),
            None => (piece, 1),
        };
        let base = base_unit(name).ok_or_else(|| name.to_string())?;
        let u = base.powi(power);
        unit = if op == '*' { unit.mul(u) } else { unit.div(u) };
        if end == rest.len() {
            return Ok(unit);
        }
        op = rest[end..].chars().next().unwrap_or('*');
        rest = &rest[end + 1..];
    }
}

/// Converts a value in internal units to the boundary unit of its dimension.
pub fn to_boundary(value: f64, dim: Dim) -> f64 {
    value / dim.boundary_factor()
}

/// Converts a value in the boundary unit of its dimension to internal units.
pub fn from_boundary(value: f64, dim: Dim) -> f64 {
    value * dim.boundary_factor()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() <= 1e-12 * b.abs().max(1.0)
    }

    #[test]
    fn rotational_stiffness_in_deg_becomes_per_radian() {
        let u = parse_unit("N*mm/deg").expect("unit");
        assert_eq!(u.dim, Dim::ROT_STIFFNESS);
        // 10000 N·mm/deg = 5.729577951e5 N·mm/rad (thesis Annexe F, ADAMS KT).
        assert!((10000.0 * u.factor - 5.729577951e5).abs() < 1e-3);
    }

    #[test]
    fn stiffness_units_convert() {
        let u = parse_unit("N/mm").expect("unit");
        assert_eq!(u.dim, Dim::STIFFNESS);
        assert!(close(u.factor, 1.0));
        let u = parse_unit("kN/m").expect("unit");
        assert_eq!(u.dim, Dim::STIFFNESS);
        assert!(close(u.factor, 1.0));
        let u = parse_unit("N/mm^3").expect("unit");
        assert_eq!(u.dim, Dim::new(-3, 1, 0));
        let u = parse_unit("N/m^2").expect("unit");
        assert!(close(u.factor, 1e-6));
    }

    #[test]
    fn lengths_angles_forces_convert() {
        assert!(close(parse_unit("m").expect("m").factor, 1000.0));
        assert!(close(parse_unit("cm").expect("cm").factor, 10.0));
        assert!(close(
            parse_unit("deg").expect("deg").factor,
            std::f64::consts::PI / 180.0
        ));
        assert!(close(parse_unit("kN").expect("kN").factor, 1000.0));
        assert!(close(parse_unit("N*m").expect("N*m").factor, 1000.0));
        assert_eq!(parse_unit("N*m").expect("N*m").dim, Dim::TORQUE);
    }

    #[test]
    fn unknown_unit_names_the_piece() {
        assert_eq!(parse_unit("N/mn"), Err("mn".to_string()));
        assert_eq!(parse_unit("N^x"), Err("N^x".to_string()));
    }

    #[test]
    fn boundary_units_round_trip() {
        for d in [
            Dim::LENGTH,
            Dim::FORCE,
            Dim::ANGLE,
            Dim::TORQUE,
            Dim::STIFFNESS,
            Dim::ROT_STIFFNESS,
            Dim::new(-3, 1, 0),
        ] {
            let u = parse_unit(&d.boundary_unit()).expect("boundary unit parses");
            assert_eq!(u.dim, d);
            assert!(close(u.factor, d.boundary_factor()));
            assert!(close(from_boundary(to_boundary(3.5, d), d), 3.5));
        }
        assert_eq!(Dim::ROT_STIFFNESS.boundary_unit(), "N*mm/deg");
        assert_eq!(Dim::STIFFNESS.boundary_unit(), "N/mm");
    }
}
