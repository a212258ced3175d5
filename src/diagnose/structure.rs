//! The structure of a model's residuals along each measured path, in words:
//! per channel whose error exceeds twice its noise (for the landmarks, the
//! worst landmark along its worst coordinate), whether it is an offset,
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

/// The patterns of `replay` against the rig: per path, each K&C channel
/// whose error exceeds twice its noise, and the landmark whose error is
/// largest (described along its worst coordinate).
pub fn patterns(rig: &[RigPath], replay: &Replay, noise: &Noise) -> Vec<Pattern> {
    let mut out = Vec::new();
    for (p, path) in rig.iter().enumerate() {
        let (load, x) = path.main_load();
        for c in Channel::KC {
            let r: Vec<f64> = replay.paths[p]
                .iter()
                .zip(&path.steps)
                .map(|(s, m)| s[c.index()] - m.measured[c.index()])
                .collect();
            let what = format!("{} error", c.words());
            let sigma = noise[c.index()].sigma;
            out.extend(describe(&path.name, c, &what, load, &x, &r, sigma));
        }
        if let Some((name, axis, xs, r)) = worst_landmark(path, &replay.landmarks[p], &x) {
            let what = format!("landmark error (largest on `{name}`, along {axis})");
            let sigma = noise[Channel::Landmarks.index()].sigma;
            out.extend(describe(
                &path.name,
                Channel::Landmarks,
                &what,
                load,
                &xs,
                &r,
                sigma,
            ));
        }
    }
    out
}

/// The landmark of `path` with the largest RMS residual: its name, its
/// worst coordinate, and the loads and signed residuals along it at the
/// steps that measured it.
fn worst_landmark(
    path: &RigPath,
    simulated: &[Vec<crate::geom::Vec3>],
    x: &[f64],
) -> Option<(String, &'static str, Vec<f64>, Vec<f64>)> {
    use std::collections::BTreeMap;
    let mut by: BTreeMap<crate::model::LandmarkId, Vec<(f64, crate::geom::Vec3)>> = BTreeMap::new();
    for ((step, sim), &load) in path.steps.iter().zip(simulated).zip(x) {
        for ((l, m), s) in step.landmarks.iter().zip(sim) {
            by.entry(*l).or_default().push((load, s - m));
        }
    }
    let ms = |v: &[(f64, crate::geom::Vec3)]| {
        v.iter().map(|(_, d)| d.norm_squared()).sum::<f64>() / v.len().max(1) as f64
    };
    let (l, v) = by
        .into_iter()
        .max_by(|a, b| ms(&a.1).total_cmp(&ms(&b.1)))?;
    let axis = (0..3)
        .max_by(|&a, &b| {
            let s = |k: usize| v.iter().map(|(_, d)| d[k] * d[k]).sum::<f64>();
            s(a).total_cmp(&s(b))
        })
        .unwrap_or(0);
    let name = path
        .landmark_names
        .get(l.index())
        .cloned()
        .unwrap_or_default();
    Some((
        name,
        ["x", "y", "z"][axis],
        v.iter().map(|(x, _)| *x).collect(),
        v.iter().map(|(_, d)| d[axis]).collect(),
    ))
}

/// The pattern of one residual series `r` against the loads `x`, when its
/// RMS exceeds twice `sigma`.
fn describe(
    path: &str,
    c: Channel,
    what: &str,
    load: &'static str,
    x: &[f64],
    r: &[f64],
    sigma: f64,
) -> Option<Pattern> {
    let (lo, hi) = x
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
            (a.min(v), b.max(v))
        });
    if x.len() < 4 || hi - lo <= 0.0 {
        return None;
    }
    let rms = (r.iter().map(|v| v * v).sum::<f64>() / r.len() as f64).sqrt();
    if rms <= 2.0 * sigma {
        return None;
    }
    let t: Vec<f64> = x.iter().map(|v| 2.0 * (v - lo) / (hi - lo) - 1.0).collect();
    let a = DMatrix::from_fn(r.len(), 3, |i, j| t[i].powi(j as i32));
    let coef = a
        .svd(true, true)
        .solve(&DVector::from_column_slice(r), 1e-12)
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
    let hysteresis = gap(x, r).filter(|g| g.abs() > 2.0 * sigma);
    let worst = (0..r.len())
        .max_by(|&a, &b| r[a].abs().total_cmp(&r[b].abs()))
        .unwrap_or(0);
    let mut sentence = format!(
        "{path}: {what} {} {} RMS, mostly {} against {load}, largest at {load} = {:.0} N",
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
    Some(Pattern {
        path: path.to_string(),
        channel: c,
        rms,
        shape,
        hysteresis,
        worst_at: (load, x[worst]),
        sentence,
    })
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
