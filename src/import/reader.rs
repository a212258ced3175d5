//! ADAMS dataset text → statements: the title line, `!` comments (and the
//! `adams_view_name` above a statement), `,` continuation lines, keyword
//! abbreviations, Fortran reals (`1.0D+03`, `1.E3`, `.4`), the `D` degree
//! suffix, leading-zero ids, and function expressions ended by `\`.
//! Syntax source: `reference/adams-formats.md` §2.2 (see `docs/adams.md`).

/// One value of an argument.
#[derive(Debug, Clone, PartialEq)]
pub enum Value {
    /// A real; angles written with `D` are converted to radians.
    Num(f64),
    Word(String),
    /// A function expression (continuation lines joined).
    Expr(String),
}

#[derive(Debug, Clone, PartialEq)]
pub struct Arg {
    /// Upper-case keyword, abbreviations resolved when known.
    pub key: String,
    /// Empty for a flag such as `GROUND`.
    pub values: Vec<Value>,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Statement {
    pub name: String,
    pub id: Option<u32>,
    pub args: Vec<Arg>,
    pub view_name: Option<String>,
    /// 1-based line of the statement head, and its byte range.
    pub line: usize,
    pub span: (usize, usize),
}

/// A line that could not be read, with the reason.
#[derive(Debug, Clone, PartialEq)]
pub struct ReadError {
    pub line: usize,
    pub span: (usize, usize),
    pub message: String,
}

use super::vocab::VOCAB;

/// The unique keyword of `list` that `word` abbreviates (exact match first).
fn resolve(word: &str, list: &[&str], min: usize) -> Option<String> {
    if let Some(k) = list.iter().find(|k| **k == word) {
        return Some(k.to_string());
    }
    if word.len() < min {
        return None;
    }
    let mut hits = list.iter().filter(|k| k.starts_with(word));
    match (hits.next(), hits.next()) {
        (Some(k), None) => Some(k.to_string()),
        _ => None,
    }
}

fn is_expr_key(stmt: &str, key: &str) -> bool {
    matches!(key, "FUNCTION" | "FX" | "FY" | "FZ" | "TX" | "TY" | "TZ")
        || (stmt == "REQUEST" && key.len() == 2 && key.starts_with('F'))
}

fn is_text_key(stmt: &str, key: &str) -> bool {
    matches!(
        key,
        "COMMENT" | "TITLE" | "FILE" | "ROUTINE" | "RESULTS_NAME" | "MATERIAL"
    ) || (stmt == "REQUEST" && key == "C")
}

/// Reads a Fortran real at the start of `s`: `(len, value, degrees)`.
pub fn number(s: &str) -> Option<(usize, f64, bool)> {
    let b = s.as_bytes();
    let mut i = 0;
    if i < b.len() && (b[i] == b'+' || b[i] == b'-') {
        i += 1;
    }
    let ds = i;
    while i < b.len() && b[i].is_ascii_digit() {
        i += 1;
    }
    let mut digits = i - ds;
    if i < b.len() && b[i] == b'.' {
        i += 1;
        let f = i;
        while i < b.len() && b[i].is_ascii_digit() {
            i += 1;
        }
        digits += i - f;
    }
    if digits == 0 {
        return None;
    }
    let mant = s[..i].to_string();
    let mut exp = String::new();
    if i < b.len() && matches!(b[i], b'e' | b'E' | b'd' | b'D') {
        let mut j = i + 1;
        if j < b.len() && (b[j] == b'+' || b[j] == b'-') {
            j += 1;
        }
        let es = j;
        while j < b.len() && b[j].is_ascii_digit() {
            j += 1;
        }
        if j > es {
            exp = s[i + 1..j].to_string();
            i = j;
        }
    }
    let mut deg = false;
    if exp.is_empty() && i < b.len() && matches!(b[i], b'd' | b'D') {
        deg = true;
        i += 1;
    }
    let text = if exp.is_empty() {
        mant
    } else {
        format!("{mant}e{exp}")
    };
    let text = if text.ends_with('.') || text.contains(".e") {
        text.replacen('.', ".0", 1)
    } else {
        text
    };
    let v: f64 = text.parse().ok()?;
    Some((i, if deg { v.to_radians() } else { v }, deg))
}

/// A statement being collected: head line, span, view name, text pieces.
type Pending = Option<(usize, (usize, usize), Option<String>, Vec<String>)>;

/// Splits the dataset into statements; errors name the line.
pub fn read(text: &str) -> (Option<String>, Vec<Statement>, Vec<ReadError>) {
    let mut title = None;
    let mut stmts = Vec::new();
    let mut errors = Vec::new();
    // (head line, span, pieces) of the statement being collected.
    let mut cur: Pending = None;
    let mut view: Option<String> = None;
    let mut offset = 0;
    let flush = |cur: &mut Pending, stmts: &mut Vec<Statement>, errors: &mut Vec<ReadError>| {
        if let Some((line, span, vn, pieces)) = cur.take() {
            match parse_statement(&pieces) {
                Ok((name, id, args)) => stmts.push(Statement {
                    name,
                    id,
                    args,
                    view_name: vn,
                    line,
                    span,
                }),
                Err(message) => errors.push(ReadError {
                    line,
                    span,
                    message,
                }),
            }
        }
    };
    for (n, raw) in text.split('\n').enumerate() {
        let start = offset;
        offset += raw.len() + 1;
        let span = (start, start + raw.trim_end().len());
        let line = raw.trim();
        if n == 0 && !line.starts_with('!') {
            // The first line of a dataset is its title.
            title = Some(line.to_string());
            continue;
        }
        if line.is_empty() {
            continue;
        }
        if let Some(c) = line.strip_prefix('!') {
            if let Some(p) = c.find("adams_view_name=") {
                let v = c[p + 16..]
                    .trim()
                    .trim_matches(|ch| ch == '\'' || ch == '"');
                view = Some(v.to_string());
            } else if n == 0 {
                title = c
                    .split_once("model name:")
                    .map(|(_, t)| t.trim().to_string())
                    .or(title);
            }
            continue;
        }
        let body = strip_comment(line);
        if let Some(rest) = body.strip_prefix(',') {
            match &mut cur {
                Some((_, _, _, pieces)) => pieces.push(rest.to_string()),
                None => errors.push(ReadError {
                    line: n + 1,
                    span,
                    message: "a continuation line (`,`) with no statement before it".into(),
                }),
            }
            continue;
        }
        flush(&mut cur, &mut stmts, &mut errors);
        if body.trim().eq_ignore_ascii_case("END") {
            break;
        }
        cur = Some((n + 1, span, view.take(), vec![body.to_string()]));
    }
    flush(&mut cur, &mut stmts, &mut errors);
    (title, stmts, errors)
}

/// The line without a trailing `! comment` (outside quotes).
fn strip_comment(line: &str) -> &str {
    let mut quote = None;
    for (i, ch) in line.char_indices() {
        match (ch, quote) {
            ('\'' | '"', None) => quote = Some(ch),
            (c, Some(q)) if c == q => quote = None,
            ('!', None) => return line[..i].trim_end(),
            _ => {}
        }
    }
    line
}

type Parsed = (String, Option<u32>, Vec<Arg>);

fn parse_statement(pieces: &[String]) -> Result<Parsed, String> {
    let head = &pieces[0];
    let Some((name, rest)) = head.split_once('/') else {
        return Err(format!(
            "expected a statement `NAME/id`, found `{}`",
            head.trim()
        ));
    };
    let upper = name.trim().to_ascii_uppercase();
    if upper.is_empty() || !upper.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') {
        return Err(format!("`{}` is not a statement name", name.trim()));
    }
    let names: Vec<&str> = VOCAB.iter().map(|v| v.0).collect();
    let name = resolve(&upper, &names, 3).unwrap_or(upper);
    let vocab: &[&str] = VOCAB.iter().find(|v| v.0 == name).map_or(&[], |v| v.1);
    let rest = rest.trim_start();
    let id_len = rest.bytes().take_while(|b| b.is_ascii_digit()).count();
    let id = if id_len > 0 {
        Some(
            rest[..id_len]
                .parse::<u32>()
                .map_err(|_| format!("id `{}` is too large", &rest[..id_len]))?,
        )
    } else {
        None
    };
    // Continuation lines are joined with '\n', which separates list values and
    // arguments, and is dropped inside expressions.
    let mut body = rest[id_len..].to_string();
    for p in &pieces[1..] {
        body.push('\n');
        body.push_str(p);
    }
    let args = parse_args(&name, vocab, &body)?;
    Ok((name, id, args))
}

