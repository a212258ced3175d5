//! pest pairs → syntax tree. The grammar (`grammar/axle.pest`) guarantees the
//! shape of every pair, so a mismatch here is a bug in this file, not user error.

use super::ast::*;
use crate::span::{FileId, Span};
use pest::iterators::{Pair, Pairs};

#[derive(pest_derive::Parser)]
#[grammar = "../grammar/axle.pest"]
pub struct AxleParser;

pub(crate) struct Builder {
    pub file: FileId,
}

type P<'a> = Pair<'a, Rule>;

/// The next inner pair; the grammar guarantees it exists.
#[allow(clippy::expect_used)] // the grammar guarantees the child
fn next<'a>(it: &mut Pairs<'a, Rule>) -> P<'a> {
    it.next()
        .expect("invariant: the grammar guarantees this child")
}

impl Builder {
    fn span(&self, p: &P) -> Span {
        let s = p.as_span();
        Span::new(self.file, s.start(), s.end())
    }

    fn ident(&self, p: P) -> Ident {
        Ident {
            name: p.as_str().to_string(),
            span: self.span(&p),
        }
    }

    fn num(&self, p: P) -> Num {
        Num {
            // The grammar only admits valid float syntax, which Rust parses.
            value: p.as_str().parse().unwrap_or(f64::NAN),
            text: p.as_str().to_string(),
            span: self.span(&p),
        }
    }

    fn unit(&self, p: P) -> UnitLit {
        UnitLit {
            text: p.as_str().to_string(),
            span: self.span(&p),
        }
    }

    pub fn file(&self, p: P) -> File {
        let span = self.span(&p);
        let items = p
            .into_inner()
            .filter(|i| i.as_rule() != Rule::EOI)
            .map(|i| self.item(i))
            .collect();
        File { items, span }
    }

    fn item(&self, p: P) -> Item {
        let span = self.span(&p);
        let rule = p.as_rule();
        let mut it = p.into_inner();
        let kind = match rule {
            Rule::model_decl => {
                next(&mut it);
                ItemKind::Model(self.ident(next(&mut it)))
            }
            Rule::import_decl => {
                next(&mut it);
                ItemKind::Import(self.ident(next(&mut it)))
            }
            Rule::default_decl => {
                next(&mut it);
                next(&mut it);
                ItemKind::DefaultLoads(self.ident(next(&mut it)))
            }
            Rule::param_decl => {
                next(&mut it);
                let name = self.ident(next(&mut it));
                let value = self.expr(next(&mut it));
                let unknown = it.next().map(|u| self.unknown(u));
                ItemKind::Param(ParamDecl {
                    name,
                    value,
                    unknown,
                })
            }
            Rule::part_decl => {
                let kw = next(&mut it);
                let keyword_span = self.span(&kw);
                let ground = kw.as_str() == "ground";
                let name = self.ident(next(&mut it));
                let items = it.map(|i| self.part_item(i)).collect();
                ItemKind::Part(PartDecl {
                    ground,
                    keyword_span,
                    name,
                    items,
                })
            }
            Rule::element_decl => ItemKind::Element(self.element(it)),
            Rule::loads_decl => {
                next(&mut it);
                let name = self.ident(next(&mut it));
                let body = self.loads_body(next(&mut it));
                ItemKind::Loads(LoadsDecl { name, body })
            }
            Rule::template_decl => {
                next(&mut it);
                let name = self.ident(next(&mut it));
                let ps = next(&mut it);
                let params_span = self.span(&ps);
                let params = ps
                    .into_inner()
                    .map(|q| {
                        let span = self.span(&q);
                        let mut qi = q.into_inner();
                        let name = self.ident(next(&mut qi));
                        let default = qi.next().map(|e| self.expr(e));
                        TemplateParam {
                            name,
                            default,
                            span,
                        }
                    })
                    .collect();
                let items = it.map(|i| self.item(i)).collect();
                ItemKind::Template(TemplateDecl {
                    name,
                    params,
                    params_span,
                    items,
                })
            }
            Rule::instance_decl => {
                next(&mut it);
                let name = self.ident(next(&mut it));
                let mut t = next(&mut it);
                let mirror = t.as_rule() == Rule::kw_mirror;
                if mirror {
                    t = next(&mut it);
                }
                let template = self.ident(t);
                let a = next(&mut it);
                let args_span = self.span(&a);
                let args = a
                    .into_inner()
                    .map(|q| {
                        let span = self.span(&q);
                        let mut qi = q.into_inner();
                        let name = self.ident(next(&mut qi));
                        let value = self.expr(next(&mut qi));
                        Argument { name, value, span }
                    })
                    .collect();
                ItemKind::Instance(InstanceDecl {
                    name,
                    mirror,
                    template,
                    args,
                    args_span,
                })
            }
            r => unreachable!("invariant: item rule {r:?}"),
        };
        Item { kind, span }
    }

