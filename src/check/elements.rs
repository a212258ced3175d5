//! Joints, bushings, springs, stops and wheels; frictions in [`super::friction`].

use super::Checker;
use super::error;
use super::props::Props;
use crate::diagnostic::Diagnostic;
use crate::model::schema::{self, FieldId, FieldSpec, Kind};
use crate::model::*;
use crate::span::Span;
use crate::syntax::ast::{ElementDecl, ElementKw, File, ItemKind};
use std::collections::BTreeMap;

const JOINT_PROPS: &[&str] = &["i", "j"];
const WHEEL_PROPS: &[&str] = &["centre", "center", "contact"];

/// The property names the checker accepts in an element of this kind (for
/// completion; the checker itself reads the same lists: the element kind's
/// schema where it has one).
pub fn properties(kw: ElementKw) -> Vec<&'static str> {
    match kw {
        ElementKw::Joint => JOINT_PROPS.to_vec(),
        ElementKw::Bushing => schema::BUSHING.keys(),
        ElementKw::Spring => schema::SPRING.keys(),
        ElementKw::Stop => schema::STOP.keys(),
        ElementKw::Friction => schema::FRICTION.keys(),
        ElementKw::Wheel => WHEEL_PROPS.to_vec(),
    }
}

impl Checker {
    pub(super) fn elements(&mut self, ast: &File) {
        let mut names: BTreeMap<String, Span> = BTreeMap::new();
        let mut frictions = Vec::new();
        for item in &ast.items {
            let ItemKind::Element(e) = &item.kind else {
                continue;
            };
            if let Some(first) = names.get(&e.name.name) {
                self.problems.push(error::duplicate(
                    "element",
                    &e.name.name,
                    e.name.span,
                    *first,
                ));
                continue;
            }
            names.insert(e.name.name.clone(), e.name.span);
            match e.keyword {
                ElementKw::Joint => self.joint(e),
                ElementKw::Bushing => self.bushing(e),
                ElementKw::Spring => self.spring(e),
                ElementKw::Stop => self.stop(e),
                ElementKw::Friction => frictions.push(e),
                ElementKw::Wheel => self.wheel(e),
            }
            if e.keyword != ElementKw::Joint && e.keyword != ElementKw::Stop {
                if let Some(k) = &e.kind {
                    self.problems.push(
                        Diagnostic::error(
                            "E0401",
                            format!("a {} takes no kind word", e.keyword.keyword()),
                        )
                        .primary(k.span, "unexpected word")
                        .hint(format!(
                            "write `{} {} {{`",
                            e.keyword.keyword(),
                            e.name.name
                        )),
                    );
                }
            }
        }
        // After every joint: a friction names its joint, declared anywhere.
        for e in frictions {
            self.friction(e);
        }
    }

    /// The I and J markers, which must be on different parts.
    pub(super) fn ij(&mut self, props: &Props) -> Option<(MarkerId, MarkerId)> {
        let i = self.prop_marker(props, "i");
        let j = self.prop_marker(props, "j");
        let (i, j) = (i?, j?);
        let (pi, pj) = (self.model.marker(i).part, self.model.marker(j).part);
        if pi == pj {
            let span = |k: &str| {
                props
                    .get(k)
                    .map_or(props.decl.name.span, |p| p.value.span())
            };
            let part = self.model.part(pi).name.clone();
            self.problems.push(error::same_part(
                props.element,
                &props.decl.name.name,
                &part,
                span("i"),
                span("j"),
            ));
            return None;
        }
        Some((i, j))
    }

    fn joint(&mut self, e: &ElementDecl) {
        let props = self.props("joint", e, JOINT_PROPS);
        let kind = match &e.kind {
            Some(k) => match JointKind::from_keyword(&k.name) {
                Some(kind) => Some(kind),
                None => {
                    let d = error::unknown_name("joint kind", &k.name, k.span, JointKind::ALL.iter().map(|k| k.keyword()))
                        .note("joint kinds: spherical, universal, revolute, cylindrical, translational, fixed, inline, inplane");
                    self.problems.push(d);
                    None
                }
            },
            None => {
                self.problems.push(
                    Diagnostic::error("E0402", format!("joint `{}` has no kind", e.name.name))
                        .primary(e.name.span, "the kind goes after the name")
                        .hint(format!("write `joint {} spherical {{` (or universal, revolute, cylindrical, translational, fixed, inline, inplane)", e.name.name)),
                );
                None
            }
        };
        let ij = self.ij(&props);
        let (Some(kind), Some((i, j))) = (kind, ij) else {
            return;
        };
        let id = JointId(self.model.joints.len() as u32);
        self.model.origins.insert(ElementId::Joint(id), e.name.span);
        self.model.joints.push(Joint {
            name: e.name.name.clone(),
            kind,
            i,
            j,
        });
    }

