//! Every number a user writes, named as a parameter address (grammar in
//! `docs/language.md`, "Addresses"): a declared parameter (`k_front`), an
//! element field (`B.k_x`, `B.k3_z`, `B.offset_y`, `spring.free_length`,
//! `bump.contact_length`, `bump.poly_2`, `L5_friction.kf`), a joint or bushing
//! point moved on both parts (`L7.z`), or a point on one part
//! (`upright.L7.z`, `chassis.m1.x`). Field names come from [`super::schema`].
//! Trim, identification, sensitivities and diagnosis change models through these.

use super::schema::{self, FieldId, Kind, Shape};
use super::*;
use crate::units::Dim;

pub use super::address_error::AddressError;

/// One scalar of a model: an element, one of its fields, and the axis for
/// fields along x, y, z.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Address {
    pub element: ElementId,
    pub field: FieldId,
    pub axis: Option<Axis>,
}

/// The schema kind of an element, for the elements that carry numbers.
pub fn kind_of(e: ElementId) -> Option<Kind> {
    Some(match e {
        ElementId::Param(_) => Kind::Param,
        ElementId::Marker(_) => Kind::Marker,
        ElementId::Landmark(_) => Kind::Landmark,
        ElementId::Joint(_) => Kind::Joint,
        ElementId::Bushing(_) => Kind::Bushing,
        ElementId::Spring(_) => Kind::Spring,
        ElementId::Stop(_) => Kind::Stop,
        ElementId::Friction(_) => Kind::Friction,
        ElementId::Part(_) | ElementId::Wheel(_) | ElementId::LoadSet(_) => return None,
    })
}

impl Address {
    pub fn param(p: ParamId) -> Address {
        Address {
            element: ElementId::Param(p),
            field: FieldId::Value,
            axis: None,
        }
    }

    /// A bushing's linear stiffness along (`rotational` false) or about an axis.
    pub fn bushing(b: BushingId, rotational: bool, axis: usize) -> Address {
        Address {
            element: ElementId::Bushing(b),
            field: if rotational { FieldId::Kt } else { FieldId::K },
            axis: Some(Axis::ALL[axis]),
        }
    }

    pub fn spring(s: SpringId, field: FieldId) -> Address {
        Address {
            element: ElementId::Spring(s),
            field,
            axis: None,
        }
    }

    /// `(bushing, rotational, axis)` for a bushing's linear stiffness.
    pub fn bushing_stiffness(self) -> Option<(BushingId, bool, usize)> {
        match (self.element, self.field, self.axis) {
            (ElementId::Bushing(b), FieldId::K, Some(a)) => Some((b, false, a.index())),
            (ElementId::Bushing(b), FieldId::Kt, Some(a)) => Some((b, true, a.index())),
            _ => None,
        }
    }

    /// The element this address belongs to, for diagnostics.
    pub fn element(self) -> ElementId {
        self.element
    }

    /// The same storage under its canonical axis: y of an axisymmetric
    /// family is x (one radial law).
    pub fn canonical(self, model: &Model) -> Address {
        match (self.element, self.axis) {
            (ElementId::Bushing(b), Some(a)) => {
                let bu = &model.bushings[b.index()];
                let laws = match self.field {
                    FieldId::K | FieldId::K3 => &bu.translational,
                    FieldId::Kt | FieldId::Kt3 => &bu.rotational,
                    _ => return self,
                };
                Address {
                    axis: Some(Axis::ALL[laws.stored_axis(a.index())]),
                    ..self
                }
            }
            _ => self,
        }
    }

    /// The name this address is written with.
    pub fn name(self, model: &Model) -> String {
        let (owner, kind) = match self.element {
            ElementId::Param(p) => return model.params[p.index()].name.clone(),
            ElementId::Marker(m) => (model.marker_path(m), Kind::Marker),
            ElementId::Landmark(l) => {
                let l = &model.landmarks[l.index()];
                (
                    format!("{}.{}", model.part(l.part).name, l.name),
                    Kind::Landmark,
                )
            }
            ElementId::Joint(j) => (model.joints[j.index()].name.clone(), Kind::Joint),
            ElementId::Bushing(b) => (model.bushings[b.index()].name.clone(), Kind::Bushing),
            ElementId::Spring(s) => (model.springs[s.index()].name.clone(), Kind::Spring),
            ElementId::Stop(s) => (model.stops[s.index()].name.clone(), Kind::Stop),
            ElementId::Friction(f) => (model.frictions[f.index()].name.clone(), Kind::Friction),
            other => return model.describe(other),
        };
        let spec = schema::of(kind).field(self.field);
        let field = match (spec.shape, self.axis, self.field) {
            (Shape::Axes, Some(a), _) if spec.name.is_empty() => a.name().to_string(),
            (Shape::Axes, Some(a), _) => format!("{}_{}", spec.name, a.name()),
            (Shape::Degrees, _, FieldId::Coefficient(n)) => {
                let single = matches!(self.element, ElementId::Stop(s)
                    if matches!(&model.stops[s.index()].law, StopLaw::Polynomial(c) if c.len() == 1));
                if n == 1 && single {
                    "k".to_string()
                } else {
                    format!("{}_{n}", spec.name)
                }
            }
            _ => spec.name.to_string(),
        };
        format!("{owner}.{field}")
    }

