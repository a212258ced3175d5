//! Generalised forces as functions of the unknowns at a fixed configuration.
//!
//! A bushing's generalised force is linear in its stiffnesses, a spring's in
//! its k (at fixed free length) and in its free length (at fixed k); so at a
//! measured pose `Q(u) = Q(0) + Σ u_i c_i` exactly, and `c_i` is found by
//! evaluating the one element with the unknown at 1 and at 0. These columns
//! are the generalised deformations D of the direct method (thesis eq. 4.37–4.42)
//! and the exact `∂Q/∂u` of the least-squares sensitivities.

use super::{IdentifyError, Unknown};
use crate::model::schema::FieldId;
use crate::model::{BushingId, ElementId, Model, Orientation, SpringId};
use crate::statics::StaticsError;
use crate::statics::coords::{Layout, State};
use crate::statics::forces;
use nalgebra::DVector;

fn statics_error(e: StaticsError, model: &Model) -> IdentifyError {
    IdentifyError::statics("", e, model)
}

/// The generalised force of one force element at `state` (n entries).
pub fn element_force(
    model: &Model,
    layout: &Layout,
    state: &State,
    e: ElementId,
) -> Result<DVector<f64>, IdentifyError> {
    let mut q = DVector::zeros(layout.n());
    match e {
        ElementId::Bushing(BushingId(b)) => {
            forces::bushing(model, layout, state, &model.bushings[b as usize])
                .wrench
                .add_force(&mut q);
        }
        ElementId::Spring(id @ SpringId(s)) => {
            forces::spring(model, layout, state, id, &model.springs[s as usize])
                .map_err(|e| statics_error(e, model))?
                .2
                .add_force(&mut q);
        }
        _ => {
            for (_, w) in forces::element_wrenches(model, layout, state)
                .map_err(|e| statics_error(e, model))?
            {
                w.add_force(&mut q);
            }
        }
    }
    Ok(q)
}

/// The generalised force of every force element and of the loads.
pub fn total_force(
    model: &Model,
    layout: &Layout,
    state: &State,
    loads: &[crate::model::PointLoad],
) -> Result<DVector<f64>, IdentifyError> {
    let mut q = DVector::zeros(layout.n());
    for (_, w) in
        forces::element_wrenches(model, layout, state).map_err(|e| statics_error(e, model))?
    {
        w.add_force(&mut q);
    }
    for l in loads {
        if let Some(w) = forces::point_load(model, layout, state, l) {
            w.add_force(&mut q);
        }
    }
    Ok(q)
}

/// The element whose force an unknown changes (`Param`: all of them).
pub fn element_of(u: &Unknown) -> ElementId {
    match u.addrs[0].element {
        ElementId::Param(_) => ElementId::Param(crate::model::ParamId(0)),
        e => e,
    }
}

/// Whether the generalised forces are affine in the unknown at a fixed
/// configuration (so [`column`] is exact and no constraint moves with it).
pub fn is_affine(model: &Model, u: &Unknown) -> bool {
    u.addrs.iter().all(|a| match (a.element, a.field) {
        // Forces are affine in stiffnesses, cubic terms, offsets, preloads and
        // polynomial coefficients at a fixed pose; a point, a contact length or
        // a friction element (path-dependent) is not.
        (ElementId::Param(p), _) => {
            // Geometry bound to the parameter moves markers; a spring with both
            // k and free length bound to it is bilinear.
            let geometric = model.markers.iter().any(|m| {
                m.position.iter().any(|v| v.param == Some(p))
                    || matches!(&m.orientation, Orientation::Euler(e) if e.iter().any(|v| v.param == Some(p)))
            }) || model
                .stops
                .iter()
                .any(|s| s.contact_length.param == Some(p));
            let bilinear = model.springs.iter().any(|s| match &s.law {
                crate::model::SpringLaw::Linear { k, free_length, .. } => {
                    k.param == Some(p) && free_length.param == Some(p)
                }
                crate::model::SpringLaw::Table(_) => false,
            });
            !geometric && !bilinear
        }
        (_, field) => matches!(
            field,
            FieldId::K
                | FieldId::Kt
                | FieldId::K3
                | FieldId::Kt3
                | FieldId::Offset
                | FieldId::AngleOffset
                | FieldId::Preload
                | FieldId::TorquePreload
                | FieldId::SpringK
                | FieldId::FreeLength
                | FieldId::SpringPreload
                | FieldId::Coefficient(_)
        ),
    })
}

/// `∂Q/∂u` at `state` for an affine unknown, evaluated on `work` (restored to
/// `current` afterwards).
pub fn column(
    work: &mut Model,
    layout: &Layout,
    state: &State,
    u: &Unknown,
    current: f64,
) -> Result<DVector<f64>, IdentifyError> {
    let e = element_of(u);
    u.set(work, 1.0);
    let one = element_force(work, layout, state, e);
    u.set(work, 0.0);
    let zero = element_force(work, layout, state, e);
    u.set(work, current);
    Ok(one? - zero?)
}
