//! Element parameters addressed by name, as `interfaces.md` writes them:
//! `<bushing>.k_x|k_y|k_z|kt_x|kt_y|kt_z`, `<spring>.k`, `<spring>.free_length`,
//! `<spring>.preload`, `<joint>.x|y|z` (the joint point moved on both parts), and
//! the names of declared parameters. Trim, identification and diagnosis change
//! models through these.

use super::*;
use crate::units::Dim;

/// A scalar of a model that a tool may change.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Address {
    Param(ParamId),
    /// Linear translational stiffness along an axis (0, 1, 2 = x, y, z of J).
    BushingK(BushingId, usize),
    /// Linear rotational stiffness about an axis.
    BushingKt(BushingId, usize),
    SpringK(SpringId),
    SpringFreeLength(SpringId),
    SpringPreload(SpringId),
    /// A global coordinate of a joint's point: both markers move together.
    JointPoint(JointId, usize),
}

/// Why a name does not address a parameter.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum AddressError {
    UnknownElement(String),
    UnknownField {
        element: String,
        field: String,
        fields: Vec<&'static str>,
    },
    /// The field exists but is not a single linear number (a table law).
    NotLinear(String),
}

impl std::fmt::Display for AddressError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            AddressError::UnknownElement(e) => {
                write!(f, "no parameter, bushing, spring or joint is called `{e}`")
            }
            AddressError::UnknownField {
                element,
                field,
                fields,
            } => {
                write!(
                    f,
                    "`{element}` has no parameter `{field}` (it has {})",
                    fields.join(", ")
                )
            }
            AddressError::NotLinear(n) => write!(f, "`{n}` is a table law, not a single stiffness"),
        }
    }
}

const AXES: [&str; 3] = ["x", "y", "z"];

impl Address {
    /// Resolves `A.k_x`, `spring.free_length`, `L8.y` or a declared parameter name.
    pub fn parse(model: &Model, name: &str) -> Result<Address, AddressError> {
        if let Some(p) = model.param_named(name) {
            return Ok(Address::Param(p));
        }
        let Some((elem, field)) = name.rsplit_once('.') else {
            return Err(AddressError::UnknownElement(name.to_string()));
        };
        if let Some(b) = model.bushings.iter().position(|b| b.name == elem) {
            let id = BushingId(b as u32);
            let fields = ["k_x", "k_y", "k_z", "kt_x", "kt_y", "kt_z"];
            let Some(n) = fields.iter().position(|f| *f == field) else {
                return Err(AddressError::UnknownField {
                    element: elem.into(),
                    field: field.into(),
                    fields: fields.to_vec(),
                });
            };
            let a = if n < 3 {
                Address::BushingK(id, n)
            } else {
                Address::BushingKt(id, n - 3)
            };
            return match a.law(model) {
                Some(AxisLaw::Table(_)) => Err(AddressError::NotLinear(name.into())),
                _ => Ok(a),
            };
        }
        if let Some(s) = model.springs.iter().position(|s| s.name == elem) {
            let id = SpringId(s as u32);
            if matches!(model.springs[s].law, SpringLaw::Table(_)) {
                return Err(AddressError::NotLinear(name.into()));
            }
            return match field {
                "k" => Ok(Address::SpringK(id)),
                "free_length" => Ok(Address::SpringFreeLength(id)),
                "preload" => Ok(Address::SpringPreload(id)),
                _ => Err(AddressError::UnknownField {
                    element: elem.into(),
                    field: field.into(),
                    fields: vec!["k", "free_length", "preload"],
                }),
            };
        }
        if let Some(j) = model.joints.iter().position(|j| j.name == elem) {
            return match AXES.iter().position(|a| *a == field) {
                Some(n) => Ok(Address::JointPoint(JointId(j as u32), n)),
                None => Err(AddressError::UnknownField {
                    element: elem.into(),
                    field: field.into(),
                    fields: AXES.to_vec(),
                }),
            };
        }
        Err(AddressError::UnknownElement(elem.to_string()))
    }

    fn law(self, model: &Model) -> Option<&AxisLaw> {
        match self {
            Address::BushingK(b, n) => Some(&model.bushings[b.index()].translational[n]),
            Address::BushingKt(b, n) => Some(&model.bushings[b.index()].rotational[n]),
            _ => None,
        }
    }

    /// The name this address is written with.
    pub fn name(self, model: &Model) -> String {
        match self {
            Address::Param(p) => model.params[p.index()].name.clone(),
            Address::BushingK(b, n) => format!("{}.k_{}", model.bushings[b.index()].name, AXES[n]),
            Address::BushingKt(b, n) => {
                format!("{}.kt_{}", model.bushings[b.index()].name, AXES[n])
            }
            Address::SpringK(s) => format!("{}.k", model.springs[s.index()].name),
            Address::SpringFreeLength(s) => {
                format!("{}.free_length", model.springs[s.index()].name)
            }
            Address::SpringPreload(s) => format!("{}.preload", model.springs[s.index()].name),
            Address::JointPoint(j, n) => format!("{}.{}", model.joints[j.index()].name, AXES[n]),
        }
    }

