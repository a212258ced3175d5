//! The K&C curves of `identify --report` (thesis figures 4.11, 5.9, 5.12):
//! toe and camber of every wheel under each load direction the measured
//! steps sweep at it, as measured, as the initial model computes them and as
//! the identified model computes them.
//!
//! The measured quantities come from the K&C file when given, else from the
//! fitted pose of the wheel's part. Both models are solved at the measured
//! loads, step after step (warm starts), so the three curves share their x
//! values: the applied wheel load.

use super::measured::Measured;
use super::{IdentifyError, IdentifyErrorKind, Method};
use crate::geom::Vec3;
use crate::kc::{KcRow, WheelQuantities, wheel_quantities};
use crate::model::{ElementId, Model, Wheel, WheelId};
use crate::statics::path;
use crate::statics::{Problem, State};

/// Names of the load directions, by force component (fx, fy, fz).
const DIRECTIONS: [&str; 3] = ["longitudinal", "lateral", "vertical"];

/// The three curves along one load direction, each ordered by that load.
#[derive(Debug, Clone, PartialEq)]
pub struct Curves {
    /// The wheel whose toe and camber these are.
    pub wheel: String,
    /// The swept force component: 0, 1, 2 = fx, fy, fz.
    pub component: usize,
    /// `longitudinal`, `lateral` or `vertical`.
    pub name: &'static str,
    /// The file's stem: `toe_camber_<name>` for a model of one wheel,
    /// `toe_camber_<wheel>_<name>` (dots of a qualified name as `_`) else.
    pub file: String,
    pub measured: Vec<KcRow>,
    pub initial: Vec<KcRow>,
    pub identified: Vec<KcRow>,
}

impl Curves {
    /// Root-mean-square difference, deg, of toe (`camber == false`) or camber
    /// between a model's curve and the measured one, over the measured steps.
    pub fn rms(&self, model: &[KcRow], camber: bool) -> f64 {
        let q = |r: &KcRow| {
            if camber {
                r.quantities.camber_deg
            } else {
                r.quantities.toe_deg
            }
        };
        let d: Vec<f64> = self
            .measured
            .iter()
            .filter_map(|m| {
                let s = model.iter().find(|r| r.step == m.step)?;
                Some(q(s) - q(m))
            })
            .filter(|d| d.is_finite())
            .collect();
        if d.is_empty() {
            return f64::NAN;
        }
        (d.iter().map(|x| x * x).sum::<f64>() / d.len() as f64).sqrt()
    }
}

/// The wheel load of every step: force and torque on the contact marker.
fn wheel_load(data: &Measured, w: &Wheel) -> Vec<(Vec3, Vec3)> {
    data.steps
        .iter()
        .map(|s| {
            s.loads
                .iter()
                .filter(|l| l.marker == w.contact)
                .fold((Vec3::zeros(), Vec3::zeros()), |(f, t), l| {
                    (f + l.force, t + l.torque)
                })
        })
        .collect()
}

fn row(step: usize, w: &Wheel, load: (Vec3, Vec3), q: WheelQuantities) -> KcRow {
    KcRow {
        step,
        loadcase: format!("step {step}"),
        wheel: w.name.clone(),
        force: load.0.into(),
        torque: load.1.into(),
        centre_force: [0.0; 3],
        quantities: q,
        roll_deg: None,
        rack_mm: None,
    }
}

/// The measured quantities of step `k`: the K&C channels, else the pose of
/// the wheel's part; `None` when neither was measured.
fn measured_row(model: &Model, data: &Measured, k: usize, w: &Wheel) -> Option<WheelQuantities> {
    let s = &data.steps[k];
    let id = model.wheels.iter().position(|x| x.name == w.name);
    if let Some(o) = s.kc.iter().find(|o| Some(o.wheel.index()) == id) {
        // Only toe, camber and the centre are channels of a K&C file.
        let design = wheel_quantities(model, &State::design(model), w);
        return Some(WheelQuantities {
            center: o.wc.into(),
            spin_axis: [f64::NAN; 3],
            toe_deg: o.toe_deg,
            camber_deg: o.camber_deg,
            travel_mm: o.wc.z - design.center[2],
            half_track_mm: f64::NAN,
            half_track_change_mm: f64::NAN,
            contact: [f64::NAN; 3],
        });
    }
    let parts = [model.marker(w.centre).part, model.marker(w.contact).part];
    if parts
        .iter()
        .all(|p| s.poses.get(p.index()).is_some_and(|x| x.is_some()))
    {
        return Some(wheel_quantities(model, &data.state(k), w));
    }
    None
}

