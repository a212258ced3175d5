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
    let line = |cells: Vec<&str>| {
        let mut s = indent.to_string();
        for (i, (c, w)) in cells.iter().zip(&widths).enumerate() {
            if i > 0 {
                s.push_str("  ");
            }
            // Text columns read better left-aligned, numbers right-aligned.
            if i == 0
                && rows
                    .first()
                    .is_some_and(|r| matches!(r.first(), Some(Cell::Text(_))))
            {
                s.push_str(&format!("{c:<w$}"));
            } else {
                s.push_str(&format!("{c:>w$}"));
            }
        }
        s.trim_end().to_string() + "\n"
    };
    let mut out = line(cols.iter().map(|c| c.title).collect());
    if cols.iter().any(|c| !c.unit.is_empty()) {
        out += &line(cols.iter().map(|c| c.unit).collect());
    }
    for r in &texts {
        out += &line(r.iter().map(String::as_str).collect());
    }
    out
}