    /// The dimension of the value (internal units are mm, N, rad).
    pub fn dim(self, model: &Model) -> Dim {
        match (self.element, self.field) {
            (ElementId::Param(p), _) => model.params[p.index()].dim,
            (ElementId::Friction(f), field) => {
                let rot = model.frictions[f.index()].motion == FrictionMotion::Rotation;
                match (field, rot) {
                    (FieldId::FrictionStiffness, false) => Dim::STIFFNESS,
                    (FieldId::FrictionStiffness, true) => Dim::ROT_STIFFNESS,
                    (_, false) => Dim::FORCE,
                    (_, true) => Dim::TORQUE,
                }
            }
            (e, field) => kind_of(e).map_or(Dim::NONE, |k| field.dim(k)),
        }
    }

    /// The unit values are shown in (`N/mm`, `N*mm/deg`, `mm`).
    pub fn unit(self, model: &Model) -> String {
        self.dim(model).boundary_unit()
    }

    /// The stored field, if this address names one (a joint or bushing point
    /// names the J marker's coordinate; both markers move on `set`).
    pub fn val(self, model: &Model) -> Option<&Val> {
        let a = self.axis.map_or(0, Axis::index);
        fn law_k(laws: &AxisLaws, a: usize, cubic: bool) -> Option<&Val> {
            match laws.get(a) {
                AxisLaw::Linear { k, k3 } => Some(if cubic { k3 } else { k }),
                AxisLaw::Table(_) => None,
            }
        }
        match self.element {
            ElementId::Param(_) => None,
            ElementId::Marker(m) => Some(&model.markers[m.index()].position[a]),
            ElementId::Landmark(l) => Some(&model.landmarks[l.index()].position[a]),
            ElementId::Joint(_) | ElementId::Bushing(_) if self.field == FieldId::Position => {
                let (_, j) = self.point_markers(model)?;
                Some(&model.markers[j.index()].position[a])
            }
            ElementId::Bushing(b) => {
                let b = &model.bushings[b.index()];
                match self.field {
                    FieldId::K => law_k(&b.translational, a, false),
                    FieldId::Kt => law_k(&b.rotational, a, false),
                    FieldId::K3 => law_k(&b.translational, a, true),
                    FieldId::Kt3 => law_k(&b.rotational, a, true),
                    FieldId::Offset => Some(&b.offset[a]),
                    FieldId::AngleOffset => Some(&b.angle_offset[a]),
                    FieldId::Preload => Some(&b.preload[a]),
                    FieldId::TorquePreload => Some(&b.torque_preload[a]),
                    _ => None,
                }
            }
            ElementId::Spring(s) => match &model.springs[s.index()].law {
                SpringLaw::Linear {
                    k,
                    free_length,
                    preload,
                } => match self.field {
                    FieldId::SpringK => Some(k),
                    FieldId::FreeLength => Some(free_length),
                    FieldId::SpringPreload => Some(preload),
                    _ => None,
                },
                SpringLaw::Table(_) => None,
            },
            ElementId::Stop(s) => {
                let s = &model.stops[s.index()];
                match (self.field, &s.law) {
                    (FieldId::ContactLength, _) => Some(&s.contact_length),
                    (FieldId::Coefficient(n), StopLaw::Polynomial(c)) => {
                        c.get(usize::from(n).checked_sub(1)?)
                    }
                    _ => None,
                }
            }
            ElementId::Friction(f) => {
                let f = &model.frictions[f.index()];
                match self.field {
                    FieldId::FrictionStiffness => Some(&f.stiffness),
                    FieldId::FrictionLimit => Some(&f.limit),
                    _ => None,
                }
            }
            _ => None,
        }
    }

