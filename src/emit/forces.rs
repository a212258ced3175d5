//! Force elements as ADAMS statements: linear bushings as `BUSHING/`, other
//! bushings as `GFORCE/` with `SPLINE/` tables, springs as `SPRINGDAMPER/` or
//! `SFORCE/`, stops as `SFORCE/` with a one-sided `IF` law
//! (`conventions.md` gives the laws these reproduce).

use super::error::EmitError;
use super::plan::{BushingForm, Plan};
use super::writer::{Stmt, list, num};
use crate::model::*;

/// A coefficient in an expression, parenthesised when negative.
fn c(v: f64) -> String {
    let s = num(v);
    if s.starts_with('-') {
        format!("({s})")
    } else {
        s
    }
}

/// `x - a`, or `x` when `a` is zero.
fn minus(x: &str, a: f64) -> String {
    if a == 0.0 {
        x.to_string()
    } else {
        format!("{x} - {}", c(a))
    }
}

fn finite(element: &str, what: &str, vals: &[f64]) -> Result<(), EmitError> {
    if vals.iter().all(|v| v.is_finite()) {
        Ok(())
    } else {
        Err(EmitError::NotFinite {
            element: element.into(),
            what: what.into(),
        })
    }
}

/// A table as SPLINE points: at least 4 (Adams needs 4), strictly increasing x.
/// Short tables get exact midpoints on their longest segments, which linear
/// interpolation reproduces exactly.
pub fn spline_points(element: &str, t: &Table) -> Result<Vec<(f64, f64)>, EmitError> {
    let mut p = t.points.clone();
    let flat: Vec<f64> = p.iter().flat_map(|q| [q.0, q.1]).collect();
    finite(element, "a table point", &flat)?;
    if p.len() < 2
        || p.windows(2)
            .any(|w| w[1].0.partial_cmp(&w[0].0) != Some(std::cmp::Ordering::Greater))
    {
        return Err(EmitError::BadTable {
            element: element.into(),
            detail: "x must increase through at least 2 points".into(),
        });
    }
    while p.len() < 4 {
        let k = (0..p.len() - 1)
            .max_by(|&a, &b| (p[a + 1].0 - p[a].0).total_cmp(&(p[b + 1].0 - p[b].0)))
            .unwrap_or(0);
        let mid = ((p[k].0 + p[k + 1].0) / 2.0, (p[k].1 + p[k + 1].1) / 2.0);
        p.insert(k + 1, mid);
    }
    Ok(p)
}

pub fn spline(out: &mut String, id: u32, view: &str, points: &[(f64, f64)]) {
    out.push_str("! Adams evaluates SPLINEs with AKISPL (Akima); axle interpolates linearly:\n! both pass through every point and extrapolate linearly.\n");
    let xs: Vec<f64> = points.iter().map(|p| p.0).collect();
    let ys: Vec<f64> = points.iter().map(|p| p.1).collect();
    Stmt::new("SPLINE", Some(id))
        .named(view)
        .arg("X", list(&xs))
        .arg("Y", list(&ys))
        .flag("LINEAR_EXTRAPOLATE")
        .write(out);
}

const MEASURE: [&str; 6] = ["DX", "DY", "DZ", "AX", "AY", "AZ"];
const GKEYS: [&str; 6] = ["FX", "FY", "FZ", "TX", "TY", "TZ"];

