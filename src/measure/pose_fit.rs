//! Rigid pose of a part from its landmarks (Arun's SVD method with the
//! reflection fix; thesis eq. 2.17–2.25, methods.md §3).

use crate::geom::{Mat3, Vec3};

/// The rigid motion `q ≈ translation + rotation · p` that best maps the part's
/// landmarks (`p`, part frame = global at design) onto the measured points.
#[derive(Debug, Clone, PartialEq)]
pub struct PoseFit {
    pub rotation: Mat3,
    pub translation: Vec3,
    /// Distance between each measured point and its fitted landmark, mm.
    pub residuals: Vec<f64>,
    /// Root mean square of the residuals, mm.
    pub rms: f64,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PoseFitError {
    /// Fewer than three point pairs.
    TooFewPoints(usize),
    /// The landmarks are (nearly) collinear: rotation about their line is undetermined.
    Collinear,
}

impl std::fmt::Display for PoseFitError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            PoseFitError::TooFewPoints(n) => {
                write!(f, "a pose needs at least 3 landmarks, {n} given")
            }
            PoseFitError::Collinear => write!(
                f,
                "the landmarks are collinear: the rotation about their line is undetermined"
            ),
        }
    }
}

fn centroid(pts: &[Vec3]) -> Vec3 {
    pts.iter().sum::<Vec3>() / pts.len() as f64
}

/// Fits the pose from pairs `(landmark, measured)`.
pub fn fit(landmarks: &[Vec3], measured: &[Vec3]) -> Result<PoseFit, PoseFitError> {
    let n = landmarks.len().min(measured.len());
    if n < 3 {
        return Err(PoseFitError::TooFewPoints(n));
    }
    let (p, q) = (&landmarks[..n], &measured[..n]);
    let (pc, qc) = (centroid(p), centroid(q));
    // Correlation M = Σ Qc Pcᵀ = U S Vᵀ, R = U diag(1, 1, det(U Vᵀ)) Vᵀ (thesis Annexe A form).
    let mut m = Mat3::zeros();
    for (a, b) in p.iter().zip(q) {
        m += (b - qc) * (a - pc).transpose();
    }
    let svd = m.svd(true, true);
    let (Some(u), Some(v_t)) = (svd.u, svd.v_t) else {
        return Err(PoseFitError::Collinear);
    };
    // Two vanishing singular values: every point on one line.
    let s = svd.singular_values;
    let scale = s.max().max(f64::MIN_POSITIVE);
    let mut sorted = [s[0], s[1], s[2]];
    sorted.sort_by(|a, b| b.total_cmp(a));
    if sorted[1] < 1e-9 * scale {
        return Err(PoseFitError::Collinear);
    }
    let d = (u * v_t).determinant().signum();
    let rotation = u * Mat3::from_diagonal(&Vec3::new(1.0, 1.0, d)) * v_t;
    let translation = qc - rotation * pc;
    let residuals: Vec<f64> = p
        .iter()
        .zip(q)
        .map(|(a, b)| (translation + rotation * a - b).norm())
        .collect();
    let rms = (residuals.iter().map(|r| r * r).sum::<f64>() / n as f64).sqrt();
    Ok(PoseFit {
        rotation,
        translation,
        residuals,
        rms,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::euler_zxz;

    fn pts() -> Vec<Vec3> {
        vec![
            Vec3::new(256.9, 432.9, 249.7),
            Vec3::new(177.6, 492.8, 229.7),
            Vec3::new(127.6, 594.2, 229.3),
            Vec3::new(53.7, 638.1, 244.8),
        ]
    }

    fn moved(r: &Mat3, t: &Vec3, p: &[Vec3]) -> Vec<Vec3> {
        p.iter().map(|x| t + r * x).collect()
    }

    #[test]
    fn recovers_a_rigid_motion_exactly() {
        let r = euler_zxz(0.3, -0.2, 0.15);
        let t = Vec3::new(12.0, -40.0, 31.5);
        let f = fit(&pts(), &moved(&r, &t, &pts())).expect("fit");
        assert!((f.rotation - r).abs().max() < 1e-12);
        assert!((f.translation - t).norm() < 1e-9);
        assert!(f.rms < 1e-9);
    }

    #[test]
    fn coplanar_points_and_mirror_images_still_give_a_rotation() {
        // Three points are always coplanar: the SVD leaves the reflection ambiguous.
        let p = vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(100.0, 0.0, 0.0),
            Vec3::new(0.0, 50.0, 0.0),
        ];
        let r = euler_zxz(1.0, 0.4, -0.3);
        let t = Vec3::new(1.0, 2.0, 3.0);
        let f = fit(&p, &moved(&r, &t, &p)).expect("fit");
        assert!((f.rotation.determinant() - 1.0).abs() < 1e-12);
        assert!((f.rotation - r).abs().max() < 1e-12);
        // A mirrored measurement cannot be matched by a rotation: the fit stays proper
        // and reports the misfit instead of returning a reflection.
        let mirror: Vec<Vec3> = pts().iter().map(|x| Vec3::new(x.x, -x.y, x.z)).collect();
        let f = fit(&pts(), &mirror).expect("fit");
        assert!((f.rotation.determinant() - 1.0).abs() < 1e-12);
        assert!(f.rms > 1.0);
    }

    #[test]
    fn noise_stays_within_its_bounds() {
        // Deterministic pseudo-noise of amplitude 0.05 mm.
        let r = euler_zxz(-0.1, 0.05, 0.2);
        let t = Vec3::new(3.0, 4.0, -5.0);
        let mut q = moved(&r, &t, &pts());
        let mut seed = 12345u64;
        for x in &mut q {
            for c in x.iter_mut() {
                seed = seed
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                *c += 0.05 * (((seed >> 33) as f64 / (1u64 << 31) as f64) - 1.0);
            }
        }
        let f = fit(&pts(), &q).expect("fit");
        let angle = ((f.rotation.transpose() * r).trace() - 1.0).clamp(-2.0, 2.0) / 2.0;
        assert!(angle.clamp(-1.0, 1.0).acos() < 1e-3, "rotation error");
        assert!((f.translation - t).norm() < 0.5);
        assert!(f.rms < 0.05 * 3f64.sqrt() && f.rms > 0.0);
    }

    #[test]
    fn degenerate_inputs_are_errors() {
        assert_eq!(
            fit(&pts()[..2], &pts()[..2]),
            Err(PoseFitError::TooFewPoints(2))
        );
        let line: Vec<Vec3> = (0..4)
            .map(|i| Vec3::new(i as f64 * 10.0, 0.0, 0.0))
            .collect();
        assert_eq!(fit(&line, &line), Err(PoseFitError::Collinear));
    }
}
