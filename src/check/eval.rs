//! Expressions with units → values in internal units, with dimension checks.

use super::Checker;
use super::error;
use crate::diagnostic::Diagnostic;
use crate::model::{ParamId, Val, Written};
use crate::syntax::ast::{BinOp, Expr, ExprKind, UnitLit, Vector};
use crate::units::{Dim, Unit, parse_unit};

/// A value in internal units with its dimension.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Q {
    pub value: f64,
    pub dim: Dim,
}

impl Checker {
    pub(super) fn unit(&mut self, u: &UnitLit) -> Option<Unit> {
        match parse_unit(&u.text) {
            Ok(unit) => Some(unit),
            Err(piece) => {
                self.problems
                    .push(error::unknown_unit(&u.text, &piece, u.span));
                None
            }
        }
    }

    /// Evaluates an expression; `None` after reporting a problem.
    pub(super) fn eval(&mut self, e: &Expr) -> Option<Q> {
        match &e.kind {
            ExprKind::Quantity { num, unit } => {
                let u = match unit {
                    Some(u) => self.unit(u)?,
                    None => Unit::ONE,
                };
                Some(Q {
                    value: num.value * u.factor,
                    dim: u.dim,
                })
            }
            ExprKind::Param(name) => {
                let id = self.param_id(name)?;
                let p = &self.model.params[id.index()];
                Some(Q {
                    value: p.value,
                    dim: p.dim,
                })
            }
            ExprKind::Paren(inner) => self.eval(inner),
            ExprKind::Neg(inner) => self.eval(inner).map(|q| Q {
                value: -q.value,
                ..q
            }),
            ExprKind::Pow(base, exp) => {
                let b = self.eval(base)?;
                let n = exp.value;
                if n.fract() != 0.0 || n.abs() > 9.0 {
                    self.problems.push(error::bad_number(
                        "an exponent",
                        exp.span,
                        "must be a whole number between -9 and 9",
                    ));
                    return None;
                }
                Some(Q {
                    value: b.value.powi(n as i32),
                    dim: b.dim.powi(n as i8),
                })
            }
            ExprKind::Binary(op, a, b) => {
                let (x, y) = (self.eval(a), self.eval(b));
                let (x, y) = (x?, y?);
                match op {
                    BinOp::Add | BinOp::Sub => {
                        if x.dim != y.dim {
                            self.problems.push(
                                Diagnostic::error(
                                    "E0209",
                                    format!(
                                        "cannot {} {} and {}",
                                        if *op == BinOp::Add { "add" } else { "subtract" },
                                        x.dim.describe(),
                                        y.dim.describe()
                                    ),
                                )
                                .primary(b.span, format!("this is {}", y.dim.describe()))
                                .secondary(a.span, format!("this is {}", x.dim.describe())),
                            );
                            return None;
                        }
                        let v = if *op == BinOp::Add {
                            x.value + y.value
                        } else {
                            x.value - y.value
                        };
                        Some(Q {
                            value: v,
                            dim: x.dim,
                        })
                    }
                    BinOp::Mul => Some(Q {
                        value: x.value * y.value,
                        dim: x.dim.mul(y.dim),
                    }),
                    BinOp::Div => {
                        if y.value == 0.0 {
                            self.problems
                                .push(error::bad_number("a divisor", b.span, "is zero"));
                            return None;
                        }
                        Some(Q {
                            value: x.value / y.value,
                            dim: x.dim.div(y.dim),
                        })
                    }
                }
            }
            ExprKind::Call(f, args) => self.call(f, args, e),
        }
    }

    fn call(&mut self, f: &crate::syntax::ast::Ident, args: &[Expr], e: &Expr) -> Option<Q> {
        const FUNCS: [(&str, usize); 6] = [
            ("sqrt", 1),
            ("abs", 1),
            ("sin", 1),
            ("cos", 1),
            ("tan", 1),
            ("atan2", 2),
        ];
        let Some(&(_, arity)) = FUNCS.iter().find(|(n, _)| *n == f.name) else {
            self.problems.push(error::unknown_name(
                "function",
                &f.name,
                f.span,
                FUNCS.iter().map(|(n, _)| *n),
            ));
            return None;
        };
        if args.len() != arity {
            self.problems.push(
                Diagnostic::error(
                    "E0210",
                    format!(
                        "`{}` takes {arity} argument(s), found {}",
                        f.name,
                        args.len()
                    ),
                )
                .primary(e.span, "wrong number of arguments"),
            );
            return None;
        }
        let vals: Vec<Option<Q>> = args.iter().map(|a| self.eval(a)).collect();
        let vals: Vec<Q> = vals.into_iter().collect::<Option<_>>()?;
        let x = vals[0];
        let angle_arg = |c: &mut Self, q: Q| -> Option<f64> {
            if q.dim == Dim::ANGLE || q.dim == Dim::NONE {
                Some(q.value)
            } else {
                c.problems.push(error::wrong_dimension(
                    Dim::ANGLE,
                    q.dim,
                    args[0].span,
                    "30 deg",
                ));
                None
            }
        };
        match f.name.as_str() {
            "sqrt" => {
                let d = x.dim;
                let even = [d.length, d.force, d.angle, d.mass, d.time]
                    .iter()
                    .all(|e| e % 2 == 0);
                if !even || x.value < 0.0 {
                    let why = if even {
                        "is negative"
                    } else {
                        "has a dimension with an odd power"
                    };
                    self.problems.push(error::bad_number(
                        "the argument of `sqrt`",
                        args[0].span,
                        why,
                    ));
                    return None;
                }
                let half = Dim {
                    length: d.length / 2,
                    force: d.force / 2,
                    angle: d.angle / 2,
                    mass: d.mass / 2,
                    time: d.time / 2,
                };
                Some(Q {
                    value: x.value.sqrt(),
                    dim: half,
                })
            }
            "abs" => Some(Q {
                value: x.value.abs(),
                dim: x.dim,
            }),
            "sin" | "cos" | "tan" => {
                let a = angle_arg(self, x)?;
                let v = match f.name.as_str() {
                    "sin" => a.sin(),
                    "cos" => a.cos(),
                    _ => a.tan(),
                };
                Some(Q {
                    value: v,
                    dim: Dim::NONE,
                })
            }
            _ => {
                let y = vals[1];
                if x.dim != y.dim {
                    self.problems.push(error::wrong_dimension(
                        x.dim,
                        y.dim,
                        args[1].span,
                        "atan2(1 mm, 2 mm)",
                    ));
                    return None;
                }
                Some(Q {
                    value: x.value.atan2(y.value),
                    dim: Dim::ANGLE,
                })
            }
        }
    }

