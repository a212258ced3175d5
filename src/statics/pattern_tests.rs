//! The pattern's slots against the stored structure, and the structure
//! against every entry the dense assembly writes.

use super::*;
use crate::statics::assembly::Workspace;

/// The slots found once per equation and part are the entries
/// `(n + k, col)` and `(col, n + k)` of the stored structure (found by
/// scanning its rows), for every multiplier and every coordinate of
/// three coupled corners; none for a part the equation does not act on.
#[test]
fn constraint_slots_are_the_stored_entries() {
    let (m, _) = crate::statics::testkit::coupled_corners(3);
    let p = Problem::new(&m).expect("problem");
    let pat = Pattern::new(&p).expect("pattern");
    let (n, mm) = (p.layout.n(), p.kept.len());
    let entry = |row: usize, col: usize| {
        (pat.col_ptr[col]..pat.col_ptr[col + 1]).find(|&s| pat.row_idx[s] == row)
    };
    let mut found = 0;
    for k in 0..mm {
        for col in 0..n {
            let searched = entry(n + k, col).zip(entry(col, n + k));
            assert_eq!(pat.constraint_slots(k, col), searched, "({k}, {col})");
            found += usize::from(searched.is_some());
        }
    }
    assert!(found >= 6 * mm, "{found}");
    // Each column's coordinate rows come first, up to `coord_end`.
    for col in 0..n + mm {
        let (start, mid, end) = (pat.col_ptr[col], pat.coord_end[col], pat.col_ptr[col + 1]);
        assert!(start < mid && mid <= end, "column {col}");
        assert!(
            pat.row_idx[start..mid].iter().all(|&r| r < n),
            "column {col}"
        );
        assert!(
            pat.row_idx[mid..end].iter().all(|&r| r >= n),
            "column {col}"
        );
        assert_eq!(
            mid == end,
            col >= n || pat.row_idx[start..end].iter().all(|&r| r < n)
        );
    }
}

/// The slots of a 3×3 block of `K` are the stored entries `(row + a,
/// col + b)` (found by scanning the column's rows), for every pair of
/// block rows and columns of three coupled corners, both from the table
/// of coupled parts and from the search it replaces (kept for models of
/// more than `BLOCK_TABLE_PARTS` parts); none for parts not coupled,
/// columns that run into the next part, or the multipliers' rows.
#[test]
fn block_slots_are_the_stored_entries() {
    let (m, _) = crate::statics::testkit::coupled_corners(3);
    let p = Problem::new(&m).expect("problem");
    let table = Pattern::new(&p).expect("pattern");
    let mut searched = table.clone();
    searched.block_at.clear();
    assert_eq!(table.block_at.len(), table.parts.len().pow(2));
    let n = p.layout.n();
    let entry = |row: usize, col: usize| {
        (table.col_ptr[col]..table.col_ptr[col + 1]).find(|&s| table.row_idx[s] == row)
    };
    let (mut coupled, mut apart) = (0, 0);
    for col in (0..n).step_by(3) {
        for row in (0..n).step_by(3) {
            // Each of the block's columns holds rows `row..row + 3` contiguously.
            let stored: Option<[usize; 3]> = (0..3)
                .map(|b| {
                    let first = entry(row, col + b)?;
                    (1..3)
                        .all(|a| entry(row + a, col + b) == Some(first + a))
                        .then_some(first)
                })
                .collect::<Option<Vec<_>>>()
                .map(|v| [v[0], v[1], v[2]]);
            assert_eq!(table.block_slots(row, col), stored, "({row}, {col})");
            assert_eq!(searched.block_slots(row, col), stored, "({row}, {col})");
            if stored.is_some() {
                coupled += 1;
            } else {
                apart += 1;
            }
        }
        // The multipliers' rows are not `K`'s.
        assert_eq!(table.block_slots(n, col), None);
        assert_eq!(searched.block_slots(n, col), None);
        // Columns that run into the next part.
        for c in [6 * (col / 6) + 4, 6 * (col / 6) + 5] {
            assert_eq!(table.block_slots(0, c), None);
            assert_eq!(searched.block_slots(0, c), None);
        }
    }
    assert!(coupled >= 4 * n / 3 && apart > coupled, "{coupled} {apart}");
}

/// Every entry the dense assembly writes, at a loaded state away from
/// equilibrium, is in the pattern: the structure read at design holds
/// elsewhere.
#[test]
fn the_pattern_holds_every_entry_of_the_mcpherson_matrix() {
    let m = crate::statics::testkit::mcpherson();
    let p = Problem::new(&m).expect("problem");
    let pat = Pattern::new(&p).expect("pattern");
    let st = away_from_equilibrium(&m, &p);
    let loads = vec![crate::model::PointLoad {
        marker: m.wheels[0].contact,
        force: crate::geom::Vec3::new(2000.0, -3000.0, 4500.0),
        torque: crate::geom::Vec3::zeros(),
    }];
    let a = dense_matrix(&p, &st, &loads);
    let mut inside = vec![false; pat.dim() * pat.dim()];
    for j in 0..pat.dim() {
        for &i in &pat.row_idx[pat.col_ptr[j]..pat.col_ptr[j + 1]] {
            inside[i + pat.dim() * j] = true;
        }
    }
    let mut written = 0;
    for j in 0..pat.dim() {
        for i in 0..pat.dim() {
            if a[(i, j)] != 0.0 {
                written += 1;
                assert!(inside[i + pat.dim() * j], "({i}, {j}) outside the pattern");
            }
        }
    }
    assert!(
        written > 300 && pat.nnz() < pat.dim() * pat.dim() / 2,
        "{written} {}",
        pat.nnz()
    );
}

