//! Force statements → bushings, springs, stops and loads. Force laws written
//! as expressions are read by evaluating them (`super::expr`), so the forms
//! axle emits and equivalent hand-written ones are understood; anything else
//! is reported and skipped.

use super::adm::Deck;
use super::expr::{self, Ctx, Expr, Measure};
use super::reader::Statement;
use crate::model::*;

pub(crate) fn all(d: &mut Deck, stmts: &[Statement]) {
    let mut loads: Vec<(MarkerId, Component, f64)> = Vec::new();
    for s in stmts {
        match s.name.as_str() {
            "BUSHING" => bushing(d, s),
            "GFORCE" => gforce(d, s, &mut loads),
            "VFORCE" | "VTORQUE" => load(d, s, &mut loads),
            "SPRINGDAMPER" => springdamper(d, s),
            "SFORCE" => sforce(d, s),
            _ => {}
        }
    }
    if loads.is_empty() {
        return;
    }
    let channels: Vec<Channel> = loads
        .iter()
        .map(|l| Channel {
            target: LoadTarget::Marker(l.0),
            component: l.1,
        })
        .collect();
    let values = loads.iter().map(|l| l.2).collect();
    d.model.load_sets.push(LoadSet {
        name: "adams".into(),
        channels,
        cases: vec![LoadCase {
            name: "deck".into(),
            values,
        }],
        form: LoadForm::Table,
    });
}

pub(super) fn name(d: &Deck, s: &Statement, fallback: &str) -> String {
    let base = super::adm::ident(
        s.view_name
            .as_deref()
            .map(|v| v.trim_end_matches(".sforce")),
        format!("{fallback}_{}", s.id.unwrap_or(0)),
    );
    let taken = d
        .model
        .bushings
        .iter()
        .map(|b| &b.name)
        .chain(d.model.springs.iter().map(|x| &x.name))
        .chain(d.model.stops.iter().map(|x| &x.name));
    let taken: Vec<&String> = taken.collect();
    if taken.contains(&&base) {
        format!("{base}_{}", s.id.unwrap_or(0))
    } else {
        base
    }
}

fn three(d: &mut Deck, s: &Statement, key: &str, scale: f64) -> Option<[f64; 3]> {
    match s.nums(key) {
        None => Some([0.0; 3]),
        Some(v) if v.len() == 3 => Some([v[0] * scale, v[1] * scale, v[2] * scale]),
        Some(_) => {
            d.error(s, format!("{key} needs 3 values"));
            None
        }
    }
}

/// ADAMS has no axisymmetric bushing: a family whose x and y laws are equal
/// is read as one (its radial law stored once).
fn symmetry(b: &mut Bushing) {
    for laws in [&mut b.translational, &mut b.rotational] {
        *laws = AxisLaws::from_three(laws.to_three(), true);
    }
}

fn bushing(d: &mut Deck, s: &Statement) {
    let (Some(i), Some(j)) = (d.marker(s, "I"), d.marker(s, "J")) else {
        return;
    };
    let (l, f) = (d.len, d.force);
    let (Some(k), Some(kt), Some(f0), Some(t0)) = (
        three(d, s, "K", f / l),
        three(d, s, "KT", f * l),
        three(d, s, "FORCE", f),
        three(d, s, "TORQUE", f * l),
    ) else {
        return;
    };
    if s.has("C") || s.has("CT") {
        d.warn(
            s,
            "damping C/CT has no effect on static equilibrium; not imported",
        );
    }
    let mut b = Bushing::linear(&name(d, s, "bushing"), i, j, k, kt);
    b.preload = vals(f0);
    b.torque_preload = vals(t0);
    symmetry(&mut b);
    d.model.bushings.push(b);
}

/// A law `g(x)` of one measure, evaluated in the deck's context.
pub(super) struct Law<'a> {
    pub e: &'a Expr,
    pub m: &'a Measure,
}

impl Law<'_> {
    pub fn at(&self, d: &Deck, x: f64) -> Result<f64, String> {
        expr::eval(
            self.e,
            &Ctx {
                measure: Some(self.m),
                x,
                splines: &d.splines,
                variables: &d.variables,
            },
            0,
        )
    }
}

