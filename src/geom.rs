//! 3-D geometry shared by every backend: ZXZ Euler angles (ADAMS `REULER`),
//! frames from direction vectors, and the projected angles of the ADAMS bushing.
//!
//! Conventions: `spec/conventions.md`. A rotation matrix's columns are the
//! marker's x, y, z axes in global coordinates.

use nalgebra::{Matrix3, Vector3};

pub type Vec3 = Vector3<f64>;
pub type Mat3 = Matrix3<f64>;

pub fn rot_x(a: f64) -> Mat3 {
    let (s, c) = a.sin_cos();
    Mat3::new(1.0, 0.0, 0.0, 0.0, c, -s, 0.0, s, c)
}

pub fn rot_z(a: f64) -> Mat3 {
    let (s, c) = a.sin_cos();
    Mat3::new(c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0)
}

/// `R = Rz(psi) · Rx(theta) · Rz(phi)`, angles in radians (ADAMS `REULER`).
pub fn euler_zxz(psi: f64, theta: f64, phi: f64) -> Mat3 {
    rot_z(psi) * rot_x(theta) * rot_z(phi)
}

/// ZXZ angles `(psi, theta, phi)` in radians of a rotation matrix, with theta in [0, π].
///
/// At the singular orientations (theta = 0 or π) only psi ± phi is defined; then
/// phi is set to 0 and psi carries the whole rotation about z, which is what ADAMS
/// does and what makes the round trip `euler_zxz(matrix_to_zxz(R)) == R` hold.
pub fn matrix_to_zxz(r: &Mat3) -> (f64, f64, f64) {
    let s_theta = (r[(0, 2)].powi(2) + r[(1, 2)].powi(2)).sqrt();
    let theta = s_theta.atan2(r[(2, 2)]);
    if s_theta > 1e-9 {
        let psi = r[(0, 2)].atan2(-r[(1, 2)]);
        let phi = r[(2, 0)].atan2(r[(2, 1)]);
        (psi, theta, phi)
    } else if r[(2, 2)] > 0.0 {
        // R = Rz(psi + phi): the first column is (cos, sin, 0).
        (r[(1, 0)].atan2(r[(0, 0)]), 0.0, 0.0)
    } else {
        // R = Rz(psi) Rx(π) Rz(phi) = [[c(psi-phi), s(psi-phi), 0], [s(psi-phi), -c(psi-phi), 0], [0,0,-1]].
        (r[(1, 0)].atan2(r[(0, 0)]), std::f64::consts::PI, 0.0)
    }
}

/// Why a pair of direction vectors cannot define a frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FrameError {
    ZeroZ,
    ZeroX,
    ParallelX,
}

/// The frame whose z axis is `z` and whose x axis is `x_hint` made orthogonal to z
/// (ADAMS `ZP`/`XP` style). Without a hint, x is the global axis least aligned
/// with z, projected, which gives a deterministic frame.
pub fn frame_from_z_x(z: Vec3, x_hint: Option<Vec3>) -> Result<Mat3, FrameError> {
    let zn = z.norm();
    if zn < 1e-12 {
        return Err(FrameError::ZeroZ);
    }
    let zu = z / zn;
    let hint = match x_hint {
        Some(x) => {
            if x.norm() < 1e-12 {
                return Err(FrameError::ZeroX);
            }
            x
        }
        None => {
            let a = zu.map(f64::abs);
            if a.x <= a.y && a.x <= a.z {
                Vec3::x()
            } else if a.y <= a.z {
                Vec3::y()
            } else {
                Vec3::z()
            }
        }
    };
    let xp = hint - zu * hint.dot(&zu);
    // Parallel within about 0.06°: the projected x is numerically meaningless.
    if xp.norm() < 1e-6 * hint.norm() {
        return Err(FrameError::ParallelX);
    }
    let xu = xp.normalize();
    let yu = zu.cross(&xu);
    Ok(Mat3::from_columns(&[xu, yu, zu]))
}