fn parse_args(stmt: &str, vocab: &[&str], s: &str) -> Result<Vec<Arg>, String> {
    let b = s.as_bytes();
    let mut i = 0;
    let mut args = Vec::new();
    let skip = |i: &mut usize, seps: bool| {
        while *i < b.len()
            && (b[*i] == b' '
                || b[*i] == b'\t'
                || b[*i] == b'\r'
                || (seps && (b[*i] == b',' || b[*i] == b'\n')))
        {
            *i += 1;
        }
    };
    loop {
        skip(&mut i, true);
        if i >= b.len() {
            return Ok(args);
        }
        let ks = i;
        while i < b.len() && (b[i].is_ascii_alphanumeric() || b[i] == b'_') {
            i += 1;
        }
        if i == ks {
            return Err(format!(
                "unexpected `{}`",
                &s[ks..].chars().next().unwrap_or(' ')
            ));
        }
        let raw = s[ks..i].to_ascii_uppercase();
        let key = resolve(&raw, vocab, 1).unwrap_or(raw);
        skip(&mut i, false);
        if i >= b.len() || b[i] != b'=' {
            args.push(Arg {
                key,
                values: vec![],
            });
            continue;
        }
        i += 1;
        skip(&mut i, false);
        if is_expr_key(stmt, &key) {
            let end = s[i..].find('\\').map_or(s.len(), |p| i + p);
            let e = s[i..end].replace('\n', " ").trim().to_string();
            if e.is_empty() {
                return Err(format!("`{key} =` has no expression"));
            }
            args.push(Arg {
                key,
                values: vec![Value::Expr(e)],
            });
            i = (end + 1).min(s.len());
            continue;
        }
        if is_text_key(stmt, &key) {
            let end = s[i..].find([',', '\n']).map_or(s.len(), |p| i + p);
            args.push(Arg {
                key,
                values: vec![Value::Word(s[i..end].trim().to_string())],
            });
            i = end;
            continue;
        }
        let mut values = Vec::new();
        loop {
            skip(&mut i, false);
            if i < b.len() && (b[i] == b'\'' || b[i] == b'"') {
                let q = b[i];
                let end = s[i + 1..]
                    .find(q as char)
                    .map(|p| i + 1 + p)
                    .ok_or("unterminated string")?;
                values.push(Value::Word(s[i + 1..end].to_string()));
                i = end + 1;
            } else if let Some((len, v, _)) = number(&s[i..]) {
                values.push(Value::Num(v));
                i += len;
            } else {
                let ws = i;
                while i < b.len() && !matches!(b[i], b',' | b'\n' | b' ' | b'\t' | b'=' | b'\\') {
                    i += 1;
                }
                if i == ws {
                    return Err(format!("`{key} =` has no value"));
                }
                values.push(Value::Word(s[ws..i].to_ascii_uppercase()));
            }
            skip(&mut i, false);
            if i < b.len() && !matches!(b[i], b',' | b'\n') {
                return Err(format!(
                    "unexpected `{}` in the value of `{key}`",
                    &s[i..].chars().next().unwrap_or(' ')
                ));
            }
            // A list continues while the next item is a number or a string.
            let mut j = i;
            while j < b.len() && matches!(b[j], b',' | b'\n' | b' ' | b'\t' | b'\r') {
                j += 1;
            }
            let next_is_value =
                j < b.len() && (number(&s[j..]).is_some() || b[j] == b'\'' || b[j] == b'"');
            if !next_is_value {
                break;
            }
            i = j;
        }
        args.push(Arg { key, values });
    }
}

