//! The property list of an element: unknown and repeated keys, and typed access
//! (`marker`, `scalar`, `vector`, `table`, `list`) with wrong-kind diagnostics.

use super::Checker;
use super::error;
use crate::model::{MarkerId, Table, Val, Val3};
use crate::syntax::ast::{ElementDecl, Property, TableLit, Value};
use crate::units::Dim;
use std::collections::BTreeMap;

/// Properties of one element by key, after unknown and duplicate keys were reported.
pub(super) struct Props<'a> {
    pub element: &'static str,
    pub decl: &'a ElementDecl,
    /// An unknown key was reported: "missing" errors would only repeat it.
    pub had_unknown: bool,
    map: BTreeMap<&'a str, &'a Property>,
}

impl<'a> Props<'a> {
    pub fn get(&self, key: &str) -> Option<&'a Property> {
        self.map.get(key).copied()
    }

    pub fn has(&self, key: &str) -> bool {
        self.map.contains_key(key)
    }
}

fn kind_of(v: &Value) -> &'static str {
    match v {
        Value::Ref(_) => "a marker reference",
        Value::Vector(_) => "a vector",
        Value::Table(_) => "a table",
        Value::List(..) => "a list",
        Value::Expr(_) => "a single value",
    }
}

impl Checker {
    pub(super) fn props<'a>(
        &mut self,
        element: &'static str,
        decl: &'a ElementDecl,
        allowed: &[&str],
    ) -> Props<'a> {
        let mut map: BTreeMap<&str, &Property> = BTreeMap::new();
        let mut had_unknown = false;
        for p in &decl.props {
            if !allowed.contains(&p.key.name.as_str()) {
                had_unknown = true;
                self.problems.push(error::unknown_property(
                    element,
                    &p.key.name,
                    p.key.span,
                    allowed.iter().copied(),
                ));
                continue;
            }
            if let Some(first) = map.get(p.key.name.as_str()) {
                self.problems.push(error::duplicate_property(
                    &p.key.name,
                    p.key.span,
                    first.key.span,
                ));
                continue;
            }
            map.insert(&p.key.name, p);
        }
        Props {
            element,
            decl,
            had_unknown,
            map,
        }
    }

    /// A required marker reference.
    pub(super) fn prop_marker(&mut self, props: &Props, key: &str) -> Option<MarkerId> {
        let Some(p) = props.get(key) else {
            if props.had_unknown {
                return None;
            }
            self.problems.push(error::missing_property(
                props.element,
                &props.decl.name.name,
                key,
                props.decl.name.span,
                &format!("{key} part.marker"),
            ));
            return None;
        };
        match &p.value {
            Value::Ref(r) => self.marker_ref(r),
            v => {
                self.problems.push(error::wrong_value_kind(
                    "a marker such as `chassis.B`",
                    kind_of(v),
                    v.span(),
                    &format!("{key} chassis.B"),
                ));
                None
            }
        }
    }

    pub(super) fn prop_scalar(&mut self, p: &Property, dim: Dim, example: &str) -> Option<Val> {
        match &p.value {
            Value::Expr(e) => self.scalar(e, dim, example),
            v => {
                self.problems.push(error::wrong_value_kind(
                    "a single value",
                    kind_of(v),
                    v.span(),
                    example,
                ));
                None
            }
        }
    }

    pub(super) fn prop_vector(&mut self, p: &Property, dim: Dim, example: &str) -> Option<Val3> {
        match &p.value {
            Value::Vector(v) => self.vector(v, dim, example),
            v => {
                self.problems.push(error::wrong_value_kind(
                    "a vector",
                    kind_of(v),
                    v.span(),
                    example,
                ));
                None
            }
        }
    }

    pub(super) fn prop_list(
        &mut self,
        p: &Property,
        dims: impl Fn(usize) -> Dim,
        example: &str,
    ) -> Option<Vec<Val>> {
        match &p.value {
            Value::List(items, _) => {
                let vals: Vec<Option<Val>> = items
                    .iter()
                    .enumerate()
                    .map(|(i, e)| self.scalar(e, dims(i), example))
                    .collect();
                vals.into_iter().collect()
            }
            v => {
                self.problems.push(error::wrong_value_kind(
                    "a list",
                    kind_of(v),
                    v.span(),
                    example,
                ));
                None
            }
        }
    }

    /// A table law with the given axis dimensions; `increasing` says whether the
    /// force must grow (true) or shrink (false) with the abscissa.
    pub(super) fn table(
        &mut self,
        t: &TableLit,
        x: Dim,
        y: Dim,
        increasing: bool,
    ) -> Option<Table> {
        let example = format!(
            "table ({}, {}) [(0, 0), (5, 5000)]",
            x.boundary_unit(),
            y.boundary_unit()
        );
        let xu = self.unit(&t.x_unit)?;
        let yu = self.unit(&t.y_unit)?;
        let mut ok = true;
        if xu.dim != x {
            self.problems
                .push(error::wrong_dimension(x, xu.dim, t.x_unit.span, &example));
            ok = false;
        }
        if yu.dim != y {
            self.problems
                .push(error::wrong_dimension(y, yu.dim, t.y_unit.span, &example));
            ok = false;
        }
        if t.points.len() < 2 {
            self.problems
                .push(error::table_too_short(t.span, t.points.len()));
            return None;
        }
        for w in t.points.windows(2) {
            let (a, b) = (&w[0], &w[1]);
            if b.0.value <= a.0.value {
                self.problems
                    .push(error::table_not_increasing(b.0.span, a.0.span));
                ok = false;
            } else if (increasing && b.1.value < a.1.value)
                || (!increasing && b.1.value > a.1.value)
            {
                self.problems.push(error::table_not_monotone(
                    b.1.span,
                    a.1.span,
                    if increasing { "grow" } else { "shrink" },
                ));
                ok = false;
            }
        }
        ok.then(|| Table {
            points: t
                .points
                .iter()
                .map(|(a, b)| (a.value * xu.factor, b.value * yu.factor))
                .collect(),
        })
    }

    pub(super) fn prop_table(
        &mut self,
        p: &Property,
        x: Dim,
        y: Dim,
        increasing: bool,
    ) -> Option<Table> {
        match &p.value {
            Value::Table(t) => self.table(t, x, y, increasing),
            v => {
                let ex = format!(
                    "table ({}, {}) [(0, 0), (5, 5000)]",
                    x.boundary_unit(),
                    y.boundary_unit()
                );
                self.problems.push(error::wrong_value_kind(
                    "a table",
                    kind_of(v),
                    v.span(),
                    &ex,
                ));
                None
            }
        }
    }

    /// A spring's free length or a stop's contact length: a distance between two
    /// points, so positive.
    pub(super) fn positive_length(&mut self, v: Val, props: &Props, p: &Property) -> Option<Val> {
        if v.value > 0.0 {
            return Some(v);
        }
        let elem = format!("{} `{}`", props.element, props.decl.name.name);
        self.problems.push(error::length_not_positive(
            &elem,
            &p.key.name,
            p.value.span(),
        ));
        None
    }

    /// A stop's table gives the force of the penetration from first contact on:
    /// it starts at penetration 0 with a force that does not pull.
    pub(super) fn stop_table_start(&mut self, t: &Table, p: &Property) -> bool {
        let Value::Table(lit) = &p.value else {
            return true;
        };
        let (Some(&(x0, y0)), Some(first)) = (t.points.first(), lit.points.first()) else {
            return true;
        };
        if x0 == 0.0 && y0 >= 0.0 {
            return true;
        }
        let (span, why) = if x0 != 0.0 {
            (
                first.0.span,
                "the first penetration must be 0 (first contact)",
            )
        } else {
            (
                first.1.span,
                "the force at first contact must not be negative (a stop only pushes)",
            )
        };
        self.problems.push(error::stop_table_start(span, why));
        false
    }

    /// Reports a negative stiffness.
    pub(super) fn non_negative(
        &mut self,
        v: Val,
        props: &Props,
        what: &str,
        span: crate::span::Span,
    ) -> Val {
        if v.value < 0.0 {
            let elem = format!("{} `{}`", props.element, props.decl.name.name);
            self.problems
                .push(error::negative_stiffness(&elem, what, span));
        }
        v
    }
}
