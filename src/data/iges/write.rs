//! Writes named points, lines and planes as an ASCII IGES file in the layout
//! the reader expects from a measuring arm (millimetres, default delimiters).
//! Synthetic measurements use it, so the IGES path is tested on data whose
//! answer is known. A name longer than the 8-character label, or different
//! from it, is written as a Name property (406 form 15).

use super::Geometry;
use std::fmt::Write;

/// One entity to write.
#[derive(Debug, Clone, PartialEq)]
pub struct Item {
    /// Full name (`part.landmark`); written as a Name property when it is not the label.
    pub name: String,
    /// Directory label: at most 8 characters are written.
    pub label: String,
    pub subscript: i64,
    pub geometry: Geometry,
}

fn ascii(s: &str) -> String {
    s.chars()
        .map(|c| {
            if c.is_ascii() && !c.is_ascii_control() {
                c
            } else {
                '?'
            }
        })
        .collect()
}

fn hollerith(s: &str) -> String {
    let s = ascii(s);
    format!("{}H{s}", s.len())
}

/// Packs delimiter-terminated tokens into lines of at most `width` columns.
fn pack(tokens: &[String], width: usize) -> Vec<String> {
    let mut lines = Vec::new();
    let mut cur = String::new();
    for t in tokens {
        if !cur.is_empty() && cur.len() + t.len() > width {
            lines.push(std::mem::take(&mut cur));
        }
        let mut t = t.as_str();
        while t.len() > width {
            let (a, b) = t.split_at(width - cur.len());
            cur += a;
            lines.push(std::mem::take(&mut cur));
            t = b;
        }
        cur += t;
    }
    if !cur.is_empty() {
        lines.push(cur);
    }
    lines
}

fn tokens(params: &[String]) -> Vec<String> {
    let n = params.len();
    params
        .iter()
        .enumerate()
        .map(|(k, p)| format!("{p}{}", if k + 1 == n { ';' } else { ',' }))
        .collect()
}

fn num(x: f64) -> String {
    format!("{x}")
}

#[derive(Default)]
struct Records {
    d: Vec<String>,
    p: Vec<String>,
}

impl Records {
    /// Adds one entity: its two directory records and its parameter records.
    fn entry(&mut self, kind: i64, form: i64, label: &str, sub: i64, params: Vec<String>) {
        let seq = self.d.len() + 1;
        let lines = pack(&tokens(&params), 64);
        let first = self.p.len() + 1;
        for l in &lines {
            let n = self.p.len() + 1;
            self.p.push(format!("{l:<64}{seq:>8}P{n:>7}"));
        }
        let label: String = ascii(label).chars().take(8).collect();
        self.d.push(format!(
            "{kind:>8}{first:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}D{seq:>7}",
            0, 0, 0, 0, 0, 0, "00000000"
        ));
        self.d.push(format!(
            "{kind:>8}{:>8}{:>8}{:>8}{form:>8}{:>8}{:>8}{label:>8}{sub:>8}D{:>7}",
            0,
            0,
            lines.len(),
            "",
            "",
            seq + 1
        ));
    }
}

/// The file: start comment, Global section in mm, and the items.
pub fn write(file_name: &str, comment: &str, items: &[Item]) -> String {
    let mut out = String::new();
    let start = pack(&[ascii(comment)], 72);
    for (k, l) in start.iter().enumerate() {
        let _ = writeln!(out, "{l:<72}S{:>7}", k + 1);
    }
    let global = [
        "1H,".to_string(),
        "1H;".into(),
        hollerith("axle"),
        hollerith(file_name),
        hollerith("axle"),
        hollerith(env!("CARGO_PKG_VERSION")),
        "32".into(),
        "308".into(),
        "15".into(),
        "308".into(),
        "15".into(),
        hollerith(file_name),
        "1.0".into(),
        "2".into(),
        hollerith("MM"),
        "1".into(),
        "0.0".into(),
        hollerith("20000101.000000"),
        "1.0E-6".into(),
        "10000.0".into(),
        hollerith("axle"),
        hollerith("axle"),
        "11".into(),
        "0".into(),
    ];
    let g = pack(&tokens(&global), 72);
    for (k, l) in g.iter().enumerate() {
        let _ = writeln!(out, "{l:<72}G{:>7}", k + 1);
    }
    // Directory entries and parameter records, built side by side.
    let mut f = Records::default();
    for it in items {
        let named = it.name != it.label || it.label.len() > 8;
        let (kind, form, mut params) = match &it.geometry {
            Geometry::Point(x) => (116, 0, vec![num(x.x), num(x.y), num(x.z), "0".into()]),
            Geometry::Line { from, to } => (
                110,
                0,
                [from.x, from.y, from.z, to.x, to.y, to.z].map(num).to_vec(),
            ),
            Geometry::Plane { normal, offset } => (
                108,
                0,
                [
                    normal.x, normal.y, normal.z, *offset, 0.0, 0.0, 0.0, 0.0, 0.0,
                ]
                .map(num)
                .to_vec(),
            ),
        };
        params.insert(0, kind.to_string());
        if named {
            // The entity's entry comes first, then its Name property's (two records on).
            let own_seq = f.d.len() + 1;
            params.extend(["0".into(), "1".into(), (own_seq + 2).to_string()]);
            f.entry(kind, form, &it.label, it.subscript, params);
            f.entry(
                406,
                15,
                "",
                0,
                vec!["406".into(), "1".into(), hollerith(&it.name)],
            );
        } else {
            f.entry(kind, form, &it.label, it.subscript, params);
        }
    }
    let (d, p) = (f.d, f.p);
    for l in &d {
        let _ = writeln!(out, "{l}");
    }
    for l in &p {
        let _ = writeln!(out, "{l}");
    }
    let _ = writeln!(
        out,
        "{:<72}T{:>7}",
        format!(
            "S{:>7}G{:>7}D{:>7}P{:>7}",
            start.len(),
            g.len(),
            d.len(),
            p.len()
        ),
        1
    );
    out
}