/// One bushing axis `g(x) = -f(x - t0) + F0` → (law, t0, F0), in deck units.
fn axis(d: &Deck, law: &Law) -> Result<(AxisLaw, f64, f64), String> {
    if let Some((arg, sid)) = expr::spline_call(law.e) {
        let a = |x: f64| {
            expr::eval(
                arg,
                &Ctx {
                    measure: Some(law.m),
                    x,
                    splines: &d.splines,
                    variables: &d.variables,
                },
                0,
            )
        };
        let t0 = -a(0.0)?;
        if ((a(1.0)? - a(0.0)?) - 1.0).abs() > 1e-9 {
            return Err("the spline argument must be the deformation minus a constant".into());
        }
        let pts = d
            .splines
            .get(&sid)
            .ok_or(format!("SPLINE/{sid} is not defined"))?;
        let (first, last) = (pts[0], pts[pts.len() - 1]);
        let (g1, g2) = (law.at(d, t0 + first.0)?, law.at(d, t0 + last.0)?);
        let s = if last.1 != first.1 {
            (g2 - g1) / (last.1 - first.1)
        } else {
            -1.0
        };
        let f0 = g1 - s * first.1;
        let table = Table {
            points: pts.iter().map(|p| (p.0, -s * p.1)).collect(),
        };
        return Ok((AxisLaw::Table(table), t0, f0));
    }
    let c = expr::polynomial(&|x| law.at(d, x), 3)?
        .ok_or("the law is neither a polynomial of degree 3 nor a spline")?;
    if c[3] != 0.0 {
        // -k3 (x - t0)^3 - k (x - t0) + F0 expanded: c3 = -k3, c2 = 3 k3 t0.
        let k3 = -c[3];
        let t0 = c[2] / (3.0 * k3);
        let k = -c[1] - 3.0 * k3 * t0 * t0;
        let f0 = law.at(d, t0)?;
        return Ok((
            AxisLaw::Linear {
                k: Val::lit(k),
                k3: Val::lit(k3),
            },
            t0,
            f0,
        ));
    }
    if c[2] != 0.0 {
        return Err("a quadratic law has no axle equivalent".into());
    }
    Ok((
        AxisLaw::Linear {
            k: Val::lit(-c[1]),
            k3: Val::ZERO,
        },
        0.0,
        c[0],
    ))
}

const GKEYS: [&str; 6] = ["FX", "FY", "FZ", "TX", "TY", "TZ"];
pub(super) const GMEAS: [&str; 6] = ["DX", "DY", "DZ", "AX", "AY", "AZ"];

fn parse_keys(d: &mut Deck, s: &Statement, keys: &[&str]) -> Option<Vec<Expr>> {
    let mut out = Vec::new();
    for k in keys {
        match s.expr(k).map(expr::parse) {
            None => out.push(Expr::Num(0.0)),
            Some(Ok(e)) => out.push(e),
            Some(Err(e)) => {
                d.error(s, format!("{k}: {e}"));
                return None;
            }
        }
    }
    Some(out)
}

fn gforce(d: &mut Deck, s: &Statement, loads: &mut Vec<(MarkerId, Component, f64)>) {
    let Some(es) = parse_keys(d, s, &GKEYS) else {
        return;
    };
    let mut ms = Vec::new();
    es.iter().for_each(|e| expr::measures(e, &mut ms));
    if ms.is_empty() {
        return load(d, s, loads);
    }
    let (Some(ii), Some(rm)) = (s.int("I"), s.int("RM")) else {
        return d.warn(s, "a GFORCE without I and RM; skipped");
    };
    let (Some(i), Some(j)) = (d.marker(s, "I"), d.marker(s, "RM")) else {
        return;
    };
    if super::friction::gforce(d, s, &es, ii as i64, rm as i64, i, j) {
        return;
    }
    let (l, f) = (d.len, d.force);
    // Scales of x (deformation) and y (force) per axis, deck units → mm, N.
    let scale = |n: usize| if n < 3 { (l, f) } else { (1.0, f * l) };
    let mut b = Bushing::linear(&name(d, s, "bushing"), i, j, [0.0; 3], [0.0; 3]);
    for (n, e) in es.iter().enumerate() {
        let m: Measure = (
            GMEAS[n].to_string(),
            if n < 3 {
                vec![ii as i64, rm as i64, rm as i64]
            } else {
                vec![ii as i64, rm as i64]
            },
        );
        let mut own = Vec::new();
        expr::measures(e, &mut own);
        if own.iter().any(|x| *x != m) {
            return d.warn(s, format!("{}: a coupled law (not a function of {}({},{}…) only) has no axle equivalent; skipped", GKEYS[n], GMEAS[n], ii, rm));
        }
        let (law, t0, f0) = match axis(d, &Law { e, m: &m }) {
            Ok(r) => r,
            Err(msg) => return d.warn(s, format!("{}: {msg}; skipped", GKEYS[n])),
        };
        let (sx, sy) = scale(n);
        let law = match law {
            AxisLaw::Linear { k, k3 } => AxisLaw::Linear {
                k: Val::lit(k.value * sy / sx),
                k3: Val::lit(k3.value * sy / sx.powi(3)),
            },
            AxisLaw::Table(t) => AxisLaw::Table(Table {
                points: t.points.iter().map(|p| (p.0 * sx, p.1 * sy)).collect(),
            }),
        };
        if n < 3 {
            *b.translational.get_mut(n) = law;
            b.offset[n] = Val::lit(t0 * sx);
            b.preload[n] = Val::lit(f0 * sy);
        } else {
            *b.rotational.get_mut(n - 3) = law;
            b.angle_offset[n - 3] = Val::lit(t0 * sx);
            b.torque_preload[n - 3] = Val::lit(f0 * sy);
        }
    }
    symmetry(&mut b);
    d.model.bushings.push(b);
}

