//! One description per element kind: the numeric fields a user writes, the
//! property keys that write them, their dimensions, axes and laws. The checker
//! (allowed keys), the address parser and printer (`B.k3_z`), the model printer
//! and the emitter read this table instead of keeping their own lists, so a
//! field added here is addressable, checked and printed under one name.

use crate::units::Dim;

/// The kinds of model element that carry numbers a user writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Kind {
    Param,
    Marker,
    Landmark,
    Joint,
    Bushing,
    Spring,
    Stop,
    Friction,
}

/// A numeric field of an element kind (the axis, if any, is separate).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum FieldId {
    /// A declared parameter's value.
    Value,
    /// A marker's or landmark's origin; for a joint or bushing, the point of
    /// both of its markers (moved together).
    Position,
    /// Bushing: linear stiffness `k` of the translational laws.
    K,
    /// Bushing: linear stiffness `kt` of the rotational laws.
    Kt,
    /// Bushing: cubic term of the translational laws.
    K3,
    /// Bushing: cubic term of the rotational laws.
    Kt3,
    Offset,
    AngleOffset,
    Preload,
    TorquePreload,
    /// Spring rate.
    SpringK,
    FreeLength,
    SpringPreload,
    ContactLength,
    /// Stop polynomial coefficient of degree n >= 1 (`k` is degree 1).
    Coefficient(u8),
    /// Friction stick stiffness `kf`.
    FrictionStiffness,
    /// Friction slip limit.
    FrictionLimit,
}

/// How a field is split into scalars, and so how its address is spelled.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Shape {
    /// One number: `spring.k`.
    Scalar,
    /// Three numbers along x, y, z: `B.k_x` (or `L7.x` when the name is empty).
    Axes,
    /// A list by degree: `stop.poly_2` (degree 1 is also `stop.k`).
    Degrees,
}

/// The law a stiffness field belongs to: what it maps from and to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LawSpec {
    /// The deformation (mm or rad).
    pub from: Dim,
    /// The restoring force or torque.
    pub to: Dim,
    /// The cubic-term field that stiffens this law, if the law has one.
    pub cubic: Option<FieldId>,
}

/// One field of an element kind.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FieldSpec {
    pub id: FieldId,
    /// The stem of its address (`k`, `free_length`; empty for a point: `L7.x`).
    pub name: &'static str,
    pub shape: Shape,
    /// Dimension (for `Degrees`, of degree 1; for friction, of a slide).
    pub dim: Dim,
    /// The source properties that write this field.
    pub keys: &'static [&'static str],
    /// An example value, for diagnostics.
    pub example: &'static str,
    pub law: Option<LawSpec>,
}

/// An element kind: its keyword, the non-numeric properties, and its fields.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ElementSchema {
    pub kind: Kind,
    pub keyword: &'static str,
    /// Properties that name markers or elements (`i`, `j`, `joint`), listed
    /// before the fields.
    pub refs: &'static [&'static str],
    pub fields: &'static [FieldSpec],
    /// Properties that choose a variant instead of the fields (`law` for a
    /// table law, `motion`), listed after the fields.
    pub choices: &'static [&'static str],
}

const fn f(
    id: FieldId,
    name: &'static str,
    shape: Shape,
    dim: Dim,
    keys: &'static [&'static str],
    example: &'static str,
) -> FieldSpec {
    FieldSpec {
        id,
        name,
        shape,
        dim,
        keys,
        example,
        law: None,
    }
}

const fn with_law(mut s: FieldSpec, from: Dim, to: Dim, cubic: Option<FieldId>) -> FieldSpec {
    s.law = Some(LawSpec { from, to, cubic });
    s
}

/// Dimension of a translational cubic term, N/mm³.
pub const K3_DIM: Dim = Dim::new(-3, 1, 0);
/// Dimension of a rotational cubic term, N·mm/rad³.
pub const KT3_DIM: Dim = Dim::new(1, 1, -3);

use FieldId::*;
use Shape::*;