/// The sparse assembly, which keeps each wrench's slots from one
/// evaluation to the next ([`Pattern::wrench_slots`]), writes the dense
/// assembly's matrix to the bit, also when a load moves to another part
/// between evaluations (its slots then found again) and back.
#[test]
fn the_sparse_assembly_keeps_its_slots_only_for_the_same_parts() {
    let m = crate::statics::testkit::mcpherson();
    let p = Problem::new(&m).expect("problem");
    let st = away_from_equilibrium(&m, &p);
    let contact = m.wheels[0].contact;
    let at_contact = m.markers[contact.index()].part;
    // A marker of another moving part than the contact's.
    let other = (0..m.markers.len())
        .map(|i| crate::model::MarkerId(i as u32))
        .find(|&k| {
            let part = m.markers[k.index()].part;
            part != at_contact && p.layout.block_of_part[part.index()].is_some()
        })
        .expect("a marker of another moving part");
    let load = |marker| crate::model::PointLoad {
        marker,
        force: crate::geom::Vec3::new(1500.0, -2500.0, 4000.0),
        torque: crate::geom::Vec3::new(0.0, 2.0e4, 0.0),
    };
    let mut sparse = Workspace::new(&p);
    assert!(
        matches!(sparse.a, crate::statics::tangent::NewtonMatrix::Sparse(..)),
        "the sparse path"
    );
    let at_the_contact = dense_matrix(&p, &st, &[load(contact)]);
    let mut moved = 0;
    for marker in [contact, other, other, contact] {
        let loads = [load(marker)];
        let want = dense_matrix(&p, &st, &loads);
        sparse.eval(&p, &st, &loads, true).expect("evaluates");
        assert_same_bits(&want, &sparse.matrix());
        moved += usize::from(want != at_the_contact);
    }
    // The other marker's load changes the matrix (its stiffness lands in
    // other blocks), so the test moves a wrench to other slots.
    assert_eq!(moved, 2);
}

/// A block outside the pattern (a bushing coupling the two arms, in a
/// workspace given the McPherson's own pattern, where they are not
/// coupled) is found by the kept slots' check, and the evaluation falls
/// back to dense storage: the dense assembly's matrix, to the bit.
#[test]
fn a_block_outside_the_pattern_falls_back_to_the_dense_matrix() {
    let base = include_str!("../../examples/mcpherson.axle");
    let coupled = format!(
        "{base}\nbushing arms {{\n    i front_arm.B\n    j rear_arm.A\n    k (100, 200, 300) N/mm\n    kt (400, 500, 600) N*mm/deg\n}}\n"
    );
    let (_, c) = crate::check::check_str("coupled.axle", &coupled);
    let m = c.model.expect("the coupled model checks");
    let own = Problem::new(&crate::statics::testkit::mcpherson()).expect("problem");
    let p = Problem::new(&m).expect("problem");
    assert_eq!(p.layout.n() + p.kept.len(), own.layout.n() + own.kept.len());
    let narrow = own.pattern.as_ref().expect("the sparse path");
    let wide = p.pattern.as_ref().expect("the sparse path");
    assert!(narrow.nnz() < wide.nnz(), "the arms' coupling adds slots");
    let st = away_from_equilibrium(&m, &p);
    let mut ws = Workspace::with_pattern(&p, narrow);
    ws.eval(&p, &st, &[], true).expect("evaluates");
    assert!(
        matches!(ws.a, crate::statics::tangent::NewtonMatrix::Dense(_)),
        "fell back to dense storage"
    );
    assert_same_bits(&dense_matrix(&p, &st, &[]), &ws.matrix());
    // With its own pattern, the coupled model stays sparse.
    let mut own_slots = Workspace::with_pattern(&p, wide);
    own_slots.eval(&p, &st, &[], true).expect("evaluates");
    assert!(matches!(
        own_slots.a,
        crate::statics::tangent::NewtonMatrix::Sparse(..)
    ));
}

/// A state of `m` away from equilibrium: every coordinate moved and every
/// multiplier non-zero, so every entry the matrix can have is written.
fn away_from_equilibrium(m: &crate::model::Model, p: &Problem) -> State {
    let mut st = State::design(m);
    let dq = nalgebra::DVector::from_fn(p.layout.n(), |i, _| 0.01 * ((i as f64) * 0.7).sin());
    st.apply(&p.layout, &dq);
    st.lambda = (0..p.kept.len()).map(|k| 1.0 + k as f64).collect();
    st
}

/// The dense assembly's Newton matrix at `st` under `loads`.
fn dense_matrix(
    p: &Problem,
    st: &State,
    loads: &[crate::model::PointLoad],
) -> nalgebra::DMatrix<f64> {
    let mut ws = Workspace::dense(p);
    ws.eval(p, st, loads, true).expect("evaluates");
    ws.matrix()
}

/// `got` is `want` to the bit.
fn assert_same_bits(want: &nalgebra::DMatrix<f64>, got: &nalgebra::DMatrix<f64>) {
    for (w, g) in want.iter().zip(got.iter()) {
        assert_eq!(w.to_bits(), g.to_bits(), "{w} {g}");
    }
}
