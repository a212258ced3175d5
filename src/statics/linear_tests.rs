//! Tests of the dense LU ([`super`]): solutions and the condition
//! estimate, the contiguous elimination against the one on a faer `Mat`,
//! and the block factorisation against the dense one.

use super::*;

/// Seeded uniform numbers in [-0.5, 0.5) for the tests' random matrices.
fn uniform(seed: u64) -> impl FnMut() -> f64 {
    let mut s = seed;
    move || {
        s = s
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (s >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    }
}

mod condition {
    use super::*;

    fn matrix(n: usize, seed: u64) -> Mat<f64> {
        let mut u = uniform(seed);
        Mat::from_fn(n, n, |_, _| u())
    }

    /// Solutions satisfy the system; the condition estimate is within a small
    /// factor of the SVD's ratio for a regular matrix and flags a singular one.
    #[test]
    fn solves_and_estimates_the_condition() {
        let n = 47;
        let a = matrix(n, 3);
        let mut lu = Lu::new(n, n);
        assert!(lu.factor(&a));
        let b: Vec<f64> = (0..n).map(|i| (i as f64).sin()).collect();
        let mut x = b.clone();
        assert!(lu.solve(&mut x));
        assert!(lu.satisfies(&a, &x, &b));
        let s = a.singular_values().expect("svd");
        let ratio = s[n - 1] / s[0];
        let est = lu.reciprocal_condition();
        assert!(est > 0.1 * ratio && est < 50.0 * ratio, "{est} vs {ratio}");
        // Rank n - 1: the last column repeats a combination of two others.
        let mut sing = a.clone();
        for i in 0..n {
            sing[(i, n - 1)] = 2.0 * a[(i, 0)] - 0.5 * a[(i, 7)];
        }
        let ok = lu.factor(&sing);
        assert!(!ok || lu.reciprocal_condition() < 1e-12);
    }
}

mod elimination {
    use super::*;

    /// The elimination as it was written on a faer `Mat` (column slices and
    /// row swaps through the matrix's accessors), the reference for the
    /// contiguous one.
    fn eliminate_on_mat(lu: &mut Mat<f64>, piv: &mut [usize]) {
        let n = piv.len();
        for k in 0..n {
            let c = &lu.col_as_slice(k)[k..n];
            let mut p = 0;
            let mut best = c[0].abs();
            for (i, v) in c.iter().enumerate().skip(1) {
                if v.abs() > best {
                    (p, best) = (i, v.abs());
                }
            }
            let p = k + p;
            piv[k] = p;
            if p != k {
                for j in 0..n {
                    lu.col_as_slice_mut(j).swap(k, p);
                }
            }
            let d = lu[(k, k)];
            if d == 0.0 || !d.is_finite() {
                continue;
            }
            for i in k + 1..n {
                lu[(i, k)] /= d;
            }
            for j in k + 1..n {
                let u = lu[(k, j)];
                if u != 0.0 {
                    for i in k + 1..n {
                        let l = lu[(i, k)];
                        if l != 0.0 {
                            lu[(i, j)] -= l * u;
                        }
                    }
                }
            }
        }
    }

    /// On a sparse matrix whose first pivots need row swaps, the
    /// elimination pivots as the plain partial-pivoting LU on a `Mat` does
    /// and gives its factors (exactly: the same updates in the same order,
    /// zeros skipped), its solution satisfies the system, and `Lu` gives the
    /// same solution bit for bit.
    #[test]
    fn the_elimination_pivots_and_solves() {
        let n = 23;
        let mut next = uniform(11);
        let a = Mat::from_fn(n, n, |i, j| {
            let v = next();
            if i == j {
                if i < 3 { 0.0 } else { 1.0 + v }
            } else if (i * 7 + j * 3) % 5 == 0 {
                v
            } else {
                0.0
            }
        });
        let mut l1: Vec<f64> = (0..n).flat_map(|j| a.col_as_slice(j).to_vec()).collect();
        let mut p1 = vec![0; n];
        let mut c1 = vec![0.0; n];
        eliminate(&mut l1, &mut p1, &mut c1);
        assert!(p1[..3].iter().enumerate().any(|(k, &p)| p != k), "{p1:?}");
        let (mut l0, mut p0) = (a.clone(), vec![0; n]);
        eliminate_on_mat(&mut l0, &mut p0);
        assert_eq!(p0, p1);
        for j in 0..n {
            for i in 0..n {
                assert!(l0[(i, j)] == l1[j * n + i], "({i}, {j})");
            }
        }
        let b: Vec<f64> = (0..n).map(|i| (i as f64 * 0.3).sin()).collect();
        let mut x1 = b.clone();
        substitute(&l1, &p1, &mut x1);
        let mut lu = Lu::new(n, n);
        assert!(lu.factor(&a));
        let mut x = b.clone();
        assert!(lu.solve(&mut x) && lu.satisfies(&a, &x, &b));
        assert!(x.iter().zip(&x1).all(|(u, v)| u.to_bits() == v.to_bits()));
        // The residual of the solution, computed independently.
        for i in 0..n {
            let r: f64 = (0..n).map(|j| a[(i, j)] * x[j]).sum::<f64>() - b[i];
            assert!(r.abs() < 1e-12, "{r}");
        }
    }
}

mod blocks {
    use super::*;

    /// A block-diagonal matrix with interleaved blocks: the block
    /// factorisation solves it as the dense one does, and its norms,
    /// scaling (the last four unknowns taken for multipliers), distance
    /// and condition estimate agree.
    #[test]
    fn blocks_factorise_as_the_dense_matrix() {
        let n = 20;
        let groups: Vec<Vec<usize>> = vec![
            (0..n).filter(|i| i % 3 == 0).collect(),
            (0..n).filter(|i| i % 3 != 0).collect(),
        ];
        let mut next = uniform(7);
        let mut a = Mat::<f64>::zeros(n, n);
        for g in &groups {
            for &i in g {
                for &j in g {
                    a[(i, j)] = next() + if i == j { 2.0 } else { 0.0 };
                }
            }
        }
        let c = n - 4;
        let (mut dense, mut blocks) = (Lu::new(n, c), Lu::with_blocks(n, c, groups));
        assert!(dense.factor(&a) && blocks.factor(&a));
        let b: Vec<f64> = (0..n).map(|i| (i as f64 * 0.7).cos()).collect();
        let (mut x, mut y) = (b.clone(), b.clone());
        assert!(dense.solve(&mut x) && blocks.solve(&mut y));
        for (u, v) in x.iter().zip(&y) {
            assert!((u - v).abs() < 1e-12 * (1.0 + u.abs()), "{u} {v}");
        }
        assert!(blocks.satisfies(&a, &y, &b));
        let mut wrong = y.clone();
        wrong[4] += 1e-3;
        assert!(!blocks.satisfies(&a, &wrong, &b));
        let (sd, sb) = (dense.scale(), blocks.scale());
        assert!((sd.fro - sb.fro).abs() < 1e-12 * sd.fro);
        assert_eq!((sd.alpha, sd.coords), (sb.alpha, sb.coords));
        assert_eq!(dense.a_max, blocks.a_max);
        assert_ne!(sd.alpha, 1.0);
        let mut moved = a.clone();
        moved[(3, 3)] += 0.25;
        assert!((dense.distance_to(&moved) - blocks.distance_to(&moved)).abs() < 1e-15);
        let (rd, rb) = (dense.reciprocal_condition(), blocks.reciprocal_condition());
        assert!((rd - rb).abs() < 1e-9 * rd, "{rd} {rb}");
    }
}
