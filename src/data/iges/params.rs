//! IGES free-format data (the Global section, columns 1–72, and each entity's
//! Parameter Data, columns 1–64): parameters separated by the parameter
//! delimiter, the record ended by the record delimiter, strings in Hollerith
//! form `nH…` (which may hold either delimiter, and may run on to the next
//! line), reals in Fortran form (`1.5D2`, `1.E-3`), an empty field meaning the
//! default. Every parameter keeps its byte range in the file for diagnostics.

use super::IgesError;
use super::records::Record;

/// Data columns of several records joined, each byte with its file offset.
#[derive(Debug, Clone, Default)]
pub struct Logical {
    pub bytes: Vec<u8>,
    pub at: Vec<usize>,
    /// File offset just past the last column read (for "ends here" errors).
    pub end: usize,
}

impl Logical {
    /// Appends columns `from..=to` (1-based) of a record.
    pub fn push(&mut self, r: &Record, from: usize, to: usize) {
        let (a, _) = r.span(from, to);
        for (k, &b) in r.cols(from, to).iter().enumerate() {
            self.bytes.push(b);
            self.at.push(a + k);
        }
        self.end = r.span(from, to).1;
    }

    /// File offset of logical byte `k` (the end, past the last one).
    pub fn offset(&self, k: usize) -> usize {
        self.at.get(k).copied().unwrap_or(self.end)
    }

    fn range(&self, a: usize, b: usize) -> (usize, usize) {
        if a >= b {
            let o = self.offset(a);
            return (o, o);
        }
        (self.offset(a), self.offset(b - 1) + 1)
    }
}

/// A parameter: defaulted (empty), a string, or the text of a number.
#[derive(Debug, Clone, PartialEq)]
pub enum Value {
    Empty,
    Text(String),
    Raw(String),
}

#[derive(Debug, Clone, PartialEq)]
pub struct Param {
    pub value: Value,
    pub start: usize,
    pub end: usize,
}

fn err(message: String, range: (usize, usize), label: &str) -> IgesError {
    IgesError::new("E0724", message, range, label)
}

/// Reads parameters from `from` up to and including the record delimiter.
/// Returns them and the position after the delimiter. `what` names the data
/// in messages ("the Global section", "point D 3").
pub fn read(
    l: &Logical,
    from: usize,
    pd: u8,
    rd: u8,
    what: &str,
) -> Result<(Vec<Param>, usize), IgesError> {
    let b = &l.bytes;
    let mut out = Vec::new();
    let mut i = from;
    loop {
        while i < b.len() && b[i] == b' ' {
            i += 1;
        }
        let start = i;
        let mut j = i;
        while j < b.len() && b[j].is_ascii_digit() {
            j += 1;
        }
        let value = if j > i && j < b.len() && b[j] == b'H' {
            // Hollerith: the count, `H`, then exactly that many characters.
            let n: usize = std::str::from_utf8(&b[i..j])
                .ok()
                .and_then(|s| s.parse().ok())
                .unwrap_or(usize::MAX);
            let body = j + 1;
            if n > b.len() - body {
                return Err(err(
                    format!(
                        "in {what}: the string `{}H…` announces {} characters but the data ends after {}",
                        String::from_utf8_lossy(&b[i..j]),
                        String::from_utf8_lossy(&b[i..j]),
                        b.len() - body
                    ),
                    l.range(i, b.len()),
                    "string runs past the end",
                ));
            }
            let s = String::from_utf8_lossy(&b[body..body + n]).into_owned();
            i = body + n;
            while i < b.len() && b[i] == b' ' {
                i += 1;
            }
            if i < b.len() && b[i] != pd && b[i] != rd {
                return Err(err(
                    format!(
                        "in {what}: `{}` follows a string; a delimiter (`{}` or `{}`) was expected",
                        b[i] as char, pd as char, rd as char
                    ),
                    l.range(i, i + 1),
                    "delimiter expected",
                ));
            }
            Value::Text(s)
        } else {
            while i < b.len() && b[i] != pd && b[i] != rd {
                i += 1;
            }
            let t = String::from_utf8_lossy(&b[start..i]).trim().to_string();
            if t.is_empty() {
                Value::Empty
            } else {
                Value::Raw(t)
            }
        };
        let mut e = i;
        while e > start && b[e - 1] == b' ' {
            e -= 1;
        }
        let (s, e) = l.range(start, e);
        out.push(Param {
            value,
            start: s,
            end: e,
        });
        if i >= b.len() {
            return Err(err(
                format!(
                    "{what} ends without its record delimiter `{}`; the file may be truncated",
                    rd as char
                ),
                (l.end, l.end),
                "data ends here",
            ));
        }
        if b[i] == rd {
            return Ok((out, i + 1));
        }
        i += 1;
    }
}

/// A real in IGES (Fortran) notation: `12`, `-1.5`, `1.`, `.5`, `1.5E-3`, `1.5D2`.
pub fn real(s: &str) -> Option<f64> {
    let ok = !s.is_empty()
        && s.bytes().any(|c| c.is_ascii_digit())
        && s.bytes()
            .all(|c| c.is_ascii_digit() || b"+-.eEdD".contains(&c));
    if !ok {
        return None;
    }
    let t: String = s
        .chars()
        .map(|c| if c == 'D' || c == 'd' { 'E' } else { c })
        .collect();
    t.parse::<f64>().ok().filter(|v| v.is_finite())
}

