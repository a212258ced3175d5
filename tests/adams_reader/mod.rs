//! An independent, strict reader of the Adams/Solver dataset statements that
//! axle emits, written from the documented syntax (`reference/adams-formats.md`
//! §2.2–2.3: title line, `!` comment lines, `NAME/id`, `,` continuation lines,
//! `KEY = values`, flags, function expressions ended by `\`), not from the
//! emitter's code. It rejects what the emitter must never write (abbreviations,
//! trailing comments, long lines) and checks the references between statements.

use std::collections::BTreeMap;

#[derive(Debug, Default, Clone)]
pub struct Stmt {
    pub name: String,
    pub id: Option<u32>,
    pub view: Option<String>,
    pub flags: Vec<String>,
    pub values: BTreeMap<String, String>,
}

impl Stmt {
    pub fn ints(&self, key: &str) -> Vec<u32> {
        self.values.get(key).map_or(vec![], |v| {
            v.split(',').filter_map(|x| x.trim().parse().ok()).collect()
        })
    }
    pub fn nums(&self, key: &str) -> Vec<f64> {
        self.values.get(key).map_or(vec![], |v| {
            v.split(',')
                .filter_map(|x| x.trim().trim_end_matches('D').parse().ok())
                .collect()
        })
    }
}

const STATEMENTS: [&str; 16] = [
    "UNITS",
    "PART",
    "MARKER",
    "JOINT",
    "JPRIM",
    "BUSHING",
    "GFORCE",
    "SFORCE",
    "SPRINGDAMPER",
    "SPLINE",
    "VARIABLE",
    "VFORCE",
    "VTORQUE",
    "REQUEST",
    "OUTPUT",
    "RESULTS",
];
const EXPR_KEYS: [&str; 15] = [
    "FUNCTION", "FX", "FY", "FZ", "TX", "TY", "TZ", "F1", "F2", "F3", "F4", "F5", "F6", "F7", "F8",
];

pub fn parse(text: &str) -> Result<Vec<Stmt>, String> {
    let mut lines = text.lines().enumerate();
    lines.next().ok_or("empty deck")?;
    let mut out: Vec<Stmt> = Vec::new();
    let mut view = None;
    let mut open_expr: Option<String> = None;
    let mut last_key: Option<String> = None;
    let mut ended = false;
    for (n, line) in lines {
        let ln = n + 1;
        if line.len() > 80 {
            return Err(format!("line {ln} is longer than 80 characters"));
        }
        if ended {
            return Err(format!("line {ln} follows END"));
        }
        if let Some(c) = line.strip_prefix('!') {
            if let Some(v) = c.trim().strip_prefix("adams_view_name='") {
                view = Some(v.trim_end_matches('\'').to_string());
            }
            continue;
        }
        if line.contains('!') {
            return Err(format!("line {ln}: a comment after arguments"));
        }
        if line == "END" {
            ended = true;
            continue;
        }
        if let Some(rest) = line.strip_prefix(", ") {
            let st = out
                .last_mut()
                .ok_or(format!("line {ln}: continuation before any statement"))?;
            if let Some(key) = open_expr.clone() {
                let v = st.values.entry(key.clone()).or_default();
                v.push(' ');
                v.push_str(rest.trim_end_matches('\\'));
                if rest.ends_with('\\') {
                    open_expr = None
                }
                continue;
            }
            if let Some((k, v)) = rest.split_once(" = ") {
                if !k
                    .chars()
                    .all(|c| c.is_ascii_uppercase() || c.is_ascii_digit() || c == '_')
                {
                    return Err(format!("line {ln}: bad keyword `{k}`"));
                }
                if st.values.contains_key(k) {
                    return Err(format!("line {ln}: `{k}` given twice"));
                }
                if EXPR_KEYS.contains(&k) {
                    // An expression continues on the next lines unless it ends with `\`
                    // or the statement ends.
                    if !v.ends_with('\\') {
                        open_expr = Some(k.to_string())
                    }
                }
                st.values
                    .insert(k.to_string(), v.trim_end_matches('\\').to_string());
                last_key = Some(k.to_string());
            } else if rest.starts_with(|c: char| c.is_ascii_digit() || c == '-') {
                // A continued number list.
                let k = last_key
                    .clone()
                    .ok_or(format!("line {ln}: a list continuation without a list"))?;
                let v = st.values.entry(k).or_default();
                v.push_str(", ");
                v.push_str(rest);
            } else if rest.chars().all(|c| c.is_ascii_uppercase() || c == '_') {
                st.flags.push(rest.to_string());
            } else {
                return Err(format!("line {ln}: cannot read `{rest}`"));
            }
            continue;
        }
        open_expr = None;
        let (name, id) = line
            .split_once('/')
            .ok_or(format!("line {ln}: `{line}` is not NAME/id"))?;
        if !STATEMENTS.contains(&name) {
            return Err(format!(
                "line {ln}: unknown or abbreviated statement `{name}`"
            ));
        }
        let id = if id.is_empty() {
            None
        } else {
            Some(
                id.parse()
                    .map_err(|_| format!("line {ln}: bad id `{id}`"))?,
            )
        };
        out.push(Stmt {
            name: name.into(),
            id,
            view: view.take(),
            ..Stmt::default()
        });
    }
    if !ended {
        return Err("no END".into());
    }
    Ok(out)
}