    fn unknown(&self, p: P) -> Unknown {
        let span = self.span(&p);
        let mut it = p.into_inner();
        next(&mut it);
        let bounds = it.next().map(|b| {
            let mut bi = b.into_inner();
            let bound = |q: P| match q.as_rule() {
                Rule::open_bound => None,
                _ => Some(self.expr(q)),
            };
            let lo = bound(next(&mut bi));
            let hi = bound(next(&mut bi));
            (lo, hi)
        });
        Unknown { bounds, span }
    }

    fn part_item(&self, p: P) -> PartItem {
        let span = self.span(&p);
        let rule = p.as_rule();
        let mut it = p.into_inner();
        next(&mut it);
        let name = self.ident(next(&mut it));
        next(&mut it); // `at`
        let at = self.vector(next(&mut it));
        match rule {
            Rule::marker_decl => {
                let orient = it.next().map(|o| {
                    let r = o.as_rule();
                    let mut oi = o.into_inner();
                    next(&mut oi);
                    let first = self.vector(next(&mut oi));
                    match r {
                        Rule::euler => Orient::Euler(first),
                        _ => {
                            let x = oi.nth(1).map(|v| self.vector(v));
                            Orient::Directions { z: first, x }
                        }
                    }
                });
                PartItem::Marker(MarkerDecl {
                    name,
                    at,
                    orient,
                    span,
                })
            }
            _ => PartItem::Landmark(LandmarkDecl { name, at, span }),
        }
    }

    fn element(&self, mut it: Pairs<Rule>) -> ElementDecl {
        let kw = next(&mut it);
        let keyword = match kw.as_str() {
            "joint" => ElementKw::Joint,
            "bushing" => ElementKw::Bushing,
            "spring" => ElementKw::Spring,
            "stop" => ElementKw::Stop,
            "friction" => ElementKw::Friction,
            _ => ElementKw::Wheel,
        };
        let name = self.ident(next(&mut it));
        let mut kind = None;
        let mut props = Vec::new();
        for p in it {
            match p.as_rule() {
                Rule::ident => kind = Some(self.ident(p)),
                _ => {
                    for prop in p.into_inner() {
                        let span = self.span(&prop);
                        let mut pi = prop.into_inner();
                        let key = self.ident(next(&mut pi));
                        let value = self.value(next(&mut pi));
                        props.push(Property { key, value, span });
                    }
                }
            }
        }
        ElementDecl {
            keyword,
            name,
            kind,
            props,
        }
    }

    fn value(&self, p: P) -> Value {
        let inner = next(&mut p.into_inner());
        let span = self.span(&inner);
        match inner.as_rule() {
            Rule::marker_ref => {
                let mut names: Vec<Ident> = inner.into_inner().map(|i| self.ident(i)).collect();
                let marker = names.pop().unwrap_or_else(|| Ident {
                    name: String::new(),
                    span,
                });
                let part = match (names.first(), names.last()) {
                    (Some(first), Some(last)) => Ident {
                        name: names
                            .iter()
                            .map(|n| n.name.as_str())
                            .collect::<Vec<_>>()
                            .join("."),
                        span: first.span.to(last.span),
                    },
                    _ => marker.clone(),
                };
                Value::Ref(MarkerRef { part, marker, span })
            }
            Rule::vector => Value::Vector(self.vector(inner)),
            Rule::list => Value::List(inner.into_inner().map(|e| self.expr(e)).collect(), span),
            Rule::table => {
                let mut it = inner.into_inner();
                next(&mut it);
                let x_unit = self.unit(next(&mut it));
                let y_unit = self.unit(next(&mut it));
                let points = it
                    .map(|pair| {
                        let mut pi = pair.into_inner();
                        let x = self.num(next(&mut pi));
                        let y = self.num(next(&mut pi));
                        (x, y)
                    })
                    .collect();
                Value::Table(TableLit {
                    x_unit,
                    y_unit,
                    points,
                    span,
                })
            }
            _ => Value::Expr(self.expr(inner)),
        }
    }

