//! The numeric fields of each element, walked in one fixed order, and its
//! shape (everything but those numbers), so that an edit can tell "only values
//! changed" (rewritten in place) from "the element changed" (printed again).

use crate::model::*;

/// A walk over the numeric fields of one element kind, in a fixed order.
pub type Walk<T> = fn(&mut T, &mut dyn FnMut(&mut Val));

/// Visits every numeric field of a marker (position, then Euler angles).
pub fn marker_vals(m: &mut Marker, f: &mut dyn FnMut(&mut Val)) {
    m.position.iter_mut().for_each(&mut *f);
    if let Orientation::Euler(a) = &mut m.orientation {
        a.iter_mut().for_each(f);
    }
}

fn law_vals(l: &mut AxisLaw, f: &mut dyn FnMut(&mut Val)) {
    if let AxisLaw::Linear { k, k3 } = l {
        f(k);
        f(k3);
    }
}

pub fn bushing_vals(b: &mut Bushing, f: &mut dyn FnMut(&mut Val)) {
    // An axisymmetric radial law is one stored law: visited once.
    for l in b
        .translational
        .stored_mut()
        .into_iter()
        .chain(b.rotational.stored_mut())
    {
        law_vals(l, f);
    }
    for v in b
        .offset
        .iter_mut()
        .chain(b.angle_offset.iter_mut())
        .chain(b.preload.iter_mut())
        .chain(b.torque_preload.iter_mut())
    {
        f(v);
    }
}

pub fn spring_vals(s: &mut Spring, f: &mut dyn FnMut(&mut Val)) {
    if let SpringLaw::Linear {
        k,
        free_length,
        preload,
    } = &mut s.law
    {
        f(k);
        f(free_length);
        f(preload);
    }
}

pub fn stop_vals(s: &mut Stop, f: &mut dyn FnMut(&mut Val)) {
    f(&mut s.contact_length);
    if let StopLaw::Polynomial(c) = &mut s.law {
        c.iter_mut().for_each(f);
    }
}

pub fn friction_vals(fr: &mut Friction, f: &mut dyn FnMut(&mut Val)) {
    f(&mut fr.stiffness);
    f(&mut fr.limit);
}

/// The fields of an element, in visiting order.
pub fn collect<T: Clone>(x: &T, walk: Walk<T>) -> Vec<Val> {
    let mut copy = x.clone();
    let mut out = Vec::new();
    walk(&mut copy, &mut |v| out.push(*v));
    out
}

/// Whether two elements differ in more than their numeric fields (kind, law,
/// markers, tables, orientation form): such an element is printed again.
pub fn same_shape<T: Clone + PartialEq>(a: &T, b: &T, walk: Walk<T>) -> bool {
    let blank = |x: &T| {
        let mut c = x.clone();
        walk(&mut c, &mut |v| *v = Val::ZERO);
        c
    };
    blank(a) == blank(b)
}

/// Markers compare without their derived rotation when it follows from the
/// Euler angles (those are fields); a frame given by directions is shape.
pub fn same_marker_shape(a: &Marker, b: &Marker) -> bool {
    let norm = |m: &Marker| {
        let mut c = m.clone();
        if matches!(c.orientation, Orientation::Euler(_)) {
            c.rotation = crate::geom::Mat3::identity();
        }
        c
    };
    same_shape(&norm(a), &norm(b), marker_vals)
}
