//! Identification failures and fit notes are data: each failure has its kind
//! and code (E11xx, `docs/language.md`) and names the elements responsible; a
//! statics failure underneath is kept whole as the source.

use axle::identify::{self, IdentifyErrorKind, Measured};
use axle::model::{ElementId, LoadSetId, Model};
use axle::statics::{self, State, StaticsErrorKind};

fn model(src: &str) -> Model {
    let (_, c) = axle::check::check_str("t.axle", src);
    c.model.expect("the model checks")
}

fn single_bushing() -> (Model, Measured) {
    measured(&model(include_str!("../examples/single_bushing.axle")))
}

/// Every case of the model's first load set, solved from design, as measured poses.
fn measured(m: &Model) -> (Model, Measured) {
    let m = m.clone();
    let set = LoadSetId(0);
    let steps: Vec<(State, Vec<_>)> = statics::solve_set(&m, set)
        .expect("truth solves")
        .into_iter()
        .enumerate()
        .map(|(c, e)| (e.state, m.point_loads(set, c)))
        .collect();
    let data = Measured::from_states(&m, &steps);
    (m, data)
}

#[test]
fn iterative_with_one_step_is_undetermined() {
    let (m, mut data) = single_bushing();
    data.steps.truncate(1);
    let u = identify::select_unknowns(&m, &[]).expect("unknowns");
    let e = identify::iterative::identify(&m, &u, &data, Default::default())
        .expect_err("one step cannot be regressed");
    assert_eq!(e.kind, IdentifyErrorKind::Undetermined);
    assert_eq!(e.kind.code(), "E1105");
    assert!(e.elements.is_empty());
    assert!(e.source.is_none());
}

#[test]
fn lsq_with_as_many_unknowns_as_observations_is_undetermined() {
    let (m, mut data) = single_bushing();
    data.steps.truncate(1);
    let u = identify::select_unknowns(&m, &[]).expect("unknowns");
    assert_eq!(u.len(), 6);
    let e = identify::lsq::identify(&m, &u, &data, Default::default())
        .expect_err("6 observations cannot determine 6 unknowns");
    assert_eq!(e.kind.code(), "E1105");
    assert!(
        e.message.contains("cannot determine 6 unknowns"),
        "{}",
        e.message
    );
}

#[test]
fn iterative_without_iterations_is_an_option_error_and_one_iteration_does_not_converge() {
    let (m, data) = single_bushing();
    let mut u = identify::select_unknowns(&m, &[]).expect("unknowns");
    let opts = identify::iterative::IterativeOptions {
        max_iterations: 0,
        ..Default::default()
    };
    let e = identify::iterative::identify(&m, &u, &data, opts).expect_err("no iteration");
    assert_eq!(e.kind.code(), "E1102");
    // Start a factor 10 off: one iteration cannot bring every stiffness
    // within 1 % of the last.
    for x in &mut u {
        x.initial *= 10.0;
    }
    let opts = identify::iterative::IterativeOptions {
        max_iterations: 1,
        ..Default::default()
    };
    let e = identify::iterative::identify(&m, &u, &data, opts).expect_err("one iteration");
    assert_eq!(e.kind, IdentifyErrorKind::NotConverged);
    assert_eq!(e.kind.code(), "E1107");
}

/// A bushing started at zero stiffness holds nothing: the statics solve of the
/// first step fails, and the failure names the bushing's part, keeps the
/// statics error as its source, and says which step.
#[test]
fn statics_failure_at_a_step_keeps_its_source_and_names_the_element() {
    let (m, data) = single_bushing();
    let mut u = identify::select_unknowns(&m, &[]).expect("unknowns");
    for x in &mut u {
        x.initial = 0.0;
    }
    let e = identify::iterative::identify(&m, &u, &data, Default::default())
        .expect_err("nothing holds the arm");
    assert_eq!(e.kind, IdentifyErrorKind::Solve);
    assert_eq!(e.kind.code(), "E1106");
    let s = e.source.as_ref().expect("the statics failure underneath");
    assert_eq!(s.kind, StaticsErrorKind::Unrestrained, "{}", e.message);
    assert_eq!(e.elements, s.elements);
    let arm = m.parts.iter().position(|p| p.name == "arm").expect("arm");
    assert!(
        e.elements
            .contains(&ElementId::Part(axle::model::PartId(arm as u32))),
        "{:?}",
        e.elements
    );
    assert!(
        e.message.starts_with("iteration 1, step 1:"),
        "{}",
        e.message
    );
    let d = e.to_diagnostic(&m);
    assert_eq!(d.code, "E1106");
    assert!(
        d.notes.iter().any(|n| n.contains(s.kind.code())),
        "{:?}",
        d.notes
    );
}

/// The iterative method identifies bushing stiffnesses only: a spring's rate
/// is a method error (E1104) naming the spring.
#[test]
fn iterative_with_a_spring_rate_is_a_method_error_naming_the_spring() {
    let m = model(include_str!("../examples/mcpherson.axle"));
    let u = identify::select_unknowns(&m, &["spring.k".to_string()]).expect("unknowns");
    let (_, data) = measured(&m);
    let e = identify::iterative::identify(&m, &u, &data, Default::default())
        .expect_err("a spring is not a bushing");
    assert_eq!(e.kind, IdentifyErrorKind::Method);
    assert_eq!(e.kind.code(), "E1104");
    let spring = m
        .springs
        .iter()
        .position(|s| s.name == "spring")
        .expect("spring");
    assert_eq!(
        e.elements,
        vec![ElementId::Spring(axle::model::SpringId(spring as u32))]
    );
}
