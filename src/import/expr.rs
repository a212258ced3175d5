//! ADAMS function expressions: a parser for the arithmetic subset used by force
//! laws (numbers, `+ - * / **`, calls, `IF(e: neg, zero, pos)`), an evaluator
//! for statics, and the measure (`DX(i,j,j)`, `DM(i,j)`, …) an expression
//! depends on. The importer reads force laws by evaluating them, so any
//! equivalent way of writing a law is understood.

use std::collections::BTreeMap;

#[derive(Debug, Clone, PartialEq)]
pub enum Expr {
    Num(f64),
    Name(String),
    Call(String, Vec<Expr>),
    Neg(Box<Expr>),
    Bin(u8, Box<Expr>, Box<Expr>),
    If(Box<Expr>, Box<Expr>, Box<Expr>, Box<Expr>),
}

/// Displacement measures between markers; the one a force law depends on.
pub const MEASURES: [&str; 7] = ["DX", "DY", "DZ", "DM", "AX", "AY", "AZ"];
/// Velocity measures: zero at static equilibrium.
const VELOCITIES: [&str; 8] = ["VR", "VX", "VY", "VZ", "VM", "WX", "WY", "WZ"];

struct P<'a> {
    s: &'a [u8],
    i: usize,
    depth: usize,
}

pub fn parse(text: &str) -> Result<Expr, String> {
    let mut p = P {
        s: text.as_bytes(),
        i: 0,
        depth: 0,
    };
    let e = p.sum()?;
    p.ws();
    if p.i < p.s.len() {
        return Err(format!(
            "unexpected `{}` in expression",
            text[p.i..].chars().next().unwrap_or(' ')
        ));
    }
    Ok(e)
}

impl P<'_> {
    fn ws(&mut self) {
        while self.i < self.s.len() && self.s[self.i].is_ascii_whitespace() {
            self.i += 1;
        }
    }
    fn eat(&mut self, c: u8) -> bool {
        self.ws();
        if self.s.get(self.i) == Some(&c) && !(c == b'*' && self.s.get(self.i + 1) == Some(&b'*')) {
            self.i += 1;
            true
        } else {
            false
        }
    }
    fn sum(&mut self) -> Result<Expr, String> {
        self.depth += 1;
        if self.depth > 200 {
            return Err("expression nested too deeply".into());
        }
        let mut e = self.product()?;
        loop {
            if self.eat(b'+') {
                e = Expr::Bin(b'+', Box::new(e), Box::new(self.product()?));
            } else if self.eat(b'-') {
                e = Expr::Bin(b'-', Box::new(e), Box::new(self.product()?));
            } else {
                self.depth -= 1;
                return Ok(e);
            }
        }
    }
    fn product(&mut self) -> Result<Expr, String> {
        let mut e = self.unary()?;
        loop {
            if self.eat(b'*') {
                e = Expr::Bin(b'*', Box::new(e), Box::new(self.unary()?));
            } else if self.eat(b'/') {
                e = Expr::Bin(b'/', Box::new(e), Box::new(self.unary()?));
            } else {
                return Ok(e);
            }
        }
    }
    fn unary(&mut self) -> Result<Expr, String> {
        if self.eat(b'-') {
            return Ok(Expr::Neg(Box::new(self.unary()?)));
        }
        if self.eat(b'+') {
            return self.unary();
        }
        let base = self.atom()?;
        self.ws();
        if self.s[self.i..].starts_with(b"**") {
            self.i += 2;
            return Ok(Expr::Bin(b'^', Box::new(base), Box::new(self.unary()?)));
        }
        Ok(base)
    }
    fn atom(&mut self) -> Result<Expr, String> {
        self.ws();
        let rest = std::str::from_utf8(&self.s[self.i..]).unwrap_or("");
        if self.eat(b'(') {
            let e = self.sum()?;
            return if self.eat(b')') {
                Ok(e)
            } else {
                Err("missing `)`".into())
            };
        }
        if let Some((len, v, _)) = super::reader::number(rest) {
            self.i += len;
            return Ok(Expr::Num(v));
        }
        let st = self.i;
        while self.i < self.s.len()
            && (self.s[self.i].is_ascii_alphanumeric() || self.s[self.i] == b'_')
        {
            self.i += 1;
        }
        if st == self.i {
            return Err(format!(
                "unexpected `{}` in expression",
                rest.chars().next().unwrap_or(' ')
            ));
        }
        let name = String::from_utf8_lossy(&self.s[st..self.i]).to_ascii_uppercase();
        if !self.eat(b'(') {
            return Ok(Expr::Name(name));
        }
        if name == "IF" {
            let c = self.sum()?;
            if !self.eat(b':') {
                return Err("IF needs `:` after its condition".into());
            }
            let a = self.sum()?;
            let b = if self.eat(b',') {
                self.sum()?
            } else {
                return Err("IF needs three branches".into());
            };
            let d = if self.eat(b',') {
                self.sum()?
            } else {
                return Err("IF needs three branches".into());
            };
            if !self.eat(b')') {
                return Err("missing `)` after IF".into());
            }
            return Ok(Expr::If(Box::new(c), Box::new(a), Box::new(b), Box::new(d)));
        }
        let mut args = Vec::new();
        if !self.eat(b')') {
            loop {
                args.push(self.sum()?);
                if self.eat(b')') {
                    break;
                }
                if !self.eat(b',') {
                    return Err(format!("missing `)` after the arguments of {name}"));
                }
            }
        }
        Ok(Expr::Call(name, args))
    }
}