    fn spring(&mut self, e: &ElementDecl) {
        let keys = schema::SPRING.keys();
        let props = self.props("spring", e, &keys);
        let ij = self.ij(&props);
        let field = |id| schema::SPRING.field(id);
        // The key of a scalar field (`k`), and the line a missing one would be.
        let key = |s: &FieldSpec| s.keys[0];
        let missing = |s: &FieldSpec| format!("{} {}", key(s), s.example);
        let (rate, free, pre) = (
            field(FieldId::SpringK),
            field(FieldId::FreeLength),
            field(FieldId::SpringPreload),
        );
        // The rate's law says what a table law maps (the schema gives it one).
        let Some(rate_law) = rate.law else {
            return;
        };
        let law = if let Some(p) = props.get("law") {
            for other in schema::SPRING.field_keys() {
                if let Some(o) = props.get(other) {
                    self.problems.push(
                        Diagnostic::error(
                            "E0406",
                            format!(
                                "spring `{}` has both a table law and `{other}`",
                                e.name.name
                            ),
                        )
                        .primary(o.key.span, "not used with a table law")
                        .secondary(p.key.span, "the table law"),
                    );
                }
            }
            self.prop_table(p, rate_law.from, rate_law.to, false)
                .map(SpringLaw::Table)
        } else {
            let k = match props.get(key(rate)) {
                Some(p) => self
                    .prop_scalar(p, rate.dim, rate.example)
                    .map(|k| self.non_negative(k, &props, rate.name, p.value.span())),
                None => {
                    self.problems.push(error::missing_property(
                        "spring",
                        &e.name.name,
                        key(rate),
                        e.name.span,
                        &missing(rate),
                    ));
                    None
                }
            };
            let free_length = props.get(key(free)).map(|p| {
                self.prop_scalar(p, free.dim, free.example)
                    .and_then(|v| self.positive_length(v, &props, p))
            });
            let preload = props
                .get(key(pre))
                .map(|p| self.prop_scalar(p, pre.dim, pre.example));
            if free_length.is_none() && preload.is_none() {
                self.problems.push(error::missing_property(
                    "spring",
                    &e.name.name,
                    key(free),
                    e.name.span,
                    &missing(free),
                ));
                return;
            }
            let (Some(k), Some((i, j))) = (k, ij) else {
                return;
            };
            let free_length = match free_length {
                Some(v) => match v {
                    Some(v) => v,
                    None => return,
                },
                // Only a preload: it is the force at the design length.
                None => {
                    Val::lit((self.model.marker(i).origin() - self.model.marker(j).origin()).norm())
                }
            };
            let preload = match preload {
                Some(Some(v)) => v,
                Some(None) => return,
                None => Val::ZERO,
            };
            Some(SpringLaw::Linear {
                k,
                free_length,
                preload,
            })
        };
        let (Some((i, j)), Some(law)) = (ij, law) else {
            return;
        };
        let id = SpringId(self.model.springs.len() as u32);
        self.model
            .origins
            .insert(ElementId::Spring(id), e.name.span);
        self.model.springs.push(Spring {
            name: e.name.name.clone(),
            i,
            j,
            law,
        });
    }

