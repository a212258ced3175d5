//! The one place where ADAMS text is formatted: numbers, angles, and statements
//! laid out as Adams/View writes them (an `adams_view_name` comment line, the
//! statement head, then one argument per `,` continuation line, every line at
//! most 80 characters). Used by the `.adm` and `.acf` writers.

use std::fmt::Write;

/// Longest line written; Adams/Solver (FORTRAN) reads 80-column lines.
pub const MAX_LINE: usize = 80;

/// The comment line above a statement that carries its axle name, as
/// Adams/View writes it: `!  adams_view_name='NAME'`.
pub const VIEW_NAME: &str = "!  adams_view_name=";

/// A real number with 12 significant digits: plain when that is short
/// (`294.7`, `-0.015`), else Fortran exponent form (`5.72957795131E+05`).
/// Twelve digits drop last-bit float noise (`0.1 + 0.2` is `0.3`) yet carry a
/// degree-based stiffness through radians and back: 4500 N*mm/deg is written
/// `257831.007809` and reads back as 4500 to the 12 digits axle prints.
pub fn num(v: f64) -> String {
    if !v.is_finite() {
        // Callers check finiteness first (EmitError::NotFinite); this keeps the
        // function total.
        return "0".into();
    }
    let sci = format!("{v:.11e}");
    let rounded: f64 = sci.parse().unwrap_or(v);
    if rounded == 0.0 {
        return "0".into();
    }
    let exp = rounded.abs().log10().floor() as i32;
    if (-4..10).contains(&exp) {
        let plain = format!("{rounded}");
        if plain.len() <= 18 {
            return plain;
        }
    }
    let (mant, e) = sci.split_once('e').unwrap_or((&sci, "0"));
    let mant = mant.trim_end_matches('0').trim_end_matches('.');
    let e: i32 = e.parse().unwrap_or(0);
    let sign = if e < 0 { '-' } else { '+' };
    format!("{mant}E{sign}{:02}", e.abs())
}

/// An angle given in radians, written in degrees with the `D` suffix.
pub fn deg(rad: f64) -> String {
    format!("{}D", num(rad.to_degrees()))
}

/// A list of numbers, `1, 2, 3`.
pub fn list(vals: &[f64]) -> String {
    vals.iter().map(|v| num(*v)).collect::<Vec<_>>().join(", ")
}

/// One statement being written.
pub struct Stmt {
    view_name: Option<String>,
    head: String,
    args: Vec<Arg>,
}

enum Arg {
    /// `KEY = value`; a value that is a list may wrap at its commas.
    Value(String, String),
    /// A flag such as `GROUND` or `TRANSLATIONAL`.
    Flag(String),
    /// `KEY = expression`, ended by `\` when more arguments follow.
    Expr(String, String),
}

impl Stmt {
    /// `NAME/id` (or `NAME/` when `id` is None).
    pub fn new(name: &str, id: Option<u32>) -> Stmt {
        Stmt {
            view_name: None,
            head: match id {
                Some(i) => format!("{name}/{i}"),
                None => format!("{name}/"),
            },
            args: Vec::new(),
        }
    }

    pub fn named(mut self, view_name: &str) -> Stmt {
        self.view_name = Some(view_name.to_string());
        self
    }

    pub fn flag(mut self, f: &str) -> Stmt {
        self.args.push(Arg::Flag(f.to_string()));
        self
    }

    pub fn arg(mut self, key: &str, value: impl Into<String>) -> Stmt {
        self.args.push(Arg::Value(key.to_string(), value.into()));
        self
    }

    /// `COMMENT = text`, cut at a word to fit one line: a string argument
    /// cannot be continued, and Adams reads 80 columns and at most 80
    /// characters a string (adams-formats.md). Long element names (an
    /// instance's, `rear.torsion_right`) would otherwise push a request's
    /// description past the edge; what is cut is the description's tail,
    /// the request's content is in its functions and its view name.
    pub fn comment(self, text: &str) -> Stmt {
        let room = MAX_LINE - ", COMMENT = ".len();
        if text.len() <= room {
            return self.arg("COMMENT", text);
        }
        let mut cut = room;
        while !text.is_char_boundary(cut) {
            cut -= 1;
        }
        let head = &text[..cut];
        // At a word when there is one to cut at (the next character a
        // space ends a word too).
        let at_word = text[cut..].starts_with(' ');
        let kept = match head.rfind(' ') {
            Some(k) if !at_word && k > 0 => &head[..k],
            _ => head,
        };
        self.arg("COMMENT", kept.trim_end())
    }

    pub fn expr(mut self, key: &str, e: impl Into<String>) -> Stmt {
        self.args.push(Arg::Expr(key.to_string(), e.into()));
        self
    }

    /// Appends the statement to `out`.
    pub fn write(&self, out: &mut String) {
        if let Some(n) = &self.view_name {
            let _ = writeln!(out, "{VIEW_NAME}'{n}'");
        }
        let _ = writeln!(out, "{}", self.head);
        let n = self.args.len();
        for (k, a) in self.args.iter().enumerate() {
            match a {
                Arg::Flag(f) => {
                    let _ = writeln!(out, ", {f}");
                }
                Arg::Value(key, v) => wrap(out, &format!(", {key} = "), v, ", "),
                Arg::Expr(key, e) => {
                    // Function expressions run to a backslash or the end of the
                    // statement ([DOC] state_field.html): a following argument
                    // needs the backslash.
                    let more = k + 1 < n;
                    let text = if more { format!("{e}\\") } else { e.clone() };
                    wrap(out, &format!(", {key} = "), &text, " ");
                }
            }
        }
    }
}

