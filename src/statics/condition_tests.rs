//! The condition estimates against the SVD, the lanes against plain
//! loops, and the continued estimate along a path.

use super::*;

/// The weight is `√(max|K| / max|C|)`, the scaled Frobenius norm that of
/// the matrix scaled entry by entry, and the scaled inverse iteration
/// the inverse iteration of that matrix.
#[test]
fn the_scale_is_that_of_the_matrix_scaled_entry_by_entry() {
    // [K Cᵀ; C 0] with K = diag(400, 9) and C = [0.5 1].
    let a = DMatrix::from_row_slice(3, 3, &[400.0, 0.0, 0.5, 0.0, 9.0, 1.0, 0.5, 1.0, 0.0]);
    let sizes = dense_sizes(&a, 2);
    assert_eq!(sizes.alpha(), 20.0);
    let s = sizes.scale(2);
    let das = scaled(&a, 2);
    assert_eq!(das[(2, 0)], 10.0);
    assert_eq!(das[(1, 2)], 20.0);
    assert!((s.fro - das.norm()).abs() < 1e-12 * das.norm());
    let lu_s = das.clone().lu();
    let lu = a.clone().lu();
    let direct = inverse_iteration(3, das.norm(), |y| {
        let x = lu_s
            .solve(&nalgebra::DVector::from_column_slice(y))
            .expect("regular");
        y.copy_from_slice(x.as_slice());
        true
    });
    let through = s.reciprocal_condition(3, |y| {
        let x = lu
            .solve(&nalgebra::DVector::from_column_slice(y))
            .expect("regular");
        y.copy_from_slice(x.as_slice());
        true
    });
    assert!(
        (direct - through).abs() < 1e-12 * direct,
        "{direct} {through}"
    );
    // Without constraints, or without stiffness, nothing is weighed.
    assert_eq!(dense_sizes(&a, 3).alpha(), 1.0);
    assert_eq!(BlockSizes::default().alpha(), 1.0);
}

/// The lanes give the plain running maximum and sum of each block,
/// whatever the halves' lengths and remainders, and a NaN entry does
/// not replace the maximum.
#[test]
fn lanes_give_the_running_maximum_and_sum() {
    for n in [0usize, 1, 3, 7, 8, 9, 23] {
        let mut x: Vec<f64> = (0..n).map(|i| ((i * 37 % 11) as f64 - 5.0) * 1.5).collect();
        let y: Vec<f64> = x.iter().map(|v| 0.5 * v + 1.0).collect();
        let max = x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let sum: f64 = x.iter().map(|v| v * v).sum();
        let diff: f64 = x.iter().zip(&y).map(|(a, b)| (a - b) * (a - b)).sum();
        // As one coordinate column's coordinate rows (K), and as two
        // columns' halves split unevenly (C of each).
        let mut one = SizeLanes::default();
        one.add_column(true, &x, &[]);
        let mut two = SizeLanes::default();
        let (a, b) = x.split_at(n / 3);
        two.add_column(true, &[], a);
        two.add_column(false, b, &[]);
        let (k, c) = (one.sizes(), two.sizes());
        assert_eq!((largest(&x), k.k_max, c.c_max), (max, max, max), "n = {n}");
        assert_eq!((k.c_max, k.z_max, c.k_max, c.z_sq), (0.0, 0.0, 0.0, 0.0));
        for s in [k.k_sq, c.c_sq] {
            assert!((s - sum).abs() <= 1e-12 * sum.max(1.0), "n = {n}");
        }
        // The differences, weighed by block: all in C here, times α².
        let scale = Scale {
            coords: 0,
            alpha: 3.0,
            fro: 1.0,
        };
        let mut d = DifferenceLanes::default();
        d.add_column(true, (&[], &[]), (a, &y[..a.len()]));
        d.add_column(false, (b, &y[a.len()..]), (&[], &[]));
        assert!((d.total(&scale) - 9.0 * diff).abs() <= 1e-12 * diff.max(1.0));
        // Both in one pass over slots spread through a longer array: the
        // lanes of a run of those entries, to the bit.
        let slots = Slots::new((0..n as u32).map(|k| 3 * k + 1).collect());
        let spread = |v: &[f64]| {
            let mut w = vec![f64::NAN; 3 * n + 2];
            v.iter().enumerate().for_each(|(k, x)| w[3 * k + 1] = *x);
            w
        };
        let mut both = SizeDifferenceLanes::default();
        both.take(1, &slots, &spread(&x), &spread(&y));
        let mut run = SizeLanes::default();
        run.add_column(false, &x, &[]);
        let mut drun = DifferenceLanes::default();
        drun.add_column(false, (&x, &y), (&[], &[]));
        assert_eq!(both.sizes.sizes(), run.sizes(), "n = {n}");
        assert_eq!(
            both.difference.total(&scale).to_bits(),
            drun.total(&scale).to_bits()
        );
        if n > 0 {
            let short = std::panic::catch_unwind(|| {
                SizeDifferenceLanes::default().take(0, &slots, &x, &spread(&y))
            });
            assert!(short.is_err(), "n = {n}: an array shorter than its slots");
        }
        if n > 3 {
            // (the largest, 7.5, is at index 0)
            x[3] = f64::NAN;
            let mut nan = SizeLanes::default();
            nan.add_column(true, &x, &[]);
            assert_eq!(largest(&x), max, "n = {n}");
            assert_eq!(nan.sizes().k_max, max, "n = {n}");
        }
    }
}

