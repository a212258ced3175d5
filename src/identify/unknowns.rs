//! Which parameters are unknown: those the file marks `unknown`, or those named
//! on the command line, else every bushing stiffness and every spring's k and
//! free length (the thesis' question). The radial pair of an axisymmetric
//! bushing (k_x and k_y, or kt_x and kt_y, both unknown) is one unknown, since
//! the model states that they are equal (thesis eq. 4.40, 5.13).

use super::IdentifyError;
use crate::model::address::Address;
use crate::model::schema::FieldId;
use crate::model::{AxisLaw, Bounds, BushingId, ElementId, Model, SpringId, SpringLaw};
use crate::statics::Parameter;
use crate::units::Dim;

/// An unknown is a parameter of the statics' sensitivity service: its
/// addresses move together.
impl Parameter for Unknown {
    fn value(&self, model: &Model) -> f64 {
        self.addrs[0].get(model)
    }

    fn set_value(&self, model: &mut Model, value: f64) {
        self.set(model, value);
    }

    fn moves_geometry(&self, model: &Model) -> bool {
        self.addrs.iter().any(|a| a.moves_geometry(model))
    }

    fn element(&self) -> ElementId {
        self.addrs[0].element()
    }

    fn force_element(&self, model: &Model) -> Option<ElementId> {
        // A tied pair (k_x = k_y) changes one bushing.
        let e = self.addrs[0].force_element(model)?;
        self.addrs
            .iter()
            .all(|a| a.force_element(model) == Some(e))
            .then_some(e)
    }
}

/// One unknown: one or more addresses that always share a value.
#[derive(Debug, Clone, PartialEq)]
pub struct Unknown {
    pub addrs: Vec<Address>,
    /// Names as `interfaces.md` writes them, one per address.
    pub names: Vec<String>,
    pub dim: Dim,
    /// Value in the model, internal units.
    pub initial: f64,
    /// Bounds declared with `unknown [lo, hi]` (internal units); open for
    /// element fields and unbounded parameters.
    pub bounds: Bounds,
}

impl Unknown {
    fn new(model: &Model, addrs: Vec<Address>) -> Unknown {
        let names = addrs.iter().map(|a| a.name(model)).collect();
        Unknown {
            dim: addrs[0].dim(model),
            initial: addrs[0].get(model),
            bounds: bounds_of(model, addrs[0]),
            addrs,
            names,
        }
    }

    /// `A.k_x` or `A.k_x = A.k_y` for a tied pair.
    pub fn label(&self) -> String {
        self.names.join(" = ")
    }

    pub fn set(&self, model: &mut Model, v: f64) {
        for a in &self.addrs {
            a.set(model, v);
        }
    }

    /// A stiffness (positive by nature): bushing k, kt, spring k, or a declared
    /// parameter with a stiffness dimension.
    pub fn is_stiffness(&self) -> bool {
        self.dim == Dim::STIFFNESS || self.dim == Dim::ROT_STIFFNESS
    }

    pub fn bushing(&self) -> Option<(BushingId, bool, usize)> {
        self.addrs[0].bushing_stiffness()
    }

    pub fn element(&self) -> ElementId {
        self.addrs[0].element()
    }
}

/// The declared bounds of an unknown: a parameter's own, or, for a field
/// written as a parameter (`k_radial kA`), that parameter's.
fn bounds_of(model: &Model, a: Address) -> Bounds {
    a.binding(model)
        .and_then(|p| model.params[p.index()].unknown)
        .unwrap_or_default()
}

fn linear(l: &AxisLaw) -> bool {
    matches!(l, AxisLaw::Linear { .. })
}

/// Every linear bushing stiffness and every linear spring's k and free length.
fn defaults(model: &Model) -> Vec<Address> {
    let mut out = Vec::new();
    for (k, b) in model.bushings.iter().enumerate() {
        let id = BushingId(k as u32);
        for n in 0..3 {
            if linear(&b.translational[n]) {
                out.push(Address::bushing(id, false, n));
            }
        }
        for n in 0..3 {
            if linear(&b.rotational[n]) {
                out.push(Address::bushing(id, true, n));
            }
        }
    }
    for (k, s) in model.springs.iter().enumerate() {
        if matches!(s.law, SpringLaw::Linear { .. }) {
            out.push(Address::spring(SpringId(k as u32), FieldId::SpringK));
            out.push(Address::spring(SpringId(k as u32), FieldId::FreeLength));
        }
    }
    out
}

/// Resolves the unknowns: `names` when given, else parameters marked unknown,
/// else the defaults; axisymmetric radial pairs tied.
pub fn select_unknowns(model: &Model, names: &[String]) -> Result<Vec<Unknown>, IdentifyError> {
    let mut addrs: Vec<Address> = Vec::new();
    if !names.is_empty() {
        for n in names {
            let a = Address::parse(model, n)
                .map_err(|e| IdentifyError::address(e.to_diagnostic("--unknown", n)))?;
            if !addrs.contains(&a) {
                addrs.push(a);
            }
        }
    } else {
        for (k, p) in model.params.iter().enumerate() {
            if p.unknown.is_some() {
                addrs.push(Address::param(crate::model::ParamId(k as u32)));
            }
        }
        if addrs.is_empty() {
            addrs = defaults(model);
        }
    }
    let mut out: Vec<Unknown> = Vec::new();
    let mut used = vec![false; addrs.len()];
    for i in 0..addrs.len() {
        if used[i] {
            continue;
        }
        used[i] = true;
        // Addresses of one stored number (x and y of an axisymmetric radial
        // law) are one unknown.
        let mut group = vec![addrs[i]];
        for j in i + 1..addrs.len() {
            if !used[j] && addrs[j].canonical(model) == addrs[i].canonical(model) {
                used[j] = true;
                group.push(addrs[j]);
            }
        }
        out.push(Unknown::new(model, group));
    }
    if out.is_empty() {
        return Err(IdentifyError::of(
            super::IdentifyErrorKind::Unknowns,
            "nothing to identify: the model has no linear bushing or spring and no parameter marked unknown",
            vec![],
        ));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mcpherson_defaults_tie_the_radial_pairs() {
        let (_, c) =
            crate::check::check_str("m.axle", include_str!("../../examples/mcpherson.axle"));
        let m = c.model.expect("checks");
        let u = select_unknowns(&m, &[]).expect("unknowns");
        // B: 6; A and F axisymmetric: 4 each; spring k and free length.
        assert_eq!(u.len(), 6 + 4 + 4 + 2);
        assert!(u.iter().any(|u| u.label() == "A.k_x = A.k_y"));
        let named = select_unknowns(&m, &["A.k_x".into(), "spring.k".into()]).expect("named");
        assert_eq!(named.len(), 2);
        assert!(select_unknowns(&m, &["nope.k".into()]).is_err());
    }
}