/// A constant force/torque at I, components along RM's axes → global loads.
fn load(d: &mut Deck, s: &Statement, loads: &mut Vec<(MarkerId, Component, f64)>) {
    let keys: &[&str] = match s.name.as_str() {
        "VFORCE" => &GKEYS[..3],
        "VTORQUE" => &GKEYS[3..],
        _ => &GKEYS,
    };
    let Some(es) = parse_keys(d, s, keys) else {
        return;
    };
    let Some(i) = d.marker(s, "I") else { return };
    let rot = match s.int("RM") {
        None => crate::geom::Mat3::identity(),
        Some(rm) => match d.markers.get(&rm) {
            Some(m) => m.rot,
            None => return d.error(s, format!("RM = {rm} is not defined")),
        },
    };
    let ctx = Ctx {
        measure: None,
        x: 0.0,
        splines: &d.splines,
        variables: &d.variables,
    };
    let mut v = Vec::new();
    for e in &es {
        match expr::eval(e, &ctx, 0) {
            Ok(x) => v.push(x),
            Err(msg) => {
                return d.warn(
                    s,
                    format!(
                        "{msg}: only constant loads (of VARIABLEs, TIME = 0) are read; skipped"
                    ),
                );
            }
        }
    }
    if es.iter().any(|e| format!("{e:?}").contains("TIME")) {
        d.warn(s, "the load depends on TIME; read at TIME = 0");
    }
    for (chunk, base) in v
        .chunks(3)
        .zip(if keys[0] == "TX" { [3usize, 3] } else { [0, 3] })
    {
        let g = rot * crate::geom::Vec3::new(chunk[0], chunk[1], chunk[2]);
        let scale = if base == 0 { d.force } else { d.force * d.len };
        for k in 0..3 {
            loads.push((i, Component::ALL[base + k], g[k] * scale));
        }
    }
}

fn springdamper(d: &mut Deck, s: &Statement) {
    if !s.has("TRANSLATIONAL") {
        return d.warn(
            s,
            "a rotational SPRINGDAMPER has no axle equivalent; skipped",
        );
    }
    let (Some(i), Some(j)) = (d.marker(s, "I"), d.marker(s, "J")) else {
        return;
    };
    let one = |key: &str| s.nums(key).and_then(|v| v.first().copied()).unwrap_or(0.0);
    let law = SpringLaw::Linear {
        k: Val::lit(one("K") * d.force / d.len),
        free_length: Val::lit(one("LENGTH") * d.len),
        preload: Val::lit(one("FORCE") * d.force),
    };
    let name = name(d, s, "spring");
    d.model.springs.push(Spring { name, i, j, law });
}

fn sforce(d: &mut Deck, s: &Statement) {
    if !s.has("TRANSLATIONAL") {
        return d.warn(s, "a rotational SFORCE has no axle equivalent; skipped");
    }
    let (Some(ii), Some(jj)) = (s.int("I"), s.int("J")) else {
        return d.error(s, "needs I and J");
    };
    let (Some(i), Some(j)) = (d.marker(s, "I"), d.marker(s, "J")) else {
        return;
    };
    let e = match s.expr("FUNCTION").map(expr::parse) {
        Some(Ok(e)) => e,
        Some(Err(e)) => return d.error(s, e),
        None => return d.error(s, "needs FUNCTION = expression"),
    };
    let m: Measure = ("DM".into(), vec![ii as i64, jj as i64]);
    let mut own = Vec::new();
    expr::measures(&e, &mut own);
    if own.iter().any(|x| *x != m) {
        return d.warn(
            s,
            format!("the force depends on more than DM({ii},{jj}); skipped"),
        );
    }
    let name = name(d, s, "sforce");
    let (l, f) = (d.len, d.force);
    let res = if let Expr::If(c, neg, zero, pos) = &e {
        stop(d, &m, c, neg, zero, pos).map(|(kind, lc, law)| {
            d.model.stops.push(Stop {
                name: name.clone(),
                kind,
                i,
                j,
                contact_length: Val::lit(lc * l),
                law: scale_stop(law, l, f),
            });
        })
    } else {
        spring(d, &Law { e: &e, m: &m }).map(|law| {
            let law = match law {
                SpringLaw::Linear {
                    k,
                    free_length,
                    preload,
                } => SpringLaw::Linear {
                    k: Val::lit(k.value * f / l),
                    free_length: Val::lit(free_length.value * l),
                    preload: Val::lit(preload.value * f),
                },
                SpringLaw::Table(t) => SpringLaw::Table(Table {
                    points: t.points.iter().map(|p| (p.0 * l, p.1 * f)).collect(),
                }),
            };
            d.model.springs.push(Spring {
                name: name.clone(),
                i,
                j,
                law,
            });
        })
    };
    if let Err(msg) = res {
        d.warn(s, format!("{msg}; skipped"));
    }
}

