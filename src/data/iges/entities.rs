//! Parameter data of the entities a measuring arm writes: point (116), line
//! (110), plane (108), with the transformation matrix (124) their directory
//! entry may point to and the Name property (406 form 15) their trailing
//! property pointers may name. Coordinates come out in mm, in the file's
//! model frame.

use super::directory::{Entry, valid_pointer};
use super::params::{Logical, Params, read};
use super::records::Record;
use super::{Geometry, IgesError};
use crate::geom::{Mat3, Vec3};

fn err(message: String, range: (usize, usize), label: &str) -> IgesError {
    IgesError::new("E0724", message, range, label)
}

/// Everything needed to decode the entries of one file.
pub struct Decoder<'a> {
    pub p: &'a [Record<'a>],
    pub d_records: usize,
    pub entries: &'a [Entry],
    pub pd: u8,
    pub rd: u8,
    pub to_mm: f64,
}

/// An entity's parameters (the entity type first), and where its data starts.
pub struct Data {
    pub params: Vec<super::params::Param>,
    pub end: usize,
    pub what: String,
    pub first_line_start: usize,
}

impl Data {
    pub fn view(&self) -> Params<'_> {
        Params {
            list: &self.params,
            end: self.end,
            what: &self.what,
        }
    }
}

pub fn describe(kind: i64) -> &'static str {
    match kind {
        116 => "point",
        110 => "line",
        108 => "plane",
        124 => "transformation matrix",
        406 => "property",
        _ => "entity",
    }
}

impl Decoder<'_> {
    fn entry(&self, pointer: usize) -> &Entry {
        &self.entries[(pointer - 1) / 2]
    }

    /// Reads and checks the parameter data of an entry.
    pub fn data(&self, e: &Entry) -> Result<Data, IgesError> {
        let what = format!("{} D {}", describe(e.kind), e.seq);
        let mut l = Logical::default();
        for r in &self.p[e.data - 1..e.data - 1 + e.data_lines] {
            let back = std::str::from_utf8(r.cols(65, 72)).unwrap_or("").trim();
            if super::params::integer(back) != Some(e.seq as i64) {
                return Err(err(
                    format!(
                        "{} points back to D `{back}`, but it holds the parameter data of D {}",
                        r.name(),
                        e.seq
                    ),
                    r.span(65, 72),
                    "back-pointer",
                ));
            }
            l.push(r, 1, 64);
        }
        let (params, _) = read(&l, 0, self.pd, self.rd, &what)?;
        let data = Data {
            params,
            end: l.end,
            what,
            first_line_start: self.p[e.data - 1].start,
        };
        let kind = data.view().int_or(0, "the entity type", 0)?;
        if kind != e.kind {
            return Err(err(
                format!(
                    "the parameter data of D {} starts with entity type {kind}, but the directory says {}",
                    e.seq, e.kind
                ),
                data.view().span(0),
                "entity type",
            ));
        }
        Ok(data)
    }

    /// The geometry of a point, line or plane, transformed and in mm.
    pub fn geometry(&self, e: &Entry, d: &Data) -> Result<Geometry, IgesError> {
        let p = d.view();
        let v = |k: usize, n: &str| -> Result<Vec3, IgesError> {
            Ok(Vec3::new(
                p.real(k, &format!("{n}x"))?,
                p.real(k + 1, &format!("{n}y"))?,
                p.real(k + 2, &format!("{n}z"))?,
            ))
        };
        let (r, t) = self.transform(e)?;
        let s = self.to_mm;
        Ok(match e.kind {
            116 => Geometry::Point((r * v(1, "")? + t) * s),
            110 => Geometry::Line {
                from: (r * v(1, "start ")? + t) * s,
                to: (r * v(4, "end ")? + t) * s,
            },
            108 => {
                let n = v(1, "normal ")?;
                let d0 = p.real(4, "D")?;
                let len = n.norm();
                if len < 1e-12 {
                    return Err(err(
                        format!("plane D {}: its normal (A, B, C) is zero", e.seq),
                        (p.span(1).0, p.span(3).1),
                        "zero normal",
                    ));
                }
                // A point of the plane, moved with the plane.
                let on = (r * (n * (d0 / (len * len))) + t) * s;
                let normal = (r * n).normalize();
                Geometry::Plane {
                    normal,
                    offset: normal.dot(&on),
                }
            }
            _ => unreachable!("only points, lines and planes are decoded"),
        })
    }

    /// The rigid transformation an entry's field 7 names (identity for none),
    /// following the matrices' own field 7 (IGES applies the chain inner first).
    fn transform(&self, e: &Entry) -> Result<(Mat3, Vec3), IgesError> {
        let (mut r, mut t) = (Mat3::identity(), Vec3::zeros());
        let mut at = e.transform;
        let mut seen = 0;
        while at != 0 {
            seen += 1;
            let m = self.entry(at);
            if m.kind != 124 || seen > 16 {
                return Err(err(
                    format!(
                        "D {} names D {at} as its transformation matrix, but {}",
                        e.seq,
                        if seen > 16 {
                            "the chain of matrices loops".to_string()
                        } else {
                            format!("D {at} is entity type {}, not 124", m.kind)
                        }
                    ),
                    e.kind_span,
                    "bad transformation",
                ));
            }
            let d = self.data(m)?;
            let p = d.view();
            let mut a = [0.0; 12];
            for (k, x) in a.iter_mut().enumerate() {
                *x = p.real(k + 1, &format!("matrix term {}", k + 1))?;
            }
            let rm = Mat3::new(a[0], a[1], a[2], a[4], a[5], a[6], a[8], a[9], a[10]);
            let tm = Vec3::new(a[3], a[7], a[11]);
            if (rm.transpose() * rm - Mat3::identity()).abs().max() > 1e-6 {
                return Err(err(
                    format!(
                        "transformation matrix D {at} is not a rotation (its columns are not orthonormal)"
                    ),
                    (p.span(1).0, p.span(12).1),
                    "not a rotation",
                ));
            }
            r = rm * r;
            t = rm * t + tm;
            at = m.transform;
        }
        Ok((r, t))
    }

    /// The Name property (406 form 15) among an entity's property pointers,
    /// which follow its own `own` parameters: NV, NV associativity pointers,
    /// NP, NP property pointers (absent means none).
    pub fn name(&self, d: &Data, own: usize) -> Result<Option<String>, IgesError> {
        let p = d.view();
        let nv = p.int_or(own + 1, "the associativity count", 0)?.max(0) as usize;
        let at_np = own + 2 + nv;
        let np = p.int_or(at_np, "the property count", 0)?.max(0) as usize;
        for k in at_np + 1..=at_np + np {
            let ptr = p.int_or(k, "a property pointer", 0)?;
            if !valid_pointer(ptr, self.d_records) {
                return Err(err(
                    format!(
                        "{}: property pointer {ptr} names no directory entry",
                        d.what
                    ),
                    p.span(k),
                    "bad pointer",
                ));
            }
            let prop = self.entry(ptr as usize);
            if prop.kind == 406 && prop.form == 15 {
                let pd = self.data(prop)?;
                return pd.view().text(2, "the name");
            }
        }
        Ok(None)
    }
}

/// Parameters an entity has before its trailing pointers.
pub fn own_params(kind: i64) -> usize {
    match kind {
        116 => 4,
        110 => 6,
        108 => 9,
        _ => 0,
    }
}
