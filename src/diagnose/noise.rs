//! The noise of each channel: given (`--noise toe_deg=0.005`), or estimated
//! from the data. A rig sweeps its load in small even steps, so along a path a
//! channel is smooth and its second difference `y[k-1] - 2 y[k] + y[k+1]` is
//! mostly noise, of variance `6 σ²` for independent noise of deviation `σ`.
//! The estimate is the median absolute second difference over every path
//! (robust to the few kinks where a path turns back or a stop engages),
//! scaled to a normal deviation: `σ = 1.4826 · median|Δ²y| / √6`.
//!
//! Landmarks are measured at a few states, not in even steps: their noise
//! is what the rigid pose fits of the parts leave (`super::landmarks`).
//!
//! A floor keeps a noise-free data set (a simulation) from giving a zero
//! weight scale: 1e-4 deg and 1e-3 mm, below any rig's resolution.

use super::channel::{Channel, Measured};
use super::rig::RigPath;

/// Where a channel's noise came from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Source {
    Given,
    /// Estimated from this many second differences.
    Estimated(usize),
    /// The estimate was below the floor (or there were fewer than 3 steps).
    Floor,
    /// Not measured (no landmark data): the channel takes no part.
    Absent,
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ChannelNoise {
    pub sigma: f64,
    pub source: Source,
}

/// The noise of every channel, in [`Channel::ALL`] order.
pub type Noise = [ChannelNoise; 6];

pub fn floor(c: Channel) -> f64 {
    match c.unit() {
        "deg" => 1e-4,
        _ => 1e-3,
    }
}

/// The noise of each channel: `given` where the user said, else estimated;
/// the landmarks' absent without landmark data, whatever was given.
pub fn noise(paths: &[RigPath], given: &[(Channel, f64)]) -> Noise {
    let landmarks = paths.iter().any(RigPath::has_landmarks);
    Channel::ALL.map(|c| {
        if c == Channel::Landmarks && !landmarks {
            return ChannelNoise {
                sigma: 1.0,
                source: Source::Absent,
            };
        }
        if let Some((_, s)) = given.iter().find(|(g, _)| *g == c) {
            return ChannelNoise {
                sigma: *s,
                source: Source::Given,
            };
        }
        if c == Channel::Landmarks {
            return landmark_noise(paths, floor(c));
        }
        let series: Vec<Vec<f64>> = paths
            .iter()
            .map(|p| p.steps.iter().map(|s| s.measured[c.index()]).collect())
            .collect();
        estimate(&series, floor(c))
    })
}

/// The landmark noise from the pose fits' residuals.
fn landmark_noise(paths: &[RigPath], floor: f64) -> ChannelNoise {
    let (sum_sq, dof) = paths.iter().fold((0.0, 0), |(s, d), p| {
        (s + p.pose_fit.sum_sq, d + p.pose_fit.dof)
    });
    let sigma = if dof > 0 {
        (sum_sq / dof as f64).sqrt()
    } else {
        0.0
    };
    ChannelNoise::floored(sigma, dof, floor)
}

impl ChannelNoise {
    /// An estimate from `n` values, or the floor when it is below it (or
    /// there was nothing to estimate from).
    fn floored(sigma: f64, n: usize, floor: f64) -> ChannelNoise {
        if n == 0 || sigma.is_nan() || sigma < floor {
            ChannelNoise {
                sigma: floor,
                source: Source::Floor,
            }
        } else {
            ChannelNoise {
                sigma,
                source: Source::Estimated(n),
            }
        }
    }

    /// Whether the channel was measured at all.
    pub fn present(&self) -> bool {
        self.source != Source::Absent
    }
}

/// The estimate from several series of one channel.
pub fn estimate(series: &[Vec<f64>], floor: f64) -> ChannelNoise {
    let mut d: Vec<f64> = series
        .iter()
        .flat_map(|y| y.windows(3).map(|w| (w[0] - 2.0 * w[1] + w[2]).abs()))
        .filter(|v| v.is_finite())
        .collect();
    if d.len() < 3 {
        return ChannelNoise {
            sigma: floor,
            source: Source::Floor,
        };
    }
    d.sort_by(f64::total_cmp);
    let n = d.len();
    let median = if n % 2 == 1 {
        d[n / 2]
    } else {
        0.5 * (d[n / 2 - 1] + d[n / 2])
    };
    ChannelNoise::floored(1.4826 * median / 6f64.sqrt(), n, floor)
}

/// K&C channel values weighted by their noise.
pub fn weighted(noise: &Noise, residual: &Measured) -> Measured {
    let mut out = *residual;
    for (k, v) in out.iter_mut().enumerate() {
        *v /= noise[k].sigma;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::measure::synthetic::Noise as Rng;

    /// Seeded white noise on a smooth curve: the estimate is within 10 % of
    /// the deviation drawn (about 400 differences: the median's own spread
    /// is about 6 %).
    #[test]
    fn estimate_recovers_the_deviation_of_noise_on_a_smooth_curve() {
        let mut rng = Rng::new(3);
        let sigma = 0.02;
        let series: Vec<Vec<f64>> = (0..4)
            .map(|p| {
                (0..100)
                    .map(|k| {
                        let x = k as f64 / 100.0;
                        50.0 * x * x + 3.0 * (p as f64) * x + sigma * rng.normal()
                    })
                    .collect()
            })
            .collect();
        let e = estimate(&series, 1e-3);
        assert!((e.sigma / sigma - 1.0).abs() < 0.1, "{e:?}");
        assert_eq!(e.source, Source::Estimated(392));
    }

    #[test]
    fn noise_free_data_gets_the_floor() {
        let series = vec![(0..20).map(|k| 0.1 * k as f64).collect::<Vec<_>>()];
        assert_eq!(estimate(&series, 1e-3).source, Source::Floor);
    }

    fn path(landmarks: bool, sum_sq: f64, dof: usize) -> RigPath {
        use crate::diagnose::rig::{PoseFitResidual, RigStep};
        RigPath {
            name: "p".into(),
            file: crate::span::FileId(0),
            wheel: crate::model::WheelId(0),
            contact: crate::model::MarkerId(0),
            steps: vec![RigStep {
                step: 1,
                loads: vec![],
                measured: [0.0; 5],
                landmarks: if landmarks {
                    vec![(crate::model::LandmarkId(0), crate::geom::Vec3::zeros())]
                } else {
                    vec![]
                },
            }],
            pose_fit: PoseFitResidual { sum_sq, dof },
            landmark_names: vec![],
        }
    }

    /// The landmark noise is the pose fits' residual per degree of freedom
    /// over every path; without landmark data the channel is absent even
    /// when a deviation was given for it (it would show an RMS of nothing).
    #[test]
    fn landmark_noise_is_the_pose_fit_residual_or_absent() {
        let n = noise(&[path(true, 2.0, 300), path(true, 0.5, 200)], &[]);
        let l = n[Channel::Landmarks.index()];
        assert_eq!(l.source, Source::Estimated(500));
        assert!((l.sigma - (2.5f64 / 500.0).sqrt()).abs() < 1e-15);
        let given = [(Channel::Landmarks, 0.05)];
        let n = noise(&[path(false, 0.0, 0)], &given);
        assert!(!n[Channel::Landmarks.index()].present());
        let n = noise(&[path(true, 2.0, 300)], &given);
        assert_eq!(n[Channel::Landmarks.index()].source, Source::Given);
    }
}