/// Projected angles `(ax, ay, az)` in radians of the relative rotation
/// `Q = R_J^T R_I` of a bushing (ADAMS AX, AY, AZ; `conventions.md`).
pub fn projected_angles(q: &Mat3) -> Vec3 {
    Vec3::new(
        (-q[(1, 2)]).atan2(q[(2, 2)]),
        q[(0, 2)].atan2(q[(2, 2)]),
        q[(1, 0)].atan2(q[(0, 0)]),
    )
}

/// The skew matrix `ũ` with `ũ v = u × v`.
pub fn skew(u: &Vec3) -> Mat3 {
    Mat3::new(0.0, -u.z, u.y, u.z, 0.0, -u.x, -u.y, u.x, 0.0)
}

/// `ã m`: `a` crossed with each column of `m`. The same bits as
/// `skew(a) * m` but for the sign of a zero entry: each entry of that
/// product is a sum of two products and a product by an exact zero, which
/// changes nothing but that sign when left out. It takes a third
/// fewer multiplications and builds no skew matrix. The statics' tangents
/// form dozens of these products every evaluation.
pub fn skew_times(a: &Vec3, m: &Mat3) -> Mat3 {
    Mat3::from_columns(&[
        a.cross(&m.column(0)),
        a.cross(&m.column(1)),
        a.cross(&m.column(2)),
    ])
}

