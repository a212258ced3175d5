//! Matching unordered measured points to a part's declared landmarks by their
//! distance tables (thesis eq. 2.13–2.16), with one corrupted point detected and
//! left out (methods.md §2.3, [impl]).

use crate::geom::Vec3;

/// The result: `assignment[k]` is the landmark index of measured point `k`
/// (`None` when the point was left out as an outlier).
#[derive(Debug, Clone, PartialEq)]
pub struct Match {
    pub assignment: Vec<Option<usize>>,
    /// Largest disagreement between a measured and a declared distance, mm.
    pub worst: f64,
}

#[derive(Debug, Clone, PartialEq)]
pub enum MatchError {
    /// No assignment agrees within the tolerance, even with one point left out.
    NoMatch { best_worst: f64 },
    /// Several assignments agree: the distance table cannot tell the points apart.
    Ambiguous,
    /// More measured points than landmarks, or fewer than 3 usable.
    Count { measured: usize, declared: usize },
}

/// Largest |distance(measured a, b) − distance(landmark σa, σb)| for an assignment.
fn worst(measured: &[Vec3], declared: &[Vec3], idx: &[usize], sigma: &[usize]) -> f64 {
    let mut w: f64 = 0.0;
    for a in 0..idx.len() {
        for b in a + 1..idx.len() {
            let dm = (measured[idx[a]] - measured[idx[b]]).norm();
            let dd = (declared[sigma[a]] - declared[sigma[b]]).norm();
            w = w.max((dm - dd).abs());
        }
    }
    w
}

/// All injective maps of `k` items into `0..n`.
fn arrangements(k: usize, n: usize) -> Vec<Vec<usize>> {
    let mut out = Vec::new();
    let mut cur = Vec::new();
    fn rec(k: usize, n: usize, cur: &mut Vec<usize>, out: &mut Vec<Vec<usize>>) {
        if cur.len() == k {
            out.push(cur.clone());
            return;
        }
        for i in 0..n {
            if !cur.contains(&i) {
                cur.push(i);
                rec(k, n, cur, out);
                cur.pop();
            }
        }
    }
    rec(k, n, &mut cur, &mut out);
    out
}

/// Matches `measured` points (any order, possibly fewer than declared) to the
/// `declared` landmarks within `tol` mm. Requires a unique accepted assignment.
pub fn match_points(measured: &[Vec3], declared: &[Vec3], tol: f64) -> Result<Match, MatchError> {
    let (m, n) = (measured.len(), declared.len());
    if m > n || m < 3 || n > 8 {
        return Err(MatchError::Count {
            measured: m,
            declared: n,
        });
    }
    let all: Vec<usize> = (0..m).collect();
    let try_subset = |idx: &[usize]| -> (Vec<(Vec<usize>, f64)>, f64) {
        let mut ok = Vec::new();
        let mut best = f64::INFINITY;
        for sigma in arrangements(idx.len(), n) {
            let w = worst(measured, declared, idx, &sigma);
            best = best.min(w);
            if w < tol {
                ok.push((sigma, w));
            }
        }
        (ok, best)
    };
    let build = |idx: &[usize], sigma: &[usize], w: f64| {
        let mut assignment = vec![None; m];
        for (k, &i) in idx.iter().enumerate() {
            assignment[i] = Some(sigma[k]);
        }
        Match {
            assignment,
            worst: w,
        }
    };
    let (ok, best) = try_subset(&all);
    match ok.len() {
        1 => return Ok(build(&all, &ok[0].0, ok[0].1)),
        0 => {}
        _ => return Err(MatchError::Ambiguous),
    }
    // No full match: leave out each point in turn and keep the unique subset that fits.
    if m <= 3 {
        return Err(MatchError::NoMatch { best_worst: best });
    }
    let mut found: Vec<Match> = Vec::new();
    for out in 0..m {
        let idx: Vec<usize> = all.iter().copied().filter(|&i| i != out).collect();
        let (ok, _) = try_subset(&idx);
        if ok.len() > 1 {
            return Err(MatchError::Ambiguous);
        }
        if let Some((sigma, w)) = ok.first() {
            found.push(build(&idx, sigma, *w));
        }
    }
    match found.len() {
        1 => Ok(found.remove(0)),
        0 => Err(MatchError::NoMatch { best_worst: best }),
        _ => Err(MatchError::Ambiguous),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::euler_zxz;

    fn declared() -> Vec<Vec3> {
        vec![
            Vec3::new(62.0, 749.0, 234.0),
            Vec3::new(-48.0, 758.0, 209.0),
            Vec3::new(35.0, 732.0, 426.0),
            Vec3::new(-81.0, 746.0, 363.0),
        ]
    }

    fn measured(order: &[usize]) -> Vec<Vec3> {
        let r = euler_zxz(0.1, 0.05, -0.02);
        let t = Vec3::new(5.0, -3.0, 40.0);
        order.iter().map(|&i| t + r * declared()[i]).collect()
    }

    #[test]
    fn shuffled_points_are_put_back_in_order() {
        let m = match_points(&measured(&[2, 0, 3, 1]), &declared(), 0.5).expect("match");
        assert_eq!(m.assignment, vec![Some(2), Some(0), Some(3), Some(1)]);
        assert!(m.worst < 1e-9);
    }

    #[test]
    fn a_corrupted_point_is_left_out() {
        let mut q = measured(&[1, 3, 0, 2]);
        q[1] += Vec3::new(4.0, -2.0, 3.0);
        let m = match_points(&q, &declared(), 0.5).expect("match with one out");
        assert_eq!(m.assignment, vec![Some(1), None, Some(0), Some(2)]);
    }

    #[test]
    fn a_missing_point_still_matches() {
        let m = match_points(&measured(&[3, 1, 2]), &declared(), 0.5).expect("three of four");
        assert_eq!(m.assignment, vec![Some(3), Some(1), Some(2)]);
    }

    #[test]
    fn symmetric_landmarks_are_ambiguous() {
        // A square: every rotation of the labels fits.
        let sq = vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(100.0, 0.0, 0.0),
            Vec3::new(100.0, 100.0, 0.0),
            Vec3::new(0.0, 100.0, 0.0),
        ];
        assert_eq!(match_points(&sq, &sq, 0.5), Err(MatchError::Ambiguous));
    }

    #[test]
    fn unrelated_points_do_not_match() {
        let q: Vec<Vec3> = (0..4)
            .map(|i| Vec3::new(i as f64 * 37.0, (i * i) as f64 * 11.0, 5.0))
            .collect();
        assert!(matches!(
            match_points(&q, &declared(), 0.5),
            Err(MatchError::NoMatch { .. })
        ));
    }
}
