//! A model without some of its force elements, for the axle metrics "without
//! the bar" (`axle kc --without bar.torsion`): each named bushing, spring,
//! stop or friction keeps its place and its id (so every id and origin a
//! diagnostic uses stays right) but carries nothing: zero laws, zero
//! preloads and offsets. Joints are not force elements: taking one away
//! changes the mechanism, not its stiffness, and is refused.

use crate::diagnostic::Diagnostic;
use crate::diagnostic::suggest::did_you_mean;
use crate::model::law::{AxisLaw, AxisLaws};
use crate::model::param::{Val, vals};
use crate::model::{Model, SpringLaw, StopLaw};

/// Laws that give no force at any deformation.
fn inert() -> AxisLaws {
    AxisLaws::General([
        AxisLaw::linear(0.0),
        AxisLaw::linear(0.0),
        AxisLaw::linear(0.0),
    ])
}

/// `model` with each force element of `names` carrying nothing. A name that
/// is no force element of the model is error E0812 (a usage error), with a
/// did-you-mean among the force elements.
pub fn without(model: &Model, names: &[String]) -> Result<Model, Diagnostic> {
    let mut m = model.clone();
    for name in names {
        if let Some(b) = m.bushings.iter_mut().find(|b| &b.name == name) {
            b.translational = inert();
            b.rotational = inert();
            b.offset = vals([0.0; 3]);
            b.angle_offset = vals([0.0; 3]);
            b.preload = vals([0.0; 3]);
            b.torque_preload = vals([0.0; 3]);
        } else if let Some(s) = m.springs.iter_mut().find(|s| &s.name == name) {
            // The free length is kept: with no rate and no preload it gives
            // no force, and the checker's rule (positive) still holds.
            let free_length = match &s.law {
                SpringLaw::Linear { free_length, .. } => *free_length,
                SpringLaw::Table(_) => Val::lit(1.0),
            };
            s.law = SpringLaw::Linear {
                k: Val::ZERO,
                free_length,
                preload: Val::ZERO,
            };
        } else if let Some(s) = m.stops.iter_mut().find(|s| &s.name == name) {
            s.law = StopLaw::Polynomial(Vec::new());
        } else if let Some(f) = m.frictions.iter_mut().find(|f| &f.name == name) {
            f.stiffness = Val::ZERO;
            f.limit = Val::ZERO;
        } else {
            let elements: Vec<&str> = model
                .bushings
                .iter()
                .map(|b| b.name.as_str())
                .chain(model.springs.iter().map(|s| s.name.as_str()))
                .chain(model.stops.iter().map(|s| s.name.as_str()))
                .chain(model.frictions.iter().map(|f| f.name.as_str()))
                .collect();
            let mut d = Diagnostic::error(
                "E0812",
                format!(
                    "--without `{name}`: the model has no bushing, spring, stop or friction of that name"
                ),
            );
            if model.joints.iter().any(|j| &j.name == name) {
                d = d.note(format!(
                    "`{name}` is a joint: without it the mechanism changes, so it cannot be left out"
                ));
            }
            d = match did_you_mean(name, elements.iter().copied()) {
                Some(h) => d.hint(h),
                None => d.hint(format!("its force elements: {}", elements.join(", "))),
            };
            return Err(d);
        }
    }
    Ok(m)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::check::check_str;

    const TWO: &str = r#"
model two
ground chassis {
    marker a at (0, 0, 100) mm
    marker s at (0, 0, 200) mm
}
part arm {
    marker a at (0, 0, 100) mm
    marker s at (0, 0, 0) mm
}
bushing B {
    i arm.a
    j chassis.a
    k (100, 100, 100) N/mm
    kt (1000, 1000, 1000) N*mm/deg
    preload (0, 0, 5) N
}
spring S {
    i arm.s
    j chassis.s
    k 10 N/mm
    free_length 250 mm
}
"#;

    fn model() -> Model {
        let (_, c) = check_str("two.axle", TWO);
        c.model.expect("checks")
    }

    #[test]
    fn a_bushing_and_a_spring_left_out_carry_nothing_at_any_deformation() {
        let m = without(&model(), &["B".to_string(), "S".to_string()]).expect("both exist");
        let b = &m.bushings[0];
        for laws in [&b.translational, &b.rotational] {
            let AxisLaws::General(l) = laws else {
                panic!("three laws")
            };
            assert!(l.iter().all(|x| x.eval(3.0) == (0.0, 0.0)));
        }
        assert_eq!(b.preload[2].value, 0.0);
        match &m.springs[0].law {
            SpringLaw::Linear { k, preload, .. } => {
                assert_eq!((k.value, preload.value), (0.0, 0.0))
            }
            l => panic!("{l:?}"),
        }
        // Ids and names stay.
        assert_eq!((m.bushings.len(), m.bushings[0].name.as_str()), (1, "B"));
    }

    #[test]
    fn a_name_that_is_no_force_element_is_e0812_with_a_suggestion() {
        let e = without(&model(), &["b".to_string()]).expect_err("no such element");
        assert_eq!(e.code, "E0812");
        assert_eq!(e.hint.as_deref(), Some("did you mean `B`?"));
    }
}
