//! `diagnose --report DIR`: one self-contained HTML page (inline SVG and CSS,
//! no script, no network): the findings in words, the held-out residuals per
//! channel, the ranked hypotheses, and per measured path and channel the
//! measured, nominal and extended curves against the path's main load, the
//! loading branches drawn solid and the unloading ones dashed (friction
//! makes them differ); with landmarks, their RMS residual per step, nominal
//! and extended.

use crate::diagnose::channel::Channel;
use crate::diagnose::landmarks::misfit;
use crate::diagnose::replay::Replay;
use crate::diagnose::rig::RigPath;
use crate::diagnose::{Diagnosis, words};
use crate::model::Model;
use std::fmt::Write;

fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

const W: f64 = 300.0;
const H: f64 = 190.0;
const L: f64 = 52.0;
const B: f64 = 30.0;

struct Frame {
    x0: f64,
    x1: f64,
    y0: f64,
    y1: f64,
}

impl Frame {
    fn px(&self, x: f64) -> f64 {
        L + (x - self.x0) / (self.x1 - self.x0).max(1e-12) * (W - L - 10.0)
    }
    fn py(&self, y: f64) -> f64 {
        H - B - (y - self.y0) / (self.y1 - self.y0).max(1e-12) * (H - B - 12.0)
    }
}

/// Indices of the maximal runs where `x` rises (loading) or falls.
fn branches(x: &[f64]) -> Vec<(bool, Vec<usize>)> {
    let mut out: Vec<(bool, Vec<usize>)> = Vec::new();
    for k in 1..x.len() {
        let up = x[k] >= x[k - 1];
        match out.last_mut() {
            Some((u, idx)) if *u == up => idx.push(k),
            _ => out.push((up, vec![k - 1, k])),
        }
    }
    out
}

fn polyline(o: &mut String, f: &Frame, x: &[f64], y: &[f64], colour: &str, width: f64) {
    for (up, idx) in branches(x) {
        let pts: Vec<String> = idx
            .iter()
            .map(|&k| format!("{:.1},{:.1}", f.px(x[k]), f.py(y[k])))
            .collect();
        let dash = if up { "" } else { r#" stroke-dasharray="5,3""# };
        let _ = write!(
            o,
            r#"<polyline fill="none" stroke="{colour}" stroke-width="{width}"{dash} points="{}"/>"#,
            pts.join(" ")
        );
    }
}

/// A K&C channel of a path: measured points, nominal and extended curves.
fn plot(p: &RigPath, c: Channel, nominal: &[f64], extended: &[f64]) -> String {
    let (load, x) = p.main_load();
    let measured: Vec<f64> = p.steps.iter().map(|s| s.measured[c.index()]).collect();
    let title = format!("{} ({})", c.name(), c.unit());
    chart(&title, load, &x, &measured, nominal, extended)
}

/// The landmarks of a path: the RMS residual (mm per coordinate) of the
/// nominal and the extended model at each step that measured landmarks.
fn landmark_plot(p: &RigPath, k: usize, d: &Diagnosis) -> Option<String> {
    let (load, all) = p.main_load();
    let rms = |r: &Replay, i: usize| {
        let s = &p.steps[i];
        (misfit(&r.landmarks[k][i], &s.landmarks) / (3 * s.landmarks.len()) as f64).sqrt()
    };
    let at: Vec<usize> = (0..p.steps.len())
        .filter(|&i| !p.steps[i].landmarks.is_empty())
        .collect();
    if at.len() < 2 {
        return None;
    }
    let x: Vec<f64> = at.iter().map(|&i| all[i]).collect();
    let nominal: Vec<f64> = at.iter().map(|&i| rms(&d.nominal, i)).collect();
    let extended: Vec<f64> = at.iter().map(|&i| rms(&d.replay, i)).collect();
    Some(chart(
        "landmark residual, RMS per coordinate (mm)",
        load,
        &x,
        &[],
        &nominal,
        &extended,
    ))
}

/// One chart against the path's main load `x`: measured points (none for a
/// residual chart), the nominal (grey) and extended (red) curves.
fn chart(
    title: &str,
    load: &str,
    x: &[f64],
    measured: &[f64],
    nominal: &[f64],
    extended: &[f64],
) -> String {
    let all = measured.iter().chain(nominal).chain(extended).cloned();
    let (mut y0, mut y1) = all.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
        (a.min(v), b.max(v))
    });
    if y1 - y0 < 1e-9 {
        y0 -= 0.5;
        y1 += 0.5;
    }
    let pad = 0.05 * (y1 - y0);
    let (x0, x1) = x
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
            (a.min(v), b.max(v))
        });
    let f = Frame {
        x0,
        x1: if x1 > x0 { x1 } else { x0 + 1.0 },
        y0: y0 - pad,
        y1: y1 + pad,
    };
    let mut o = format!(
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{H}" viewBox="0 0 {W} {H}" font-family="sans-serif" font-size="10">"#
    );
    let _ = write!(
        o,
        r##"<rect x="{L}" y="12" width="{}" height="{}" fill="#fbfbfb" stroke="#bbb"/>"##,
        W - L - 10.0,
        H - B - 12.0
    );
    for (v, anchor) in [(f.y0 + pad, "end"), (f.y1 - pad, "end")] {
        let _ = write!(
            o,
            r#"<text x="{}" y="{:.1}" text-anchor="{anchor}">{}</text>"#,
            L - 3.0,
            f.py(v) + 3.0,
            words::num(v)
        );
    }
    for v in [f.x0, f.x1] {
        let _ = write!(
            o,
            r#"<text x="{:.1}" y="{}" text-anchor="middle">{}</text>"#,
            f.px(v),
            H - B + 12.0,
            words::num(v)
        );
    }
    let _ = write!(
        o,
        r#"<text x="{:.1}" y="{}" text-anchor="middle">{load} (N)</text><text x="{L}" y="9">{}</text>"#,
        L + (W - L) / 2.0,
        H - 4.0,
        esc(title)
    );
    polyline(&mut o, &f, x, nominal, "#999", 1.2);
    polyline(&mut o, &f, x, extended, "#c0392b", 1.6);
    for (k, (&xv, &yv)) in x.iter().zip(measured).enumerate() {
        let up = k == 0 || xv >= x[k - 1];
        let fill = if up { "#1f4e99" } else { "none" };
        let _ = write!(
            o,
            r##"<circle cx="{:.1}" cy="{:.1}" r="1.8" fill="{fill}" stroke="#1f4e99" stroke-width="0.8"/>"##,
            f.px(xv),
            f.py(yv)
        );
    }
    o += "</svg>";
    o
}

