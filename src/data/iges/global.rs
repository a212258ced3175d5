//! The Global section: the two delimiters every later parameter is split by
//! (declared as `1Hx`, or defaulted to `,` and `;` by an empty field), and the
//! units the coordinates are in (units flag, units name, model space scale).

use super::IgesError;
use super::params::{Logical, Params, read};
use super::records::Record;

/// What the reader needs from the Global section.
#[derive(Debug, Clone, PartialEq)]
pub struct Global {
    pub param_delim: u8,
    pub record_delim: u8,
    /// Sending product (parameter 3) and file name (parameter 4), for messages.
    pub product: String,
    pub file_name: String,
    /// Units flag (parameter 14) and name (parameter 15).
    pub units_flag: i64,
    pub units_name: String,
    /// Model space scale (parameter 13): model units per real unit.
    pub scale: f64,
    /// Millimetres per model-space unit: coordinates are multiplied by this.
    pub to_mm: f64,
}

fn err(message: String, range: (usize, usize), label: &str) -> IgesError {
    IgesError::new("E0722", message, range, label)
}

/// mm per unit of each IGES units flag (IGES 5.3, Global parameter 14).
fn flag_mm(flag: i64) -> Option<f64> {
    Some(match flag {
        1 => 25.4,
        2 => 1.0,
        4 => 304.8,
        5 => 1_609_344.0,
        6 => 1000.0,
        7 => 1.0e6,
        8 => 0.0254,
        9 => 0.001,
        10 => 10.0,
        11 => 2.54e-5,
        _ => return None,
    })
}

/// mm per unit of a units name (used with flag 3, and checked against the flag).
fn name_mm(name: &str) -> Option<f64> {
    Some(match name.trim().to_ascii_uppercase().as_str() {
        "IN" | "INCH" => 25.4,
        "MM" => 1.0,
        "FT" => 304.8,
        "MI" => 1_609_344.0,
        "M" => 1000.0,
        "KM" => 1.0e6,
        "MIL" => 0.0254,
        "UM" | "MICRON" => 0.001,
        "CM" => 10.0,
        "UIN" => 2.54e-5,
        _ => return None,
    })
}

/// Reads one delimiter declaration (`1Hx`, or empty for the default) at `i`;
/// returns the delimiter and the position of what follows it.
fn delimiter(l: &Logical, mut i: usize, default: u8) -> Result<(u8, usize), IgesError> {
    let b = &l.bytes;
    while i < b.len() && b[i] == b' ' {
        i += 1;
    }
    if b[i..].starts_with(b"1H") && i + 2 < b.len() {
        let d = b[i + 2];
        if d == b' ' || d.is_ascii_digit() || b"+-.EeDdH".contains(&d) {
            return Err(err(
                format!("`{}` cannot be a delimiter", d as char),
                (l.offset(i + 2), l.offset(i + 2) + 1),
                "not a delimiter",
            ));
        }
        return Ok((d, i + 3));
    }
    Ok((default, i))
}

/// Parses the Global section records.
pub fn parse(records: &[Record]) -> Result<(Global, Vec<IgesError>), IgesError> {
    let mut l = Logical::default();
    for r in records {
        l.push(r, 1, 72);
    }
    let expect = |i: usize, d: &[u8], what: &str| -> Result<usize, IgesError> {
        let mut i = i;
        while i < l.bytes.len() && l.bytes[i] == b' ' {
            i += 1;
        }
        match l.bytes.get(i) {
            Some(c) if d.contains(c) => Ok(i),
            _ => Err(err(
                format!(
                    "the Global section should begin with the parameter and record delimiters (`1H,,1H;,` or `,,`); {what}"
                ),
                (l.offset(i), l.at.get(i).map_or(l.end, |a| a + 1)),
                "delimiter expected",
            )),
        }
    };
    let (pd, i) = delimiter(&l, 0, b',')?;
    let i = expect(
        i,
        &[pd],
        "the parameter delimiter is not followed by itself",
    )?;
    let (rd, j) = delimiter(&l, i + 1, b';')?;
    if pd == rd {
        return Err(err(
            format!(
                "the parameter and record delimiters are both `{}`",
                pd as char
            ),
            (l.offset(i + 1), l.offset(j)),
            "must differ",
        ));
    }
    let j = expect(
        j,
        &[pd, rd],
        "the record delimiter is not followed by a delimiter",
    )?;
    let list = if l.bytes[j] == rd {
        Vec::new()
    } else {
        read(&l, j + 1, pd, rd, "the Global section")?.0
    };
    // `list[0]` is parameter 3.
    let p = Params {
        list: &list,
        end: l.end,
        what: "the Global section",
    };
    let at = |n: usize| n - 3;
    let product = p
        .text(at(3), "the sending product")
        .ok()
        .flatten()
        .unwrap_or_default();
    let file_name = p
        .text(at(4), "the file name")
        .ok()
        .flatten()
        .unwrap_or_default();
    let scale = p.real_or(at(13), "the model space scale (parameter 13)", 1.0)?;
    if scale <= 0.0 {
        return Err(err(
            format!("the model space scale is {scale}; it must be positive"),
            p.span(at(13)),
            "model space scale",
        ));
    }
    let mut warnings = Vec::new();
    let given = p.int_or(at(14), "the units flag (parameter 14)", 0)?;
    let units_name = p
        .text(at(15), "the units name (parameter 15)")?
        .unwrap_or_default();
    let units_flag = if given == 0 {
        warnings.push(IgesError::new(
            "W0712",
            "the Global section gives no units flag; IGES then means inches",
            p.span(at(14)),
            "units flag defaulted",
        ));
        1
    } else {
        given
    };
    let unit = if units_flag == 3 {
        name_mm(&units_name)
    } else {
        flag_mm(units_flag)
    };
    let Some(unit) = unit else {
        return Err(err(
            format!(
                "units flag {units_flag} with units name `{units_name}` is not a length unit IGES defines"
            ),
            p.span(at(14)),
            "unknown units",
        ));
    };
    if let Some(named) = name_mm(&units_name)
        && (named - unit).abs() > 1e-12 * unit
    {
        return Err(err(
            format!("units flag {units_flag} disagrees with the units name `{units_name}`"),
            p.span(at(15)),
            "which unit?",
        ));
    }
    Ok((
        Global {
            param_delim: pd,
            record_delim: rd,
            product,
            file_name,
            units_flag,
            units_name,
            scale,
            to_mm: unit / scale,
        },
        warnings,
    ))
}
