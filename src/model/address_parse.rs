//! From names to [`Address`]es and back to every address of a model: the
//! parser reads field names from [`super::schema`], and [`Address::all`] walks
//! every number of the model (what `edits` maps to source spans, what the
//! address tests round-trip).

use super::address::{Address, AddressError, kind_of};
use super::schema::{self, FieldId, Shape};
use super::*;

/// Addresses of one element's fields, with their names (canonical first,
/// then aliases such as `k_radial`), or why a field cannot be addressed.
fn element_fields(model: &Model, element: ElementId) -> Vec<(String, Result<Address, ()>)> {
    let Some(kind) = kind_of(element) else {
        return Vec::new();
    };
    let mut out = Vec::new();
    for spec in schema::of(kind).fields {
        let at = |axis: Option<Axis>, field: FieldId| Address {
            element,
            field,
            axis,
        };
        match spec.shape {
            Shape::Scalar => out.push((spec.name.to_string(), Ok(at(None, spec.id)))),
            Shape::Axes => {
                for a in Axis::ALL {
                    let n = if spec.name.is_empty() {
                        a.name().to_string()
                    } else {
                        format!("{}_{}", spec.name, a.name())
                    };
                    out.push((n, Ok(at(Some(a), spec.id))));
                }
                // `k_radial`/`k_axial` of an axisymmetric family.
                if let (ElementId::Bushing(b), FieldId::K | FieldId::Kt) = (element, spec.id) {
                    let bu = &model.bushings[b.index()];
                    let laws = if spec.id == FieldId::K {
                        &bu.translational
                    } else {
                        &bu.rotational
                    };
                    if laws.is_axisymmetric() {
                        out.push((
                            format!("{}_radial", spec.name),
                            Ok(at(Some(Axis::X), spec.id)),
                        ));
                        out.push((
                            format!("{}_axial", spec.name),
                            Ok(at(Some(Axis::Z), spec.id)),
                        ));
                    }
                }
            }
            Shape::Degrees => {
                let n = match element {
                    ElementId::Stop(s) => match &model.stops[s.index()].law {
                        StopLaw::Polynomial(c) => c.len(),
                        StopLaw::Table(_) => 1,
                    },
                    _ => 0,
                };
                out.push(("k".to_string(), Ok(at(None, FieldId::Coefficient(1)))));
                for d in 1..=n.min(u8::MAX as usize) {
                    out.push((
                        format!("{}_{d}", spec.name),
                        Ok(at(None, FieldId::Coefficient(d as u8))),
                    ));
                }
            }
        }
    }
    // A field whose law is a table (or absent) has no number.
    for (_, r) in &mut out {
        if let Ok(a) = r
            && a.val(model).is_none()
            && !matches!(a.element, ElementId::Param(_))
        {
            *r = Err(());
        }
    }
    out
}

impl Address {
    /// Resolves a declared parameter name, `element.field`, `joint.x` or
    /// `part.marker.x`.
    pub fn parse(model: &Model, name: &str) -> Result<Address, AddressError> {
        if let Some(p) = model.param_named(name) {
            return Ok(Address::param(p));
        }
        let pieces: Vec<&str> = name.split('.').collect();
        let (element, field) = match pieces[..] {
            [elem, field] => match Self::element_named(model, elem) {
                Some(e) => (e, field),
                None => {
                    return Err(AddressError::UnknownElement {
                        name: elem.to_string(),
                        candidates: Self::element_names(model),
                    });
                }
            },
            [.., field] if pieces.len() >= 3 => (Self::qualified(model, &pieces)?, field),
            _ => {
                return Err(AddressError::UnknownElement {
                    name: name.to_string(),
                    candidates: Self::element_names(model),
                });
            }
        };
        let fields = element_fields(model, element);
        match fields.iter().find(|(n, _)| n == field) {
            Some((_, Ok(a))) => Ok(*a),
            Some((_, Err(()))) => Err(AddressError::NotLinear(name.to_string())),
            None => Err(AddressError::UnknownField {
                element: name[..name.len() - field.len() - 1].to_string(),
                field: field.to_string(),
                fields: fields
                    .into_iter()
                    .filter(|(_, r)| r.is_ok())
                    .map(|(n, _)| n)
                    .collect(),
            }),
        }
    }

    /// What `pieces` without the last (the field) name, when they are three
    /// or more: an element of an instance (`front_right.B`), or a point on a
    /// part (`upright.WC`, `front_left.upright.WC`), the part's name being
    /// the first pieces that name a part.
    fn qualified(model: &Model, pieces: &[&str]) -> Result<ElementId, AddressError> {
        let head = &pieces[..pieces.len() - 1];
        if let Some(e) = Self::element_named(model, &head.join(".")) {
            return Ok(e);
        }
        let mut first_err = None;
        for k in 1..head.len() {
            let part = head[..k].join(".");
            if model.part_named(&part).is_some() {
                match Self::point_on_part(model, &part, &head[k..].join(".")) {
                    Ok(e) => return Ok(e),
                    Err(e) => {
                        first_err.get_or_insert(e);
                    }
                }
            }
        }
        Err(first_err.unwrap_or_else(|| match head {
            [part, _] => AddressError::UnknownElement {
                name: part.to_string(),
                candidates: model.parts.iter().map(|p| p.name.clone()).collect(),
            },
            _ => AddressError::UnknownElement {
                name: pieces.join("."),
                candidates: Self::element_names(model),
            },
        }))
    }

