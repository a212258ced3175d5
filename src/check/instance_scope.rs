//! The names of one template instance and the rewriting of a template's
//! syntax into them (what [`super::expand`] does to every item of an
//! instance's body): parameters replaced by the instance's arguments, local
//! names qualified by the instance, references to parts outside it pointed
//! at the parts they extend.

use crate::syntax::ast::*;
use std::collections::BTreeMap;

/// The names of one instance: template parameters → their values, local
/// names → expanded names.
#[derive(Default, Clone)]
pub(super) struct Scope {
    pub args: BTreeMap<String, Expr>,
    /// Params, elements and nested instances.
    pub names: BTreeMap<String, String>,
    pub parts: BTreeMap<String, String>,
    /// Parts outside the instance it adds markers to, by the name the body
    /// uses: the template's `ground` block (the model's ground) and every
    /// part parameter (`rack = chassis`): local name → (the part's name in
    /// the expanded model, the markers it adds → their expanded names).
    pub extends: BTreeMap<String, (String, BTreeMap<String, String>)>,
}

/// A marker or landmark of an instance's body, named `prefix.name` and
/// its values in the instance's names.
pub(super) fn rewrite_part_item(pi: &PartItem, scope: &Scope, prefix: &str) -> PartItem {
    let name = |n: &Ident| Ident {
        name: if prefix.is_empty() {
            n.name.clone()
        } else {
            format!("{prefix}.{}", n.name)
        },
        span: n.span,
    };
    match pi {
        PartItem::Marker(m) => PartItem::Marker(MarkerDecl {
            name: name(&m.name),
            at: rewrite_vector(&m.at, scope),
            orient: m.orient.as_ref().map(|o| match o {
                Orient::Euler(v) => Orient::Euler(rewrite_vector(v, scope)),
                Orient::Directions { z, x } => Orient::Directions {
                    z: rewrite_vector(z, scope),
                    x: x.as_ref().map(|x| rewrite_vector(x, scope)),
                },
            }),
            span: m.span,
        }),
        PartItem::Landmark(l) => PartItem::Landmark(LandmarkDecl {
            name: name(&l.name),
            at: rewrite_vector(&l.at, scope),
            span: l.span,
        }),
    }
}

fn rewrite_vector(v: &Vector, scope: &Scope) -> Vector {
    Vector {
        comps: [
            rewrite_expr(&v.comps[0], scope),
            rewrite_expr(&v.comps[1], scope),
            rewrite_expr(&v.comps[2], scope),
        ],
        unit: v.unit.clone(),
        span: v.span,
    }
}

/// A property value in the instance's names: marker references to its
/// parts (or the parts it extends), expressions with its arguments.
pub(super) fn rewrite_value(v: &Value, scope: &Scope) -> Value {
    match v {
        Value::Ref(r) => {
            let (part, marker) = if let Some(p) = scope.parts.get(&r.part.name) {
                (p.clone(), r.marker.name.clone())
            } else if let Some((target, ms)) = scope.extends.get(&r.part.name) {
                let m = ms.get(&r.marker.name).unwrap_or(&r.marker.name);
                (target.clone(), m.clone())
            } else {
                (r.part.name.clone(), r.marker.name.clone())
            };
            Value::Ref(MarkerRef {
                part: Ident {
                    name: part,
                    span: r.part.span,
                },
                marker: Ident {
                    name: marker,
                    span: r.marker.span,
                },
                span: r.span,
            })
        }
        Value::Vector(x) => Value::Vector(rewrite_vector(x, scope)),
        Value::List(es, s) => Value::List(es.iter().map(|e| rewrite_expr(e, scope)).collect(), *s),
        Value::Table(t) => Value::Table(t.clone()),
        Value::Expr(e) => Value::Expr(rewrite_expr(e, scope)),
    }
}

/// An expression with the instance's arguments substituted and its
/// parameters renamed.
pub(super) fn rewrite_expr(e: &Expr, scope: &Scope) -> Expr {
    let b = |x: &Expr| Box::new(rewrite_expr(x, scope));
    let kind = match &e.kind {
        ExprKind::Param(id) => {
            if let Some(v) = scope.args.get(&id.name) {
                return v.clone();
            }
            ExprKind::Param(Ident {
                name: scope
                    .names
                    .get(&id.name)
                    .cloned()
                    .unwrap_or_else(|| id.name.clone()),
                span: id.span,
            })
        }
        ExprKind::Quantity { .. } => e.kind.clone(),
        ExprKind::Neg(a) => ExprKind::Neg(b(a)),
        ExprKind::Binary(op, l, r) => ExprKind::Binary(*op, b(l), b(r)),
        ExprKind::Pow(a, n) => ExprKind::Pow(b(a), n.clone()),
        ExprKind::Call(f, args) => ExprKind::Call(
            f.clone(),
            args.iter().map(|a| rewrite_expr(a, scope)).collect(),
        ),
        ExprKind::Paren(a) => ExprKind::Paren(b(a)),
    };
    Expr { kind, span: e.span }
}