/// Writes one bushing (and its splines).
pub fn bushing(out: &mut String, m: &Model, plan: &Plan, idx: usize) -> Result<(), EmitError> {
    let b = &m.bushings[idx];
    let name = format!("bushing `{}`", b.name);
    let (i, j) = (plan.marker(b.i), plan.marker(b.j));
    let laws: Vec<&AxisLaw> = b.translational.iter().chain(&b.rotational).collect();
    let offs: Vec<f64> = b
        .offset
        .iter()
        .chain(&b.angle_offset)
        .map(|v| v.value)
        .collect();
    let pre: Vec<f64> = b
        .preload
        .iter()
        .chain(&b.torque_preload)
        .map(|v| v.value)
        .collect();
    finite(
        &name,
        "an offset or preload",
        &[offs.clone(), pre.clone()].concat(),
    )?;
    match &plan.bushings[idx] {
        BushingForm::Linear { id } => {
            let k: Vec<f64> = laws.iter().map(|l| l.initial_stiffness()).collect();
            finite(&name, "a stiffness", &k)?;
            // A linear law with an offset equals one with a preload: -k (t - t0) + F0
            // = -k t + (F0 + k t0). BUSHING has no offset argument, so the offset
            // goes into FORCE/TORQUE exactly (the importer reads it back as a preload).
            let f: Vec<f64> = (0..6).map(|n| pre[n] + k[n] * offs[n]).collect();
            let mut s = Stmt::new("BUSHING", Some(*id))
                .named(&b.name)
                .arg("I", i.to_string())
                .arg("J", j.to_string());
            s = s.arg("K", list(&k[..3])).arg("KT", list(&k[3..]));
            if f[..3].iter().any(|v| *v != 0.0) {
                s = s.arg("FORCE", list(&f[..3]));
            }
            if f[3..].iter().any(|v| *v != 0.0) {
                s = s.arg("TORQUE", list(&f[3..]));
            }
            s.write(out);
        }
        BushingForm::General { id, float, splines } => {
            let mut exprs = Vec::new();
            for n in 0..6 {
                let x = if n < 3 {
                    format!("{}({i},{j},{j})", MEASURE[n])
                } else {
                    format!("{}({i},{j})", MEASURE[n])
                };
                let law = match laws[n] {
                    AxisLaw::Linear { k, k3 } if k3.value == 0.0 => {
                        finite(&name, "a stiffness", &[k.value])?;
                        // Offset folded into the constant, as for BUSHING.
                        let f0 = pre[n] + k.value * offs[n];
                        exprs.push(with_const(format!("-{}*{x}", c(k.value)), f0));
                        continue;
                    }
                    AxisLaw::Linear { k, k3 } => {
                        finite(&name, "a stiffness", &[k.value, k3.value])?;
                        let d = format!("({})", minus(&x, offs[n]));
                        format!("-({}*{d} + {}*{d}**3)", c(k.value), c(k3.value))
                    }
                    AxisLaw::Table(t) => {
                        let sid = splines[n].unwrap_or(0);
                        let view =
                            format!("{}.{}", b.name, ["fx", "fy", "fz", "tx", "ty", "tz"][n]);
                        spline(out, sid, &view, &spline_points(&name, t)?);
                        format!("-AKISPL({}, 0, {sid})", minus(&x, offs[n]))
                    }
                };
                exprs.push(with_const(law, pre[n]));
            }
            let mut s = Stmt::new("GFORCE", Some(*id))
                .named(&b.name)
                .arg("I", i.to_string())
                .arg("JFLOAT", float.to_string())
                .arg("RM", j.to_string());
            for (k, e) in GKEYS.iter().zip(exprs) {
                s = s.expr(k, e);
            }
            s.write(out);
        }
    }
    Ok(())
}

fn with_const(e: String, f0: f64) -> String {
    if f0 == 0.0 {
        e
    } else {
        format!("{e} + {}", c(f0))
    }
}

/// The polynomial `c1 p + c2 p² + …` of a penetration expression `p`.
fn poly(coefs: &[Val], p: &str) -> String {
    let terms: Vec<String> = coefs
        .iter()
        .enumerate()
        .map(|(n, v)| {
            if n == 0 {
                format!("{}*{p}", c(v.value))
            } else {
                format!("{}*{p}**{}", c(v.value), n + 1)
            }
        })
        .collect();
    if terms.is_empty() {
        "0".into()
    } else {
        terms.join(" + ")
    }
}

pub fn spring(
    out: &mut String,
    m: &Model,
    plan: &Plan,
    idx: usize,
    sforce_id: &mut u32,
    sd_id: &mut u32,
) -> Result<(), EmitError> {
    let s = &m.springs[idx];
    let name = format!("spring `{}`", s.name);
    let (i, j) = (plan.marker(s.i), plan.marker(s.j));
    match &s.law {
        SpringLaw::Linear {
            k,
            free_length,
            preload,
        } if k.value >= 0.0 => {
            finite(
                &name,
                "a value",
                &[k.value, free_length.value, preload.value],
            )?;
            *sd_id += 1;
            let mut st = Stmt::new("SPRINGDAMPER", Some(*sd_id))
                .named(&s.name)
                .flag("TRANSLATIONAL")
                .arg("I", i.to_string())
                .arg("J", j.to_string())
                .arg("K", num(k.value))
                .arg("C", "0")
                .arg("LENGTH", num(free_length.value));
            if preload.value != 0.0 {
                st = st.arg("FORCE", num(preload.value));
            }
            st.write(out);
        }
        law => {
            // SPRINGDAMPER needs K >= 0; a negative rate and tables go to SFORCE,
            // whose positive value pushes I and J apart.
            let f = match law {
                SpringLaw::Linear {
                    k,
                    free_length,
                    preload,
                } => {
                    finite(
                        &name,
                        "a value",
                        &[k.value, free_length.value, preload.value],
                    )?;
                    with_const(
                        format!("{}*({} - DM({i},{j}))", c(k.value), num(free_length.value)),
                        preload.value,
                    )
                }
                SpringLaw::Table(t) => {
                    let sid = plan.spring_splines[idx].unwrap_or(0);
                    spline(
                        out,
                        sid,
                        &format!("{}.law", s.name),
                        &spline_points(&name, t)?,
                    );
                    format!("AKISPL(DM({i},{j}), 0, {sid})")
                }
            };
            *sforce_id += 1;
            Stmt::new("SFORCE", Some(*sforce_id))
                .named(&s.name)
                .flag("TRANSLATIONAL")
                .arg("I", i.to_string())
                .arg("J", j.to_string())
                .expr("FUNCTION", f)
                .write(out);
        }
    }
    Ok(())
}