/// The `(name, args)` calls of an expression with integer arguments.
fn calls(e: &str) -> Vec<(String, Vec<i64>)> {
    let mut out = Vec::new();
    let b = e.as_bytes();
    for (i, _) in e.match_indices('(') {
        let st = e[..i]
            .rfind(|c: char| !c.is_ascii_alphanumeric())
            .map_or(0, |p| p + 1);
        let name = &e[st..i];
        if name.is_empty() || !b[st].is_ascii_alphabetic() {
            continue;
        }
        let mut depth = 0;
        let mut end = e.len();
        for (k, ch) in e[i..].char_indices() {
            match ch {
                '(' => depth += 1,
                ')' => {
                    depth -= 1;
                    if depth == 0 {
                        end = i + k;
                        break;
                    }
                }
                _ => {}
            }
        }
        // Top-level arguments only; non-integer ones are skipped.
        let (mut args, mut d, mut cur) = (Vec::new(), 0, String::new());
        for ch in e[i + 1..end].chars() {
            match ch {
                '(' => d += 1,
                ')' => d -= 1,
                ',' if d == 0 => {
                    args.extend(cur.trim().parse::<i64>().ok());
                    cur.clear();
                    continue;
                }
                _ => {}
            }
            cur.push(ch);
        }
        args.extend(cur.trim().parse::<i64>().ok());
        out.push((name.to_string(), args));
    }
    out
}

