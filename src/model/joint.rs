//! Joints as tables of primitive constraint equations (`conventions.md`, "Joints").

use super::id::MarkerId;

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum JointKind {
    Spherical,
    Universal,
    Revolute,
    Cylindrical,
    Translational,
    Fixed,
    Inline,
    Inplane,
}

/// A marker axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Axis {
    X,
    Y,
    Z,
}

impl Axis {
    pub const ALL: [Axis; 3] = [Axis::X, Axis::Y, Axis::Z];

    pub fn index(self) -> usize {
        self as usize
    }

    /// `x`, `y` or `z`, as addresses and diagnostics write it.
    pub fn name(self) -> &'static str {
        ["x", "y", "z"][self.index()]
    }

    pub fn from_name(s: &str) -> Option<Axis> {
        Axis::ALL.into_iter().find(|a| a.name() == s)
    }
}

/// One scalar constraint equation between the I and J markers of a joint, with
/// `d = p_I - p_J`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Primitive {
    /// `d · e_k = 0` with `e_k` the global axis k (three of these make `d = 0`).
    Coincident(Axis),
    /// `a_I · b_J = 0` for marker axes `a` of I and `b` of J.
    Perpendicular(Axis, Axis),
    /// `d · b_J = 0` for the J marker axis `b`.
    InPlane(Axis),
}

use Axis::*;
use Primitive::*;

impl JointKind {
    pub const ALL: [JointKind; 8] = [
        JointKind::Spherical,
        JointKind::Universal,
        JointKind::Revolute,
        JointKind::Cylindrical,
        JointKind::Translational,
        JointKind::Fixed,
        JointKind::Inline,
        JointKind::Inplane,
    ];

    /// The keyword used in the language.
    pub fn keyword(self) -> &'static str {
        match self {
            JointKind::Spherical => "spherical",
            JointKind::Universal => "universal",
            JointKind::Revolute => "revolute",
            JointKind::Cylindrical => "cylindrical",
            JointKind::Translational => "translational",
            JointKind::Fixed => "fixed",
            JointKind::Inline => "inline",
            JointKind::Inplane => "inplane",
        }
    }

    pub fn from_keyword(s: &str) -> Option<JointKind> {
        Self::ALL.into_iter().find(|k| k.keyword() == s)
    }

    /// The primitive equations of this joint, exactly the table of `conventions.md`.
    pub fn equations(self) -> &'static [Primitive] {
        match self {
            JointKind::Spherical => &[Coincident(X), Coincident(Y), Coincident(Z)],
            JointKind::Universal => &[
                Coincident(X),
                Coincident(Y),
                Coincident(Z),
                Perpendicular(Z, Z),
            ],
            JointKind::Revolute => &[
                Coincident(X),
                Coincident(Y),
                Coincident(Z),
                Perpendicular(Z, X),
                Perpendicular(Z, Y),
            ],
            JointKind::Cylindrical => &[
                Perpendicular(Z, X),
                Perpendicular(Z, Y),
                InPlane(X),
                InPlane(Y),
            ],
            JointKind::Translational => &[
                Perpendicular(Z, X),
                Perpendicular(Z, Y),
                InPlane(X),
                InPlane(Y),
                Perpendicular(X, Y),
            ],
            JointKind::Fixed => &[
                Coincident(X),
                Coincident(Y),
                Coincident(Z),
                Perpendicular(Z, X),
                Perpendicular(Z, Y),
                Perpendicular(X, Y),
            ],
            JointKind::Inline => &[InPlane(X), InPlane(Y)],
            JointKind::Inplane => &[InPlane(Z)],
        }
    }

    /// Whether the orientation of the markers matters (false: only the I and J origins do).
    pub fn uses_orientation(self) -> bool {
        !matches!(self, JointKind::Spherical)
    }
}

/// A joint between the I marker (on part 1) and the J marker (on part 2).
#[derive(Debug, Clone, PartialEq)]
pub struct Joint {
    pub name: String,
    pub kind: JointKind,
    pub i: MarkerId,
    pub j: MarkerId,
}

impl Primitive {
    /// A short description for redundancy reports: `d·x`, `z_I·x_J`.
    pub fn describe(self) -> String {
        let a = |x: Axis| ["x", "y", "z"][x.index()];
        match self {
            Coincident(k) => format!("d·{}", a(k)),
            Perpendicular(p, q) => format!("{}_I·{}_J", a(p), a(q)),
            InPlane(q) => format!("d·{}_J", a(q)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn equation_counts_match_the_convention_table() {
        let counts = [3, 4, 5, 4, 5, 6, 2, 1];
        for (k, n) in JointKind::ALL.iter().zip(counts) {
            assert_eq!(k.equations().len(), n, "{k:?}");
            assert_eq!(JointKind::from_keyword(k.keyword()), Some(*k));
        }
    }
}
