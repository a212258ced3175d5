//! K&C plots as one SVG of small multiples, like the thesis figures 2.18 and
//! 4.11: each panel one quantity against the swept variable, with a title,
//! axis labels with units, and one line per wheel, or the measured, initial
//! and identified curves of `identify --report` overlaid. SVG only (no system
//! fonts).

use crate::kc::{Input, KcRow};
use plotters::prelude::*;

/// What the panels are plotted against.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Sweep {
    /// Vertical load: everything against wheel travel, with the load as a panel.
    Bump,
    /// A force component (0, 1, 2 = fx, fy, fz) or torque (3, 4, 5).
    Force(usize),
    /// A load table whose cases vary several components: against the case.
    Case,
    /// Opposed travel of an axle's wheels: everything against the body's
    /// roll angle (`KcRow::roll_deg`), with the wheel load as a panel.
    Roll,
    /// A steering path: everything against the rack's travel
    /// (`KcRow::rack_mm`).
    Steer,
    /// A compliance event: each wheel against its own swept load (a
    /// traction force at the wheel centre included), in the wheel's own
    /// frame (`kc::Input::own`: lateral force and torque outboard positive).
    Compliance(Input),
}

/// The quantity a panel draws, to attach a [`Note`] to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Quantity {
    Toe,
    Camber,
    HalfTrack,
    Load,
}

/// A line of text under a panel: a metric read off its curves (bump
/// steer under the toe panel, roll stiffness under the load panel, ...).
#[derive(Debug, Clone, PartialEq)]
pub struct Note {
    pub panel: Quantity,
    pub text: String,
}

/// A panel: title, y label, and the quantity.
struct Panel {
    quantity: Quantity,
    title: &'static str,
    y_label: &'static str,
    y: fn(&KcRow) -> f64,
}

const TOE: Panel = Panel {
    quantity: Quantity::Toe,
    title: "Toe angle",
    y_label: "toe-in [deg]",
    y: |r| r.quantities.toe_deg,
};
const CAMBER: Panel = Panel {
    quantity: Quantity::Camber,
    title: "Camber angle",
    y_label: "camber [deg]",
    y: |r| r.quantities.camber_deg,
};
const TRACK: Panel = Panel {
    quantity: Quantity::HalfTrack,
    title: "Half-track change",
    y_label: "half-track change [mm]",
    y: |r| r.quantities.half_track_change_mm,
};
const LOAD: Panel = Panel {
    quantity: Quantity::Load,
    title: "Wheel load",
    y_label: "vertical load fz [N]",
    y: |r| r.force[2],
};

const FORCE_LABELS: [&str; 6] = [
    "longitudinal force fx [N]",
    "lateral force fy [N]",
    "vertical force fz [N]",
    "moment mx [N*mm]",
    "moment my [N*mm]",
    "moment mz [N*mm]",
];

/// The panel titles of a sweep, in drawing order.
pub fn panel_titles(sweep: Sweep) -> Vec<&'static str> {
    panels(sweep).iter().map(|p| p.title).collect()
}

fn panels(sweep: Sweep) -> Vec<Panel> {
    match sweep {
        Sweep::Bump | Sweep::Roll => vec![TOE, CAMBER, TRACK, LOAD],
        Sweep::Force(_) | Sweep::Case | Sweep::Compliance(_) => vec![TOE, CAMBER],
        Sweep::Steer => vec![TOE, CAMBER, TRACK],
    }
}

fn x_of(sweep: Sweep, r: &KcRow) -> f64 {
    match sweep {
        Sweep::Bump => r.quantities.travel_mm,
        Sweep::Force(c) if c < 3 => r.force[c],
        Sweep::Force(c) => r.torque[(c - 3).min(2)],
        Sweep::Case => r.step as f64,
        Sweep::Roll => r.roll_deg.unwrap_or(f64::NAN),
        Sweep::Steer => r.rack_mm.unwrap_or(f64::NAN),
        Sweep::Compliance(i) => i.own(r),
    }
}

/// Ticks per axis: few enough that labels like `-4000` never touch on a
/// 460 px panel.
const TICKS: usize = 6;

/// A tick label: at most 6 decimals, no trailing zeros, and never `-0`
/// (plotters hands ticks such as -0.0 and 0.30000000000000004).
fn tick(v: &f64) -> String {
    let r = (v * 1e6).round() / 1e6;
    if r == 0.0 || !r.is_finite() {
        return "0".to_string();
    }
    format!("{r}")
}

/// A range around the values with 5 % margins (a flat curve gets a unit band).
fn range(values: impl Iterator<Item = f64>) -> std::ops::Range<f64> {
    let (lo, hi) = values
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        });
    if !lo.is_finite() {
        return -1.0..1.0;
    }
    let pad = if hi - lo > 1e-9 * (1.0 + hi.abs()) {
        0.05 * (hi - lo)
    } else {
        0.5 * (1.0 + hi.abs() * 0.1)
    };
    (lo - pad)..(hi + pad)
}

