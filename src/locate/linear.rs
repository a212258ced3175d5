//! Joint centres and axes from linear systems (thesis eq. 3.7–3.21): the
//! spherical joint, the ball joint on a rack sliding along a known direction,
//! and the revolute axis from the SVD of the stacked `R_c − I`.

use super::motion::Rel;
use crate::geom::{Mat3, Vec3};
use nalgebra::{DMatrix, DVector};

/// A located point (and axis) with its quality.
#[derive(Debug, Clone, PartialEq)]
pub struct Fit {
    pub center: Vec3,
    pub axis: Option<Vec3>,
    /// RMS of the equation residuals, mm.
    pub residual: f64,
    /// One standard deviation of the centre along its worst direction, mm.
    pub uncertainty: f64,
    /// Singular values of the stacked system, largest first.
    pub singular: Vec<f64>,
}

/// Solves the stacked system `M x = b` by SVD, truncating directions whose
/// singular value is below `drop` (they stay at the `prior` point's value).
fn solve(m: &DMatrix<f64>, b: &DVector<f64>, prior: &Vec3, drop: usize, sigma: f64) -> Option<Fit> {
    let svd = m.clone().svd(true, true);
    let (u, v_t) = (svd.u.as_ref()?, svd.v_t.as_ref()?);
    let s = &svd.singular_values;
    let mut order: Vec<usize> = (0..s.len()).collect();
    order.sort_by(|a, c| s[*c].total_cmp(&s[*a]));
    // Start from the prior and correct only along the kept directions.
    let r0 = b - m * DVector::from_column_slice(prior.as_slice());
    let mut x = *prior;
    let keep = s.len().saturating_sub(drop);
    for &k in &order[..keep] {
        if s[k] <= f64::EPSILON * s[order[0]].max(1e-300) {
            continue;
        }
        let coef = u.column(k).dot(&r0) / s[k];
        let vk = v_t.row(k).transpose();
        x += Vec3::new(vk[0], vk[1], vk[2]) * coef;
    }
    let res = b - m * DVector::from_column_slice(x.as_slice());
    let dof = (m.nrows() as f64 - 3.0).max(1.0);
    let residual = (res.norm_squared() / dof).sqrt();
    let smallest_kept = order[..keep]
        .iter()
        .map(|&k| s[k])
        .fold(f64::INFINITY, f64::min);
    let sigma_eff = residual.max(sigma);
    let uncertainty = if smallest_kept > 0.0 {
        sigma_eff / smallest_kept
    } else {
        f64::INFINITY
    };
    let axis = (drop > 0).then(|| {
        let k = order[s.len() - 1];
        let v = v_t.row(k).transpose();
        let a = Vec3::new(v[0], v[1], v[2]).normalize();
        // A deterministic sign: the largest component positive.
        let i = a.iamax();
        if a[i] < 0.0 { -a } else { a }
    });
    let singular = order.iter().map(|&k| s[k]).collect();
    Some(Fit {
        center: x,
        axis,
        residual,
        uncertainty,
        singular,
    })
}

fn stack(
    rels: &[Rel],
    rows: impl Fn(&Rel) -> (Mat3, Vec3),
    n_rows: usize,
) -> (DMatrix<f64>, DVector<f64>) {
    let mut m = DMatrix::zeros(n_rows * rels.len(), 3);
    let mut b = DVector::zeros(n_rows * rels.len());
    for (c, r) in rels.iter().enumerate() {
        let (a, t) = rows(r);
        for i in 0..n_rows {
            for j in 0..3 {
                m[(n_rows * c + i, j)] = a[(i, j)];
            }
            b[n_rows * c + i] = t[i];
        }
    }
    (m, b)
}

/// Spherical joint: `(R_c − I) x = −T_c` stacked over the steps (eq. 3.12).
/// `sigma` is the noise of the relative translations (mm), used when the
/// residual underestimates it (exact data).
pub fn spherical(rels: &[Rel], prior: &Vec3, sigma: f64) -> Option<Fit> {
    let (m, b) = stack(rels, |r| (r.rotation - Mat3::identity(), -r.translation), 3);
    solve(&m, &b, prior, 0, sigma)
}

/// How far the spherical fit's centre moves per mm of an unmodelled
/// displacement along `dirs[c]` at each step (`M⁺` applied to the stacked
/// directions): a bushing that yields along its link biases the centre by this
/// much times its deformation.
pub fn sensitivity(rels: &[Rel], dirs: &[Vec3]) -> Option<Vec3> {
    let (m, _) = stack(rels, |r| (r.rotation - Mat3::identity(), Vec3::zeros()), 3);
    let mut d = DVector::zeros(3 * rels.len());
    for (c, u) in dirs.iter().enumerate().take(rels.len()) {
        for i in 0..3 {
            d[3 * c + i] = u[i];
        }
    }
    let x = m.svd(true, true).solve(&d, 1e-12).ok()?;
    Some(Vec3::new(x[0], x[1], x[2]))
}

