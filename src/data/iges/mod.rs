//! IGES files from a measuring arm (thesis Annexe B, `methods.md` §10.4):
//! the named points (entity 116) a landmark file needs, and the lines (110)
//! and planes (108) measured with them. A pure function of the text, like the
//! CSV readers; every error carries the byte range of the record or field at
//! fault and names the IGES record (`D 7`, `P 12`), and a malformed file is an
//! error, never a panic.
//!
//! Names: the Name property (406 form 15) an entity points to, else its
//! directory label (8 characters) with its subscript kept alongside.

mod directory;
mod entities;
mod global;
mod params;
mod records;
mod write;

pub use global::Global;
pub use write::{Item, write};

use crate::geom::Vec3;

/// The readers' error type: a code, message and byte range in the file.
pub type IgesError = super::CsvError;

/// Geometry in mm, in the file's model frame (after any transformation matrix).
#[derive(Debug, Clone, PartialEq)]
pub enum Geometry {
    Point(Vec3),
    Line {
        from: Vec3,
        to: Vec3,
    },
    /// The plane `normal · x = offset`, `normal` of unit length.
    Plane {
        normal: Vec3,
        offset: f64,
    },
}

/// One entity of the directory.
#[derive(Debug, Clone, PartialEq)]
pub struct Entity {
    /// IGES entity type number.
    pub kind: i64,
    pub form: i64,
    /// Sequence number of its first directory record.
    pub de: usize,
    pub label: String,
    pub subscript: i64,
    /// From a Name property (406 form 15), when the entity has one.
    pub property_name: Option<String>,
    /// For points, lines and planes; `None` for the types not read.
    pub geometry: Option<Geometry>,
    /// Byte offset of its directory entry's first record, and of its label field.
    pub de_start: usize,
    pub label_span: (usize, usize),
    /// Byte offset of its first parameter record.
    pub data_start: usize,
}

impl Entity {
    /// The name the measuring software gave: the Name property, else the
    /// label; `None` when it has neither.
    pub fn name(&self) -> Option<&str> {
        self.property_name
            .as_deref()
            .or((!self.label.is_empty()).then_some(self.label.as_str()))
    }
}

/// A read file.
#[derive(Debug, Clone, PartialEq)]
pub struct Iges {
    pub global: Global,
    /// Every directory entry, in file order (types not read included, so
    /// nothing is dropped silently).
    pub entities: Vec<Entity>,
    /// Things the file leaves to defaults that change the numbers (`W07xx`).
    pub warnings: Vec<IgesError>,
}

impl Iges {
    pub fn points(&self) -> impl Iterator<Item = (&Entity, Vec3)> {
        self.entities.iter().filter_map(|e| match e.geometry {
            Some(Geometry::Point(p)) => Some((e, p)),
            _ => None,
        })
    }
}

/// Reads an ASCII IGES file.
pub fn parse(text: &str) -> Result<Iges, IgesError> {
    let s = records::split(text)?;
    let (global, warnings) = global::parse(&s.global)?;
    let entries = directory::parse(&s.directory, s.parameter.len())?;
    let dec = entities::Decoder {
        p: &s.parameter,
        d_records: s.directory.len(),
        entries: &entries,
        pd: global.param_delim,
        rd: global.record_delim,
        to_mm: global.to_mm,
    };
    let mut out = Vec::with_capacity(entries.len());
    for e in &entries {
        let own = entities::own_params(e.kind);
        let (geometry, property_name, data_start) = if own > 0 {
            let d = dec.data(e)?;
            (
                Some(dec.geometry(e, &d)?),
                dec.name(&d, own)?,
                d.first_line_start,
            )
        } else {
            (None, None, s.parameter[e.data - 1].start)
        };
        out.push(Entity {
            kind: e.kind,
            form: e.form,
            de: e.seq,
            label: e.label.clone(),
            subscript: e.subscript,
            property_name,
            geometry,
            de_start: s.directory[e.seq - 1].start,
            label_span: e.label_span,
            data_start,
        });
    }
    Ok(Iges {
        global,
        entities: out,
        warnings,
    })
}

/// A file's bytes as text whose columns are its characters: IGES is ASCII, so
/// any other character (a comment in Latin-1 or UTF-8) becomes one `?`,
/// keeping column 73 where the writer put it.
pub fn ascii_columns(bytes: &[u8]) -> String {
    match std::str::from_utf8(bytes) {
        Ok(s) => s
            .chars()
            .map(|c| if c.is_ascii() { c } else { '?' })
            .collect(),
        Err(_) => bytes
            .iter()
            .map(|&b| if b.is_ascii() { b as char } else { '?' })
            .collect(),
    }
}