/// A measure call with its integer marker arguments: `("DX", [3, 4, 4])`.
pub type Measure = (String, Vec<i64>);

fn as_measure(name: &str, args: &[Expr]) -> Option<Measure> {
    if !MEASURES.contains(&name) {
        return None;
    }
    let ids: Option<Vec<i64>> = args
        .iter()
        .map(|a| {
            if let Expr::Num(v) = a {
                Some(*v as i64)
            } else {
                None
            }
        })
        .collect();
    Some((name.to_string(), ids?))
}

/// Every measure the expression uses (VARVAL not followed).
pub fn measures(e: &Expr, out: &mut Vec<Measure>) {
    match e {
        Expr::Call(n, a) => {
            if let Some(m) = as_measure(n, a)
                && !out.contains(&m)
            {
                out.push(m);
            }
            a.iter().for_each(|x| measures(x, out));
        }
        Expr::Neg(a) => measures(a, out),
        Expr::Bin(_, a, b) => {
            measures(a, out);
            measures(b, out);
        }
        Expr::If(a, b, c, d) => [a, b, c, d].iter().for_each(|x| measures(x, out)),
        _ => {}
    }
}

/// Evaluation context: the value of the one measure, spline tables and variables.
pub struct Ctx<'a> {
    pub measure: Option<&'a Measure>,
    pub x: f64,
    pub splines: &'a BTreeMap<u32, Vec<(f64, f64)>>,
    pub variables: &'a BTreeMap<u32, Expr>,
}

pub fn eval(e: &Expr, c: &Ctx, depth: usize) -> Result<f64, String> {
    if depth > 64 {
        return Err("VARVAL references nest too deeply (a cycle?)".into());
    }
    let ev = |x: &Expr| eval(x, c, depth);
    Ok(match e {
        Expr::Num(v) => *v,
        Expr::Name(n) => match n.as_str() {
            "PI" => std::f64::consts::PI,
            "RTOD" => 180.0 / std::f64::consts::PI,
            "DTOR" => std::f64::consts::PI / 180.0,
            // Statics are solved at time 0.
            "TIME" => 0.0,
            _ => return Err(format!("unknown name `{n}`")),
        },
        Expr::Neg(a) => -ev(a)?,
        Expr::Bin(op, a, b) => {
            let (x, y) = (ev(a)?, ev(b)?);
            match op {
                b'+' => x + y,
                b'-' => x - y,
                b'*' => x * y,
                b'/' => x / y,
                _ => x.powf(y),
            }
        }
        Expr::If(cond, neg, zero, pos) => {
            let v = ev(cond)?;
            if v < 0.0 {
                ev(neg)?
            } else if v == 0.0 {
                ev(zero)?
            } else {
                ev(pos)?
            }
        }
        Expr::Call(n, a) => {
            if let Some(m) = as_measure(n, a) {
                return match c.measure {
                    Some(t) if *t == m => Ok(c.x),
                    _ => Err(format!(
                        "depends on {n}({})",
                        m.1.iter()
                            .map(|v| v.to_string())
                            .collect::<Vec<_>>()
                            .join(",")
                    )),
                };
            }
            if VELOCITIES.contains(&n.as_str()) {
                return Ok(0.0);
            }
            let v: Vec<f64> = a.iter().map(ev).collect::<Result<_, _>>()?;
            match (n.as_str(), v.as_slice()) {
                ("SIN", [x]) => x.sin(),
                ("COS", [x]) => x.cos(),
                ("TAN", [x]) => x.tan(),
                ("ASIN", [x]) => x.asin(),
                ("ACOS", [x]) => x.acos(),
                ("ATAN", [x]) => x.atan(),
                ("ATAN2", [y, x]) => y.atan2(*x),
                ("SQRT", [x]) => x.sqrt(),
                ("ABS", [x]) => x.abs(),
                ("EXP", [x]) => x.exp(),
                ("LOG", [x]) => x.ln(),
                ("MAX", [x, y]) => x.max(*y),
                ("MIN", [x, y]) => x.min(*y),
                ("SIGN", [x, y]) => x.abs() * y.signum(),
                ("AKISPL" | "CUBSPL", [x, _, id, ..]) => {
                    let t = c
                        .splines
                        .get(&(*id as u32))
                        .ok_or_else(|| format!("SPLINE/{id} is not defined"))?;
                    let table = crate::model::Table { points: t.clone() };
                    table.eval(*x).0
                }
                ("VARVAL", [id]) => {
                    let var = c
                        .variables
                        .get(&(*id as u32))
                        .ok_or_else(|| format!("VARIABLE/{id} is not defined"))?;
                    eval(var, c, depth + 1)?
                }
                _ => {
                    return Err(format!(
                        "function {n} with {} arguments is not supported",
                        v.len()
                    ));
                }
            }
        }
    })
}