    fn stop(&mut self, e: &ElementDecl) {
        let keys = schema::STOP.keys();
        let props = self.props("stop", e, &keys);
        let contact_spec = schema::STOP.field(FieldId::ContactLength);
        let poly_spec = schema::STOP.field(FieldId::Coefficient(1));
        let contact_key = contact_spec.keys[0];
        let kind = match e.kind.as_ref().map(|k| (k, k.name.as_str())) {
            Some((_, "compression")) => Some(StopKind::Compression),
            Some((_, "rebound")) => Some(StopKind::Rebound),
            Some((k, _)) => {
                self.problems.push(error::unknown_name(
                    "stop kind",
                    &k.name,
                    k.span,
                    ["compression", "rebound"],
                ));
                None
            }
            None => {
                self.problems.push(
                    Diagnostic::error("E0407", format!("stop `{}` has no kind", e.name.name))
                        .primary(e.name.span, "compression or rebound?")
                        .hint(format!(
                            "write `stop {} compression {{` (bump stop) or `rebound`",
                            e.name.name
                        )),
                );
                None
            }
        };
        let ij = self.ij(&props);
        let contact = match props.get(contact_key) {
            Some(p) => self
                .prop_scalar(p, contact_spec.dim, contact_spec.example)
                .and_then(|v| self.positive_length(v, &props, p)),
            None => {
                self.problems.push(error::missing_property(
                    "stop",
                    &e.name.name,
                    contact_key,
                    e.name.span,
                    &format!("{contact_key} {}", contact_spec.example),
                ));
                None
            }
        };
        // The law: `k` (degree 1) or `poly` (the polynomial field's keys), or
        // a table `law` (a choice).
        let laws: Vec<&str> = poly_spec
            .keys
            .iter()
            .chain(schema::STOP.choices)
            .copied()
            .filter(|k| props.has(k))
            .collect();
        if laws.len() != 1 {
            let span = laws
                .get(1)
                .and_then(|k| props.get(k))
                .map_or(e.name.span, |p| p.key.span);
            self.problems.push(
                Diagnostic::error("E0408", format!("stop `{}` needs exactly one law: `k`, `poly` or `law`", e.name.name))
                    .primary(span, if laws.is_empty() { "no law" } else { "a second law" })
                    .hint("e.g. `k 500 N/mm`, `poly [500 N/mm, 20 N/mm^2]` or `law table (mm, N) [(0, 0), (10, 8000)]`"),
            );
            return;
        }
        let Some(poly_law) = poly_spec.law else {
            return;
        };
        let law = match laws[0] {
            "k" => props.get("k").and_then(|p| {
                self.prop_scalar(p, poly_spec.dim, poly_spec.scalar_example())
                    .map(|k| {
                        StopLaw::Polynomial(vec![self.non_negative(k, &props, "k", p.value.span())])
                    })
            }),
            "poly" => props.get("poly").and_then(|p| {
                self.prop_list(
                    p,
                    // Item n is the coefficient of degree n + 1.
                    |n| {
                        FieldId::Coefficient(u8::try_from(n + 1).unwrap_or(u8::MAX)).dim(Kind::Stop)
                    },
                    poly_spec.example,
                )
                .map(|c| {
                    for (n, v) in c.iter().enumerate() {
                        let what = format!("coefficient {} of `poly`", n + 1);
                        self.non_negative(*v, &props, &what, p.value.span());
                    }
                    StopLaw::Polynomial(c)
                })
            }),
            _ => props.get("law").and_then(|p| {
                let t = self.prop_table(p, poly_law.from, poly_law.to, true)?;
                self.stop_table_start(&t, p).then_some(StopLaw::Table(t))
            }),
        };
        let (Some(kind), Some((i, j)), Some(contact_length), Some(law)) = (kind, ij, contact, law)
        else {
            return;
        };
        let id = StopId(self.model.stops.len() as u32);
        self.model.origins.insert(ElementId::Stop(id), e.name.span);
        self.model.stops.push(Stop {
            name: e.name.name.clone(),
            kind,
            i,
            j,
            contact_length,
            law,
        });
    }

    fn wheel(&mut self, e: &ElementDecl) {
        let props = self.props("wheel", e, WHEEL_PROPS);
        if let (Some(a), Some(b)) = (props.get("centre"), props.get("center")) {
            let (first, second) = if a.key.span.start < b.key.span.start {
                (a, b)
            } else {
                (b, a)
            };
            self.problems.push(
                error::duplicate_property("centre", second.key.span, first.key.span)
                    .hint("`centre` and `center` are one property; keep one"),
            );
        }
        let centre_key = if props.has("center") && !props.has("centre") {
            "center"
        } else {
            "centre"
        };
        let centre = self.prop_marker(&props, centre_key);
        let contact = self.prop_marker(&props, "contact");
        let (Some(centre), Some(contact)) = (centre, contact) else {
            return;
        };
        let (pc, pk) = (
            self.model.marker(centre).part,
            self.model.marker(contact).part,
        );
        if pc != pk {
            let span = |k: &str| props.get(k).map_or(e.name.span, |p| p.value.span());
            self.problems.push(
                Diagnostic::error(
                    "E0409",
                    format!(
                        "the centre and contact markers of wheel `{}` are on different parts",
                        e.name.name
                    ),
                )
                .primary(
                    span("contact"),
                    format!("on `{}`", self.model.part(pk).name),
                )
                .secondary(
                    span(centre_key),
                    format!("on `{}`", self.model.part(pc).name),
                )
                .hint("both markers belong to the part that carries the wheel"),
            );
            return;
        }
        let id = WheelId(self.model.wheels.len() as u32);
        self.model.origins.insert(ElementId::Wheel(id), e.name.span);
        self.model.wheels.push(Wheel {
            name: e.name.name.clone(),
            part: pc,
            centre,
            contact,
        });
    }
}
