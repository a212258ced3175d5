//! Identification failures and fit notes are data: each failure has its kind
//! and code (E11xx, `docs/language.md`) and names the elements responsible; a
//! statics failure underneath is kept whole as the source.

mod common;
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

/// Issue 15: `identify` on landmark data that cannot determine anything
/// says what is missing (the checks `locate` makes, `locate::preflight`).
mod data_preflight {
    use super::common::{axle, scratch};

    const DATA: &str =
        include_str!("data/expected/mcpherson_thesis_table_4_4_landmarks_sigma0.05_seed1.csv");

    /// The header and the rows of `DATA` that `keep` accepts (step, part).
    fn rows(keep: impl Fn(&str, &str) -> bool) -> String {
        let mut out = String::new();
        for l in DATA.lines().filter(|l| !l.starts_with('#')) {
            let mut f = l.split(',');
            let (step, part) = (f.next().unwrap_or(""), f.next().unwrap_or(""));
            if step == "step" || keep(step, part) {
                out += l;
                out += "\n";
            }
        }
        out
    }

    fn identify(name: &str, csv: &str, loads: &str, method: &str) -> (i32, String, String) {
        let (data, loads) = (
            scratch(name, csv),
            scratch(&format!("{name}.loads.csv"), loads),
        );
        let args = ["identify", "examples/mcpherson.axle", "--landmarks", &data];
        let rest = ["--loads", &loads, "--method", method];
        axle(&[&args[..], &rest[..]].concat())
    }

    /// No number in the output: one error and nothing on stdout.
    fn one_error(code: i32, out: &str, err: &str, expected: &str) {
        assert_eq!(code, 1, "{out}{err}");
        assert!(out.is_empty(), "{out}");
        assert!(err.contains(expected), "{err}");
        assert_eq!(err.matches("error[").count(), 1, "{err}");
        assert!(!err.contains("NaN") && !err.contains("inf"), "{err}");
    }

    /// One measured state (today: E1105 for the iterative method, a table of
    /// "does not affect the observations" for lsq).
    #[test]
    fn one_state_is_an_error_for_every_method() {
        let loads = "step,fx,fy,fz\n1,0,0,1500\n";
        for method in ["iterative", "lsq"] {
            let (code, out, err) = identify(
                "identify_one_step.csv",
                &rows(|s, _| s == "1"),
                loads,
                method,
            );
            one_error(
                code,
                &out,
                &err,
                "error[E0810]: identify needs at least two measured states with relative motion: the data has 1 (step 1)",
            );
            assert!(
                err.contains("identify_one_step.csv"),
                "the data file named: {err}"
            );
        }
    }

    /// The same state measured twice (today: a table of parameters kept at
    /// their values for "no deformation or force spread").
    #[test]
    fn two_identical_states_are_no_motion() {
        let first = rows(|s, _| s == "1");
        let again: String = first
            .lines()
            .skip(1)
            .map(|l| format!("2{}\n", &l[1..]))
            .collect();
        let loads = "step,fx,fy,fz\n1,0,0,1500\n2,0,0,1500\n";
        for method in ["iterative", "lsq"] {
            let csv = format!("{first}{again}");
            let (code, out, err) = identify("identify_same_twice.csv", &csv, loads, method);
            one_error(
                code,
                &out,
                &err,
                "no two connected parts move relative to each other between steps 1, 2",
            );
        }
    }

    /// A part the model gives landmarks, absent from the data (today: the
    /// iterative and lsq methods identify what they can and say nothing;
    /// direct already fails with E1104 naming the part).
    #[test]
    fn a_measured_part_missing_from_the_data_is_named() {
        let loads: String = std::iter::once("step,fx,fy,fz\n".to_string())
            .chain((1..=17).map(|s| format!("{s},0,0,{}\n", 1000 + 100 * s)))
            .collect();
        for method in ["direct", "iterative", "lsq"] {
            let (code, out, err) = identify(
                "identify_no_tie_rod.csv",
                &rows(|_, p| p != "tie_rod"),
                &loads,
                method,
            );
            one_error(
                code,
                &out,
                &err,
                "error[E0811]: the landmark data measures no pose of part `tie_rod`",
            );
            assert!(
                err.contains("these cannot be identified: `L3`, `L6`"),
                "{err}"
            );
            assert!(
                err.contains("examples/mcpherson.axle:42"),
                "at the part: {err}"
            );
        }
    }
}
