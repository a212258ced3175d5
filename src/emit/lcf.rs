//! Model + load set → Adams/Car suspension loadcase file (`.lcf`, FILE_VERSION
//! 6.0, the header of thesis Annexe H and the 19 columns of the public
//! Adams/Car files): one row per load case, left and right columns from the
//! model's wheels (left: centre y >= 0 at design), or of one axle's two wheels
//! of a model of more ([`emit_lcf_axle`]). The vertical columns are the
//! wheel forces (`wheel_vertical_force`) or the wheel-centre heights axle
//! solves for (`wheel_center_height`). A force at a wheel's centre marker is
//! its drive force (`drive`, forward positive).

use super::error::EmitError;
use super::writer::num;
use crate::model::*;

const COLUMNS: [&str; 19] = [
    "whl_z_l",
    "whl_z_r",
    "lat_l",
    "lat_r",
    "dam_rad_l",
    "dam_rad_r",
    "dam_for_l",
    "dam_for_r",
    "align_l",
    "align_r",
    "brake_l",
    "brake_r",
    "drive_l",
    "drive_r",
    "otm_l",
    "otm_r",
    "rollres_l",
    "rollres_r",
    "steer",
];

/// The wheel a channel loads (at its contact marker, or a force at its
/// centre marker: `true`, the drive force), or an error naming the channel.
fn wheel_of(m: &Model, set: &LoadSet, ch: &Channel) -> Result<(WheelId, bool), EmitError> {
    let name = || match ch.target {
        LoadTarget::Marker(mk) => format!("{}.{}", m.marker_path(mk), ch.component.name()),
        LoadTarget::Wheel(w) => format!("{}.{}", m.wheels[w.index()].name, ch.component.name()),
        LoadTarget::DefaultWheel => ch.component.name().to_string(),
    };
    let not_a_wheel_load = || EmitError::NotAWheelLoad {
        set: set.name.clone(),
        channel: name(),
    };
    match ch.target {
        LoadTarget::Wheel(w) => Ok((w, false)),
        LoadTarget::DefaultWheel if m.wheels.len() == 1 => Ok((WheelId(0), false)),
        LoadTarget::DefaultWheel => Err(EmitError::UnresolvedLoad {
            set: set.name.clone(),
            channel: name(),
        }),
        LoadTarget::Marker(mk) => {
            if let Some(k) = m.wheels.iter().position(|w| w.contact == mk) {
                return Ok((WheelId(k as u32), false));
            }
            // Only the longitudinal force has a column at the centre.
            match m.wheels.iter().position(|w| w.centre == mk) {
                Some(k) if ch.component == Component::Fx => Ok((WheelId(k as u32), true)),
                _ => Err(not_a_wheel_load()),
            }
        }
    }
}

/// The wheels of the axle of wheel `name`: its pair ([`Model::wheel_pairs`],
/// as `kc` pairs them), or the wheel alone when it has no partner.
fn axle_of(m: &Model, name: &str) -> Result<Vec<WheelId>, EmitError> {
    let Some(k) = m.wheels.iter().position(|w| w.name == name) else {
        return Err(EmitError::UnknownWheel {
            name: name.to_string(),
            known: m.wheels.iter().map(|w| w.name.clone()).collect(),
        });
    };
    let k = WheelId(k as u32);
    Ok(
        match m.wheel_pairs().into_iter().find(|&(l, r)| l == k || r == k) {
            Some((l, r)) => vec![l, r],
            None => vec![k],
        },
    )
}

/// What the vertical columns `whl_z_l`, `whl_z_r` hold.
#[derive(Debug, Clone, PartialEq)]
pub enum Vertical {
    /// The wheels' `fz` loads, N.
    Force,
    /// Per case, per wheel: the wheel-centre z at axle's equilibrium, mm
    /// ([`crate::kc::heights::centre_heights`]).
    CentreHeight(Vec<Vec<f64>>),
}

/// The loadcase file in `wheel_vertical_force` mode.
pub fn emit_lcf(m: &Model, set: LoadSetId) -> Result<String, EmitError> {
    emit_lcf_as(m, set, &Vertical::Force)
}

pub fn emit_lcf_as(m: &Model, set: LoadSetId, vertical: &Vertical) -> Result<String, EmitError> {
    emit_lcf_axle(m, set, vertical, None)
}