pub const BUSHING: ElementSchema = ElementSchema {
    kind: Kind::Bushing,
    keyword: "bushing",
    refs: &["i", "j"],
    fields: &[
        with_law(
            f(
                K,
                "k",
                Axes,
                Dim::STIFFNESS,
                &["k", "k_radial", "k_axial", "k_x", "k_y", "k_z"],
                "(310, 2400, 180) N/mm",
            ),
            Dim::LENGTH,
            Dim::FORCE,
            Some(K3),
        ),
        with_law(
            f(
                Kt,
                "kt",
                Axes,
                Dim::ROT_STIFFNESS,
                &["kt", "kt_radial", "kt_axial", "kt_x", "kt_y", "kt_z"],
                "(4500, 1100, 1600) N*mm/deg",
            ),
            Dim::ANGLE,
            Dim::TORQUE,
            Some(Kt3),
        ),
        f(K3, "k3", Axes, K3_DIM, &["k3"], "(0, 0, 2) N/mm^3"),
        f(Kt3, "kt3", Axes, KT3_DIM, &["kt3"], "(0, 0, 2) N*mm/deg^3"),
        f(
            Offset,
            "offset",
            Axes,
            Dim::LENGTH,
            &["offset"],
            "(0, 0, 1.5) mm",
        ),
        f(
            AngleOffset,
            "angle_offset",
            Axes,
            Dim::ANGLE,
            &["angle_offset"],
            "(0, 0, 2) deg",
        ),
        f(
            Preload,
            "preload",
            Axes,
            Dim::FORCE,
            &["preload"],
            "(0, 0, 100) N",
        ),
        f(
            TorquePreload,
            "torque_preload",
            Axes,
            Dim::TORQUE,
            &["torque_preload"],
            "(0, 0, 1000) N*mm",
        ),
        f(Position, "", Axes, Dim::LENGTH, &[], "(0, 0, 0) mm"),
    ],
    choices: &[],
};

pub const SPRING: ElementSchema = ElementSchema {
    kind: Kind::Spring,
    keyword: "spring",
    refs: &["i", "j"],
    fields: &[
        with_law(
            f(SpringK, "k", Scalar, Dim::STIFFNESS, &["k"], "30 N/mm"),
            Dim::LENGTH,
            Dim::FORCE,
            None,
        ),
        f(
            FreeLength,
            "free_length",
            Scalar,
            Dim::LENGTH,
            &["free_length"],
            "290 mm",
        ),
        f(
            SpringPreload,
            "preload",
            Scalar,
            Dim::FORCE,
            &["preload"],
            "4800 N",
        ),
    ],
    choices: &["law"],
};

pub const STOP: ElementSchema = ElementSchema {
    kind: Kind::Stop,
    keyword: "stop",
    refs: &["i", "j"],
    fields: &[
        f(
            ContactLength,
            "contact_length",
            Scalar,
            Dim::LENGTH,
            &["contact_length"],
            "120 mm",
        ),
        with_law(
            f(
                Coefficient(1),
                "poly",
                Degrees,
                Dim::STIFFNESS,
                &["k", "poly"],
                "[500 N/mm, 20 N/mm^2]",
            ),
            Dim::LENGTH,
            Dim::FORCE,
            None,
        ),
    ],
    choices: &["law"],
};

pub const FRICTION: ElementSchema = ElementSchema {
    kind: Kind::Friction,
    keyword: "friction",
    refs: &["joint"],
    fields: &[
        f(
            FrictionStiffness,
            "kf",
            Scalar,
            Dim::STIFFNESS,
            &["kf"],
            "1000 N/mm",
        ),
        f(
            FrictionLimit,
            "limit",
            Scalar,
            Dim::FORCE,
            &["limit"],
            "150 N",
        ),
    ],
    choices: &["motion"],
};

pub const JOINT: ElementSchema = ElementSchema {
    kind: Kind::Joint,
    keyword: "joint",
    refs: &["i", "j"],
    fields: &[f(Position, "", Axes, Dim::LENGTH, &[], "(0, 0, 0) mm")],
    choices: &[],
};

pub const MARKER: ElementSchema = ElementSchema {
    kind: Kind::Marker,
    keyword: "marker",
    refs: &[],
    fields: &[f(Position, "", Axes, Dim::LENGTH, &["at"], "(0, 0, 0) mm")],
    choices: &[],
};

pub const LANDMARK: ElementSchema = ElementSchema {
    kind: Kind::Landmark,
    keyword: "landmark",
    refs: &[],
    fields: &[f(Position, "", Axes, Dim::LENGTH, &["at"], "(0, 0, 0) mm")],
    choices: &[],
};

