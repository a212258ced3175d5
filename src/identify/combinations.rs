//! What a rank-deficient linear identification determines: each unknown on its
//! own when it is orthogonal to the null space, otherwise the combinations of
//! the unknowns it is entangled with that are orthogonal to the null space
//! (thesis eq. 4.55: `kt_x(b1) + kt_x(b2)` is determined, the split is not).
//!
//! Works in the column-scaled variables `z` of the SVD (`A_s z = b`,
//! `z_i = scale_i · y_i` with `y` in boundary units); the projector `N Nᵀ` on
//! the null space does not depend on the basis the SVD happens to return.

use super::Combination;
use nalgebra::{DMatrix, SymmetricEigen};

/// Below this norm a row of the null-space basis counts as zero.
pub const NULL_TOL: f64 = 1e-3;

pub struct Determination {
    /// Per unknown: determined on its own.
    pub determined: Vec<bool>,
    /// Groups of undetermined unknowns entangled through the null space.
    pub groups: Vec<Vec<usize>>,
    pub combinations: Vec<Combination>,
}

/// `null`: null-space basis (columns) in z; `scale[i]`: z_i / y_i (boundary
/// units); `values`: a least-squares solution y (boundary units); `names`,
/// `units`: per unknown.
pub fn determine(
    null: &DMatrix<f64>,
    scale: &[f64],
    values: &[f64],
    names: &[String],
    units: &[String],
) -> Determination {
    let n = scale.len();
    let p = null * null.transpose();
    let determined: Vec<bool> = (0..n)
        .map(|i| p[(i, i)].max(0.0).sqrt() < NULL_TOL)
        .collect();
    // Connected components of the undetermined unknowns through P.
    let mut group_of: Vec<Option<usize>> = vec![None; n];
    let mut groups: Vec<Vec<usize>> = Vec::new();
    for i in 0..n {
        if determined[i] || group_of[i].is_some() {
            continue;
        }
        let g = groups.len();
        let mut members = vec![i];
        group_of[i] = Some(g);
        let mut k = 0;
        while k < members.len() {
            let a = members[k];
            for b in 0..n {
                if !determined[b] && group_of[b].is_none() && p[(a, b)].abs() > NULL_TOL {
                    group_of[b] = Some(g);
                    members.push(b);
                }
            }
            k += 1;
        }
        members.sort_unstable();
        groups.push(members);
    }
    let mut combinations = Vec::new();
    for g in &groups {
        if g.len() < 2 {
            continue;
        }
        let sub = DMatrix::from_fn(g.len(), g.len(), |a, b| p[(g[a], g[b])]);
        let eig = SymmetricEigen::new(sub);
        // Eigenvalue ~0 of the projector block: a direction orthogonal to the null space.
        let mut order: Vec<usize> = (0..g.len()).collect();
        order.sort_by(|&a, &b| eig.eigenvalues[a].total_cmp(&eig.eigenvalues[b]));
        for &e in &order {
            if eig.eigenvalues[e] > 0.5 {
                continue;
            }
            let c = eig.eigenvectors.column(e);
            let coef: Vec<f64> = (0..g.len()).map(|a| c[a] * scale[g[a]]).collect();
            let top = coef.iter().fold(0.0f64, |m, x| m.max(x.abs()));
            if !(top > 0.0) || !top.is_finite() {
                continue;
            }
            // Lead with a positive coefficient on the first term.
            let first = coef
                .iter()
                .copied()
                .find(|x| x.abs() > 1e-9 * top)
                .unwrap_or(1.0);
            let sign = if first < 0.0 { -1.0 } else { 1.0 };
            let mut terms = Vec::new();
            let mut value = 0.0;
            let mut lead = (0.0, String::new());
            for (a, &ci) in coef.iter().enumerate() {
                let c = sign * ci / top;
                if c.abs() < 1e-9 {
                    continue;
                }
                let c = if (c.abs() - 1.0).abs() < 1e-6 {
                    c.signum()
                } else {
                    c
                };
                value += c * values[g[a]];
                if c.abs() > lead.0 {
                    lead = (c.abs(), units[g[a]].clone());
                }
                terms.push((names[g[a]].clone(), c));
            }
            combinations.push(Combination {
                terms,
                value,
                unit: lead.1,
            });
        }
    }
    Determination {
        determined,
        groups,
        combinations,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_sum_is_determined_when_the_difference_is_free() {
        // Null space of z: (1, -1, 0)/√2 with scales 2 and 2: y0 + y1 determined.
        let s = std::f64::consts::FRAC_1_SQRT_2;
        let null = DMatrix::from_column_slice(3, 1, &[s, -s, 0.0]);
        let names: Vec<String> = ["b1.kt_x", "b2.kt_x", "b1.k_x"].map(String::from).to_vec();
        let units = vec!["N*mm/deg".to_string(); 3];
        let d = determine(&null, &[2.0, 2.0, 1.0], &[12.0, 8.0, 5.0], &names, &units);
        assert_eq!(d.determined, vec![false, false, true]);
        assert_eq!(d.groups, vec![vec![0, 1]]);
        assert_eq!(d.combinations.len(), 1);
        assert_eq!(d.combinations[0].expression(), "kt_x(b1) + kt_x(b2)");
        assert!((d.combinations[0].value - 20.0).abs() < 1e-12);
    }
}
