//! Load paths: the predictor, sensitivities, friction's history, budgets and
//! hand-overs.

use crate::support::*;
use axle::geom::Vec3;
use axle::model::*;
use axle::statics::{self, Problem, State, StaticsErrorKind};

/// The path simulator keeps one solver along the path, so every case after
/// the first starts with the previous equilibrium's factorisation as a linear
/// predictor: it needs fewer factorisations than the same case solved by a
/// fresh solver from the same start, which factorises on every Newton step
/// but the chord steps near the equilibrium.
/// (Fails when the predictor is not used: the counts are then equal.)
#[test]
fn the_path_reuses_the_previous_factorisation_as_a_predictor() {
    let m = mcpherson(1000.0);
    let set = m.model.load_set_named("thesis_table_5_1").expect("set");
    let problem = Problem::new(&m.model).expect("problem");
    let path = statics::path::solve_path(&problem, set).expect("the path solves");
    let mut fresh_total = 0;
    let mut path_total = 0;
    let mut predicted = 0;
    for k in 1..path.len() {
        let fresh = statics::solve(&problem, &m.model.point_loads(set, k), &path[k - 1].state)
            .expect("the case solves alone");
        eprintln!(
            "case {}: path {} factorisations in {} iterations, fresh {} in {}",
            k + 1,
            path[k].factorizations,
            path[k].iterations,
            fresh.factorizations,
            fresh.iterations
        );
        // A fresh solver factorises for every Newton step but its chord
        // steps, each of which follows a factorised step.
        assert!(
            2 * fresh.factorizations >= fresh.iterations,
            "case {}",
            k + 1
        );
        // Both reach the same equilibrium.
        let (a, b) = (
            path[k].state.part_pose(PartId(1)).0,
            fresh.state.part_pose(PartId(1)).0,
        );
        assert!((a - b).norm() < 1e-8, "case {}: {a} {b}", k + 1);
        fresh_total += fresh.factorizations;
        path_total += path[k].factorizations;
        assert!(
            path[k].factorizations <= fresh.factorizations,
            "case {}",
            k + 1
        );
        predicted += usize::from(path[k].factorizations < fresh.factorizations);
    }
    eprintln!(
        "cases 2..13: path {path_total} factorisations, fresh solvers {fresh_total}; predictor saved one in {predicted} cases"
    );
    assert!(
        predicted >= 9,
        "the predictor worked in only {predicted} of 12 cases"
    );
}