pub const PARAM: ElementSchema = ElementSchema {
    kind: Kind::Param,
    keyword: "param",
    refs: &[],
    fields: &[f(Value, "", Scalar, Dim::NONE, &[], "310 N/mm")],
    choices: &[],
};

/// The description of an element kind.
pub fn of(kind: Kind) -> &'static ElementSchema {
    match kind {
        Kind::Param => &PARAM,
        Kind::Marker => &MARKER,
        Kind::Landmark => &LANDMARK,
        Kind::Joint => &JOINT,
        Kind::Bushing => &BUSHING,
        Kind::Spring => &SPRING,
        Kind::Stop => &STOP,
        Kind::Friction => &FRICTION,
    }
}

impl ElementSchema {
    /// Every property key the element accepts, for the checker: the
    /// references, the fields' keys, then the choices.
    pub fn keys(&self) -> Vec<&'static str> {
        let mut out = self.refs.to_vec();
        for k in self
            .field_keys()
            .into_iter()
            .chain(self.choices.iter().copied())
        {
            if !out.contains(&k) {
                out.push(k);
            }
        }
        out
    }

    /// The keys that write the fields, in order (a spring's `k`,
    /// `free_length`, `preload`).
    pub fn field_keys(&self) -> Vec<&'static str> {
        let mut out = Vec::new();
        for k in self.fields.iter().flat_map(|s| s.keys.iter().copied()) {
            if !out.contains(&k) {
                out.push(k);
            }
        }
        out
    }

    /// The description of a field (a stop coefficient of any degree finds `poly`).
    pub fn field(&self, id: FieldId) -> &'static FieldSpec {
        let want = match id {
            Coefficient(_) => Coefficient(1),
            other => other,
        };
        self.fields
            .iter()
            .find(|s| s.id == want)
            .unwrap_or(&self.fields[0])
    }
}

impl FieldSpec {
    /// The example of a single value: for a list, its first item (`500 N/mm`
    /// of `[500 N/mm, 20 N/mm^2]`, a stop's `k`).
    pub fn scalar_example(&self) -> &'static str {
        match self.example.strip_prefix('[') {
            Some(list) => list.split(',').next().unwrap_or(list).trim_end_matches(']'),
            None => self.example,
        }
    }
}

impl FieldId {
    /// The dimension of this field when it is fixed by the kind alone (friction
    /// fields and parameters depend on the element: see `Address::dim`).
    pub fn dim(self, kind: Kind) -> Dim {
        match self {
            Coefficient(n) => Dim::new(-(n as i8), 1, 0),
            other => of(kind).field(other).dim,
        }
    }
}

/// Axis names in address order.
pub const AXES: [&str; 3] = ["x", "y", "z"];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_kind_finds_its_own_fields() {
        for kind in [
            Kind::Param,
            Kind::Marker,
            Kind::Landmark,
            Kind::Joint,
            Kind::Bushing,
            Kind::Spring,
            Kind::Stop,
            Kind::Friction,
        ] {
            let s = of(kind);
            assert_eq!(s.kind, kind);
            for fs in s.fields {
                assert_eq!(s.field(fs.id).id, fs.id, "{:?} {:?}", kind, fs.id);
            }
        }
    }

    #[test]
    fn bushing_keys_are_the_language_ones() {
        let k = BUSHING.keys();
        assert_eq!(k.len(), 20, "{k:?}");
        for key in ["i", "j", "k_radial", "kt_z", "k3", "torque_preload"] {
            assert!(k.contains(&key), "{key}");
        }
        // A stop's poly of degree 2 is N/mm², degree 1 a stiffness.
        assert_eq!(Coefficient(2).dim(Kind::Stop), Dim::new(-2, 1, 0));
        assert_eq!(Coefficient(1).dim(Kind::Stop), Dim::STIFFNESS);
    }

    #[test]
    fn a_list_example_gives_its_first_item_as_a_scalar_example() {
        let poly = STOP.field(Coefficient(1));
        assert_eq!(poly.scalar_example(), "500 N/mm");
        assert_eq!(SPRING.field(SpringK).scalar_example(), "30 N/mm");
    }
}