/// Writes `prefix + text`, breaking it onto `, ` continuation lines at `sep`
/// boundaries (list commas, or spaces between expression terms) so that no
/// line exceeds [`MAX_LINE`]. A list separator comma becomes the continuation
/// comma, which is how ADAMS reads continued lists.
fn wrap(out: &mut String, prefix: &str, text: &str, sep: &str) {
    let mut line = prefix.to_string();
    let mut first = true;
    for piece in split_keep(text, sep) {
        let cand_len = line.len() + piece.len() + if first { 0 } else { sep.len() };
        if !first && cand_len > MAX_LINE {
            let _ = writeln!(out, "{line}");
            line = format!(", {piece}");
        } else {
            if !first {
                line.push_str(sep);
            }
            line.push_str(&piece);
        }
        first = false;
    }
    let _ = writeln!(out, "{line}");
}

/// Splits a list at `sep` outside parentheses, or an expression (sep = " ")
/// before each ` + ` / ` - ` term, so a continuation line never cuts a call's
/// argument list or a number.
fn split_keep(text: &str, sep: &str) -> Vec<String> {
    let mut parts = Vec::new();
    let mut depth = 0i32;
    let mut cur = String::new();
    let bytes = text.as_bytes();
    let mut i = 0;
    while i < bytes.len() {
        let c = bytes[i] as char;
        match c {
            '(' => depth += 1,
            ')' => depth -= 1,
            _ => {}
        }
        // Expressions may continue at any term, even inside parentheses: Adams
        // drops the continuation comma there ([CHR-T] VARIABLE/3 of
        // test_TransSpring_Case01.adm breaks inside a parenthesis).
        let ok = if sep == " " {
            text[i..].starts_with(" + ") || text[i..].starts_with(" - ")
        } else {
            depth == 0 && text[i..].starts_with(sep)
        };
        if ok && !cur.is_empty() {
            parts.push(std::mem::take(&mut cur));
            i += sep.len();
            continue;
        }
        cur.push(c);
        i += 1;
    }
    if !cur.is_empty() {
        parts.push(cur);
    }
    parts
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_are_plain_when_short_and_fortran_otherwise() {
        assert_eq!(num(0.0), "0");
        assert_eq!(num(-0.0), "0");
        assert_eq!(num(294.7), "294.7");
        assert_eq!(num(0.1 + 0.2), "0.3");
        assert_eq!(num(10000.0_f64.to_degrees()), "572957.795131");
        assert_eq!(num(4500.0_f64.to_degrees()), "257831.007809");
        assert_eq!(num(4000.0_f64.to_degrees()), "229183.118052");
        assert_eq!(num(1.0e-6), "1E-06");
        assert_eq!(num(-2.5e12), "-2.5E+12");
        assert_eq!(num(f64::NAN), "0");
    }

    #[test]
    fn a_long_comment_is_cut_at_a_word_within_80_columns() {
        let name = "rear.torsion_right";
        let text = format!("bushing {name} force and torque on I in J axes N and N*mm");
        let mut out = String::new();
        Stmt::new("REQUEST", Some(14))
            .comment(&text)
            .write(&mut out);
        let line = out.lines().nth(1).expect("the comment line");
        assert_eq!(
            line,
            ", COMMENT = bushing rear.torsion_right force and torque on I in J axes N and"
        );
        assert!(line.len() <= MAX_LINE);
        // A short one is written whole; one without a space is cut at the edge.
        let mut out = String::new();
        Stmt::new("REQUEST", Some(1))
            .comment("wheel left")
            .write(&mut out);
        assert_eq!(out.lines().nth(1), Some(", COMMENT = wheel left"));
        let mut out = String::new();
        Stmt::new("REQUEST", Some(1))
            .comment(&"x".repeat(100))
            .write(&mut out);
        assert_eq!(out.lines().nth(1).map(str::len), Some(MAX_LINE));
    }

    #[test]
    fn long_lists_wrap_at_commas_within_80_columns() {
        let vals: Vec<f64> = (0..40).map(|k| k as f64 * 1234.5678).collect();
        let mut out = String::new();
        Stmt::new("SPLINE", Some(1))
            .arg("X", list(&vals))
            .write(&mut out);
        assert!(out.lines().all(|l| l.len() <= MAX_LINE), "{out}");
        let joined: String = out.lines().skip(1).collect::<Vec<_>>().join("");
        assert_eq!(joined.matches(',').count(), 40);
    }

    #[test]
    fn expressions_end_with_a_backslash_when_more_arguments_follow() {
        let mut out = String::new();
        Stmt::new("VFORCE", Some(1))
            .named("load")
            .arg("I", "3")
            .expr("FX", "VARVAL(1)")
            .expr("FY", "VARVAL(2)")
            .write(&mut out);
        assert_eq!(
            out,
            "!  adams_view_name='load'\nVFORCE/1\n, I = 3\n, FX = VARVAL(1)\\\n, FY = VARVAL(2)\n"
        );
    }
}