impl Statement {
    pub fn arg(&self, key: &str) -> Option<&Arg> {
        self.args.iter().find(|a| a.key == key)
    }

    pub fn has(&self, flag: &str) -> bool {
        self.arg(flag).is_some()
    }

    /// The numbers of an argument.
    pub fn nums(&self, key: &str) -> Option<Vec<f64>> {
        let a = self.arg(key)?;
        a.values
            .iter()
            .map(|v| {
                if let Value::Num(x) = v {
                    Some(*x)
                } else {
                    None
                }
            })
            .collect()
    }

    pub fn int(&self, key: &str) -> Option<u32> {
        match self.nums(key)?.as_slice() {
            [x] if *x >= 0.0 && x.fract() == 0.0 && *x < 4.0e9 => Some(*x as u32),
            _ => None,
        }
    }

    pub fn expr(&self, key: &str) -> Option<&str> {
        match self.arg(key)?.values.first()? {
            Value::Expr(e) => Some(e),
            _ => None,
        }
    }

    pub fn word(&self, key: &str) -> Option<&str> {
        match self.arg(key)?.values.first()? {
            Value::Word(w) => Some(w),
            _ => None,
        }
    }

    /// `NAME/id` for messages.
    pub fn label(&self) -> String {
        match self.id {
            Some(i) => format!("{}/{i}", self.name),
            None => format!("{}/", self.name),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fortran_numbers_and_degrees() {
        assert_eq!(number("1.0D+03").map(|n| n.1), Some(1000.0));
        assert_eq!(number("1.E3").map(|n| n.1), Some(1000.0));
        assert_eq!(number(".4").map(|n| n.1), Some(0.4));
        assert_eq!(number("-5.").map(|n| n.1), Some(-5.0));
        let (len, v, d) = number("90D, 0D").unwrap_or_default();
        assert_eq!((len, d), (3, true));
        assert!((v - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
        assert_eq!(number("D"), None);
    }

    #[test]
    fn statements_with_continuations_abbreviations_and_expressions() {
        let text = "title line\n!  adams_view_name='arm.B'\nMARK/0102, PART = 01\n, QP = 0, 1.5E+01,\n, -3\n, REULER = 180D, 90D, 0D\nSFORCE/1\n, TRANSLATIONAL\n, I = 204, J = 205\n, FUNCTION =  - 100.0*(dm(204,205)-2.0)\n, - 1.0*vr(204,205)\n, + 0.0\nREQUEST/01, D,I=0201,J=0101,C=DISPLACEMENT: X Y Z\nEND\nPART/9\n";
        let (title, st, errs) = read(text);
        assert!(errs.is_empty(), "{errs:?}");
        assert_eq!(title.as_deref(), Some("title line"));
        assert_eq!(st.len(), 3);
        assert_eq!(st[0].name, "MARKER");
        assert_eq!(st[0].id, Some(102));
        assert_eq!(st[0].view_name.as_deref(), Some("arm.B"));
        assert_eq!(st[0].nums("QP"), Some(vec![0.0, 15.0, -3.0]));
        assert_eq!(st[0].int("PART"), Some(1));
        assert_eq!(
            st[1].expr("FUNCTION"),
            Some("- 100.0*(dm(204,205)-2.0)  - 1.0*vr(204,205)  + 0.0")
        );
        assert!(st[1].has("TRANSLATIONAL"));
        assert!(st[2].has("DISPLACEMENT"));
        assert_eq!(st[2].word("C"), Some("DISPLACEMENT: X Y Z"));
    }

    #[test]
    fn malformed_lines_name_their_line() {
        let (_, _, errs) = read("t\nPART/1, GROUND\nMARKER 3, PART = 1\n, QP = 1, x2\n");
        assert_eq!(errs.len(), 1);
        assert_eq!(errs[0].line, 3);
    }
}