/// `m ã`: each row of `m` crossed with `a` (`mᵢ ã = (mᵢ × a)ᵀ`), the same
/// bits as `m * skew(a)` (see [`skew_times`]).
pub fn times_skew(m: &Mat3, a: &Vec3) -> Mat3 {
    let row = |i: usize| m.row(i).transpose().cross(a).transpose();
    Mat3::from_rows(&[row(0), row(1), row(2)])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::units::DEG;

    fn close_m(a: &Mat3, b: &Mat3, tol: f64) -> bool {
        (a - b).abs().max() < tol
    }

    /// Every entry the same bits, but for the sign of an exact zero (the
    /// generic product adds `±0` products the cross product leaves out).
    fn same_bits(got: &Mat3, want: &Mat3) {
        for (g, w) in got.iter().zip(want.iter()) {
            assert!(
                g.to_bits() == w.to_bits() || (*g == 0.0 && *w == 0.0),
                "{got} against {want}"
            );
        }
    }

    /// The products with a skew matrix by cross products are the generic
    /// products to the bit, but for the sign of a zero (random vectors and
    /// matrices, a skew matrix as the other factor too, and entries that
    /// are exact zeros).
    #[test]
    fn products_with_a_skew_matrix_are_the_generic_products_to_the_bit() {
        let mut rng = crate::statics::testkit::Lcg::new(0x2545_f491);
        // Some exact zeros and integers, as structural entries are.
        let mut rnd = || match rng.next() {
            x if x.abs() < 0.15 => 0.0,
            x if x.abs() < 0.3 => (x * 20.0).round(),
            x => x * 1e3,
        };
        for _ in 0..2000 {
            let a = Vec3::new(rnd(), rnd(), rnd());
            let m = Mat3::from_fn(|_, _| rnd());
            let b = skew(&Vec3::new(rnd(), rnd(), rnd()));
            for m in [m, b, -b, Mat3::identity()] {
                same_bits(&skew_times(&a, &m), &(skew(&a) * m));
                same_bits(&times_skew(&m, &a), &(m * skew(&a)));
            }
        }
    }

    #[test]
    fn euler_matches_the_closed_form() {
        let (psi, theta, phi): (f64, f64, f64) = (0.3, 1.1, -0.7);
        let (sp, cp) = psi.sin_cos();
        let (st, ct) = theta.sin_cos();
        let (sf, cf) = phi.sin_cos();
        let closed = Mat3::new(
            cp * cf - sp * ct * sf,
            -cp * sf - sp * ct * cf,
            sp * st,
            sp * cf + cp * ct * sf,
            -sp * sf + cp * ct * cf,
            -cp * st,
            st * sf,
            st * cf,
            ct,
        );
        assert!(close_m(&euler_zxz(psi, theta, phi), &closed, 1e-15));
    }

    #[test]
    fn euler_round_trips_generic_angles() {
        for &(p, t, f) in &[
            (10.0, 20.0, 30.0),
            (-170.0, 179.0, 45.0),
            (309.5 - 360.0, 90.22, 181.7 - 360.0),
            (141.5, 166.7, 53.68),
            (0.0, 1.0, 0.0),
        ] {
            let r = euler_zxz(p * DEG, t * DEG, f * DEG);
            let (a, b, c) = matrix_to_zxz(&r);
            assert!((a / DEG - p).abs() < 1e-9, "psi {p} -> {}", a / DEG);
            assert!((b / DEG - t).abs() < 1e-9);
            assert!((c / DEG - f).abs() < 1e-9);
        }
    }

    #[test]
    fn euler_singular_cases_reconstruct_the_matrix() {
        for &(p, t, f) in &[
            (30.0, 0.0, 20.0),
            (30.0, 180.0, 20.0),
            (0.0, 0.0, 0.0),
            (-90.0, 180.0, 0.0),
        ] {
            let r = euler_zxz(p * DEG, t * DEG, f * DEG);
            let (a, b, c) = matrix_to_zxz(&r);
            assert!(close_m(&euler_zxz(a, b, c), &r, 1e-12), "({p},{t},{f})");
            assert_eq!(c, 0.0);
        }
        // theta = 0: psi carries psi + phi.
        let (a, _, _) = matrix_to_zxz(&euler_zxz(30.0 * DEG, 0.0, 20.0 * DEG));
        assert!((a / DEG - 50.0).abs() < 1e-9);
    }

    #[test]
    fn thesis_bushing_b_x_axis_points_along_the_arm() {
        // methods.md §1.4: in the ADAMS/Car frame, B = (129.5, 90.22, 181.7) has x = (0.636, -0.771, -0.030).
        let r = euler_zxz(129.5 * DEG, 90.22 * DEG, 181.7 * DEG);
        let x = r.column(0);
        assert!(
            (x[0] - 0.636).abs() < 2e-3
                && (x[1] + 0.771).abs() < 2e-3
                && (x[2] + 0.030).abs() < 2e-3
        );
    }

    #[test]
    fn frame_from_directions() {
        let r = frame_from_z_x(Vec3::new(0.0, 0.0, 2.0), Some(Vec3::new(1.0, 1.0, 0.5)))
            .expect("frame");
        assert!((r.column(2) - Vec3::z()).norm() < 1e-15);
        assert!((r.column(0) - Vec3::new(1.0, 1.0, 0.0).normalize()).norm() < 1e-15);
        assert!((r.determinant() - 1.0).abs() < 1e-14);
        assert_eq!(frame_from_z_x(Vec3::zeros(), None), Err(FrameError::ZeroZ));
        assert_eq!(
            frame_from_z_x(Vec3::z(), Some(Vec3::z() * 3.0)),
            Err(FrameError::ParallelX)
        );
        assert_eq!(
            frame_from_z_x(Vec3::z(), Some(Vec3::zeros())),
            Err(FrameError::ZeroX)
        );
        let r = frame_from_z_x(Vec3::new(0.3, -0.2, 0.9), None).expect("frame");
        assert!((r.transpose() * r - Mat3::identity()).abs().max() < 1e-14);
    }

    #[test]
    fn projected_angles_are_exact_for_single_axis_rotations() {
        let a = 0.2;
        assert!((projected_angles(&rot_x(a)) - Vec3::new(a, 0.0, 0.0)).norm() < 1e-15);
        assert!((projected_angles(&rot_z(a)) - Vec3::new(0.0, 0.0, a)).norm() < 1e-15);
        let ry = euler_zxz(std::f64::consts::FRAC_PI_2, a, -std::f64::consts::FRAC_PI_2);
        assert!((projected_angles(&ry) - Vec3::new(0.0, a, 0.0)).norm() < 1e-14);
    }
}