    /// The I and J markers of a joint or bushing point.
    fn point_markers(self, model: &Model) -> Option<(MarkerId, MarkerId)> {
        match self.element {
            ElementId::Joint(j) => Some((model.joints[j.index()].i, model.joints[j.index()].j)),
            ElementId::Bushing(b) => {
                Some((model.bushings[b.index()].i, model.bushings[b.index()].j))
            }
            _ => None,
        }
    }

    fn val_mut(self, model: &mut Model) -> Option<&mut Val> {
        // The mutable twin of `val` (points are handled by `set`).
        let a = self.axis.map_or(0, Axis::index);
        fn law_k(laws: &mut AxisLaws, a: usize, cubic: bool) -> Option<&mut Val> {
            match laws.get_mut(a) {
                AxisLaw::Linear { k, k3 } => Some(if cubic { k3 } else { k }),
                AxisLaw::Table(_) => None,
            }
        }
        match self.element {
            ElementId::Marker(m) => Some(&mut model.markers[m.index()].position[a]),
            ElementId::Landmark(l) => Some(&mut model.landmarks[l.index()].position[a]),
            ElementId::Bushing(b) => {
                let b = &mut model.bushings[b.index()];
                match self.field {
                    FieldId::K => law_k(&mut b.translational, a, false),
                    FieldId::Kt => law_k(&mut b.rotational, a, false),
                    FieldId::K3 => law_k(&mut b.translational, a, true),
                    FieldId::Kt3 => law_k(&mut b.rotational, a, true),
                    FieldId::Offset => Some(&mut b.offset[a]),
                    FieldId::AngleOffset => Some(&mut b.angle_offset[a]),
                    FieldId::Preload => Some(&mut b.preload[a]),
                    FieldId::TorquePreload => Some(&mut b.torque_preload[a]),
                    _ => None,
                }
            }
            ElementId::Spring(s) => match &mut model.springs[s.index()].law {
                SpringLaw::Linear {
                    k,
                    free_length,
                    preload,
                } => match self.field {
                    FieldId::SpringK => Some(k),
                    FieldId::FreeLength => Some(free_length),
                    FieldId::SpringPreload => Some(preload),
                    _ => None,
                },
                SpringLaw::Table(_) => None,
            },
            ElementId::Stop(s) => {
                let s = &mut model.stops[s.index()];
                match (self.field, &mut s.law) {
                    (FieldId::ContactLength, _) => Some(&mut s.contact_length),
                    (FieldId::Coefficient(n), StopLaw::Polynomial(c)) => {
                        c.get_mut(usize::from(n).checked_sub(1)?)
                    }
                    _ => None,
                }
            }
            ElementId::Friction(f) => {
                let f = &mut model.frictions[f.index()];
                match self.field {
                    FieldId::FrictionStiffness => Some(&mut f.stiffness),
                    FieldId::FrictionLimit => Some(&mut f.limit),
                    _ => None,
                }
            }
            _ => None,
        }
    }

    /// Current value, internal units (NaN if the address no longer names a
    /// number, e.g. after its law was replaced by a table).
    pub fn get(self, model: &Model) -> f64 {
        match self.element {
            ElementId::Param(p) => model.params[p.index()].value,
            _ => self.val(model).map_or(f64::NAN, |v| v.value),
        }
    }

    /// The declared parameter this field is written as, if any.
    pub fn binding(self, model: &Model) -> Option<ParamId> {
        match self.element {
            ElementId::Param(p) => Some(p),
            _ => self.val(model).and_then(|v| v.param),
        }
    }

    /// Sets the value (internal units). A field bound to a declared parameter
    /// sets that parameter (and so every field bound to it); a joint or bushing
    /// point moves both markers, as the thesis' geometric correction does, each
    /// through its own binding.
    pub fn set(self, model: &mut Model, value: f64) {
        if let ElementId::Param(p) = self.element {
            return model.set_param(p, value);
        }
        if self.field == FieldId::Position
            && let Some((i, j)) = self.point_markers(model)
        {
            for m in [i, j] {
                let at = Address {
                    element: ElementId::Marker(m),
                    ..self
                };
                at.set(model, value);
            }
            return;
        }
        match self.binding(model) {
            Some(p) => model.set_param(p, value),
            None => {
                if let Some(v) = self.val_mut(model) {
                    v.value = value;
                }
            }
        }
    }
}

#[cfg(test)]
#[path = "address_tests.rs"]
mod tests;