const COLOURS: [RGBColor; 4] = [
    RGBColor(0, 90, 180),
    RGBColor(200, 60, 20),
    RGBColor(30, 140, 60),
    RGBColor(120, 60, 160),
];

/// One line of every panel: a legend label, a colour, the rows it joins in
/// order, and whether each row is also marked by a dot (measured points).
struct Line<'a> {
    label: String,
    /// The first line of its label: the one the legend lists.
    in_legend: bool,
    colour: RGBColor,
    rows: Vec<&'a KcRow>,
    dots: bool,
}

/// The swept load of a row: what the rig drives, whose direction of change
/// tells loading from unloading.
fn load_of(sweep: Sweep, r: &KcRow) -> f64 {
    match sweep {
        Sweep::Bump => r.force[2],
        Sweep::Force(c) if c < 3 => r.force[c],
        Sweep::Force(c) => r.torque[(c - 3).min(2)],
        // Cases in order: one run, never "unloading".
        Sweep::Case => r.step as f64,
        // Branches by the direction the body rolls.
        Sweep::Roll => r.roll_deg.unwrap_or(0.0),
        Sweep::Steer => r.rack_mm.unwrap_or(0.0),
        Sweep::Compliance(i) => i.own(r),
    }
}

/// The rows split where the swept load turns back: runs of one direction
/// (`true`: increasing), each starting at the turning row of the previous
/// one so the curve stays connected. A path that never turns is one run.
fn runs<'a>(rows: &[&'a KcRow], sweep: Sweep) -> Vec<(bool, Vec<&'a KcRow>)> {
    let mut out: Vec<(bool, Vec<&KcRow>)> = Vec::new();
    for (k, r) in rows.iter().enumerate() {
        let Some(prev) = k.checked_sub(1).map(|p| rows[p]) else {
            continue;
        };
        let d = load_of(sweep, r) - load_of(sweep, prev);
        if d == 0.0 {
            if let Some(last) = out.last_mut() {
                last.1.push(r);
            }
            continue;
        }
        let up = d > 0.0;
        match out.last_mut() {
            Some(last) if last.0 == up => last.1.push(r),
            _ => out.push((up, vec![prev, r])),
        }
    }
    if out.is_empty() {
        out.push((true, rows.to_vec()));
    }
    out
}

/// Loading and unloading branches of a K&C path that turns back:
/// the legend word of each direction.
pub const BRANCH_LABELS: [&str; 2] = ["load increasing", "load decreasing"];

/// The legend word of a branch: by the swept load, or for a roll by the
/// direction the body rolls.
fn branch_label(sweep: Sweep, up: bool) -> &'static str {
    match sweep {
        Sweep::Roll => ["roll increasing", "roll decreasing"][usize::from(!up)],
        Sweep::Steer => ["rack moving left", "rack moving right"][usize::from(!up)],
        _ => BRANCH_LABELS[usize::from(!up)],
    }
}

/// The SVG text of the plots of a K&C path. A path that turns back (a sweep
/// up and down) is drawn as one polyline per direction, each direction with
/// its colour and legend entry, so that hysteresis (dry friction) shows as
/// two branches.
pub fn svg(title: &str, rows: &[KcRow], sweep: Sweep) -> Result<String, String> {
    annotated_svg(title, rows, sweep, &[])
}

/// [`svg`] with lines of text under the panels: the metrics of the path
/// (`axle kc --plot`).
pub fn annotated_svg(
    title: &str,
    rows: &[KcRow],
    sweep: Sweep,
    notes: &[Note],
) -> Result<String, String> {
    let mut wheels: Vec<&str> = Vec::new();
    for r in rows {
        if !wheels.contains(&r.wheel.as_str()) {
            wheels.push(&r.wheel);
        }
    }
    let mut lines: Vec<Line> = Vec::new();
    for (k, w) in wheels.iter().enumerate() {
        let mine: Vec<&KcRow> = rows.iter().filter(|r| r.wheel == *w).collect();
        let rs = runs(&mine, sweep);
        let turns = rs.len() > 1;
        for (up, run) in rs {
            let label = match (turns, wheels.len() > 1) {
                (false, _) => w.to_string(),
                (true, false) => branch_label(sweep, up).to_string(),
                (true, true) => format!("{w}, {}", branch_label(sweep, up)),
            };
            let first = !lines.iter().any(|l| l.label == label);
            lines.push(Line {
                label,
                in_legend: first,
                colour: COLOURS[(2 * k + usize::from(turns && !up)) % COLOURS.len()],
                rows: run,
                dots: false,
            });
        }
    }
    let legend = lines.iter().filter(|l| l.in_legend).count() > 1;
    draw(title, &lines, sweep, legend, notes)
}

/// The legend labels of [`overlay_svg`], in drawing order.
pub const OVERLAY_LABELS: [&str; 3] = ["measured", "initial model", "identified model"];