    fn vector(&self, p: P) -> Vector {
        let span = self.span(&p);
        let mut it = p.into_inner();
        let a = self.expr(next(&mut it));
        let b = self.expr(next(&mut it));
        let c = self.expr(next(&mut it));
        let unit = it.next().map(|u| self.unit(u));
        Vector {
            comps: [a, b, c],
            unit,
            span,
        }
    }

    pub fn expr(&self, p: P) -> Expr {
        let span = self.span(&p);
        match p.as_rule() {
            Rule::expr | Rule::term => {
                let mut it = p.into_inner();
                let mut lhs = self.expr(next(&mut it));
                while let Some(op) = it.next() {
                    let op = match op.as_str() {
                        "+" => BinOp::Add,
                        "-" => BinOp::Sub,
                        "*" => BinOp::Mul,
                        _ => BinOp::Div,
                    };
                    let rhs = self.expr(next(&mut it));
                    let s = lhs.span.to(rhs.span);
                    lhs = Expr {
                        kind: ExprKind::Binary(op, Box::new(lhs), Box::new(rhs)),
                        span: s,
                    };
                }
                lhs
            }
            Rule::factor => {
                let parts: Vec<P> = p.into_inner().collect();
                let negs = parts.len() - 1;
                let mut e = self.expr(parts[negs].clone());
                for n in parts[..negs].iter().rev() {
                    let s = self.span(n).to(e.span);
                    e = Expr {
                        kind: ExprKind::Neg(Box::new(e)),
                        span: s,
                    };
                }
                e
            }
            Rule::power => {
                let mut it = p.into_inner();
                let base = self.expr(next(&mut it));
                match it.next() {
                    Some(exp) => Expr {
                        kind: ExprKind::Pow(Box::new(base), self.num(exp)),
                        span,
                    },
                    None => base,
                }
            }
            Rule::quantity => {
                let mut it = p.into_inner();
                let num = self.num(next(&mut it));
                let unit = it.next().map(|u| self.unit(u));
                Expr {
                    kind: ExprKind::Quantity { num, unit },
                    span,
                }
            }
            Rule::param_ref => Expr {
                kind: ExprKind::Param(self.ident(next(&mut p.into_inner()))),
                span,
            },
            Rule::call => {
                let mut it = p.into_inner();
                let f = self.ident(next(&mut it));
                let args = it.map(|a| self.expr(a)).collect();
                Expr {
                    kind: ExprKind::Call(f, args),
                    span,
                }
            }
            Rule::paren => Expr {
                kind: ExprKind::Paren(Box::new(self.expr(next(&mut p.into_inner())))),
                span,
            },
            r => unreachable!("invariant: expression rule {r:?}"),
        }
    }

    fn channel(&self, p: P) -> ChannelLit {
        ChannelLit {
            path: p.as_str().split('.').map(str::to_string).collect(),
            span: self.span(&p),
        }
    }

    fn loads_body(&self, p: P) -> LoadsBody {
        let rule = p.as_rule();
        let mut it = p.into_inner();
        next(&mut it);
        match rule {
            Rule::load_table => {
                let mut columns = Vec::new();
                let mut rows = Vec::new();
                for q in it {
                    let span = self.span(&q);
                    match q.as_rule() {
                        Rule::column => {
                            let mut ci = q.into_inner();
                            let channel = self.channel(next(&mut ci));
                            let unit = self.unit(next(&mut ci));
                            columns.push(Column {
                                channel,
                                unit,
                                span,
                            });
                        }
                        _ => {
                            let mut ri = q.into_inner();
                            let name = self.ident(next(&mut ri));
                            let values = ri.map(|n| self.num(n)).collect();
                            rows.push(Row { name, values, span });
                        }
                    }
                }
                LoadsBody::Table { columns, rows }
            }
            _ => {
                let lines = it
                    .map(|l| {
                        let span = self.span(&l);
                        let mut li = l.into_inner();
                        let channel = self.channel(next(&mut li));
                        let mut waypoints = Vec::new();
                        let mut step = None;
                        let mut after_by = false;
                        for q in li {
                            match q.as_rule() {
                                Rule::kw_by => after_by = true,
                                _ if after_by => step = Some(self.expr(q)),
                                _ => waypoints.push(self.expr(q)),
                            }
                        }
                        SweepLine {
                            channel,
                            waypoints,
                            step,
                            span,
                        }
                    })
                    .collect();
                LoadsBody::Sweep { lines }
            }
        }
    }
}