/// Checks references: ids resolve, markers belong to the stated parts, joints
/// and bushings join markers of two different parts, every BUSHING has K and
/// KT with three values each, floating markers serve as JFLOAT only.
pub fn check(st: &[Stmt]) -> Result<(), String> {
    let mut ids: BTreeMap<(&str, u32), &Stmt> = BTreeMap::new();
    for s in st {
        if let Some(id) = s.id
            && ids.insert((s.name.as_str(), id), s).is_some()
        {
            return Err(format!("{}/{id} defined twice", s.name));
        }
        if s.view.is_none() && !matches!(s.name.as_str(), "UNITS" | "OUTPUT" | "RESULTS") {
            return Err(format!("{}/{:?} has no adams_view_name", s.name, s.id));
        }
    }
    let grounds = st
        .iter()
        .filter(|s| s.name == "PART" && s.flags.contains(&"GROUND".into()))
        .count();
    if grounds != 1 {
        return Err(format!("{grounds} ground parts"));
    }
    let marker = |id: u32| {
        ids.get(&("MARKER", id))
            .copied()
            .ok_or(format!("MARKER/{id} is not defined"))
    };
    let part_of = |id: u32| -> Result<u32, String> {
        marker(id)?
            .ints("PART")
            .first()
            .copied()
            .ok_or(format!("MARKER/{id} has no PART"))
    };
    for s in st.iter().filter(|s| s.name == "MARKER") {
        let p = s.ints("PART");
        let part = ids
            .get(&("PART", p.first().copied().unwrap_or(0)))
            .ok_or(format!("MARKER/{:?}: PART not defined", s.id))?;
        // The view name is `part.marker`: the stated part is that part.
        let (pv, mv) = (
            part.view.clone().unwrap_or_default(),
            s.view.clone().unwrap_or_default(),
        );
        if !mv.starts_with(&format!("{pv}.")) {
            return Err(format!("MARKER/{:?} `{mv}` is not on part `{pv}`", s.id));
        }
        if !s.flags.contains(&"FLOATING".into()) && s.nums("QP").len() != 3 {
            return Err(format!("MARKER/{:?} needs QP with 3 values", s.id));
        }
        if let Some(r) = s.values.get("REULER")
            && (r.split(',').count() != 3 || !r.split(',').all(|a| a.trim().ends_with('D')))
        {
            return Err(format!(
                "MARKER/{:?}: REULER must be 3 angles in degrees",
                s.id
            ));
        }
    }
    for s in st {
        let two = |s: &Stmt| -> Result<(), String> {
            let (i, j) = (s.ints("I"), s.ints("J"));
            let ([i], [j]) = (i.as_slice(), j.as_slice()) else {
                return Err(format!("{}/{:?} needs one I and one J", s.name, s.id));
            };
            if part_of(*i)? == part_of(*j)? {
                return Err(format!(
                    "{}/{:?} joins two markers of one part",
                    s.name, s.id
                ));
            }
            Ok(())
        };
        match s.name.as_str() {
            "PART" if !s.flags.contains(&"GROUND".into()) => {
                let cm = s.ints("CM");
                if cm.len() != 1 || part_of(cm[0])? != s.id.unwrap_or(0) {
                    return Err(format!("PART/{:?}: CM is not a marker of the part", s.id));
                }
            }
            "JOINT" | "JPRIM" => {
                two(s)?;
                if s.flags.len() != 1 {
                    return Err(format!("{}/{:?} needs exactly one kind", s.name, s.id));
                }
            }
            "BUSHING" => {
                two(s)?;
                if s.nums("K").len() != 3 || s.nums("KT").len() != 3 {
                    return Err(format!(
                        "BUSHING/{:?} needs K and KT with 3 values each",
                        s.id
                    ));
                }
            }
            "SPRINGDAMPER" | "SFORCE" => two(s)?,
            "REQUEST" => {
                for k in ["I", "J"] {
                    for id in s.ints(k) {
                        marker(id)?;
                    }
                }
            }
            "GFORCE" | "VFORCE" | "VTORQUE" => {
                let f = s.ints("JFLOAT");
                let fm = marker(*f.first().ok_or("no JFLOAT")?)?;
                if !fm.flags.contains(&"FLOATING".into()) {
                    return Err(format!(
                        "{}/{:?}: JFLOAT is not a floating marker",
                        s.name, s.id
                    ));
                }
                marker(*s.ints("I").first().ok_or("no I")?)?;
                marker(*s.ints("RM").first().ok_or("no RM")?)?;
            }
            _ => {}
        }
        for (k, v) in &s.values {
            if !EXPR_KEYS.contains(&k.as_str()) {
                continue;
            }
            for (name, args) in calls(v) {
                let bad = |what: &str, id: i64| {
                    format!(
                        "{}/{:?} {k}: {name} refers to {what}/{id} which is not defined",
                        s.name, s.id
                    )
                };
                match name.as_str() {
                    "DX" | "DY" | "DZ" | "DM" | "AX" | "AY" | "AZ" => {
                        for a in &args {
                            marker(*a as u32).map_err(|_| bad("MARKER", *a))?;
                        }
                    }
                    "AKISPL" => {
                        let id = args.last().copied().unwrap_or(0);
                        ids.get(&("SPLINE", id as u32)).ok_or(bad("SPLINE", id))?;
                    }
                    "VARVAL" => {
                        ids.get(&("VARIABLE", args[0] as u32))
                            .ok_or(bad("VARIABLE", args[0]))?;
                    }
                    "BUSH" => {
                        ids.get(&("BUSHING", args[0] as u32))
                            .ok_or(bad("BUSHING", args[0]))?;
                    }
                    "GFORCE" => {
                        ids.get(&("GFORCE", args[0] as u32))
                            .ok_or(bad("GFORCE", args[0]))?;
                    }
                    _ => {}
                }
            }
        }
    }
    Ok(())
}
