//! Canonical text of expressions and values.

use crate::syntax::ast::*;

pub fn expr(e: &Expr) -> String {
    match &e.kind {
        ExprKind::Quantity { num, unit } => match unit {
            Some(u) => format!("{} {}", num.text, u.text),
            None => num.text.clone(),
        },
        ExprKind::Param(name) => name.name.clone(),
        ExprKind::Neg(a) => format!("-{}", expr(a)),
        ExprKind::Binary(op, a, b) => format!("{} {} {}", expr(a), op.symbol(), expr(b)),
        ExprKind::Pow(a, n) => format!("{}^{}", expr(a), n.text),
        ExprKind::Call(f, args) => format!(
            "{}({})",
            f.name,
            args.iter().map(expr).collect::<Vec<_>>().join(", ")
        ),
        ExprKind::Paren(a) => format!("({})", expr(a)),
    }
}

pub fn vector(v: &Vector) -> String {
    let body = v.comps.iter().map(expr).collect::<Vec<_>>().join(", ");
    match &v.unit {
        Some(u) => format!("({body}) {}", u.text),
        None => format!("({body})"),
    }
}

/// Tables longer than this go one point per line.
const LINE_WIDTH: usize = 100;

pub fn value(v: &Value, indent: &str) -> String {
    match v {
        Value::Ref(r) => format!("{}.{}", r.part.name, r.marker.name),
        Value::Vector(v) => vector(v),
        Value::Expr(e) => expr(e),
        Value::List(items, _) => format!(
            "[{}]",
            items.iter().map(expr).collect::<Vec<_>>().join(", ")
        ),
        Value::Table(t) => {
            let head = format!("table ({}, {})", t.x_unit.text, t.y_unit.text);
            let pts: Vec<String> = t
                .points
                .iter()
                .map(|(a, b)| format!("({}, {})", a.text, b.text))
                .collect();
            let one = format!("{head} [{}]", pts.join(", "));
            if one.len() + indent.len() <= LINE_WIDTH {
                one
            } else {
                let inner = format!("{indent}    ");
                let lines: Vec<String> = pts.iter().map(|p| format!("{inner}{p},")).collect();
                format!("{head} [\n{}\n{indent}]", lines.join("\n"))
            }
        }
    }
}

pub fn marker(m: &MarkerDecl) -> String {
    let mut s = format!("marker {} at {}", m.name.name, vector(&m.at));
    match &m.orient {
        None => {}
        Some(Orient::Euler(v)) => s += &format!(" euler {}", vector(v)),
        Some(Orient::Directions { z, x }) => {
            s += &format!(" z {}", vector(z));
            if let Some(x) = x {
                s += &format!(" x {}", vector(x));
            }
        }
    }
    s
}

pub fn param(p: &ParamDecl) -> String {
    let mut s = format!("param {} = {}", p.name.name, expr(&p.value));
    if let Some(u) = &p.unknown {
        s += " unknown";
        if let Some((lo, hi)) = &u.bounds {
            let b = |e: &Option<Expr>| e.as_ref().map_or("_".to_string(), expr);
            s += &format!(" [{}, {}]", b(lo), b(hi));
        }
    }
    s
}

pub fn sweep_line(l: &SweepLine) -> String {
    let pts: Vec<String> = l.waypoints.iter().map(expr).collect();
    let mut s = format!("{} {}", l.channel.text(), pts.join(" -> "));
    if let Some(step) = &l.step {
        s += &format!(" by {}", expr(step));
    }
    s
}

/// Rows of a load table with the case names left-aligned and every value
/// column right-aligned.
pub fn table_rows(rows: &[Row], ncols: usize) -> Vec<String> {
    let name_w = rows.iter().map(|r| r.name.name.len()).max().unwrap_or(0);
    let mut widths = vec![0; ncols];
    for r in rows {
        for (c, v) in r.values.iter().enumerate() {
            if c < ncols {
                widths[c] = widths[c].max(v.text.len());
            } else {
                widths.push(v.text.len());
            }
        }
    }
    rows.iter()
        .map(|r| {
            let mut s = format!("{:<name_w$}", r.name.name);
            for (c, v) in r.values.iter().enumerate() {
                let w = widths.get(c).copied().unwrap_or(0);
                s += &format!("  {:>w$}", v.text);
            }
            s.trim_end().to_string()
        })
        .collect()
}

/// `p1, p2 = 30 N/mm`: a template's parameter list without its brackets.
pub fn template_params(t: &TemplateDecl) -> String {
    t.params
        .iter()
        .map(|p| match &p.default {
            Some(d) => format!("{} = {}", p.name.name, expr(d)),
            None => p.name.name.clone(),
        })
        .collect::<Vec<_>>()
        .join(", ")
}

/// `instance front_right = mirror corner(k = 30 N/mm)`.
pub fn instance(i: &InstanceDecl) -> String {
    let args: Vec<String> = i
        .args
        .iter()
        .map(|a| format!("{} = {}", a.name.name, expr(&a.value)))
        .collect();
    let mirror = if i.mirror { "mirror " } else { "" };
    format!(
        "instance {} = {mirror}{}({})",
        i.name.name,
        i.template.name,
        args.join(", ")
    )
}