pub fn stop(
    out: &mut String,
    m: &Model,
    plan: &Plan,
    idx: usize,
    sforce_id: &mut u32,
) -> Result<(), EmitError> {
    let s = &m.stops[idx];
    let name = format!("stop `{}`", s.name);
    let (i, j) = (plan.marker(s.i), plan.marker(s.j));
    let lc = s.contact_length.value;
    finite(&name, "the contact length", &[lc])?;
    let dm = format!("DM({i},{j})");
    let pen = match s.kind {
        StopKind::Compression => format!("({} - {dm})", num(lc)),
        StopKind::Rebound => format!("({})", minus(&dm, lc)),
    };
    let f = match &s.law {
        StopLaw::Polynomial(cs) => {
            finite(
                &name,
                "a coefficient",
                &cs.iter().map(|v| v.value).collect::<Vec<_>>(),
            )?;
            poly(cs, &pen)
        }
        StopLaw::Table(t) => {
            let sid = plan.stop_splines[idx].unwrap_or(0);
            spline(
                out,
                sid,
                &format!("{}.law", s.name),
                &spline_points(&name, t)?,
            );
            format!("AKISPL({}, 0, {sid})", &pen[1..pen.len() - 1])
        }
    };
    // IF(e: negative, zero, positive): the force acts on one side of contact only.
    let e = match s.kind {
        StopKind::Compression => format!("IF({}: {f}, 0, 0)", minus(&dm, lc)),
        StopKind::Rebound => format!("IF({}: 0, 0, -({f}))", minus(&dm, lc)),
    };
    *sforce_id += 1;
    Stmt::new("SFORCE", Some(*sforce_id))
        .named(&s.name)
        .flag("TRANSLATIONAL")
        .arg("I", i.to_string())
        .arg("J", j.to_string())
        .expr("FUNCTION", e)
        .write(out);
    Ok(())
}

/// A friction as a GFORCE along (or about) z of the joint's J marker: the
/// stick spring capped at the slip limit, `-kf (s - s_p)` clamped to ±Ff, with
/// `s_p` the design offset. ADAMS statics carries no slip history, so this is
/// axle's element on a first loading from design (a case solved alone), and
/// has no hysteresis along a path that turns back (`docs/adams.md`).
pub fn friction(out: &mut String, m: &Model, plan: &Plan, idx: usize) -> Result<(), EmitError> {
    let f = &m.frictions[idx];
    let name = format!("friction `{}`", f.name);
    // A checked model's friction always names one of its joints.
    let Some(joint) = m.joints.get(f.joint.index()) else {
        return Ok(());
    };
    let (i, j) = (plan.marker(joint.i), plan.marker(joint.j));
    let (kf, limit) = (f.stiffness.value, f.limit.value);
    let sp = crate::statics::friction::design_slip(m)[idx];
    finite(
        &name,
        "its stiffness, limit or design offset",
        &[kf, limit, sp],
    )?;
    let (key, x) = match f.motion {
        FrictionMotion::Slide => (2, format!("DZ({i},{j},{j})")),
        FrictionMotion::Rotation => (5, format!("AZ({i},{j})")),
    };
    let law = format!(
        "MAX(-{lim}, MIN({lim}, -{}*({})))",
        c(kf),
        minus(&x, sp),
        lim = c(limit)
    );
    let (gid, float) = plan.frictions[idx];
    let mut s = Stmt::new("GFORCE", Some(gid))
        .named(&f.name)
        .arg("I", i.to_string())
        .arg("JFLOAT", float.to_string())
        .arg("RM", j.to_string());
    for (n, k) in GKEYS.iter().enumerate() {
        s = s.expr(k, if n == key { law.clone() } else { "0".into() });
    }
    s.write(out);
    Ok(())
}