/// `model` solved at every measured step in order, from design.
fn simulate(model: &Model, data: &Measured, which: &str) -> Result<Vec<State>, IdentifyError> {
    let problem = Problem::new(model)
        .map_err(|e| IdentifyError::statics(format!("report: the {which} model"), e, model))?;
    let run = path::simulate(
        &problem,
        data.steps.iter().map(|s| &s.loads),
        &State::design(model),
    );
    if let Some(e) = run.failure {
        let context = format!(
            "report: the {which} model does not solve at step {}",
            data.steps[e.case].step
        );
        return Err(IdentifyError::statics(context, e.error, model));
    }
    Ok(run.steps.into_iter().map(|eq| eq.state).collect())
}

/// The steps of each load direction: those loaded along `c` alone (besides a
/// common vertical load for the horizontal directions), with at least three
/// distinct loads; ordered by the load. When the steps sweep no direction
/// alone, all of them along the component that varies most.
fn groups(loads: &[(Vec3, Vec3)]) -> Vec<(usize, Vec<usize>)> {
    let scale = loads
        .iter()
        .map(|(f, _)| f.amax())
        .fold(0.0, f64::max)
        .max(1e-9);
    let zero = |v: f64| v.abs() <= 1e-6 * scale;
    let same = |a: f64, b: f64| (a - b).abs() <= 1e-6 * scale;
    let distinct = |idx: &[usize], c: usize| {
        let mut v: Vec<f64> = idx.iter().map(|&k| loads[k].0[c]).collect();
        v.sort_by(f64::total_cmp);
        v.dedup_by(|a, b| same(*a, *b));
        v.len()
    };
    let mut out = Vec::new();
    for c in 0..3 {
        let other: Vec<usize> = (0..2).filter(|&o| o != c).collect();
        let mut idx: Vec<usize> = (0..loads.len())
            .filter(|&k| other.iter().all(|&o| zero(loads[k].0[o])))
            .collect();
        if c < 2 {
            // The vertical load the steps loaded along c are measured at.
            let Some(fz) = idx
                .iter()
                .find(|&&k| !zero(loads[k].0[c]))
                .map(|&k| loads[k].0[2])
            else {
                continue;
            };
            idx.retain(|&k| same(loads[k].0[2], fz));
        }
        if distinct(&idx, c) >= 3 {
            idx.sort_by(|&a, &b| loads[a].0[c].total_cmp(&loads[b].0[c]));
            out.push((c, idx));
        }
    }
    if out.is_empty() && !loads.is_empty() {
        let spread = |c: usize| {
            let v = loads.iter().map(|(f, _)| f[c]);
            v.clone().fold(f64::MIN, f64::max) - v.fold(f64::MAX, f64::min)
        };
        let c = (0..3)
            .max_by(|&a, &b| spread(a).total_cmp(&spread(b)))
            .unwrap_or(2);
        let mut idx: Vec<usize> = (0..loads.len()).collect();
        idx.sort_by(|&a, &b| loads[a].0[c].total_cmp(&loads[b].0[c]));
        out.push((c, idx));
    }
    out
}