    /// A force element or joint by name (names of these kinds are unique).
    fn element_named(model: &Model, name: &str) -> Option<ElementId> {
        let pos = |names: Vec<&String>| names.iter().position(|n| *n == name).map(|i| i as u32);
        if let Some(i) = pos(model.bushings.iter().map(|b| &b.name).collect()) {
            return Some(ElementId::Bushing(BushingId(i)));
        }
        if let Some(i) = pos(model.springs.iter().map(|b| &b.name).collect()) {
            return Some(ElementId::Spring(SpringId(i)));
        }
        if let Some(i) = pos(model.stops.iter().map(|b| &b.name).collect()) {
            return Some(ElementId::Stop(StopId(i)));
        }
        if let Some(i) = pos(model.frictions.iter().map(|b| &b.name).collect()) {
            return Some(ElementId::Friction(FrictionId(i)));
        }
        if let Some(i) = pos(model.joints.iter().map(|b| &b.name).collect()) {
            return Some(ElementId::Joint(JointId(i)));
        }
        None
    }

    fn element_names(model: &Model) -> Vec<String> {
        let mut v: Vec<String> = model.params.iter().map(|p| p.name.clone()).collect();
        v.extend(model.bushings.iter().map(|b| b.name.clone()));
        v.extend(model.springs.iter().map(|b| b.name.clone()));
        v.extend(model.stops.iter().map(|b| b.name.clone()));
        v.extend(model.frictions.iter().map(|b| b.name.clone()));
        v.extend(model.joints.iter().map(|b| b.name.clone()));
        v.extend(model.parts.iter().map(|b| b.name.clone()));
        v
    }

    /// `part.X`: the marker or landmark X on the part, or the marker on the
    /// part of the joint or bushing X.
    fn point_on_part(model: &Model, part: &str, x: &str) -> Result<ElementId, AddressError> {
        let Some(p) = model.part_named(part) else {
            return Err(AddressError::UnknownElement {
                name: part.to_string(),
                candidates: model.parts.iter().map(|p| p.name.clone()).collect(),
            });
        };
        if let Some(m) = model.marker_named(p, x) {
            return Ok(ElementId::Marker(m));
        }
        if let Some(l) = model
            .landmarks
            .iter()
            .position(|l| l.part == p && l.name == x)
        {
            return Ok(ElementId::Landmark(LandmarkId(l as u32)));
        }
        let ends = match Self::element_named(model, x) {
            Some(ElementId::Joint(j)) => {
                Some((model.joints[j.index()].i, model.joints[j.index()].j))
            }
            Some(ElementId::Bushing(b)) => {
                Some((model.bushings[b.index()].i, model.bushings[b.index()].j))
            }
            _ => None,
        };
        if let Some(m) =
            ends.and_then(|(i, j)| [i, j].into_iter().find(|m| model.marker(*m).part == p))
        {
            return Ok(ElementId::Marker(m));
        }
        let mut candidates: Vec<String> = model
            .markers
            .iter()
            .filter(|m| m.part == p)
            .map(|m| m.name.clone())
            .collect();
        candidates.extend(
            model
                .landmarks
                .iter()
                .filter(|l| l.part == p)
                .map(|l| l.name.clone()),
        );
        Err(AddressError::UnknownPoint {
            part: part.to_string(),
            name: x.to_string(),
            candidates,
        })
    }

    /// Every number of the model, once per storage (an axisymmetric radial law
    /// once, under x), in model order: parameters, markers, landmarks, joints,
    /// bushings, springs, stops, frictions.
    pub fn all(model: &Model) -> Vec<Address> {
        let mut elements: Vec<ElementId> = Vec::new();
        let n = |len: usize| 0..len as u32;
        elements.extend(n(model.params.len()).map(|i| ElementId::Param(ParamId(i))));
        elements.extend(n(model.markers.len()).map(|i| ElementId::Marker(MarkerId(i))));
        elements.extend(n(model.landmarks.len()).map(|i| ElementId::Landmark(LandmarkId(i))));
        elements.extend(model.active_joints().map(|(id, _)| ElementId::Joint(id)));
        elements.extend(n(model.bushings.len()).map(|i| ElementId::Bushing(BushingId(i))));
        elements.extend(n(model.springs.len()).map(|i| ElementId::Spring(SpringId(i))));
        elements.extend(n(model.stops.len()).map(|i| ElementId::Stop(StopId(i))));
        elements.extend(n(model.frictions.len()).map(|i| ElementId::Friction(FrictionId(i))));
        let mut out: Vec<Address> = Vec::new();
        for e in elements {
            if let ElementId::Param(p) = e {
                out.push(Address::param(p));
                continue;
            }
            for (_, r) in element_fields(model, e) {
                if let Ok(a) = r {
                    let a = a.canonical(model);
                    if !out.contains(&a) {
                        out.push(a);
                    }
                }
            }
        }
        out
    }
}