/// The first `AKISPL`/`CUBSPL` call: (argument expression, spline id).
pub fn spline_call(e: &Expr) -> Option<(&Expr, u32)> {
    match e {
        Expr::Call(n, a) if (n == "AKISPL" || n == "CUBSPL") && a.len() >= 3 => match a[2] {
            Expr::Num(id) => Some((&a[0], id as u32)),
            _ => None,
        },
        Expr::Call(_, a) => a.iter().find_map(spline_call),
        Expr::Neg(a) => spline_call(a),
        Expr::Bin(_, a, b) => spline_call(a).or_else(|| spline_call(b)),
        Expr::If(a, b, c, d) => [a, b, c, d].iter().find_map(|x| spline_call(x)),
        _ => None,
    }
}

/// Coefficients `c0..=deg` of `f` if it is a polynomial of degree <= `deg` in x
/// (checked at extra points), from exact interpolation at x = 0, ±1, ±2, ….
pub fn polynomial(
    f: &dyn Fn(f64) -> Result<f64, String>,
    deg: usize,
) -> Result<Option<Vec<f64>>, String> {
    let n = deg + 1;
    let xs: Vec<f64> = (0..n)
        .map(|k| {
            if k % 2 == 1 {
                (k / 2 + 1) as f64
            } else {
                -((k / 2) as f64)
            }
        })
        .collect();
    let ys: Vec<f64> = xs.iter().map(|x| f(*x)).collect::<Result<_, _>>()?;
    let a = nalgebra::DMatrix::from_fn(n, n, |r, c| xs[r].powi(c as i32));
    let Some(c) = a.lu().solve(&nalgebra::DVector::from_vec(ys.clone())) else {
        return Ok(None);
    };
    let scale = ys.iter().fold(1e-12_f64, |m, y| m.max(y.abs()));
    for x in [0.37_f64, -1.61, 2.9] {
        let p: f64 = c
            .iter()
            .enumerate()
            .map(|(k, ck)| ck * x.powi(k as i32))
            .sum();
        if (p - f(x)?).abs() > 1e-9 * scale {
            return Ok(None);
        }
    }
    // Round away interpolation noise relative to the size of the law.
    Ok(Some(
        c.iter()
            .map(|v| if v.abs() < 1e-12 * scale { 0.0 } else { *v })
            .collect(),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_and_evaluates_force_laws() {
        let e = parse("- 100.0*(dm(204,205)-2.0)  - 1.0*vr(204,205)  + 0.0")
            .unwrap_or(Expr::Num(f64::NAN));
        let mut ms = Vec::new();
        measures(&e, &mut ms);
        assert_eq!(ms, vec![("DM".to_string(), vec![204, 205])]);
        let (s, v) = (BTreeMap::new(), BTreeMap::new());
        let c = Ctx {
            measure: Some(&ms[0]),
            x: 5.0,
            splines: &s,
            variables: &v,
        };
        assert_eq!(eval(&e, &c, 0), Ok(-300.0));
        let p = polynomial(&|x| eval(&e, &Ctx { x, ..c }, 0), 3)
            .ok()
            .flatten();
        assert_eq!(p, Some(vec![200.0, -100.0, 0.0, 0.0]));
        let e = parse("IF(DM(1,2) - 70: 2*(70 - DM(1,2))**2, 0, 0)").unwrap_or(Expr::Num(0.0));
        assert_eq!(eval(&e, &Ctx { x: 60.0, ..c }, 0).ok(), None);
        let m = ("DM".to_string(), vec![1, 2]);
        assert_eq!(
            eval(
                &e,
                &Ctx {
                    measure: Some(&m),
                    x: 60.0,
                    ..c
                },
                0
            ),
            Ok(200.0)
        );
        assert!(parse("1 +").is_err());
        assert!(parse("AKISPL(1, 0").is_err());
    }
}
