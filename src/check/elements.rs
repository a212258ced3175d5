//! Joints, bushings, springs, stops and wheels.

use super::Checker;
use super::error;
use super::props::Props;
use crate::diagnostic::Diagnostic;
use crate::model::*;
use crate::span::Span;
use crate::syntax::ast::{ElementDecl, ElementKw, File, ItemKind, Value};
use crate::units::Dim;
use std::collections::BTreeMap;

const JOINT_PROPS: &[&str] = &["i", "j"];
const BUSHING_PROPS: &[&str] = &[
    "i",
    "j",
    "k",
    "kt",
    "k_radial",
    "k_axial",
    "kt_radial",
    "kt_axial",
    "k_x",
    "k_y",
    "k_z",
    "kt_x",
    "kt_y",
    "kt_z",
    "k3",
    "kt3",
    "offset",
    "angle_offset",
    "preload",
    "torque_preload",
];
const SPRING_PROPS: &[&str] = &["i", "j", "k", "free_length", "preload", "law"];
const STOP_PROPS: &[&str] = &["i", "j", "contact_length", "k", "poly", "law"];
const WHEEL_PROPS: &[&str] = &["centre", "center", "contact"];

impl Checker {
    pub(super) fn elements(&mut self, ast: &File) {
        let mut names: BTreeMap<String, Span> = BTreeMap::new();
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
    }