fn spring(d: &Deck, law: &Law) -> Result<SpringLaw, String> {
    if let Some((arg, sid)) = expr::spline_call(law.e) {
        let pts = d
            .splines
            .get(&sid)
            .ok_or(format!("SPLINE/{sid} is not defined"))?;
        let a = |x: f64| {
            expr::eval(
                arg,
                &Ctx {
                    measure: Some(law.m),
                    x,
                    splines: &d.splines,
                    variables: &d.variables,
                },
                0,
            )
        };
        let t0 = -a(0.0)?;
        let points = pts
            .iter()
            .map(|p| Ok((p.0 + t0, law.at(d, p.0 + t0)?)))
            .collect::<Result<_, String>>()?;
        return Ok(SpringLaw::Table(Table { points }));
    }
    let c = expr::polynomial(&|x| law.at(d, x), 1)?
        .ok_or("the spring law is neither linear nor a spline")?;
    let k = -c[1];
    Ok(if k != 0.0 {
        SpringLaw::Linear {
            k: Val::lit(k),
            free_length: Val::lit(c[0] / k),
            preload: Val::ZERO,
        }
    } else {
        SpringLaw::Linear {
            k: Val::ZERO,
            free_length: Val::ZERO,
            preload: Val::lit(c[0]),
        }
    })
}

/// `IF(DM - lc: f(lc - DM), 0, 0)` (compression) or `IF(DM - lc: 0, 0, -f(DM - lc))` (rebound).
fn stop(
    d: &Deck,
    m: &Measure,
    c: &Expr,
    neg: &Expr,
    zero: &Expr,
    pos: &Expr,
) -> Result<(StopKind, f64, StopLaw), String> {
    let ev = |e: &Expr, x: f64| {
        expr::eval(
            e,
            &Ctx {
                measure: Some(m),
                x,
                splines: &d.splines,
                variables: &d.variables,
            },
            0,
        )
    };
    let cond = expr::polynomial(&|x| ev(c, x), 1)?
        .ok_or("the IF condition must be DM minus a contact length")?;
    if cond[1] <= 0.0 {
        return Err("the IF condition must grow with DM".into());
    }
    let lc = -cond[0] / cond[1];
    let is_zero =
        |e: &Expr| matches!(expr::polynomial(&|x| ev(e, x), 0), Ok(Some(v)) if v[0] == 0.0);
    if !is_zero(zero) {
        return Err("a stop acts on one side of contact only".into());
    }
    let (kind, branch, sign, dir) = match (is_zero(neg), is_zero(pos)) {
        (false, true) => (StopKind::Compression, neg, 1.0, -1.0),
        (true, false) => (StopKind::Rebound, pos, -1.0, 1.0),
        _ => return Err("a stop acts on one side of contact only".into()),
    };
    // f(p) with the penetration p = dir * (DM - lc).
    let f = |p: f64| Ok::<f64, String>(sign * ev(branch, lc + dir * p)?);
    if let Some((_, sid)) = expr::spline_call(branch) {
        let pts = d
            .splines
            .get(&sid)
            .ok_or(format!("SPLINE/{sid} is not defined"))?;
        let points = pts
            .iter()
            .map(|p| Ok((p.0, f(p.0)?)))
            .collect::<Result<_, String>>()?;
        return Ok((kind, lc, StopLaw::Table(Table { points })));
    }
    let c = expr::polynomial(&f, 6)?.ok_or("the stop law is neither a polynomial nor a spline")?;
    let mut coefs: Vec<Val> = c[1..].iter().map(|v| Val::lit(*v)).collect();
    while coefs.len() > 1 && coefs.last().is_some_and(|v| v.value == 0.0) {
        coefs.pop();
    }
    Ok((kind, lc, StopLaw::Polynomial(coefs)))
}

fn scale_stop(law: StopLaw, l: f64, f: f64) -> StopLaw {
    match law {
        StopLaw::Polynomial(c) => StopLaw::Polynomial(
            c.iter()
                .enumerate()
                .map(|(n, v)| Val::lit(v.value * f / l.powi(n as i32 + 1)))
                .collect(),
        ),
        StopLaw::Table(t) => StopLaw::Table(Table {
            points: t.points.iter().map(|p| (p.0 * l, p.1 * f)).collect(),
        }),
    }
}
