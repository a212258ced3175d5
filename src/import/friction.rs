//! A friction read back from the GFORCE axle writes for it (`docs/adams.md`,
//! "Friction"): a linear law along (or about) z of a joint's J marker capped
//! at a level, between that joint's I and J markers.

use super::adm::Deck;
use super::expr::{Expr, Measure};
use super::forces::{GMEAS, Law, name};
use super::reader::Statement;
use crate::model::*;

/// A GFORCE between the I and J markers of a cylindrical, translational,
/// revolute or spherical joint whose only law is a force along z_J (or a
/// torque about it) that is linear and capped at a level, as axle writes a
/// friction: read back as that friction (kf, limit; the design offset comes
/// back from the geometry). Returns whether the statement was one.
pub(super) fn gforce(
    d: &mut Deck,
    s: &Statement,
    es: &[Expr],
    ii: i64,
    rm: i64,
    i: MarkerId,
    j: MarkerId,
) -> bool {
    let live: Vec<usize> = (0..6)
        .filter(|&n| !matches!(es[n], Expr::Num(v) if v == 0.0))
        .collect();
    let (n, motion) = match live.as_slice() {
        [2] => (2, FrictionMotion::Slide),
        [5] => (5, FrictionMotion::Rotation),
        _ => return false,
    };
    let uses = |e: &Expr, f: &str| match e {
        Expr::Call(c, _) => c == f,
        _ => false,
    };
    // The capped form: MAX(.., MIN(.., law)) (or MIN of MAX).
    let capped = match &es[n] {
        Expr::Call(c, a) if (c == "MAX" || c == "MIN") && a.len() == 2 => a
            .iter()
            .any(|x| uses(x, if c == "MAX" { "MIN" } else { "MAX" })),
        _ => false,
    };
    let Some(k) = d.model.joints.iter().position(|jt| jt.i == i && jt.j == j) else {
        return false;
    };
    if !capped || !crate::check::friction_allows(d.model.joints[k].kind, motion) {
        return false;
    }
    let m: Measure = (
        GMEAS[n].to_string(),
        if n < 3 {
            vec![ii, rm, rm]
        } else {
            vec![ii, rm]
        },
    );
    let law = Law { e: &es[n], m: &m };
    let g = |x: f64| law.at(d, x);
    // Decreasing from +Ff to -Ff: the level, the zero (the offset), and the
    // point of half the level give the stiffness.
    let (Ok(hi), Ok(lo)) = (g(-1e9), g(1e9)) else {
        return false;
    };
    if !(hi > 0.0 && (hi + lo).abs() <= 1e-9 * hi) {
        return false;
    }
    let root = |target: f64| -> Option<f64> {
        let (mut a, mut b) = (-1e9, 1e9);
        for _ in 0..200 {
            let mid = 0.5 * (a + b);
            if g(mid).ok()? > target {
                a = mid
            } else {
                b = mid
            }
        }
        Some(0.5 * (a + b))
    };
    let (Some(x0), Some(xh)) = (root(0.0), root(0.5 * hi)) else {
        return false;
    };
    if x0 <= xh {
        return false;
    }
    let kf = 0.5 * hi / (x0 - xh);
    let (l, f) = (d.len, d.force);
    let (sx, sy) = if n < 3 { (l, f) } else { (1.0, f * l) };
    let name = name(d, s, "friction");
    if let Some(fr) = [kf * sy / sx, hi * sy].iter().find(|v| !v.is_finite()) {
        d.warn(s, format!("friction law gives {fr}; skipped"));
        return true;
    }
    d.model.frictions.push(Friction {
        name,
        joint: JointId(k as u32),
        motion,
        stiffness: Val::lit(kf * sy / sx),
        limit: Val::lit(hi * sy),
    });
    true
}
