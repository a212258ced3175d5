//! Joint locations that need a search (thesis §6.5, §6.6 b): the strut top (a
//! point of part 2 that moves along a line fixed in part 1) and a bushing on a
//! link whose other end is a located ball joint.

use super::motion::Rel;
use super::simplex::{curvature, minimise};
use crate::geom::{Mat3, Vec3};

/// A searched location with its quality.
#[derive(Debug, Clone, PartialEq)]
pub struct Searched {
    pub center: Vec3,
    pub axis: Option<Vec3>,
    /// RMS misfit of the hypothesis at the optimum, mm.
    pub residual: f64,
    /// How far the point can move along its flattest direction before the misfit
    /// grows by the noise level, mm (one standard deviation).
    pub uncertainty: f64,
}

/// The trajectory of a point `x` of part 2 seen from part 1, the design
/// position included (the reference case of eq. 3.22).
fn cloud(rels: &[Rel], x: &Vec3) -> Vec<Vec3> {
    std::iter::once(*x)
        .chain(rels.iter().map(|r| r.apply(x)))
        .collect()
}

/// Squared distances of the cloud from its best line, and that line's direction.
fn line_misfit(pts: &[Vec3]) -> (f64, Vec3) {
    let g = pts.iter().sum::<Vec3>() / pts.len() as f64;
    let mut cov = Mat3::zeros();
    for p in pts {
        cov += (p - g) * (p - g).transpose();
    }
    // The smallest inertia eigenvalue (eq. 3.24) is the sum of squared distances
    // from the principal line: trace minus the largest covariance eigenvalue.
    let eig = cov.symmetric_eigen();
    let k = eig.eigenvalues.imax();
    let dir = eig.eigenvectors.column(k).into_owned();
    (cov.trace() - eig.eigenvalues[k], dir)
}

/// Turns the misfit's curvature at the optimum into an uncertainty. For a sum
/// of squared residuals `f` with Hessian `H` and residual noise `σ`, the
/// estimate's covariance is `2σ² H⁻¹`; its worst direction is the flattest one.
fn uncertainty(f: &dyn Fn(&Vec3) -> f64, x: &Vec3, sigma: f64) -> f64 {
    let (vals, _) = curvature(f, x, 0.5);
    let flattest = vals[0];
    if flattest <= 0.0 {
        return f64::INFINITY;
    }
    (2.0 * sigma * sigma / flattest).sqrt()
}

/// The strut top: the point of part 2 whose positions seen from part 1 lie on
/// one straight line (the strut axis), found by Nelder–Mead from `start`.
pub fn strut_top(rels: &[Rel], start: &Vec3, sigma: f64) -> Searched {
    let f = |x: &Vec3| line_misfit(&cloud(rels, x)).0;
    let (x, fx) = minimise(&f, *start, 20.0, 1e-6, 4000);
    let pts = cloud(rels, &x);
    let (_, dir) = line_misfit(&pts);
    let i = dir.iamax();
    let axis = if dir[i] < 0.0 { -dir } else { dir };
    let residual = (fx / pts.len() as f64).sqrt();
    // A misfit above the noise is model error (a yielding top mount): it, not
    // the noise, bounds what the search can claim. Only the directions across
    // the axis count: the top's height along its own axis is confounded with
    // the mount's deformation (thesis §6.7–6.9: axis right, height wrong).
    let s = sigma.max(residual);
    let (vals, vecs) = curvature(&f, &x, 0.5);
    let h = vecs * nalgebra::Matrix3::from_diagonal(&vals) * vecs.transpose();
    let e1 = axis
        .cross(&if axis.x.abs() < 0.9 {
            Vec3::x()
        } else {
            Vec3::y()
        })
        .normalize();
    let e2 = axis.cross(&e1);
    let b = nalgebra::Matrix2::new(
        e1.dot(&(h * e1)),
        e1.dot(&(h * e2)),
        e2.dot(&(h * e1)),
        e2.dot(&(h * e2)),
    );
    let flattest = b.symmetric_eigenvalues().min();
    Searched {
        center: x,
        axis: Some(axis),
        residual,
        uncertainty: if flattest > 0.0 {
            (2.0 * s * s / flattest).sqrt()
        } else {
            f64::INFINITY
        },
    }
}

/// A bushing on a link (part 2) whose other end is the ball joint `ball`: the
/// bushing centre moves, relative to part 1, only along the link (eq. 3.31–3.35).
pub fn link_bushing(rels: &[Rel], ball: &Vec3, start: &Vec3, sigma: f64) -> Searched {
    let f = |x: &Vec3| {
        let d = x - ball;
        if d.norm() < 1e-9 {
            return f64::INFINITY;
        }
        let u = d.normalize();
        rels.iter()
            .map(|r| (r.apply(x) - x).cross(&(r.rotation * u)).norm_squared())
            .sum::<f64>()
    };
    let (x, fx) = minimise(&f, *start, 5.0, 1e-7, 4000);
    let residual = (fx / rels.len().max(1) as f64).sqrt();
    Searched {
        center: x,
        axis: Some((x - ball).normalize()),
        residual,
        uncertainty: uncertainty(&f, &x, sigma.max(residual)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::euler_zxz;

    fn strut_motion() -> (Vec3, Vec3, Vec<Rel>) {
        // Part 2 rotates about a point p and slides along the line through p along `a`.
        let p = Vec3::new(-73.7, 594.7, 762.6);
        let a = Vec3::new(-0.1, -0.2, 0.97).normalize();
        let rels = [
            (0.2, 0.1, -0.15, 10.0),
            (-0.1, 0.15, 0.1, -20.0),
            (0.05, -0.2, 0.2, 35.0),
            (0.3, 0.05, -0.3, 5.0),
        ]
        .iter()
        .map(|&(x, y, z, s)| {
            let r = euler_zxz(x, y, z);
            Rel {
                rotation: r,
                translation: p + a * s - r * p,
            }
        })
        .collect();
        (p, a, rels)
    }

    #[test]
    fn a_point_sliding_on_a_line_is_found() {
        let (p, a, rels) = strut_motion();
        let found = strut_top(&rels, &(p + Vec3::new(15.0, -10.0, 20.0)), 0.05);
        assert!((found.center - p).norm() < 1e-3, "{}", found.center - p);
        assert!(found.axis.expect("axis").cross(&a).norm() < 1e-6);
    }

    #[test]
    fn the_predicted_uncertainty_matches_the_scatter_under_noise() {
        let (p, _, rels) = strut_motion();
        let sigma = 0.05;
        let predicted = strut_top(&rels, &p, sigma).uncertainty;
        let mut noise = crate::measure::synthetic::Noise::new(3);
        let mut found = Vec::new();
        for _ in 0..60 {
            let noisy: Vec<Rel> = rels
                .iter()
                .map(|r| Rel {
                    rotation: r.rotation,
                    translation: r.translation
                        + Vec3::new(noise.normal(), noise.normal(), noise.normal()) * sigma,
                })
                .collect();
            found.push(strut_top(&noisy, &p, sigma).center);
        }
        let mean = found.iter().sum::<Vec3>() / found.len() as f64;
        let mut cov = Mat3::zeros();
        for f in &found {
            cov += (f - mean) * (f - mean).transpose() / found.len() as f64;
        }
        let worst = cov.symmetric_eigen().eigenvalues.max().sqrt();
        assert!(
            worst > 0.5 * predicted && worst < 2.0 * predicted,
            "scatter {worst} mm vs predicted {predicted} mm"
        );
    }
}
