//! The structure of a model's residuals along each measured path, in words:
//! per channel whose error exceeds twice its noise, whether it is an offset,
//! a slope or a curvature against the path's main load (the least-squares
//! fit of `a + b x + c x²` on the load scaled to [-1, 1]: the term with the
//! largest share of the fitted variation), whether loading and unloading
//! differ (hysteresis: the mean gap between the branches at the same load,
//! against the noise), and where along the path it is largest.

use super::channel::Channel;
use super::noise::Noise;
use super::replay::Replay;
use super::rig::RigPath;
use nalgebra::{DMatrix, DVector};

/// One sentence per (path, channel) worth describing.
#[derive(Debug, Clone, PartialEq)]
pub struct Pattern {
    pub path: String,
    pub channel: Channel,
    pub rms: f64,
    /// "offset", "slope" or "curvature".
    pub shape: &'static str,
    /// The mean gap between unloading and loading at the same load, when
    /// larger than twice the noise.
    pub hysteresis: Option<f64>,
    /// The load (N) where the residual is largest, and its name.
    pub worst_at: (&'static str, f64),
    pub sentence: String,
}

/// The patterns of `replay` against the rig.
pub fn patterns(rig: &[RigPath], replay: &Replay, noise: &Noise) -> Vec<Pattern> {
    let mut out = Vec::new();
    for (p, path) in rig.iter().enumerate() {
        let (load, x) = path.main_load();
        let (lo, hi) = x
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
                (a.min(v), b.max(v))
            });
        if x.len() < 4 || hi - lo <= 0.0 {
            continue;
        }
        let t: Vec<f64> = x.iter().map(|v| 2.0 * (v - lo) / (hi - lo) - 1.0).collect();
        for c in Channel::KC {
            let r: Vec<f64> = replay.paths[p]
                .iter()
                .zip(&path.steps)
                .map(|(s, m)| s[c.index()] - m.measured[c.index()])
                .collect();
            let rms = (r.iter().map(|v| v * v).sum::<f64>() / r.len() as f64).sqrt();
            let sigma = noise[c.index()].sigma;
            if rms <= 2.0 * sigma {
                continue;
            }
            let a = DMatrix::from_fn(r.len(), 3, |i, j| t[i].powi(j as i32));
            let coef = a
                .clone()
                .svd(true, true)
                .solve(&DVector::from_column_slice(&r), 1e-12)
                .unwrap_or_else(|_| DVector::zeros(3));
            // Share of each term: its RMS over the path.
            let share: Vec<f64> = (0..3)
                .map(|j| {
                    (t.iter()
                        .map(|v| (coef[j] * v.powi(j as i32)).powi(2))
                        .sum::<f64>()
                        / t.len() as f64)
                        .sqrt()
                })
                .collect();
            let shape = ["offset", "slope", "curvature"][(0..3)
                .max_by(|&a, &b| share[a].total_cmp(&share[b]))
                .unwrap_or(0)];
            let hysteresis = gap(&x, &r).filter(|g| g.abs() > 2.0 * sigma);
            let worst = (0..r.len())
                .max_by(|&a, &b| r[a].abs().total_cmp(&r[b].abs()))
                .unwrap_or(0);
            let mut sentence = format!(
                "{}: {} error {} {} RMS, mostly {} against {load}, largest at {load} = {:.0} N",
                path.name,
                c.words(),
                super::words::num(rms),
                c.unit(),
                match shape {
                    "offset" => "an offset",
                    "slope" => "a slope",
                    _ => "a curvature",
                },
                x[worst]
            );
            if let Some(g) = hysteresis {
                sentence += &format!(
                    "; loading and unloading differ by {} {} (hysteresis)",
                    super::words::num(g.abs()),
                    c.unit()
                );
            }
            out.push(Pattern {
                path: path.name.clone(),
                channel: c,
                rms,
                shape,
                hysteresis,
                worst_at: (load, x[worst]),
                sentence,
            });
        }
    }
    out
}

/// The mean residual of the unloading steps less that of the loading steps
/// at the same load (linear interpolation on the loading branch), or `None`
/// when the path has no unloading step inside its loading range.
fn gap(x: &[f64], r: &[f64]) -> Option<f64> {
    let mut up: Vec<(f64, f64)> = Vec::new();
    let mut down: Vec<(f64, f64)> = Vec::new();
    for k in 1..x.len() {
        if x[k] > x[k - 1] {
            up.push((x[k], r[k]));
        } else if x[k] < x[k - 1] {
            down.push((x[k], r[k]));
        }
    }
    up.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut diffs = Vec::new();
    for (xd, rd) in down {
        if let Some(w) = up.windows(2).find(|w| w[0].0 <= xd && xd <= w[1].0) {
            let f = if w[1].0 > w[0].0 {
                (xd - w[0].0) / (w[1].0 - w[0].0)
            } else {
                0.0
            };
            diffs.push(rd - (w[0].1 + f * (w[1].1 - w[0].1)));
        }
    }
    (!diffs.is_empty()).then(|| diffs.iter().sum::<f64>() / diffs.len() as f64)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A residual that is +1 loading and -1 unloading along 0 → 10 → 0
    /// has a gap of -2 (unloading less loading).
    #[test]
    fn the_gap_between_branches_is_their_difference_at_the_same_load() {
        let x: Vec<f64> = (0..=10).chain((0..10).rev()).map(f64::from).collect();
        let r: Vec<f64> = (0..x.len())
            .map(|k| if k <= 10 { 1.0 } else { -1.0 })
            .collect();
        let g = gap(&x, &r).expect("a gap");
        assert!((g + 2.0).abs() < 1e-12, "{g}");
        // No unloading: no gap.
        assert_eq!(gap(&[0.0, 1.0, 2.0], &[0.0; 3]), None);
    }
}