/// An integer: optional sign and digits.
pub fn integer(s: &str) -> Option<i64> {
    let digits = s.strip_prefix(['+', '-']).unwrap_or(s);
    if digits.is_empty() || !digits.bytes().all(|c| c.is_ascii_digit()) {
        return None;
    }
    s.parse().ok()
}

/// The parameters of one entity (or of the Global section), with typed access.
pub struct Params<'a> {
    pub list: &'a [Param],
    /// Where to point for a missing parameter.
    pub end: usize,
    pub what: &'a str,
}

impl Params<'_> {
    fn missing(&self, k: usize, name: &str) -> IgesError {
        IgesError::new(
            "E0724",
            format!(
                "{} has no {name} (parameter {k} after the entity type)",
                self.what
            ),
            (self.end, self.end),
            "data ends here",
        )
    }

    fn get(&self, k: usize) -> Option<&Param> {
        self.list.get(k).filter(|p| p.value != Value::Empty)
    }

    fn bad(&self, p: &Param, name: &str, kind: &str) -> IgesError {
        let text = match &p.value {
            Value::Raw(t) => format!("`{t}`"),
            Value::Text(t) => format!("the string `{t}`"),
            Value::Empty => "nothing".into(),
        };
        IgesError::new(
            "E0724",
            format!("{}: {name} is {text}, not {kind}", self.what),
            (p.start, p.end),
            format!("not {kind}"),
        )
    }

    /// A real parameter that must be given.
    pub fn real(&self, k: usize, name: &str) -> Result<f64, IgesError> {
        match self.get(k) {
            None => Err(self.missing(k, name)),
            Some(p) => self.real_of(p, name),
        }
    }

    fn real_of(&self, p: &Param, name: &str) -> Result<f64, IgesError> {
        match &p.value {
            Value::Raw(t) => real(t).ok_or_else(|| self.bad(p, name, "a number")),
            _ => Err(self.bad(p, name, "a number")),
        }
    }

    /// A real parameter with a default.
    pub fn real_or(&self, k: usize, name: &str, default: f64) -> Result<f64, IgesError> {
        match self.get(k) {
            None => Ok(default),
            Some(p) => self.real_of(p, name),
        }
    }

    /// An integer parameter with a default.
    pub fn int_or(&self, k: usize, name: &str, default: i64) -> Result<i64, IgesError> {
        match self.get(k) {
            None => Ok(default),
            Some(p) => match &p.value {
                Value::Raw(t) => integer(t).ok_or_else(|| self.bad(p, name, "an integer")),
                _ => Err(self.bad(p, name, "an integer")),
            },
        }
    }

    /// A string parameter, if given.
    pub fn text(&self, k: usize, name: &str) -> Result<Option<String>, IgesError> {
        match self.get(k) {
            None => Ok(None),
            Some(p) => match &p.value {
                Value::Text(t) => Ok(Some(t.clone())),
                _ => Err(self.bad(p, name, "a string")),
            },
        }
    }

    /// The byte range of parameter `k` (or the end of the data).
    pub fn span(&self, k: usize) -> (usize, usize) {
        self.list
            .get(k)
            .map_or((self.end, self.end), |p| (p.start, p.end))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn logical(s: &str) -> Logical {
        Logical {
            bytes: s.as_bytes().to_vec(),
            at: (0..s.len()).collect(),
            end: s.len(),
        }
    }

    #[test]
    fn fortran_reals_and_integers() {
        assert_eq!(real("1.5D2"), Some(150.0));
        assert_eq!(real("1.E-3"), Some(0.001));
        assert_eq!(real("-.5"), Some(-0.5));
        assert_eq!(real("7"), Some(7.0));
        assert_eq!(real("1.0d+1"), Some(10.0));
        for bad in ["inf", "NaN", "1.2.3", "1x", "E5", "", "-", "1D999"] {
            assert_eq!(real(bad), None, "{bad}");
        }
        assert_eq!(integer("-21"), Some(-21));
        assert_eq!(integer("2."), None);
    }

    #[test]
    fn hollerith_strings_may_hold_delimiters() {
        let text = "406,1,7HA,B;C.D , 2.5 ,,3;rest";
        let l = logical(text);
        let (p, next) = read(&l, 0, b',', b';', "test").expect("reads");
        let v: Vec<&Value> = p.iter().map(|p| &p.value).collect();
        assert_eq!(
            v,
            [
                &Value::Raw("406".into()),
                &Value::Raw("1".into()),
                &Value::Text("A,B;C.D".into()),
                &Value::Raw("2.5".into()),
                &Value::Empty,
                &Value::Raw("3".into()),
            ]
        );
        assert_eq!(&l.bytes[next..], b"rest");
        assert_eq!(&text[p[3].start..p[3].end], "2.5", "the trimmed span");
    }

    #[test]
    fn declared_delimiters_and_truncation() {
        let l = logical("116/1.0/2.0/3.0/0#");
        let (p, _) = read(&l, 0, b'/', b'#', "test").expect("reads");
        assert_eq!(p.len(), 5);
        let e = read(&logical("116,1.0,2.0"), 0, b',', b';', "point D 1").unwrap_err();
        assert!(e.message.contains("ends without its record delimiter"));
        let e = read(&logical("406,1,9HABC;"), 0, b',', b';', "x").unwrap_err();
        assert!(
            e.message.contains("announces 9 characters"),
            "{}",
            e.message
        );
    }
}