    /// The I and J markers, which must be on different parts.
    fn ij(&mut self, props: &Props) -> Option<(MarkerId, MarkerId)> {
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

    fn bushing(&mut self, e: &ElementDecl) {
        let props = self.props("bushing", e, BUSHING_PROPS);
        let ij = self.ij(&props);
        let translational = self.axis_laws(
            &props,
            "k",
            Dim::STIFFNESS,
            Dim::LENGTH,
            Dim::FORCE,
            "(310, 2400, 180) N/mm",
        );
        let rotational = self.axis_laws(
            &props,
            "kt",
            Dim::ROT_STIFFNESS,
            Dim::ANGLE,
            Dim::TORQUE,
            "(4500, 1100, 1600) N*mm/deg",
        );
        let vec_or_zero = |c: &mut Self, key: &str, dim: Dim, ex: &str| -> Option<Val3> {
            match props.get(key) {
                Some(p) => c.prop_vector(p, dim, ex),
                None => Some([Val::ZERO; 3]),
            }
        };
        let k3 = vec_or_zero(self, "k3", Dim::new(-3, 1, 0), "(0, 0, 2) N/mm^3");
        let kt3 = vec_or_zero(self, "kt3", Dim::new(1, 1, -3), "(0, 0, 2) N*mm/deg^3");
        let offset = vec_or_zero(self, "offset", Dim::LENGTH, "(0, 0, 1.5) mm");
        let angle_offset = vec_or_zero(self, "angle_offset", Dim::ANGLE, "(0, 0, 2) deg");
        let preload = vec_or_zero(self, "preload", Dim::FORCE, "(0, 0, 100) N");
        let torque_preload = vec_or_zero(self, "torque_preload", Dim::TORQUE, "(0, 0, 1000) N*mm");
        let (Some((i, j)), Some(mut translational), Some(mut rotational)) =
            (ij, translational, rotational)
        else {
            return;
        };
        let (
            Some(k3),
            Some(kt3),
            Some(offset),
            Some(angle_offset),
            Some(preload),
            Some(torque_preload),
        ) = (k3, kt3, offset, angle_offset, preload, torque_preload)
        else {
            return;
        };
        for (laws, cubic, key) in [
            (&mut translational, k3, "k3"),
            (&mut rotational, kt3, "kt3"),
        ] {
            for (law, c) in laws.iter_mut().zip(cubic) {
                match law {
                    AxisLaw::Linear { k3, .. } => *k3 = c,
                    AxisLaw::Table(_) if c.value != 0.0 => {
                        let span = props.get(key).map_or(e.name.span, |p| p.value.span());
                        self.problems.push(
                            Diagnostic::error(
                                "E0403",
                                "a cubic term cannot be added to a table law",
                            )
                            .primary(span, "cubic term on an axis that has a table")
                            .hint("put the stiffening into the table itself"),
                        );
                    }
                    AxisLaw::Table(_) => {}
                }
            }
        }
        let symmetry = if props.has("k_radial") || props.has("kt_radial") {
            Symmetry::Axisymmetric
        } else {
            Symmetry::General
        };
        let id = BushingId(self.model.bushings.len() as u32);
        self.model
            .origins
            .insert(ElementId::Bushing(id), e.name.span);
        self.model.bushings.push(Bushing {
            name: e.name.name.clone(),
            i,
            j,
            translational,
            rotational,
            symmetry,
            offset,
            angle_offset,
            preload,
            torque_preload,
        });
    }

    /// The three laws of a bushing family (`k` or `kt`): from the vector, the
    /// radial/axial shorthand or per-axis properties, each axis set exactly once.
    #[allow(clippy::too_many_arguments)]
    fn axis_laws(
        &mut self,
        props: &Props,
        base: &str,
        dim: Dim,
        x: Dim,
        y: Dim,
        example: &str,
    ) -> Option<[AxisLaw; 3]> {
        let mut laws: [Option<(AxisLaw, Span, String)>; 3] = [None, None, None];
        let mut ok = true;
        let set = |c: &mut Self,
                   axis: usize,
                   law: AxisLaw,
                   span: Span,
                   key: &str,
                   laws: &mut [Option<(AxisLaw, Span, String)>; 3]| {
            if let Some((_, first, by)) = &laws[axis] {
                c.problems.push(
                    Diagnostic::error(
                        "E0404",
                        format!("the {base} along {} is given twice", ["x", "y", "z"][axis]),
                    )
                    .primary(span, format!("`{key}` sets it"))
                    .secondary(*first, format!("`{by}` already set it")),
                );
                return false;
            }
            laws[axis] = Some((law, span, key.to_string()));
            true
        };
        let unit = dim.boundary_unit();
        if let Some(p) = props.get(base) {
            match self.prop_vector(p, dim, example) {
                Some(v) => {
                    for (a, k) in v.iter().enumerate() {
                        let k = self.non_negative(
                            *k,
                            props,
                            &format!("{base} along {}", ["x", "y", "z"][a]),
                            p.value.span(),
                        );
                        ok &= set(
                            self,
                            a,
                            AxisLaw::Linear { k, k3: Val::ZERO },
                            p.key.span,
                            base,
                            &mut laws,
                        );
                    }
                }
                None => ok = false,
            }
        }
        for (suffix, axes) in [("radial", &[0usize, 1][..]), ("axial", &[2][..])] {
            let key = format!("{base}_{suffix}");
            if let Some(p) = props.get(&key) {
                match self.prop_scalar(p, dim, &format!("1000 {unit}")) {
                    Some(k) => {
                        let k = self.non_negative(k, props, &key, p.value.span());
                        for &a in axes {
                            ok &= set(
                                self,
                                a,
                                AxisLaw::Linear { k, k3: Val::ZERO },
                                p.key.span,
                                &key,
                                &mut laws,
                            );
                        }
                    }
                    None => ok = false,
                }
            }
        }
        for (a, axis) in ["x", "y", "z"].iter().enumerate() {
            let key = format!("{base}_{axis}");
            let Some(p) = props.get(&key) else { continue };
            let law = match &p.value {
                Value::Table(t) => self.table(t, x, y, true).map(AxisLaw::Table),
                _ => self.prop_scalar(p, dim, &format!("1000 {unit}")).map(|k| {
                    let k = self.non_negative(k, props, &key, p.value.span());
                    AxisLaw::Linear { k, k3: Val::ZERO }
                }),
            };
            match law {
                Some(l) => ok &= set(self, a, l, p.key.span, &key, &mut laws),
                None => ok = false,
            }
        }
        let missing: Vec<&str> = (0..3)
            .filter(|&a| laws[a].is_none())
            .map(|a| ["x", "y", "z"][a])
            .collect();
        if !missing.is_empty() && props.had_unknown {
            return None;
        }
        if ok && !missing.is_empty() {
            self.problems.push(
                Diagnostic::error("E0405", format!("bushing `{}` has no {base} along {}", props.decl.name.name, missing.join(", ")))
                    .primary(props.decl.name.span, format!("`{base}` incomplete"))
                    .hint(format!("give all three axes, e.g. `{base} {example}`, or `{base}_radial` and `{base}_axial`")),
            );
            return None;
        }
        if !ok {
            return None;
        }
        let [a, b, c] = laws;
        Some([a?.0, b?.0, c?.0])
    }

    fn spring(&mut self, e: &ElementDecl) {
        let props = self.props("spring", e, SPRING_PROPS);
        let ij = self.ij(&props);
        let law = if let Some(p) = props.get("law") {
            for other in ["k", "free_length", "preload"] {
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
            self.prop_table(p, Dim::LENGTH, Dim::FORCE, false)
                .map(SpringLaw::Table)
        } else {
            let k = match props.get("k") {
                Some(p) => self
                    .prop_scalar(p, Dim::STIFFNESS, "30 N/mm")
                    .map(|k| self.non_negative(k, &props, "k", p.value.span())),
                None => {
                    self.problems.push(error::missing_property(
                        "spring",
                        &e.name.name,
                        "k",
                        e.name.span,
                        "k 30 N/mm",
                    ));
                    None
                }
            };
            let free_length = props
                .get("free_length")
                .map(|p| self.prop_scalar(p, Dim::LENGTH, "290 mm"));
            let preload = props
                .get("preload")
                .map(|p| self.prop_scalar(p, Dim::FORCE, "4800 N"));
            if free_length.is_none() && preload.is_none() {
                self.problems.push(error::missing_property(
                    "spring",
                    &e.name.name,
                    "free_length",
                    e.name.span,
                    "free_length 290 mm",
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
        let props = self.props("stop", e, STOP_PROPS);
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
        let contact = match props.get("contact_length") {
            Some(p) => self.prop_scalar(p, Dim::LENGTH, "120 mm"),
            None => {
                self.problems.push(error::missing_property(
                    "stop",
                    &e.name.name,
                    "contact_length",
                    e.name.span,
                    "contact_length 120 mm",
                ));
                None
            }
        };
        let laws: Vec<&str> = ["k", "poly", "law"]
            .into_iter()
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
        let law = match laws[0] {
            "k" => props.get("k").and_then(|p| {
                self.prop_scalar(p, Dim::STIFFNESS, "500 N/mm").map(|k| {
                    StopLaw::Polynomial(vec![self.non_negative(k, &props, "k", p.value.span())])
                })
            }),
            "poly" => props.get("poly").and_then(|p| {
                self.prop_list(
                    p,
                    |n| Dim::new(-(n as i8) - 1, 1, 0),
                    "[500 N/mm, 20 N/mm^2]",
                )
                .map(StopLaw::Polynomial)
            }),
            _ => props.get("law").and_then(|p| {
                self.prop_table(p, Dim::LENGTH, Dim::FORCE, true)
                    .map(StopLaw::Table)
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
