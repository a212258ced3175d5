//! Nelder–Mead minimisation in three dimensions (the thesis' choice for the
//! strut top and the bushing on a link), and a local curvature estimate that
//! turns a minimum's flatness into an uncertainty.

use crate::geom::Vec3;

/// Minimises `f` from `start` with an initial simplex of size `step` (mm).
/// Returns the best point and value; stops when the simplex is smaller than
/// `tol` or after `max_iter` iterations.
pub fn minimise(
    f: &dyn Fn(&Vec3) -> f64,
    start: Vec3,
    step: f64,
    tol: f64,
    max_iter: usize,
) -> (Vec3, f64) {
    let mut pts: Vec<(Vec3, f64)> = (0..4)
        .map(|i| {
            let mut p = start;
            if i > 0 {
                p[i - 1] += step;
            }
            (p, f(&p))
        })
        .collect();
    for _ in 0..max_iter {
        pts.sort_by(|a, b| a.1.total_cmp(&b.1));
        let size = pts[1..]
            .iter()
            .map(|(p, _)| (p - pts[0].0).norm())
            .fold(0.0, f64::max);
        if size < tol {
            break;
        }
        let centroid = (pts[0].0 + pts[1].0 + pts[2].0) / 3.0;
        let worst = pts[3];
        let reflect = centroid + (centroid - worst.0);
        let fr = f(&reflect);
        if fr < pts[0].1 {
            let expand = centroid + (centroid - worst.0) * 2.0;
            let fe = f(&expand);
            pts[3] = if fe < fr { (expand, fe) } else { (reflect, fr) };
        } else if fr < pts[2].1 {
            pts[3] = (reflect, fr);
        } else {
            let contract = if fr < worst.1 {
                centroid + (reflect - centroid) * 0.5
            } else {
                centroid + (worst.0 - centroid) * 0.5
            };
            let fc = f(&contract);
            if fc < worst.1.min(fr) {
                pts[3] = (contract, fc);
            } else {
                let best = pts[0].0;
                for p in pts.iter_mut().skip(1) {
                    p.0 = best + (p.0 - best) * 0.5;
                    p.1 = f(&p.0);
                }
            }
        }
    }
    pts.sort_by(|a, b| a.1.total_cmp(&b.1));
    pts[0]
}

/// Curvature of `f` at `x` (finite differences with step `h`): the symmetric
/// Hessian's eigenvalues and eigenvectors, smallest first. Local to this 3-D
/// geometric fit; no simulator is involved.
pub fn curvature(f: &dyn Fn(&Vec3) -> f64, x: &Vec3, h: f64) -> (Vec3, nalgebra::Matrix3<f64>) {
    let mut hess = nalgebra::Matrix3::zeros();
    let e = |i: usize| Vec3::ith(i, h);
    let f0 = f(x);
    for i in 0..3 {
        for j in i..3 {
            let v = if i == j {
                (f(&(x + e(i))) - 2.0 * f0 + f(&(x - e(i)))) / (h * h)
            } else {
                (f(&(x + e(i) + e(j))) - f(&(x + e(i) - e(j))) - f(&(x - e(i) + e(j)))
                    + f(&(x - e(i) - e(j))))
                    / (4.0 * h * h)
            };
            hess[(i, j)] = v;
            hess[(j, i)] = v;
        }
    }
    let eig = hess.symmetric_eigen();
    let mut idx = [0usize, 1, 2];
    idx.sort_by(|a, b| eig.eigenvalues[*a].total_cmp(&eig.eigenvalues[*b]));
    let vals = Vec3::new(
        eig.eigenvalues[idx[0]],
        eig.eigenvalues[idx[1]],
        eig.eigenvalues[idx[2]],
    );
    let vecs = nalgebra::Matrix3::from_columns(&[
        eig.eigenvectors.column(idx[0]),
        eig.eigenvectors.column(idx[1]),
        eig.eigenvectors.column(idx[2]),
    ]);
    (vals, vecs)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_the_minimum_of_a_quadratic_bowl() {
        let c = Vec3::new(3.0, -2.0, 10.0);
        let f = |x: &Vec3| {
            (x - c)
                .component_mul(&Vec3::new(1.0, 4.0, 9.0))
                .dot(&(x - c))
        };
        let (x, fx) = minimise(&f, Vec3::zeros(), 5.0, 1e-9, 5000);
        assert!((x - c).norm() < 1e-6, "{x}");
        assert!(fx < 1e-10);
        let (vals, _) = curvature(&f, &x, 1e-2);
        assert!((vals - Vec3::new(2.0, 8.0, 18.0)).norm() < 1e-4, "{vals}");
    }
}