    pub fn dim(self, model: &Model) -> Dim {
        match self {
            Address::Param(p) => model.params[p.index()].dim,
            Address::BushingK(..) | Address::SpringK(_) => Dim::STIFFNESS,
            Address::BushingKt(..) => Dim::ROT_STIFFNESS,
            Address::SpringFreeLength(_) | Address::JointPoint(..) => Dim::LENGTH,
            Address::SpringPreload(_) => Dim::FORCE,
        }
    }

    /// The element this address belongs to, for diagnostics.
    pub fn element(self) -> ElementId {
        match self {
            Address::Param(p) => ElementId::Param(p),
            Address::BushingK(b, _) | Address::BushingKt(b, _) => ElementId::Bushing(b),
            Address::SpringK(s) | Address::SpringFreeLength(s) | Address::SpringPreload(s) => {
                ElementId::Spring(s)
            }
            Address::JointPoint(j, _) => ElementId::Joint(j),
        }
    }

    fn spring_field<'m>(
        model: &'m mut Model,
        s: SpringId,
        f: impl FnOnce(&'m mut Val, &'m mut Val, &'m mut Val) -> &'m mut Val,
    ) -> Option<&'m mut Val> {
        match &mut model.springs[s.index()].law {
            SpringLaw::Linear {
                k,
                free_length,
                preload,
            } => Some(f(k, free_length, preload)),
            SpringLaw::Table(_) => None,
        }
    }

    /// Current value, internal units.
    pub fn get(self, model: &Model) -> f64 {
        match self {
            Address::Param(p) => model.params[p.index()].value,
            Address::JointPoint(j, n) => model.marker(model.joints[j.index()].j).position[n].value,
            _ => {
                let mut m = model.clone();
                self.field(&mut m).map_or(f64::NAN, |v| v.value)
            }
        }
    }

    fn field(self, model: &mut Model) -> Option<&mut Val> {
        match self {
            Address::BushingK(b, n) | Address::BushingKt(b, n) => {
                let bush = &mut model.bushings[b.index()];
                let law = if matches!(self, Address::BushingK(..)) {
                    &mut bush.translational[n]
                } else {
                    &mut bush.rotational[n]
                };
                match law {
                    AxisLaw::Linear { k, .. } => Some(k),
                    AxisLaw::Table(_) => None,
                }
            }
            Address::SpringK(s) => Self::spring_field(model, s, |k, _, _| k),
            Address::SpringFreeLength(s) => Self::spring_field(model, s, |_, l, _| l),
            Address::SpringPreload(s) => Self::spring_field(model, s, |_, _, p| p),
            Address::Param(_) | Address::JointPoint(..) => None,
        }
    }

    /// Sets the value (internal units). A field bound to a declared parameter
    /// sets that parameter (and so every field bound to it); a joint point moves
    /// both joint markers, which the thesis' geometric correction does.
    pub fn set(self, model: &mut Model, value: f64) {
        match self {
            Address::Param(p) => model.set_param(p, value),
            Address::JointPoint(j, n) => {
                let joint = model.joints[j.index()].clone();
                for m in [joint.i, joint.j] {
                    model.markers[m.index()].position[n] = Val::lit(value);
                }
            }
            _ => {
                let bound = self.field(model).and_then(|v| v.param);
                match bound {
                    Some(p) => model.set_param(p, value),
                    None => {
                        if let Some(v) = self.field(model) {
                            v.value = value;
                        }
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn model() -> Model {
        let src = "param kz = 1000 N/mm\nground g {\n    marker o at (0, 0, 0) mm\n}\npart p {\n    marker o at (0, 0, 0) mm\n    marker t at (0, 0, 100) mm\n}\nbushing b {\n    i g.o\n    j p.o\n    k (10 N/mm, 20 N/mm, kz)\n    kt (1, 2, 3) N*mm/deg\n}\nspring s {\n    i g.o\n    j p.t\n    k 30 N/mm\n    free_length 290 mm\n}\n";
        let (_, c) = crate::check::check_str("t.axle", src);
        c.model.expect("checks")
    }

    #[test]
    fn addresses_resolve_read_and_write() {
        let mut m = model();
        let a = Address::parse(&m, "b.k_y").expect("bushing field");
        assert_eq!(a.get(&m), 20.0);
        a.set(&mut m, 25.0);
        assert_eq!(a.get(&m), 25.0);
        assert_eq!(a.name(&m), "b.k_y");
        let kt = Address::parse(&m, "b.kt_z").expect("rotational");
        assert!((kt.get(&m) - 3.0 / crate::units::DEG).abs() < 1e-9);
        let l0 = Address::parse(&m, "s.free_length").expect("spring");
        assert_eq!(l0.get(&m), 290.0);
        assert_eq!(l0.dim(&m), Dim::LENGTH);
    }

    #[test]
    fn a_bound_field_sets_its_parameter() {
        let mut m = model();
        let a = Address::parse(&m, "b.k_z").expect("bound field");
        a.set(&mut m, 1500.0);
        assert_eq!(m.params[0].value, 1500.0);
        assert_eq!(Address::parse(&m, "kz").expect("param").get(&m), 1500.0);
    }

    #[test]
    fn unknown_names_say_what_exists() {
        let m = model();
        assert_eq!(
            Address::parse(&m, "nope.k"),
            Err(AddressError::UnknownElement("nope".into()))
        );
        match Address::parse(&m, "b.k_w") {
            Err(AddressError::UnknownField { fields, .. }) => assert!(fields.contains(&"k_x")),
            other => panic!("{other:?}"),
        }
    }
}