/// The sensitivity service along a whole path (`thesis_table_5_1`) against
/// central differences of whole path solves: part poses, a landmark-like
/// point and the wheel toe, for a bushing stiffness, a rotational stiffness,
/// the spring's rate and free length (force parameters, changed in place in
/// the compiled problem) and a joint point (geometry, recompiled).
#[test]
fn path_sensitivities_match_central_differences_of_whole_solves() {
    use axle::model::address::Address;
    use axle::statics::Parameter;
    use axle::statics::path::{Simulator, set_loads, simulate};
    let m = mcpherson(1000.0);
    let set = m.model.load_set_named("thesis_table_5_1").expect("set");
    let cases = set_loads(&m.model, set).expect("loads");
    let names = ["A.k_x", "B.kt_z", "spring.k", "spring.free_length", "L7.z"];
    let params: Vec<Address> = names
        .iter()
        .map(|n| Address::parse(&m.model, n).expect("address"))
        .collect();
    let problem = Problem::new(&m.model).expect("problem");
    let design = State::design(&m.model);
    let (run, sens) =
        Simulator::new().run_with_sensitivities(&problem, &cases, &design, &[], &params);
    let sens = sens.expect("sensitivities");
    let steps = run.into_result().expect("the path solves");
    assert_eq!(sens.len(), cases.len());
    let upright = m.model.part_named("upright").expect("upright");
    let wheel = &m.model.wheels[0];
    let point = Vec3::new(50.0, 700.0, 200.0);
    // Largest error and largest derivative, per 1 % of each parameter:
    // point (mm) and toe (deg).
    let (mut err, mut size) = ([0.0f64; 2], [0.0f64; 2]);
    for (j, p) in params.iter().enumerate() {
        let v = p.value(&m.model);
        let h = 1e-4 * v.abs().max(1.0);
        let solve_at = |x: f64| {
            let mut mm = m.model.clone();
            p.set_value(&mut mm, x);
            let pr = Problem::new(&mm).expect("problem");
            simulate(&pr, &cases, &design)
                .into_result()
                .expect("solves")
        };
        let (plus, minus) = (solve_at(v + h), solve_at(v - h));
        let unit = 0.01 * v.abs().max(1.0);
        for k in 0..cases.len() {
            let st = &steps[k].state;
            let at = |e: &statics::Equilibrium| {
                let (x, r) = e.state.part_pose(upright);
                let q = axle::kc::wheel_quantities(&m.model, &e.state, wheel);
                (x + r * point, q.toe_deg)
            };
            let ((pp, tp), (pm, tm)) = (at(&plus[k]), at(&minus[k]));
            let fd_point = (pp - pm) / (2.0 * h);
            let fd_toe = (tp - tm) / (2.0 * h);
            let d_point = sens[k].point(st, upright, &point).column(j).into_owned();
            let d_toe = sens[k].output(&problem, st, |s| {
                axle::kc::wheel_quantities(&m.model, s, wheel).toe_deg
            })[j];
            err[0] = err[0].max((d_point - fd_point).amax() * unit);
            err[1] = err[1].max((d_toe - fd_toe).abs() * unit);
            size[0] = size[0].max(fd_point.amax() * unit);
            size[1] = size[1].max(fd_toe.abs() * unit);
        }
        eprintln!(
            "{}: worst so far {:.2e} mm, {:.2e} deg per 1 %",
            names[j], err[0], err[1]
        );
    }
    eprintln!(
        "largest effect of 1 % of a parameter: {:.3} mm, {:.4} deg",
        size[0], size[1]
    );
    assert!(
        size[0] > 1e-3 && size[1] > 1e-4,
        "the parameters move the wheel"
    );
    assert!(
        err[0] < 1e-6 * size[0],
        "point: {:e} against {:e}",
        err[0],
        size[0]
    );
    assert!(
        err[1] < 1e-5 * size[1],
        "toe: {:e} against {:e}",
        err[1],
        size[1]
    );
}

/// The McPherson with dry friction on the strut slide L5 (kf 1000 N/mm,
/// Ff `limit` N), as the friction engineer's example states it.
fn mcpherson_with_friction(limit: f64) -> Model {
    let mut m = mcpherson(1000.0).model;
    let joint = JointId(
        m.joints
            .iter()
            .position(|j| j.name == "L5")
            .expect("joint L5") as u32,
    );
    m.frictions.push(Friction {
        name: "L5_friction".into(),
        joint,
        motion: FrictionMotion::Slide,
        stiffness: Val::lit(1000.0),
        limit: Val::lit(limit),
    });
    m
}