/// A residual's size in lanes is the one running maximum's, to the bit,
/// wherever the largest entry sits; a NaN anywhere makes it infinite (the
/// chain it replaced returned infinity from the NaN on, and a later entry
/// could not lower that), an infinity stays one.
#[test]
fn residual_sizes_in_lanes_are_the_chain_and_a_nan_is_infinite() {
    let chain = |v: &[f64]| {
        v.iter().fold(0.0f64, |m, x| {
            if x.is_nan() {
                f64::INFINITY
            } else {
                m.max(x.abs())
            }
        })
    };
    for n in 0..=19usize {
        for at in 0..n.max(1) {
            let mut v: Vec<f64> = (0..n).map(|i| ((i * 7 % 11) as f64 - 5.0) * 0.37).collect();
            if n > 0 {
                v[at] = -12.25;
            }
            assert_eq!(
                largest_or_infinite(&v).to_bits(),
                chain(&v).to_bits(),
                "n = {n}, at {at}"
            );
            if n > 0 {
                v[at] = f64::NAN;
                assert_eq!(
                    largest_or_infinite(&v),
                    f64::INFINITY,
                    "n = {n}, NaN at {at}"
                );
                v[at] = f64::NEG_INFINITY;
                assert_eq!(
                    largest_or_infinite(&v),
                    f64::INFINITY,
                    "n = {n}, -inf at {at}"
                );
            }
        }
    }
    assert_eq!(largest_or_infinite(&[]), 0.0);
}

/// The problem of two coupled McPherson corners and the Newton
/// matrices at its equilibria along table 5-1, in order.
fn corner_matrices() -> (crate::statics::Problem, Vec<DMatrix<f64>>) {
    use crate::statics::Problem;
    use crate::statics::path::{set_loads, solve_path};
    use crate::statics::system::{assemble, kkt};
    use crate::statics::testkit::coupled_corners;
    let (m, set) = coupled_corners(2);
    let p = Problem::new(&m).expect("problem");
    let loads = set_loads(&m, set).expect("loads");
    let eqs = solve_path(&p, set).expect("solves");
    let matrices = eqs
        .iter()
        .zip(&loads)
        .map(|(eq, l)| kkt(&assemble(&p, &eq.state, l).expect("assembles")))
        .collect();
    (p, matrices)
}

/// At the equilibria of a mechanism (two coupled McPherson corners,
/// table 5-1), weighing the multipliers raises the ratio
/// `σ_min / ‖D A D‖_F` of the SVD more than tenfold, and the estimate
/// of both factorisations (dense and sparse) is within 1.3 of it, from
/// above: the estimate a threshold is set on is that of the matrix.
#[test]
fn on_a_mechanism_the_weighed_estimate_is_close_and_far_from_singular() {
    use crate::statics::linear::Lu;
    use crate::statics::tangent::{Factorisation, NewtonMatrix};
    let (p, matrices) = corner_matrices();
    let n = p.layout.n();
    for k in [0, matrices.len() - 1] {
        let a = &matrices[k];
        let dim = a.nrows();
        let raw = a.singular_values().min() / a.norm();
        let s = scaled(a, n);
        let ratio = s.singular_values().min() / s.norm();
        assert!(
            ratio > 10.0 * raw,
            "case {k}: {ratio:.3e} against {raw:.3e}"
        );
        let mut dense = Lu::new(dim, n);
        let fa = faer::Mat::from_fn(dim, dim, |i, j| a[(i, j)]);
        assert!(dense.factor(&fa));
        let pat = p.pattern.clone().expect("the sparse path");
        let mut values = vec![0.0; pat.nnz()];
        for j in 0..dim {
            for slot in pat.col_ptr[j]..pat.col_ptr[j + 1] {
                values[slot] = a[(pat.row_idx[slot], j)];
            }
        }
        let sparse_m = NewtonMatrix::Sparse(pat.clone(), values);
        let mut sparse = Factorisation::for_matrix(&sparse_m, n, Vec::new);
        assert!(sparse.factor(&sparse_m));
        for est in [dense.reciprocal_condition(), sparse.reciprocal_condition()] {
            assert!(
                est >= ratio * (1.0 - 1e-9) && est < 1.3 * ratio,
                "case {k}: estimate {est:.4e}, SVD {ratio:.4e}"
            );
        }
    }
}

