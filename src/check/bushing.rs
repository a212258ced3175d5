//! Bushings: the I and J markers, the six force laws (vector, radial/axial
//! shorthand or per axis, linear with a cubic term or tabulated), offsets and
//! preloads.

use super::Checker;
use super::props::Props;
use crate::diagnostic::Diagnostic;
use crate::model::schema::{self, FieldId};
use crate::model::*;
use crate::span::Span;
use crate::syntax::ast::{ElementDecl, Value};
use crate::units::Dim;

impl Checker {
    pub(super) fn bushing(&mut self, e: &ElementDecl) {
        let keys = schema::BUSHING.keys();
        let props = self.props("bushing", e, &keys);
        let ij = self.ij(&props);
        let family = |c: &mut Self, id: FieldId| {
            let spec = schema::BUSHING.field(id);
            // K and Kt are law fields in the schema (a unit test there says so);
            // without a law there is nothing to read, not a panic.
            let law = spec.law?;
            c.axis_laws(&props, spec.name, spec.dim, law.from, law.to, spec.example)
        };
        let translational = family(self, FieldId::K);
        let rotational = family(self, FieldId::Kt);
        let vec_or_zero = |c: &mut Self, id: FieldId| -> Option<Val3> {
            let spec = schema::BUSHING.field(id);
            match props.get(spec.name) {
                Some(p) => c.prop_vector(p, spec.dim, spec.example),
                None => Some([Val::ZERO; 3]),
            }
        };
        let k3 = vec_or_zero(self, FieldId::K3);
        let kt3 = vec_or_zero(self, FieldId::Kt3);
        // A negative cubic term softens the law until it turns back (several
        // equilibria for one load, then none): reported like a negative stiffness.
        for (key, cubic) in [("k3", &k3), ("kt3", &kt3)] {
            if let (Some(v), Some(p)) = (cubic, props.get(key)) {
                for (a, c) in v.iter().enumerate() {
                    let what = format!("{key} along {}", ["x", "y", "z"][a]);
                    self.non_negative(*c, &props, &what, p.value.span());
                }
            }
        }
        let offset = vec_or_zero(self, FieldId::Offset);
        let angle_offset = vec_or_zero(self, FieldId::AngleOffset);
        let preload = vec_or_zero(self, FieldId::Preload);
        let torque_preload = vec_or_zero(self, FieldId::TorquePreload);
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
        for ((laws, _), cubic, key) in [
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
        // The radial shorthand makes a family axisymmetric: its x and y laws
        // are stored once, so they must agree (a cubic term may split them).
        let mut axisymmetric = |laws: [AxisLaw; 3], radial: bool, base: &str| {
            if radial && laws[0] != laws[1] {
                let key = format!("{base}3");
                let span = props.get(&key).map_or(e.name.span, |p| p.value.span());
                self.problems.push(
                    Diagnostic::error(
                        "E0415",
                        format!("`{key}` differs along x and y of an axisymmetric bushing"),
                    )
                    .primary(span, "x and y cubic terms differ")
                    .secondary_opt(
                        props.get(&format!("{base}_radial")).map(|p| p.key.span),
                        "x and y share one radial law",
                    )
                    .hint(format!(
                        "give x and y the same cubic term, or write `{base}` per axis"
                    )),
                );
                return None;
            }
            Some(AxisLaws::from_three(laws, radial))
        };
        let (Some(translational), Some(rotational)) = (
            axisymmetric(translational.0, translational.1, "k"),
            axisymmetric(rotational.0, rotational.1, "kt"),
        ) else {
            return;
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
            offset,
            angle_offset,
            preload,
            torque_preload,
        });
    }

    /// The three laws of a bushing family (`k` or `kt`): from the vector, the
    /// radial/axial shorthand or per-axis properties, each axis set exactly once;
    /// with whether the radial shorthand set x and y.
    #[allow(clippy::too_many_arguments)]
    fn axis_laws(
        &mut self,
        props: &Props,
        base: &str,
        dim: Dim,
        x: Dim,
        y: Dim,
        example: &str,
    ) -> Option<([AxisLaw; 3], bool)> {
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
        let radial = props.has(&format!("{base}_radial"));
        let [a, b, c] = laws;
        Some(([a?.0, b?.0, c?.0], radial))
    }
}