/// Identification warm-starts step k from the previous iterate's solution at
/// step k. With friction the history must still come from the path's own
/// step k - 1: a path guessed from another model's solution (a smaller
/// friction limit, so other slip offsets) equals the cold path exactly, while
/// starting each step from the guessed state whole (its history included)
/// gives other physics.
#[test]
fn warm_started_paths_keep_the_friction_history_of_the_cold_path() {
    use axle::statics::path::{Simulator, set_loads, simulate};
    let m = mcpherson_with_friction(150.0);
    let other = mcpherson_with_friction(50.0);
    let set = m.load_set_named("bump").expect("bump set");
    let cases = set_loads(&m, set).expect("loads");
    let (p, po) = (
        Problem::new(&m).expect("problem"),
        Problem::new(&other).expect("problem"),
    );
    let design = State::design(&m);
    let cold = simulate(&p, &cases, &design)
        .into_result()
        .expect("cold path");
    let guesses: Vec<State> = simulate(&po, &cases, &design)
        .into_result()
        .expect("the other path")
        .into_iter()
        .map(|e| e.state)
        .collect();
    let warm = Simulator::new()
        .run(&p, &cases, &design, &guesses)
        .into_result()
        .expect("warm path");
    let f = FrictionId(0);
    let upright = m.part_named("upright").expect("upright");
    let (mut same, mut whole_differs, mut slip_range) = (0.0f64, 0.0f64, (f64::MAX, f64::MIN));
    for k in 0..cases.len() {
        let (a, b) = (&cold[k].state, &warm[k].state);
        same = same
            .max((a.part_pose(upright).0 - b.part_pose(upright).0).amax())
            .max((a.slip_offset(&m, f) - b.slip_offset(&m, f)).abs());
        slip_range = (
            slip_range.0.min(a.slip_offset(&m, f)),
            slip_range.1.max(a.slip_offset(&m, f)),
        );
        // The old way: the whole guessed state, its slip history included.
        let whole = statics::solve(&p, &cases[k], &guesses[k]).expect("solves");
        whole_differs =
            whole_differs.max((whole.state.part_pose(upright).0 - a.part_pose(upright).0).amax());
    }
    eprintln!(
        "warm vs cold: {same:.2e}; whole guessed state vs cold: {whole_differs:.3e} mm; slip {:.4}..{:.4} mm",
        slip_range.0, slip_range.1
    );
    assert!(
        slip_range.1 - slip_range.0 > 1e-2,
        "the friction slips along the path"
    );
    assert!(
        same < 1e-8,
        "warm-started path differs from the cold one by {same:e}"
    );
    assert!(
        whole_differs > 1e-3,
        "the guessed history would have changed the physics"
    );
}

/// With friction, sensitivities along a path come from central differences of
/// whole paths (the per-case implicit derivative would miss the history's
/// dependence on the parameter): checked along the bump path against an
/// independent central difference of whole solves with a 100 times larger step.
#[test]
fn path_sensitivities_with_friction_match_central_differences() {
    use axle::model::address::Address;
    use axle::statics::Parameter;
    use axle::statics::path::{Simulator, set_loads, simulate};
    let m = mcpherson_with_friction(150.0);
    let set = m.load_set_named("bump").expect("bump set");
    let cases = set_loads(&m, set).expect("loads");
    let p = Problem::new(&m).expect("problem");
    let design = State::design(&m);
    let params = vec![Address::parse(&m, "A.k_x").expect("address")];
    let (_, sens) = Simulator::new().run_with_sensitivities(&p, &cases, &design, &[], &params);
    let sens = sens.expect("sensitivities");
    let upright = m.part_named("upright").expect("upright");
    let v = params[0].value(&m);
    let h = 1e-3 * v;
    let at = |x: f64| {
        let mut mm = m.clone();
        params[0].set_value(&mut mm, x);
        simulate(&Problem::new(&mm).expect("problem"), &cases, &design)
            .into_result()
            .expect("solves")
    };
    let (plus, minus) = (at(v + h), at(v - h));
    let (mut worst, mut scale) = (0.0f64, 0.0f64);
    for k in 0..cases.len() {
        let fd =
            (plus[k].state.part_pose(upright).0 - minus[k].state.part_pose(upright).0) / (2.0 * h);
        let (d, _) = sens[k].part(upright, 0);
        worst = worst.max((d - fd).amax());
        scale = scale.max(fd.amax());
    }
    eprintln!("friction path sensitivity: worst {worst:.2e} of {scale:.2e} mm per N/mm");
    assert!(scale > 0.0);
    assert!(worst < 1e-3 * scale, "{worst:e} vs {scale:e}");
}