/// Continued along a path (the equilibria of every case of table 5-1 on
/// two coupled McPherson corners, in order), each estimate after the
/// first takes one solve instead of two and stays within 1.3 of the
/// SVD's ratio, from above, as the cold estimates do.
#[test]
fn a_continued_estimate_takes_one_solve_and_is_as_close() {
    use crate::statics::linear::Lu;
    let (p, matrices) = corner_matrices();
    let n = p.layout.n();
    let mut direction = Direction::default();
    for (k, a) in matrices.iter().enumerate() {
        let s = scaled(a, n);
        let ratio = s.singular_values().min() / s.norm();
        let dim = a.nrows();
        let mut lu = Lu::new(dim, n);
        assert!(lu.factor(&faer::Mat::from_fn(dim, dim, |i, j| a[(i, j)])));
        let scale = lu.scale();
        let mut solves = 0;
        let est = scale.reciprocal_condition_along(dim, &mut direction, |y| {
            solves += 1;
            lu.solve(y)
        });
        assert_eq!(solves, if k == 0 { 2 } else { 1 }, "case {k}");
        assert!(
            est >= ratio * (1.0 - 1e-9) && est < 1.3 * ratio,
            "case {k}: estimate {est:.4e}, SVD {ratio:.4e}"
        );
    }
}

/// A matrix whose softest direction is one the last matrix held
/// stiffly, and which the last estimate's direction holds none of:
/// the continued estimate still finds it singular (below the threshold
/// of the exact test), by the irregular part of its start. From the
/// last direction alone it would read the matrix as regular (the
/// growth of a unit vector the matrix holds at 1).
#[test]
fn a_continued_estimate_finds_a_new_soft_direction() {
    use nalgebra::{DMatrix, DVector};
    let n = 12;
    let estimate = |d: &DMatrix<f64>, direction: &mut Direction| {
        let lu = d.clone().lu();
        inverse_iteration_along(n, d.norm(), direction, |y| {
            let x = lu.solve(&DVector::from_column_slice(y)).expect("regular");
            y.copy_from_slice(x.as_slice());
            true
        })
    };
    // Soft along the first coordinate, then stiff there and singular
    // to rounding along the sixth.
    let soft_first = DMatrix::from_fn(n, n, |i, j| match (i, j) {
        (0, 0) => 1e-3,
        _ if i == j => 1.0 + i as f64,
        _ => 0.0,
    });
    let soft_sixth = DMatrix::from_fn(n, n, |i, j| match (i, j) {
        (5, 5) => 1e-15,
        _ if i == j => 1.0 + i as f64,
        _ => 0.0,
    });
    let mut direction = Direction::default();
    let first = estimate(&soft_first, &mut direction);
    assert!(
        first > 1e-5 && first < 1.3e-3 / soft_first.norm(),
        "{first:e}"
    );
    // The last direction is the first coordinate's, to rounding.
    assert!(direction.last[0].abs() > 1.0 - 1e-6, "{:?}", direction.last);
    let next = estimate(&soft_sixth, &mut direction);
    assert!(
        next < crate::statics::isolation::CHECK_SINGULAR_BELOW,
        "{next:e}"
    );
    let mut bare = Direction {
        last: (0..n).map(|i| if i == 0 { 1.0 } else { 0.0 }).collect(),
        irregular: vec![0.0; n],
    };
    assert!(estimate(&soft_sixth, &mut bare) > 1e-3);
}
