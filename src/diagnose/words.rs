//! A finding as a sentence an engineer can act on: what differs, by how
//! much (with its 95 % interval, against the model's value), and what it buys
//! on the held-out steps. A parameter the data cannot determine is said to
//! be undetermined, never printed as a number.

use super::channel::Channel;
use super::choose::{Effect, Hypothesis, ParamResult};
use super::kind::Kind;
use super::noise::Noise;

/// `v` with three significant digits (no exponent for rig-sized numbers).
pub fn num(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return format!("{v}");
    }
    let mag = v.abs().log10().floor() as i32;
    if !(-4..6).contains(&mag) {
        return format!("{v:.2e}");
    }
    let decimals = (2 - mag).max(0) as usize;
    format!("{v:.decimals$}")
}

/// "775 [742, 810] N/mm", or "undetermined".
pub fn value(p: &ParamResult) -> String {
    if p.at_bound {
        return "at the end of its search range (not an estimate)".to_string();
    }
    match (p.value, p.interval) {
        (Some(v), Some((a, b))) => format!("{} [{}, {}] {}", num(v), num(a), num(b), p.unit),
        _ => "undetermined".to_string(),
    }
}

fn against(p: &ParamResult) -> String {
    match p.nominal {
        Some(n) => format!(" against {}", num(n)),
        None => String::new(),
    }
}

/// The channels an effect improves, best first: those whose held-out RMS
/// was above twice its noise, with a gain of at least 10 %.
fn improved(e: &Effect, noise: &Noise) -> String {
    let mut ch: Vec<(Channel, f64)> = Channel::ALL
        .into_iter()
        .filter(|c| e.before.rms_held_out[c.index()] > 2.0 * noise[c.index()].sigma)
        .map(|c| (c, e.gain[c.index()]))
        .filter(|(_, g)| *g >= 0.1)
        .collect();
    ch.sort_by(|a, b| b.1.total_cmp(&a.1));
    if ch.is_empty() {
        return "the held-out error falls within the noise".to_string();
    }
    let parts: Vec<String> = ch
        .iter()
        .take(3)
        .enumerate()
        .map(|(k, (c, g))| {
            let pct = (g * 100.0).round();
            if k == 0 {
                format!("held-out {} error falls {pct:.0} %", c.words())
            } else {
                format!("{} {pct:.0} %", c.words())
            }
        })
        .collect();
    parts.join(", ")
}

/// What the hypothesis says, without its gain.
pub fn claim(h: &Hypothesis) -> String {
    let p = &h.params;
    let name = &h.element_name;
    match h.kind {
        Kind::Stiffness => {
            let q = &p[0];
            let axis = h.detail.rsplit(' ').next().unwrap_or("");
            let what = if h.detail.starts_with("rate") {
                format!("spring `{name}` is")
            } else if h.detail.starts_with("torsional") {
                format!("bushing `{name}` is, about its {axis} axis,")
            } else {
                format!("bushing `{name}` is, along its {axis} axis,")
            };
            match (q.value, q.nominal) {
                (Some(v), Some(n)) if n > 0.0 => {
                    let (r, word) = if v >= n {
                        (v / n, "stiffer")
                    } else {
                        (n / v, "softer")
                    };
                    format!(
                        "{what} {}× {word} than the model ({}{})",
                        num(r),
                        value(q),
                        against(q)
                    )
                }
                _ if q.at_bound => format!(
                    "{what} of a stiffness beyond 10 times the model's (the end of its search range)"
                ),
                _ => format!("{what} of a stiffness the data do not determine"),
            }
        }
        Kind::JointLocation => {
            let d: Vec<String> = p
                .iter()
                .map(|q| match (q.value, q.interval, q.nominal) {
                    (Some(v), Some((a, b)), Some(n)) => {
                        format!("{} [{}, {}]", num(v - n), num(a - n), num(b - n))
                    }
                    _ => "undetermined".into(),
                })
                .collect();
            format!(
                "joint `{name}` sits off its modelled point: displaced by ({}) mm in x, y, z",
                d.join(", ")
            )
        }
        Kind::BumpStop | Kind::ReboundStop => {
            let which = if h.kind == Kind::BumpStop {
                "bump"
            } else {
                "rebound"
            };
            format!(
                "a {which} stop the model lacks acts along spring `{name}`: contact at length {}, rate {}",
                value(&p[0]),
                value(&p[1])
            )
        }
        Kind::NonlinearBushing => {
            let axis = h.detail.rsplit(' ').next().unwrap_or("");
            format!(
                "bushing `{name}` stiffens along its {axis} axis: cubic term {}",
                value(&p[0])
            )
        }
        Kind::Preload => {
            let d: Vec<String> = p.iter().map(value_short).collect();
            format!(
                "bushing `{name}` is preloaded: deformation offset ({}) mm in x, y, z (the forces of its point displaced that much on one part)",
                d.join(", ")
            )
        }
        Kind::SpringFreeLength => format!(
            "spring `{name}` has a free length of {}{}",
            value(&p[0]),
            against(&p[0])
        ),
        Kind::PartCompliance => format!(
            "part `{name}` is not rigid ({}): it bends like a joint of stiffness {} and {}",
            h.detail,
            value(&p[0]),
            value(&p[1])
        ),
        Kind::Friction => format!(
            "joint `{name}` has dry friction {}: slip limit {}",
            h.detail.split(" of joint").next().unwrap_or(""),
            value(&p[0])
        ),
        Kind::None => "the model explains the data within the noise".into(),
    }
}

fn value_short(p: &ParamResult) -> String {
    match (p.value, p.interval) {
        (Some(v), Some((a, b))) => format!("{} [{}, {}]", num(v), num(a), num(b)),
        _ => "undetermined".into(),
    }
}

/// The finding as one sentence.
pub fn sentence(e: &Effect, noise: &Noise) -> String {
    format!(
        "{}: {}.",
        capital(&claim(&e.hypothesis)),
        improved(e, noise)
    )
}

fn capital(s: &str) -> String {
    let mut c = s.chars();
    match c.next() {
        Some(f) => f.to_uppercase().collect::<String>() + c.as_str(),
        None => String::new(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_have_three_significant_digits() {
        assert_eq!(num(775.4), "775");
        assert_eq!(num(2.4567), "2.46");
        assert_eq!(num(-0.01234), "-0.0123");
        assert_eq!(num(123456.0), "123456");
        assert_eq!(num(2.0e7), "2.00e7");
    }
}