/// A path's sub-step budget (`Simulator::with_budget`): every load step a
/// case takes (one when it converges at once) counts against `per_case` per
/// case so far plus `extra`; the run fails at the case that finds the budget
/// spent, names it, and keeps the cases before; a budget that covers the path
/// gives exactly the unbudgeted result.
#[test]
fn a_path_that_exhausts_its_sub_step_budget_fails_at_that_case() {
    use axle::statics::path::Simulator;
    let m = mcpherson(1000.0);
    let problem = Problem::new(&m.model).expect("compiles");
    let cases: Vec<_> = [3000.0, 3300.0, 3600.0, 3900.0]
        .iter()
        .map(|&fz| wheel(&m, 0.0, 0.0, fz))
        .collect();
    let start = State::design(&m.model);
    let free = Simulator::new().run(&problem, &cases, &start, &[]);
    assert!(free.failure.is_none(), "{:?}", free.failure);
    assert!(free.steps[1..].iter().all(|e| e.substeps == 0));
    // Nothing per case and one step in all: the fresh solver's first case is
    // not counted, the second takes the one step, the third finds none left.
    let tight = Simulator::with_budget(0, 1).run(&problem, &cases, &start, &[]);
    let f = tight.failure.expect("the third case exceeds the budget");
    assert_eq!((f.case, tight.steps.len()), (2, 2));
    assert_eq!(f.error.kind, StaticsErrorKind::NotConverged);
    assert!(f.error.detail.contains("budget"), "{}", f.error.detail);
    assert_eq!(tight.steps[1].state, free.steps[1].state);
    let ample = Simulator::with_budget(1, 0).run(&problem, &cases, &start, &[]);
    assert!(ample.failure.is_none(), "{:?}", ample.failure);
    assert_eq!(ample.steps[3].state, free.steps[3].state);
}

/// A path run case by case (`Simulator::run_each`, as `solve --format
/// json` writes a long path) hands every converged case over in order, the
/// same equilibria as the run that keeps them all, and keeps only the last;
/// a break stops it there.
#[test]
fn a_path_handed_over_case_by_case_keeps_only_its_last_state() {
    use axle::statics::path::Simulator;
    use std::ops::ControlFlow;
    let m = mcpherson(1000.0);
    let problem = Problem::new(&m.model).expect("compiles");
    let cases: Vec<_> = [3000.0, 4500.0, 2500.0, 6000.0]
        .iter()
        .map(|&fz| wheel(&m, 500.0, -800.0, fz))
        .collect();
    let start = State::design(&m.model);
    let kept = Simulator::new().run(&problem, &cases, &start, &[]);
    assert!(kept.failure.is_none(), "{:?}", kept.failure);
    let mut seen = Vec::new();
    let each = Simulator::new().run_each(&problem, &cases, &start, |k, eq| {
        seen.push((k, eq.state.clone()));
        ControlFlow::Continue(())
    });
    assert!(each.failure.is_none(), "{:?}", each.failure);
    assert_eq!(seen.len(), 4);
    for (k, (case, state)) in seen.iter().enumerate() {
        assert_eq!((*case, state), (k, &kept.steps[k].state));
    }
    assert_eq!(each.steps.len(), 1);
    assert_eq!(each.steps[0].state, kept.steps[3].state);
    // A break (the output gone) stops the path at that case, not a failure.
    let mut count = 0;
    let stopped = Simulator::new().run_each(&problem, &cases, &start, |_, _| {
        count += 1;
        if count == 2 {
            ControlFlow::Break(())
        } else {
            ControlFlow::Continue(())
        }
    });
    assert!(stopped.failure.is_none(), "{:?}", stopped.failure);
    assert_eq!(count, 2);
    assert_eq!(stopped.steps.len(), 1);
    assert_eq!(stopped.steps[0].state, kept.steps[1].state);
}