/// Ball joint on a part that slides along the known unit direction `u`
/// relative to part 1 (the rack, eq. 3.17–3.21): only the components of the
/// displacement across `u` must vanish.
pub fn sliding_ball(rels: &[Rel], u: &Vec3, prior: &Vec3, sigma: f64) -> Option<Fit> {
    sliding_ball_keeping(rels, u, prior, sigma, 0)
}

/// [`sliding_ball`] with its `drop` least determined directions kept at the
/// prior's value (`axis` is then the least determined one).
pub fn sliding_ball_keeping(
    rels: &[Rel],
    u: &Vec3,
    prior: &Vec3,
    sigma: f64,
    drop: usize,
) -> Option<Fit> {
    let u = u.normalize();
    let helper = if u.x.abs() < 0.9 {
        Vec3::x()
    } else {
        Vec3::y()
    };
    let v = u.cross(&helper).normalize();
    let w = u.cross(&v);
    let p = Mat3::from_rows(&[v.transpose(), w.transpose(), Vec3::zeros().transpose()]);
    let (m, b) = stack(
        rels,
        |r| (p * (r.rotation - Mat3::identity()), -(p * r.translation)),
        2,
    );
    solve(&m, &b, prior, drop, sigma)
}

/// Revolute joint: the axis is the right singular vector of the smallest
/// singular value of the stacked `R_c − I` (eq. 3.14–3.16); the point along the
/// axis is not determined by the motion, so it is taken nearest the prior.
pub fn revolute(rels: &[Rel], prior: &Vec3, sigma: f64) -> Option<Fit> {
    let (m, b) = stack(rels, |r| (r.rotation - Mat3::identity(), -r.translation), 3);
    solve(&m, &b, prior, 1, sigma)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::euler_zxz;

    /// Rotations about a centre `c`: `x ↦ R (x − c) + c`.
    fn about(c: Vec3, angles: &[(f64, f64, f64)]) -> Vec<Rel> {
        angles
            .iter()
            .map(|&(a, b, g)| {
                let r = euler_zxz(a, b, g);
                Rel {
                    rotation: r,
                    translation: c - r * c,
                }
            })
            .collect()
    }

    #[test]
    fn a_ball_centre_is_recovered_exactly() {
        let c = Vec3::new(25.5, 691.2, 233.0);
        let rels = about(
            c,
            &[(0.1, 0.05, -0.1), (-0.05, 0.1, 0.02), (0.2, -0.07, 0.1)],
        );
        let f = spherical(&rels, &Vec3::zeros(), 0.0).expect("fit");
        assert!((f.center - c).norm() < 1e-9);
    }

    #[test]
    fn a_revolute_axis_is_its_null_direction() {
        let c = Vec3::new(10.0, 380.0, 200.0);
        let axis = Vec3::new(0.98, 0.2, 0.0).normalize();
        let rels: Vec<Rel> = [0.05, -0.1, 0.15]
            .iter()
            .map(|&a| {
                let r =
                    nalgebra::Rotation3::from_axis_angle(&nalgebra::Unit::new_normalize(axis), a)
                        .into_inner();
                Rel {
                    rotation: r,
                    translation: c - r * c,
                }
            })
            .collect();
        let prior = c + axis * 30.0 + Vec3::new(0.0, 0.0, 2.0);
        let f = revolute(&rels, &prior, 0.0).expect("fit");
        let a = f.axis.expect("axis");
        assert!((a.cross(&axis)).norm() < 1e-9);
        // The centre lies on the axis, nearest the prior.
        let d = f.center - c;
        assert!(d.cross(&axis).norm() < 1e-6);
        assert!((d.dot(&axis) - 30.0).abs() < 1e-6);
        // A pure rotation about one axis: a spherical fit cannot place the centre along it.
        let s = spherical(&rels, &prior, 0.05).expect("fit");
        assert!(s.uncertainty > 1e6 || s.singular[2] < 1e-9);
    }

    #[test]
    fn a_ball_on_a_rack_ignores_the_rack_travel() {
        let c = Vec3::new(73.7, 353.4, 228.3);
        let u = Vec3::y();
        let mut rels = about(
            c,
            &[(0.1, 0.05, -0.1), (-0.05, 0.1, 0.02), (0.2, -0.07, 0.1)],
        );
        for (k, r) in rels.iter_mut().enumerate() {
            r.translation += u * (k as f64 * 7.0 - 5.0);
        }
        let f = sliding_ball(&rels, &u, &Vec3::zeros(), 0.0).expect("fit");
        // Rotations about varied axes determine the centre, rack travel aside.
        assert!((f.center - c).norm() < 1e-6);
    }
}
