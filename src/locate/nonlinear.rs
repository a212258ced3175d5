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
    /// One standard deviation of the axis direction along its worst way to
    /// tilt, rad ([`line_direction_covariance`]); infinite when not estimated.
    pub axis_uncertainty: f64,
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

/// Two unit vectors across `axis`, completing a right-handed frame.
fn across(axis: &Vec3) -> (Vec3, Vec3) {
    let e1 = axis
        .cross(&if axis.x.abs() < 0.9 {
            Vec3::x()
        } else {
            Vec3::y()
        })
        .normalize();
    (e1, axis.cross(&e1))
}

/// Covariance (rad², in the basis of [`across`]) of the direction of the line
/// through the trajectory of `x`, linearised about the fit (eq. 3.22–3.25).
///
/// The line fit is a least-squares problem in the point (`free`: the
/// directions along which it is estimated, global), the line's offset (two
/// coordinates across it) and its direction (two angles): each trajectory
/// point `p_c = R_c x + T_c` contributes its two coordinates across the line,
/// whose derivatives are `E R_c` (point), `−I₂` (offset) and `−s_c I₂`
/// (direction; `s_c` the point's position along the line from the centroid),
/// `E` the two rows of [`across`]. With noise `s` on each coordinate the
/// covariance of all parameters is `s² (JᵀJ)⁻¹`; its direction block is
/// returned. The point's own uncertainty is in it: moving the point tilts its
/// trajectory when the part turns as it slides. `None` when `JᵀJ` is singular.
pub fn line_direction_covariance(
    rels: &[Rel],
    x: &Vec3,
    axis: &Vec3,
    free: &[Vec3],
    s: f64,
) -> Option<nalgebra::Matrix2<f64>> {
    let pts = cloud(rels, x);
    let rots: Vec<Mat3> = std::iter::once(Mat3::identity())
        .chain(rels.iter().map(|r| r.rotation))
        .collect();
    let g = pts.iter().sum::<Vec3>() / pts.len() as f64;
    let (e1, e2) = across(axis);
    let k = free.len();
    let n = k + 4;
    let mut jtj = nalgebra::DMatrix::<f64>::zeros(n, n);
    for (p, r) in pts.iter().zip(&rots) {
        let sc = axis.dot(&(p - g));
        for (row, e) in [e1, e2].iter().enumerate() {
            let mut j = nalgebra::DVector::<f64>::zeros(n);
            for (m, v) in free.iter().enumerate() {
                j[m] = e.dot(&(r * v));
            }
            j[k + row] = -1.0;
            j[k + 2 + row] = -sc;
            jtj += &j * j.transpose();
        }
    }
    let inv = jtj.cholesky()?.inverse();
    let block = inv.fixed_view::<2, 2>(k + 2, k + 2).into_owned() * (s * s);
    block.iter().all(|v| v.is_finite()).then_some(block)
}

/// One standard deviation of a direction along its worst way to tilt, rad,
/// from its 2×2 covariance.
pub fn cone(cov: &nalgebra::Matrix2<f64>) -> f64 {
    cov.symmetric_eigenvalues().max().max(0.0).sqrt()
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
    let (e1, e2) = across(&axis);
    let b = nalgebra::Matrix2::new(
        e1.dot(&(h * e1)),
        e1.dot(&(h * e2)),
        e2.dot(&(h * e1)),
        e2.dot(&(h * e2)),
    );
    let flattest = b.symmetric_eigenvalues().min();
    // The direction is determined even where the point is not (without
    // steering the top is uncertain by tens of mm across the axis, yet every
    // point near it slides along nearly the same line): its uncertainty
    // includes the point's, all three coordinates free as in the search.
    let free = [Vec3::x(), Vec3::y(), Vec3::z()];
    let axis_uncertainty =
        line_direction_covariance(rels, &x, &axis, &free, s).map_or(f64::INFINITY, |c| cone(&c));
    Searched {
        center: x,
        axis: Some(axis),
        residual,
        uncertainty: if flattest > 0.0 {
            (2.0 * s * s / flattest).sqrt()
        } else {
            f64::INFINITY
        },
        axis_uncertainty,
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
        axis_uncertainty: f64::INFINITY,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::euler_zxz;

    /// `rels` with seeded noise of deviation `sigma` mm on each translation.
    fn noisy(rels: &[Rel], noise: &mut crate::measure::synthetic::Noise, sigma: f64) -> Vec<Rel> {
        rels.iter()
            .map(|r| Rel {
                rotation: r.rotation,
                translation: r.translation
                    + Vec3::new(noise.normal(), noise.normal(), noise.normal()) * sigma,
            })
            .collect()
    }

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

    /// The axis direction's predicted cone (linearised line fit, eq. 3.22–3.25)
    /// matches the scatter of the found axis over noisy repetitions, is
    /// negligible without noise and shrinks with the noise.
    #[test]
    fn the_predicted_axis_uncertainty_matches_the_scatter_under_noise() {
        let (p, a, rels) = strut_motion();
        let exact = strut_top(&rels, &p, 1e-9);
        assert!(exact.axis_uncertainty < 1e-5, "{}", exact.axis_uncertainty);
        let sigma = 0.05;
        let predicted = strut_top(&rels, &p, sigma).axis_uncertainty;
        let quarter = strut_top(&rels, &p, sigma / 4.0).axis_uncertainty;
        assert!(
            (quarter / predicted - 0.25).abs() < 1e-6,
            "{quarter} {predicted}"
        );
        let (e1, e2) = across(&a);
        let mut noise = crate::measure::synthetic::Noise::new(7);
        let mut tilts = Vec::new();
        for _ in 0..200 {
            let noisy = noisy(&rels, &mut noise, sigma);
            let found = strut_top(&noisy, &p, sigma).axis.expect("axis");
            let found = if found.dot(&a) < 0.0 { -found } else { found };
            tilts.push(nalgebra::Vector2::new(e1.dot(&found), e2.dot(&found)));
        }
        let mean = tilts.iter().sum::<nalgebra::Vector2<f64>>() / tilts.len() as f64;
        let mut cov = nalgebra::Matrix2::zeros();
        for t in &tilts {
            cov += (t - mean) * (t - mean).transpose() / tilts.len() as f64;
        }
        let worst = cone(&cov);
        eprintln!("axis scatter {worst:.3e} rad, predicted {predicted:.3e} rad");
        assert!(
            worst > 0.5 * predicted && worst < 2.0 * predicted,
            "scatter {worst} rad vs predicted {predicted} rad"
        );
    }

    #[test]
    fn the_predicted_uncertainty_matches_the_scatter_under_noise() {
        let (p, _, rels) = strut_motion();
        let sigma = 0.05;
        let predicted = strut_top(&rels, &p, sigma).uncertainty;
        let mut noise = crate::measure::synthetic::Noise::new(3);
        let mut found = Vec::new();
        for _ in 0..60 {
            let noisy = noisy(&rels, &mut noise, sigma);
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
