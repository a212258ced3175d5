//! Fixed-width text tables: a title row and a unit row over right-aligned
//! columns, so an engineer can scan a column of numbers in a terminal.

use super::number::fixed;

/// A column: its title, unit (shown under the title), and decimals.
#[derive(Debug, Clone, Copy)]
pub struct Col {
    pub title: &'static str,
    pub unit: &'static str,
    pub decimals: usize,
}

pub const fn col(title: &'static str, unit: &'static str, decimals: usize) -> Col {
    Col {
        title,
        unit,
        decimals,
    }
}

/// A cell: a number formatted by its column, or text.
#[derive(Debug, Clone)]
pub enum Cell {
    Num(f64),
    Text(String),
}

/// Renders rows under the columns; each column as wide as its widest cell.
pub fn render(cols: &[Col], rows: &[Vec<Cell>], indent: &str) -> String {
    let texts: Vec<Vec<String>> = rows
        .iter()
        .map(|r| {
            r.iter()
                .zip(cols)
                .map(|(c, col)| match c {
                    Cell::Num(v) => fixed(*v, col.decimals, 0),
                    Cell::Text(t) => t.clone(),
                })
                .collect()
        })
        .collect();
    let widths: Vec<usize> = cols
        .iter()
        .enumerate()
        .map(|(i, c)| {
            let cells = texts
                .iter()
                .map(|r| r.get(i).map_or(0, |t| t.chars().count()));
            cells
                .chain([c.title.chars().count(), c.unit.chars().count()])
                .max()
                .unwrap_or(0)
        })
        .collect();
    // Text columns read better left-aligned, numbers right-aligned.
    let left_first = rows
        .first()
        .is_some_and(|r| matches!(r.first(), Some(Cell::Text(_))));
    // Each line padded in place: a table of a 500-case path has some 75 000
    // cells, and a `format!` per cell to pad it, with the numbers' printing,
    // made the tables cost two thirds of the solves.
    let line = |out: &mut String, cells: &mut dyn Iterator<Item = &str>| {
        let start = out.len();
        out.push_str(indent);
        for (i, (c, &w)) in cells.zip(&widths).enumerate() {
            if i > 0 {
                out.push_str("  ");
            }
            let pad = w.saturating_sub(c.chars().count());
            if i == 0 && left_first {
                out.push_str(c);
                out.extend(std::iter::repeat_n(' ', pad));
            } else {
                out.extend(std::iter::repeat_n(' ', pad));
                out.push_str(c);
            }
        }
        let kept = out[start..].trim_end().len();
        out.truncate(start + kept);
        out.push('\n');
    };
    let mut out = String::new();
    line(&mut out, &mut cols.iter().map(|c| c.title));
    if cols.iter().any(|c| !c.unit.is_empty()) {
        line(&mut out, &mut cols.iter().map(|c| c.unit));
    }
    for r in &texts {
        line(&mut out, &mut r.iter().map(String::as_str));
    }
    out
}