/// Measured, initial-model and identified-model K&C curves of one wheel on
/// the same panels with a legend (thesis figures 4.11, 5.9, 5.12). Each slice
/// is drawn in its order; the measured one also with a dot per row.
pub fn overlay_svg(
    title: &str,
    measured: &[KcRow],
    initial: &[KcRow],
    identified: &[KcRow],
    sweep: Sweep,
) -> Result<String, String> {
    let lines: Vec<Line> = [measured, initial, identified]
        .iter()
        .zip(OVERLAY_LABELS)
        .enumerate()
        .map(|(k, (rows, label))| Line {
            label: label.to_string(),
            in_legend: true,
            colour: COLOURS[k],
            rows: rows.iter().collect(),
            dots: k == 0,
        })
        .collect();
    draw(title, &lines, sweep, true, &[])
}

/// Height of a line of notes under a panel, px.
const NOTE_LINE: u32 = 18;

fn draw(
    title: &str,
    lines: &[Line],
    sweep: Sweep,
    legend: bool,
    notes: &[Note],
) -> Result<String, String> {
    let panels = panels(sweep);
    let x_label = match sweep {
        Sweep::Bump => "wheel travel [mm]",
        Sweep::Force(c) => FORCE_LABELS[c.min(5)],
        Sweep::Case => "load case (step)",
        Sweep::Roll => "body roll angle [deg]",
        Sweep::Steer => "rack travel [mm] (+ toward the left)",
        Sweep::Compliance(i) => match i {
            Input::Lateral => "lateral force at the contact point, outboard + [N]",
            Input::Braking => "longitudinal force fx at the contact point [N]",
            Input::Traction => "longitudinal force fx at the wheel centre [N]",
            Input::AligningTorque => "aligning torque mz, front turning outboard + [N*mm]",
        },
    };
    let cols = 2u32;
    let nrows = panels.len().div_ceil(2) as u32;
    // Every panel gets the strip of the panel with the most notes, so the
    // grid stays even.
    let strip = panels
        .iter()
        .map(|p| notes.iter().filter(|n| n.panel == p.quantity).count() as u32)
        .max()
        .unwrap_or(0)
        * NOTE_LINE
        + if notes.is_empty() { 0 } else { 8 };
    let all = || lines.iter().flat_map(|l| l.rows.iter().copied());
    let mut out = String::new();
    {
        let root = SVGBackend::with_string(&mut out, (cols * 460, nrows * (340 + strip) + 40))
            .into_drawing_area();
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        let root = root
            .titled(title, ("sans-serif", 22))
            .map_err(|e| e.to_string())?;
        let areas = root.split_evenly((nrows as usize, cols as usize));
        let xr = range(all().map(|r| x_of(sweep, r)));
        for (panel, cell) in panels.iter().zip(areas.iter()) {
            let (area, below) = cell.split_vertically(340);
            for (k, n) in notes
                .iter()
                .filter(|n| n.panel == panel.quantity)
                .enumerate()
            {
                below
                    .draw(&Text::new(
                        n.text.as_str(),
                        (72, 2 + k as i32 * NOTE_LINE as i32),
                        ("sans-serif", 14).into_font().color(&BLACK),
                    ))
                    .map_err(|e| e.to_string())?;
            }
            let yr = range(all().map(panel.y));
            let mut chart = ChartBuilder::on(&area)
                .caption(panel.title, ("sans-serif", 18))
                .margin(12)
                .x_label_area_size(40)
                .y_label_area_size(60)
                .build_cartesian_2d(xr.clone(), yr)
                .map_err(|e| e.to_string())?;
            chart
                .configure_mesh()
                .x_desc(x_label)
                .y_desc(panel.y_label)
                .x_labels(TICKS)
                .y_labels(TICKS)
                .x_label_formatter(&tick)
                .y_label_formatter(&tick)
                .light_line_style(RGBColor(235, 235, 235))
                .draw()
                .map_err(|e| e.to_string())?;
            for line in lines {
                let colour = line.colour;
                let pts: Vec<(f64, f64)> = line
                    .rows
                    .iter()
                    .map(|r| (x_of(sweep, r), (panel.y)(r)))
                    .filter(|(x, y)| x.is_finite() && y.is_finite())
                    .collect();
                if line.dots {
                    chart
                        .draw_series(pts.iter().map(|p| Circle::new(*p, 3, colour.filled())))
                        .map_err(|e| e.to_string())?;
                }
                let series = chart
                    .draw_series(LineSeries::new(pts, colour.stroke_width(2)))
                    .map_err(|e| e.to_string())?;
                if legend && line.in_legend {
                    series
                        .label(line.label.as_str())
                        .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], colour));
                }
            }
            if legend {
                chart
                    .configure_series_labels()
                    .background_style(WHITE)
                    .border_style(BLACK)
                    .draw()
                    .map_err(|e| e.to_string())?;
            }
        }
        root.present().map_err(|e| e.to_string())?;
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::tick;

    #[test]
    fn tick_labels_have_no_negative_zero_and_no_float_noise() {
        assert_eq!(tick(&-0.0), "0");
        assert_eq!(tick(&-1e-12), "0");
        assert_eq!(tick(&0.30000000000000004), "0.3");
        assert_eq!(tick(&-4000.0), "-4000");
        assert_eq!(tick(&2.5), "2.5");
    }
}
