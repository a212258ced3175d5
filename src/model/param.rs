//! First-class parameters and the values that may refer to them.

use super::id::ParamId;
use crate::units::Dim;

/// A named parameter, `param k_front = 310 N/mm unknown [100 N/mm, 1000 N/mm]`.
#[derive(Debug, Clone, PartialEq)]
pub struct Param {
    pub name: String,
    /// Value in internal units.
    pub value: f64,
    pub dim: Dim,
    /// Present when identification or diagnosis may change the parameter.
    pub unknown: Option<Bounds>,
}

/// Bounds of an unknown parameter, internal units; either side may be open.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Bounds {
    pub lower: Option<f64>,
    pub upper: Option<f64>,
}

/// A numeric field of an element: its value in internal units, and the parameter
/// it was written as, if any. When a parameter changes, [`super::Model::set_param`]
/// updates every field bound to it, so backends only read `value`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Val {
    pub value: f64,
    pub param: Option<ParamId>,
}

impl Val {
    pub const ZERO: Val = Val {
        value: 0.0,
        param: None,
    };

    pub fn lit(value: f64) -> Val {
        Val { value, param: None }
    }
}

impl From<f64> for Val {
    fn from(v: f64) -> Val {
        Val::lit(v)
    }
}

/// Three fields along the x, y, z axes of a frame.
pub type Val3 = [Val; 3];

pub fn vals(v: [f64; 3]) -> Val3 {
    [Val::lit(v[0]), Val::lit(v[1]), Val::lit(v[2])]
}

pub fn values(v: &Val3) -> nalgebra::Vector3<f64> {
    nalgebra::Vector3::new(v[0].value, v[1].value, v[2].value)
}