    /// Whether an expression contains a unit or a parameter anywhere (then a
    /// vector's trailing unit does not apply to it).
    fn has_units(e: &Expr) -> bool {
        match &e.kind {
            ExprKind::Quantity { unit, .. } => unit.is_some(),
            ExprKind::Param(_) => true,
            ExprKind::Paren(a) | ExprKind::Neg(a) | ExprKind::Pow(a, _) => Self::has_units(a),
            ExprKind::Binary(_, a, b) => Self::has_units(a) || Self::has_units(b),
            ExprKind::Call(_, args) => args.iter().any(Self::has_units),
        }
    }

    /// A scalar of the expected dimension as a [`Val`], bound to a parameter when
    /// the expression is just that parameter's name.
    pub(super) fn scalar(&mut self, e: &Expr, expected: Dim, example: &str) -> Option<Val> {
        self.scalar_with_default(e, None, expected, example)
    }

    fn scalar_with_default(
        &mut self,
        e: &Expr,
        default: Option<Unit>,
        expected: Dim,
        example: &str,
    ) -> Option<Val> {
        let mut q = self.eval(e)?;
        let mut trailing = 1.0;
        if let Some(u) = default {
            if !Self::has_units(e) {
                trailing = u.factor;
                q = Q {
                    value: q.value * u.factor,
                    dim: u.dim,
                };
            }
        }
        if q.dim != expected {
            self.problems
                .push(error::wrong_dimension(expected, q.dim, e.span, example));
            return None;
        }
        if !q.value.is_finite() {
            self.problems
                .push(error::bad_number("this value", e.span, "is not finite"));
            return None;
        }
        if let Some(d) = error::beyond_any_suspension(q.value, q.dim, e.span) {
            self.problems.push(d);
            return None;
        }
        let param = match &e.kind {
            ExprKind::Param(name) => self.param_lookup(&name.name),
            _ => None,
        };
        Some(Val {
            value: q.value,
            param,
            written: Some(Self::written(e, trailing, expected)),
        })
    }

    /// Where a field was written: a plain number (`-5.2 mm`, or `310` under a
    /// vector's trailing unit) can be rewritten in its own unit; anything else
    /// is replaced whole by a tool that changes it.
    fn written(e: &Expr, trailing: f64, dim: Dim) -> Written {
        match plain_number(e, trailing) {
            Some((span, factor)) => Written {
                span,
                factor: Some(factor),
                dim,
            },
            None => Written {
                span: e.span,
                factor: None,
                dim,
            },
        }
    }

    /// A three-component vector of the expected dimension.
    pub(super) fn vector(&mut self, v: &Vector, expected: Dim, example: &str) -> Option<[Val; 3]> {
        let default = match &v.unit {
            Some(u) => Some(self.unit(u)?),
            None => None,
        };
        // A missing or wrong trailing unit is one mistake, not three.
        if v.unit.is_none() && expected != Dim::NONE && v.comps.iter().all(|c| !Self::has_units(c))
        {
            self.problems
                .push(error::wrong_dimension(expected, Dim::NONE, v.span, example));
            return None;
        }
        // (trailing unit) trailing unit is one mistake, not three.
        if let (Some(u), Some(lit)) = (default, &v.unit) {
            if u.dim != expected && v.comps.iter().all(|c| !Self::has_units(c)) {
                self.problems
                    .push(error::wrong_dimension(expected, u.dim, lit.span, example));
                return None;
            }
        }
        let comps: Vec<Option<Val>> = v
            .comps
            .iter()
            .map(|c| self.scalar_with_default(c, default, expected, example))
            .collect();
        let comps: Vec<Val> = comps.into_iter().collect::<Option<_>>()?;
        Some([comps[0], comps[1], comps[2]])
    }

    pub(super) fn param_lookup(&self, name: &str) -> Option<ParamId> {
        self.model.param_named(name)
    }
}

/// A plain number with an optional sign and unit (`310`, `-5.2 mm`): the span
/// of the signed number (without its unit) and the internal units per unit of
/// that number (its own unit's, else `trailing`, the factor of the vector's
/// trailing unit or 1). `None` for anything else (a name, an expression).
pub(crate) fn plain_number(e: &Expr, trailing: f64) -> Option<(crate::span::Span, f64)> {
    let (neg, inner) = match &e.kind {
        ExprKind::Neg(inner) => (true, inner.as_ref()),
        _ => (false, e),
    };
    let ExprKind::Quantity { num, unit } = &inner.kind else {
        return None;
    };
    let factor = match unit {
        Some(u) => parse_unit(&u.text).ok()?.factor,
        None => trailing,
    };
    let start = if neg { e.span.start } else { num.span.start };
    Some((crate::span::Span { start, ..num.span }, factor))
}
