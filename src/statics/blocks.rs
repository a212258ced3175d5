//! The independent blocks of the Newton matrix: groups of moving parts that
//! no element, joint or load couples to another group (they share at most
//! the ground), with the multipliers of their joints. The matrix is block
//! diagonal over them (after a permutation), so [`super::linear::Lu`]
//! factorises each block on its own: a model of N corners on one ground
//! costs N corner factorisations, not one of an N-times larger matrix.
//!
//! The structure comes from which parts each wrench acts on, not from the
//! values at one state, so it holds at every state (a stop out of contact
//! still couples its parts structurally, with zero stiffness).

use super::Problem;
use super::constraint::evaluate;
use super::coords::State;
use super::forces::for_each_element;

fn find(parent: &mut [usize], mut i: usize) -> usize {
    while parent[i] != i {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    i
}

fn unite(parent: &mut [usize], a: usize, b: usize) {
    let (ra, rb) = (find(parent, a), find(parent, b));
    if ra != rb {
        parent[ra.max(rb)] = ra.min(rb);
    }
}

/// The groups of Newton-matrix indices (coordinates `0..n`, multipliers
/// `n..n+m`), each ascending, in the order of their first index; one group
/// when the model is one mechanism or its structure cannot be read at `st`.
pub fn groups(p: &Problem, st: &State) -> Vec<Vec<usize>> {
    let n = p.layout.n();
    let m = p.kept.len();
    let all = || vec![(0..n + m).collect::<Vec<usize>>()];
    let parts = n / 6;
    let mut parent: Vec<usize> = (0..parts).collect();
    let coupled = for_each_element(&p.model, &p.layout, st, |_, w| {
        if let [Some(a), Some(b)] = w.offsets() {
            unite(&mut parent, a / 6, b / 6);
        }
    });
    if coupled.is_err() {
        return all();
    }
    // The part each multiplier belongs to (a joint of two moving parts unites them).
    let mut owner = Vec::with_capacity(m);
    for &e in &p.kept {
        let (_, w) = evaluate(&p.model, &p.layout, st, &p.equations[e]);
        match w.offsets() {
            [Some(a), Some(b)] => {
                unite(&mut parent, a / 6, b / 6);
                owner.push(a / 6);
            }
            [Some(a), None] | [None, Some(a)] => owner.push(a / 6),
            [None, None] => return all(),
        }
    }
    let mut group_of = vec![usize::MAX; parts];
    let mut out: Vec<Vec<usize>> = Vec::new();
    for part in 0..parts {
        let r = find(&mut parent, part);
        if group_of[r] == usize::MAX {
            group_of[r] = out.len();
            out.push(Vec::new());
        }
        let g = group_of[r];
        out[g].extend(6 * part..6 * part + 6);
    }
    for (k, &part) in owner.iter().enumerate() {
        let g = group_of[find(&mut parent, part)];
        out[g].push(n + k);
    }
    if out.len() <= 1 {
        return all();
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::Model;
    use crate::statics::path::solve_path;

    fn model(text: &str) -> Model {
        let (_, c) = crate::check::check_str("t.axle", text);
        c.model.expect("checks")
    }

    /// `single_bushing.axle` with a second, identical arm on its own bushing
    /// beside the first, loaded by the same cases at its own tip.
    fn two_arms() -> String {
        let one = include_str!("../../examples/single_bushing.axle");
        let mut s = one.replace(
            "    marker b at (0, 0, 0) mm\n}",
            "    marker b at (0, 0, 0) mm\n    marker b2 at (0, 1000, 0) mm\n}",
        );
        s = s.replace(
            "// Identity orientation",
            "part arm2 {\n    marker b at (0, 1000, 0) mm\n    marker tip at (300, 1000, 0) mm\n}\n\nbushing b2 {\n    i ground.b2\n    j arm2.b\n    k (10000, 10000, 10000) N/mm\n    kt (10000, 10000, 10000) N*mm/deg\n}\n\n// Identity orientation",
        );
        s.replace(
            "arm.tip.mz N*mm) {\n    c1   100  200  -300   1000  -2000   500\n    c2  -400   50   250  -3000   1500  2500\n    c3     0    0  1000      0      0     0",
            "arm.tip.mz N*mm, arm2.tip.fx N, arm2.tip.fz N) {\n    c1   100  200  -300   1000  -2000   500  100 -300\n    c2  -400   50   250  -3000   1500  2500  -400 250\n    c3     0    0  1000      0      0     0  0 1000",
        )
    }

    #[test]
    fn two_independent_arms_are_two_blocks_and_solve_as_each_alone() {
        let m2 = model(&two_arms());
        assert_eq!(m2.parts.len(), 3, "the second arm is in the model");
        let p2 = Problem::new(&m2).expect("problem");
        let g = groups(&p2, &State::design(&m2));
        assert_eq!(g, vec![(0..6).collect::<Vec<_>>(), (6..12).collect()]);
        let one = model(include_str!("../../examples/single_bushing.axle"));
        let p1 = Problem::new(&one).expect("problem");
        assert_eq!(groups(&p1, &State::design(&one)).len(), 1);
        let set = |m: &Model| m.load_sets.len() as u32 - 1;
        let e2 = solve_path(&p2, crate::model::LoadSetId(set(&m2))).expect("solves");
        let e1 = solve_path(&p1, crate::model::LoadSetId(set(&one))).expect("solves");
        let arm = |m: &Model, name: &str| m.part_named(name).expect("part");
        for (a, b) in e2.iter().zip(&e1) {
            // the first arm as in the one-arm model
            let (x2, r2) = a.state.part_pose(arm(&m2, "arm"));
            let (x1, r1) = b.state.part_pose(arm(&one, "arm"));
            assert!((x2 - x1).norm() < 1e-9 && (r2 - r1).norm() < 1e-12);
        }
        // the second arm moves under its own loads: fz 1000 N on 10000 N/mm in c3
        let (x, _) = e2[2].state.part_pose(arm(&m2, "arm2"));
        assert!((x.z - 0.1).abs() < 0.05, "{x}");
    }
}