/// The curves of every wheel and load direction the data sweep at it, in
/// wheel order. A wheel that no step loads, or whose toe and camber were
/// not measured, has none; a model none of whose wheels has them is an
/// error. `initial` is the model identification started from, `identified`
/// the result applied to it.
pub fn curves(
    initial: &Model,
    identified: &Model,
    data: &Measured,
) -> Result<Vec<Curves>, IdentifyError> {
    if initial.wheels.is_empty() {
        return Err(IdentifyError::of(
            IdentifyErrorKind::Report,
            "the report plots toe and camber of a wheel, and the model has none (declare a `wheel`)",
            vec![],
        ));
    }
    // A report error names every wheel: none of them can be plotted.
    let all_wheels = || {
        (0..initial.wheels.len() as u32)
            .map(|w| ElementId::Wheel(WheelId(w)))
            .collect()
    };
    let names = initial
        .wheels
        .iter()
        .map(|w| format!("`{}`", w.name))
        .collect::<Vec<_>>()
        .join(" or ");
    let loads: Vec<Vec<(Vec3, Vec3)>> =
        initial.wheels.iter().map(|w| wheel_load(data, w)).collect();
    let loaded = |w: usize| {
        loads[w]
            .iter()
            .any(|(f, t)| f.amax() != 0.0 || t.amax() != 0.0)
    };
    if !(0..loads.len()).any(loaded) {
        return Err(IdentifyError::of(
            IdentifyErrorKind::Report,
            format!(
                "the report plots against the load on a wheel, and no step loads the contact marker of {names}"
            ),
            all_wheels(),
        ));
    }
    let measured: Vec<Vec<Option<WheelQuantities>>> = initial
        .wheels
        .iter()
        .map(|w| {
            (0..data.steps.len())
                .map(|k| measured_row(initial, data, k, w))
                .collect()
        })
        .collect();
    let plotted = |w: usize| loaded(w) && measured[w].iter().any(Option::is_some);
    if !(0..loads.len()).any(plotted) {
        return Err(IdentifyError::of(
            IdentifyErrorKind::Report,
            format!(
                "the report needs the measured toe and camber of a loaded wheel: give --kc, or landmarks on the part of {names}"
            ),
            all_wheels(),
        ));
    }
    let init = simulate(initial, data, "initial")?;
    let ident = simulate(identified, data, "identified")?;
    let step = |k: usize| data.steps[k].step;
    let one = initial.wheels.len() == 1;
    let mut out = Vec::new();
    for (wi, w) in initial
        .wheels
        .iter()
        .enumerate()
        .filter(|(wi, _)| plotted(*wi))
    {
        let loads = &loads[wi];
        let q = |model: &Model, states: &[State], k: usize| {
            wheel_quantities(model, &states[k], &model.wheels[wi])
        };
        for (c, idx) in groups(loads) {
            let name = DIRECTIONS[c];
            out.push(Curves {
                wheel: w.name.clone(),
                component: c,
                name,
                file: if one {
                    format!("toe_camber_{name}")
                } else {
                    format!("toe_camber_{}_{name}", w.name.replace('.', "_"))
                },
                measured: idx
                    .iter()
                    .filter_map(|&k| measured[wi][k].map(|m| row(step(k), w, loads[k], m)))
                    .collect(),
                initial: idx
                    .iter()
                    .map(|&k| row(step(k), w, loads[k], q(initial, &init, k)))
                    .collect(),
                identified: idx
                    .iter()
                    .map(|&k| row(step(k), w, loads[k], q(identified, &ident, k)))
                    .collect(),
            });
        }
    }
    Ok(out)
}

/// The SVG of one direction's curves.
pub fn svg(c: &Curves, model: &str, method: Method) -> Result<String, String> {
    let title = format!(
        "{model}: toe and camber of {} under {} load, measured vs {} identification",
        c.wheel,
        c.name,
        method.name()
    );
    crate::output::plot::overlay_svg(
        &title,
        &c.measured,
        &c.initial,
        &c.identified,
        crate::output::plot::Sweep::Force(c.component),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn f(x: f64, y: f64, z: f64) -> (Vec3, Vec3) {
        (Vec3::new(x, y, z), Vec3::zeros())
    }

    /// Table 5-1's pattern: a vertical sweep, then lateral and longitudinal
    /// sweeps at 4500 N, each through the 4500 N vertical step.
    #[test]
    fn table_5_1_splits_into_three_sweeps() {
        let mut l: Vec<(Vec3, Vec3)> = [1500.0, 3000.0, 4500.0, 6000.0, 7500.0]
            .map(|z| f(0.0, 0.0, z))
            .to_vec();
        l.extend([-4000.0, -2000.0, 2000.0, 4000.0].map(|y| f(0.0, y, 4500.0)));
        l.extend([4000.0, 2000.0, -2000.0, -4000.0].map(|x| f(x, 0.0, 4500.0)));
        let g = groups(&l);
        assert_eq!(
            g,
            vec![
                (0, vec![12, 11, 2, 10, 9]),
                (1, vec![5, 6, 2, 7, 8]),
                (2, vec![0, 1, 2, 3, 4]),
            ]
        );
    }

    /// Combined loads sweep no direction alone: all steps, along the component
    /// with the largest spread.
    #[test]
    fn combined_loads_fall_back_to_the_widest_component() {
        let l = vec![
            f(100.0, 900.0, 3000.0),
            f(-100.0, -900.0, 3100.0),
            f(50.0, 10.0, 3050.0),
        ];
        assert_eq!(groups(&l), vec![(1, vec![1, 2, 0])]);
    }
}