/// The loadcase file of the axle of wheel `axle` (with the wheel on the other
/// side nearest its mirror image), or, without it, of the model's wheels (at
/// most one a side). Loads on the other wheels are not written: the file is
/// that axle's rig.
pub fn emit_lcf_axle(
    m: &Model,
    set: LoadSetId,
    vertical: &Vertical,
    axle: Option<&str>,
) -> Result<String, EmitError> {
    let ls = m.load_sets.get(set.index()).ok_or(EmitError::NoLoadSet)?;
    let chosen: Vec<WheelId> = match axle {
        Some(name) => axle_of(m, name)?,
        None => (0..m.wheels.len() as u32).map(WheelId).collect(),
    };
    // Side of each wheel written: 0 left, 1 right; `None` for the others.
    let mut side_of: Vec<Option<usize>> = vec![None; m.wheels.len()];
    let mut taken: [Option<&str>; 2] = [None, None];
    for &id in &chosen {
        let w = &m.wheels[id.index()];
        let side = usize::from(m.marker(w.centre).origin().y < 0.0);
        if let Some(other) = taken[side] {
            return Err(EmitError::WheelSide {
                wheel: w.name.clone(),
                other: other.to_string(),
            });
        }
        taken[side] = Some(&w.name);
        side_of[id.index()] = Some(side);
    }
    // Per channel: its side (none: another axle's wheel) and whether it is a
    // drive force at the centre.
    let mut targets = Vec::new();
    for ch in &ls.channels {
        let (w, drive) = wheel_of(m, ls, ch)?;
        targets.push((side_of[w.index()], drive));
    }
    let mut o = String::new();
    let bar = |o: &mut String, t: &str| o.push_str(&format!("${}{t}\n", "-".repeat(79 - t.len())));
    bar(&mut o, "MDI_HEADER");
    o.push_str(
        "[MDI_HEADER]\n FILE_TYPE     =  'lcf'\n FILE_VERSION  =  6.0\n FILE_FORMAT   =  'ascii'\n",
    );
    o.push_str("(COMMENTS)\n{comment_string}\n");
    o.push_str(&format!(
        "'axle model {} -- load set {} -- Static Load'\n",
        m.name, ls.name
    ));
    bar(&mut o, "UNITS");
    o.push_str("[UNITS]\n LENGTH  =  'mm'\n FORCE   =  'newton'\n ANGLE   =  'deg'\n MASS    =  'kg'\n TIME    =  'sec'\n");
    bar(&mut o, "MODE");
    let heights = match vertical {
        Vertical::Force => None,
        Vertical::CentreHeight(h) => Some(h),
    };
    // The setup (design) position is given by wheel-centre heights, as in
    // the public Adams/Car loadcase files.
    o.push_str(
        "[MODE]\n STEERING_MODE  =  'angle'\n VERTICAL_MODE_FOR_SETUP  =  'wheel_center_height'\n",
    );
    o.push_str(if heights.is_some() {
        " VERTICAL_MODE  =  'wheel_center_height'\n VERTICAL_TYPE  =  'absolute'\n"
    } else {
        " VERTICAL_MODE  =  'wheel_vertical_force'\n"
    });
    o.push_str(" COORDINATE_SYSTEM  =  'vehicle'\n");
    bar(&mut o, "DATA");
    o.push_str("[DATA]\n");
    o.push_str("$ axle wheel loads at the contact point, global axes (x forward, y left, z up):\n");
    o.push_str(if heights.is_some() {
        "$   whl_z = wheel-centre z (mm) at axle's equilibrium under the case's loads,\n$   lat = fy, brake = -fx (positive toward the rear),\n"
    } else {
        "$   whl_z = fz, lat = fy, brake = -fx (positive toward the rear),\n"
    });
    o.push_str("$   align = mz, otm = mx, rollres = my, drive = fx at the wheel centre;\n$   damage and steer are 0.\n");
    for (w, s) in m.wheels.iter().zip(&side_of) {
        if let Some(s) = s {
            o.push_str(&format!("$ {} wheel: {}\n", ["left", "right"][*s], w.name));
        }
    }
    // A half axle has one side: zeros on the other would ask Adams/Car for a
    // 0 mm wheel-centre height and no load; its mirror image is what a
    // symmetric axle sees.
    let mirror = match taken {
        [Some(_), None] => Some((0, 1)),
        [None, Some(_)] => Some((1, 0)),
        _ => None,
    };
    if let Some((from, to)) = mirror {
        let side = ["left", "right"];
        o.push_str(&format!(
            "$ {} wheel: none in the model; its columns mirror the {} wheel's in y = 0 (lat, align and otm change sign)\n",
            side[to], side[from]
        ));
    }
    let names: Vec<&str> = ls.cases.iter().map(|c| c.name.as_str()).collect();
    o.push_str(&format!("$ rows: {}\n", names.join(" ")));
    o.push_str(&format!("{{ {} }}\n", COLUMNS.join("  ")));
    for (k, case) in ls.cases.iter().enumerate() {
        let mut row = [0.0f64; 19];
        for ((ch, v), &(side, drive)) in ls.channels.iter().zip(&case.values).zip(&targets) {
            if !v.is_finite() {
                return Err(EmitError::NotFinite {
                    element: format!("load case `{}`", case.name),
                    what: "a load".into(),
                });
            }
            let Some(side) = side else {
                continue;
            };
            let (col, val) = match ch.component {
                // `wheel_of` takes only fx at a centre.
                _ if drive => (12, *v),
                // In height mode the vertical columns are heights, set below.
                Component::Fz if heights.is_some() => continue,
                Component::Fz => (0, *v),
                Component::Fy => (2, *v),
                Component::Mz => (8, *v),
                Component::Fx => (10, -*v),
                Component::Mx => (14, *v),
                Component::My => (16, *v),
            };
            row[col + side] += val;
        }
        if let Some(h) = heights {
            let hk = h.get(k).ok_or(EmitError::NoLoadSet)?;
            for (w, side) in hk.iter().zip(&side_of) {
                let Some(side) = side else {
                    continue;
                };
                if !w.is_finite() {
                    return Err(EmitError::NotFinite {
                        element: format!("load case `{}`", case.name),
                        what: "a wheel-centre height".into(),
                    });
                }
                row[*side] = *w;
            }
        }
        if let Some((from, to)) = mirror {
            for col in (0..18).step_by(2) {
                // lat (fy), align (mz) and otm (mx) are odd under y -> -y.
                let sign = if matches!(col, 2 | 8 | 14) { -1.0 } else { 1.0 };
                row[col + to] = sign * row[col + from];
            }
        }
        let cells: Vec<String> = row.iter().map(|v| num(*v)).collect();
        o.push_str(&format!(" {}\n", cells.join("  ")));
    }
    Ok(o)
}
