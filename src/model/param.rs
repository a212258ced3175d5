//! First-class parameters and the values that may refer to them.

use super::id::ParamId;
use crate::span::Span;
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
///
/// `written` says where the checker read it, so that a tool changing the value
/// can rewrite it in place in the user's file (`fmt::edit`). Two values are
/// equal when their value and parameter are: where they were written is not
/// part of what they mean.
#[derive(Debug, Clone, Copy)]
pub struct Val {
    pub value: f64,
    pub param: Option<ParamId>,
    pub written: Option<Written>,
}

impl PartialEq for Val {
    fn eq(&self, other: &Val) -> bool {
        self.value == other.value && self.param == other.param
    }
}

/// Where and how a field was written in its source file.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Written {
    /// A plain number (`310`, `-5.2`: the number and its sign, without the
    /// unit after it): the span of that number. Otherwise (a parameter's name,
    /// an expression) the span of the whole expression.
    pub span: Span,
    /// Internal units per unit of the written number, when it is a plain number
    /// (its own unit, or the trailing unit of its vector). `None` for expressions.
    pub factor: Option<f64>,
    /// The dimension of the field, to write a replacing quantity with a unit.
    pub dim: Dim,
}

impl Val {
    pub const ZERO: Val = Val {
        value: 0.0,
        param: None,
        written: None,
    };

    pub fn lit(value: f64) -> Val {
        Val {
            value,
            param: None,
            written: None,
        }
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
