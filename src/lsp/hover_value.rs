//! Hover on a value: the number as written with its unit, and its value in
//! internal units (mm, N, rad); and the fields a parameter is bound to.

use super::document::Document;
use super::hover::num;
use crate::model::ParamId;
use crate::span::Span;
use crate::syntax::ast::*;

/// The innermost number with a unit (or in a vector with a unit) at `offset`.
pub fn value(doc: &Document, ast: &File, offset: usize) -> Option<(Span, String)> {
    let mut best: Option<(Span, String)> = None;
    let mut visit = |num: &Num, unit: Option<&UnitLit>| {
        let inside = num.span.start as usize <= offset
            && offset <= unit.map_or(num.span.end, |u| u.span.end.max(num.span.end)) as usize;
        if inside {
            let span = unit.map_or(num.span, |u| num.span.to(u.span));
            best = Some((span, describe(num, unit)));
        }
    };
    for item in &ast.items {
        if !(item.span.start as usize <= offset && offset <= item.span.end as usize) {
            continue;
        }
        each_number(item, &mut visit);
    }
    let _ = doc;
    best
}

fn describe(n: &Num, unit: Option<&UnitLit>) -> String {
    let Some(u) = unit else {
        return format!("`{}`: a plain number", n.text);
    };
    match crate::units::parse_unit(&u.text) {
        Ok(unit) => {
            let internal = n.value * unit.factor;
            let iu = unit.dim.boundary_unit().replace("deg", "rad");
            format!(
                "`{} {}`: {}\n\ninternal: {} {iu}",
                n.text,
                u.text,
                unit.dim.describe(),
                num(internal)
            )
        }
        Err(piece) => format!("`{}`: unknown unit `{piece}`", u.text),
    }
}

/// Calls `f` on every number of an item with the unit that applies to it.
fn each_number(item: &Item, f: &mut impl FnMut(&Num, Option<&UnitLit>)) {
    match &item.kind {
        ItemKind::Param(p) => {
            expr(&p.value, None, f);
            if let Some(Unknown {
                bounds: Some((lo, hi)),
                ..
            }) = &p.unknown
            {
                for b in [lo, hi].into_iter().flatten() {
                    expr(b, None, f);
                }
            }
        }
        ItemKind::Part(p) => {
            for pi in &p.items {
                match pi {
                    PartItem::Marker(m) => {
                        vector(&m.at, f);
                        match &m.orient {
                            Some(Orient::Euler(v)) => vector(v, f),
                            Some(Orient::Directions { z, x }) => {
                                vector(z, f);
                                if let Some(x) = x {
                                    vector(x, f);
                                }
                            }
                            None => {}
                        }
                    }
                    PartItem::Landmark(l) => vector(&l.at, f),
                }
            }
        }
        ItemKind::Element(e) => {
            for p in &e.props {
                match &p.value {
                    Value::Vector(v) => vector(v, f),
                    Value::List(es, _) => es.iter().for_each(|e| expr(e, None, f)),
                    Value::Expr(e) => expr(e, None, f),
                    Value::Table(t) => {
                        for (x, y) in &t.points {
                            f(x, Some(&t.x_unit));
                            f(y, Some(&t.y_unit));
                        }
                    }
                    Value::Ref(_) => {}
                }
            }
        }
        ItemKind::Loads(l) => match &l.body {
            LoadsBody::Table { columns, rows } => {
                for r in rows {
                    for (v, c) in r.values.iter().zip(columns) {
                        f(v, Some(&c.unit));
                    }
                }
            }
            LoadsBody::Sweep { lines } => {
                for line in lines {
                    line.waypoints
                        .iter()
                        .chain(&line.step)
                        .for_each(|e| expr(e, None, f));
                }
            }
        },
        ItemKind::Template(t) => {
            for p in &t.params {
                if let Some(d) = &p.default {
                    expr(d, None, f);
                }
            }
            for i in &t.items {
                each_number(i, f);
            }
        }
        ItemKind::Instance(i) => i.args.iter().for_each(|a| expr(&a.value, None, f)),
        ItemKind::Model(_) | ItemKind::Import(_) | ItemKind::DefaultLoads(_) => {}
    }
}

fn vector(v: &Vector, f: &mut impl FnMut(&Num, Option<&UnitLit>)) {
    for c in &v.comps {
        expr(c, v.unit.as_ref(), f);
    }
}

/// `outer`: the unit of the enclosing vector, for its bare numbers.
fn expr(e: &Expr, outer: Option<&UnitLit>, f: &mut impl FnMut(&Num, Option<&UnitLit>)) {
    match &e.kind {
        ExprKind::Quantity { num, unit } => f(num, unit.as_ref().or(outer)),
        ExprKind::Param(_) => {}
        ExprKind::Neg(x) | ExprKind::Paren(x) => expr(x, outer, f),
        ExprKind::Binary(_, a, b) => {
            expr(a, outer, f);
            expr(b, outer, f);
        }
        ExprKind::Pow(x, _) => expr(x, outer, f),
        ExprKind::Call(_, args) => args.iter().for_each(|a| expr(a, outer, f)),
    }
}

/// `element.property` (or `param NAME`) for every use of the parameter.
pub fn fields_using(doc: &Document, k: ParamId) -> Vec<String> {
    let Some(a) = doc.analysis.as_ref() else {
        return Vec::new();
    };
    let sym = crate::check::Symbol::Element(crate::model::ElementId::Param(k));
    let mut out = Vec::new();
    for span in a.resolution.references(sym) {
        let within = |s: Span| s.start <= span.start && span.end <= s.end;
        let Some(item) = a.ast.items.iter().find(|i| within(i.span)) else {
            continue;
        };
        let field = match &item.kind {
            ItemKind::Element(e) => e
                .props
                .iter()
                .find(|p| within(p.span))
                .map(|p| format!("{}.{}", e.name.name, p.key.name)),
            ItemKind::Param(p) => Some(format!("param {}", p.name.name)),
            ItemKind::Part(p) => Some(format!("part {}", p.name.name)),
            ItemKind::Loads(l) => Some(format!("loads {}", l.name.name)),
            _ => None,
        };
        if let Some(f) = field
            && !out.contains(&f)
        {
            out.push(f);
        }
    }
    out
}