fn series(r: &Replay, path: usize, c: Channel) -> Vec<f64> {
    r.paths[path].iter().map(|m| m[c.index()]).collect()
}

/// The report page.
pub fn page(model: &Model, rig: &[RigPath], d: &Diagnosis) -> String {
    let mut o = String::new();
    let title = format!("axle diagnose: {}", model.name);
    let _ = write!(
        o,
        "<!DOCTYPE html><html lang=\"en\"><head><meta charset=\"utf-8\"><title>{}</title><style>{}</style></head><body>",
        esc(&title),
        "body{font-family:sans-serif;margin:24px;color:#222;max-width:1000px}h1{font-size:20px}h2{font-size:16px;margin-top:28px}\
         table{border-collapse:collapse;font-size:13px}td,th{padding:3px 8px;border-bottom:1px solid #ddd;text-align:right}\
         td:first-child,th:first-child{text-align:left}.finding{font-size:15px;margin:6px 0}.plots{display:flex;flex-wrap:wrap;gap:6px}\
         .key span{margin-right:16px}.note{color:#666;font-size:12px}"
    );
    let _ = write!(o, "<h1>{}</h1>", esc(&title));
    let _ = write!(o, "<h2>Findings</h2>");
    if d.effects.is_empty() {
        let _ = write!(
            o,
            "<p class=\"finding\">Verdict: none. The model explains the data within the noise.</p>"
        );
    }
    for (k, e) in d.effects.iter().enumerate() {
        let _ = write!(
            o,
            "<p class=\"finding\">{}. {}</p>",
            k + 1,
            esc(&words::sentence(e, &d.noise))
        );
    }
    let after = d.effects.last().map_or(d.baseline.rms_held_out, |e| {
        e.hypothesis.summary.rms_held_out
    });
    let total = d.total_gain();
    let _ = write!(
        o,
        "<h2>Held-out error</h2><p class=\"note\">RMS over the held-out steps (every third step of each path), which no fit saw.</p>\
         <table><tr><th>channel</th><th>nominal</th><th>extended</th><th>gain</th><th>noise σ</th></tr>"
    );
    for c in d.channels() {
        let _ = write!(
            o,
            "<tr><td>{} ({})</td><td>{}</td><td>{}</td><td>{:.0} %</td><td>{}</td></tr>",
            c.name(),
            c.unit(),
            words::num(d.baseline.rms_held_out[c.index()]),
            words::num(after[c.index()]),
            100.0 * total[c.index()],
            words::num(d.noise[c.index()].sigma)
        );
    }
    o += "</table>";
    let _ = write!(
        o,
        "<h2>Causes ranked (first round)</h2><table><tr><th>rank</th><th>kind</th><th>element</th><th>score</th><th>what it says</th></tr>"
    );
    for (k, h) in d.hypotheses.iter().enumerate() {
        let _ = write!(
            o,
            "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td style=\"text-align:left\">{}{}</td></tr>",
            k + 1,
            h.kind.name(),
            esc(&h.element_name),
            words::num(h.score),
            esc(&words::claim(h)),
            if h.significant {
                ""
            } else {
                " (not significant)"
            }
        );
    }
    o += "</table>";
    let _ = write!(
        o,
        "<h2>K&amp;C curves</h2><p class=\"key\"><span style=\"color:#1f4e99\">● measured (open: unloading)</span>\
         <span style=\"color:#999\">— nominal model</span><span style=\"color:#c0392b\">— extended model</span>\
         <span>dashed: unloading</span></p>"
    );
    for (k, p) in rig.iter().enumerate() {
        let _ = write!(o, "<h3>{}</h3><div class=\"plots\">", esc(&p.name));
        for c in Channel::KC {
            o += &plot(p, c, &series(&d.nominal, k, c), &series(&d.replay, k, c));
        }
        if let Some(svg) = landmark_plot(p, k, d) {
            o += &svg;
        }
        o += "</div>";
    }
    o += "</body></html>\n";
    o
}
