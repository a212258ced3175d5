//! Ride-height trim: the value of one model parameter (a spring's free length
//! or preload, a stiffness, a declared parameter) for which a marker returns to
//! its design height under a load case. Secant steps, kept inside a bracket
//! once the sign of the height error changes (then bisection when a secant step
//! would leave it), so a badly scaled first guess cannot run away.

use crate::model::address::Address;
use crate::model::{MarkerId, Model, PointLoad};
use crate::statics::path::solve_case;
use crate::statics::{Problem, State};
use crate::statics::{StaticsError, StaticsErrorKind};

/// Height error below which the trim has converged, mm.
pub const TOLERANCE_MM: f64 = 1e-8;
const MAX_EVALUATIONS: usize = 60;

/// A converged trim.
#[derive(Debug, Clone, PartialEq)]
pub struct Trimmed {
    /// The parameter's value, internal units.
    pub value: f64,
    /// Its value before trimming.
    pub initial: f64,
    /// The marker's design height (the target) and its height at `value`, mm.
    pub target_z: f64,
    pub z: f64,
    /// Equilibria solved.
    pub evaluations: usize,
}

/// The marker's global z at the equilibrium under `loads` with the parameter at `value`.
fn height(
    model: &Model,
    address: Address,
    value: f64,
    loads: &[PointLoad],
    marker: MarkerId,
) -> Result<f64, StaticsError> {
    let mut m = model.clone();
    address.set(&mut m, value);
    let problem = Problem::new(&m)?;
    let eq = solve_case(&problem, loads, &State::design(&m))?;
    let mk = m.marker(marker);
    let (x, r) = eq.state.part_pose(mk.part);
    Ok((x + r * mk.origin()).z)
}

fn failure(
    model: &Model,
    address: Address,
    detail: String,
    cause: Option<&StaticsError>,
) -> StaticsError {
    let mut elements = vec![address.element()];
    if let Some(c) = cause {
        elements.extend(
            c.elements
                .iter()
                .copied()
                .filter(|e| *e != address.element()),
        );
    }
    let kind = cause.map_or(StaticsErrorKind::NotConverged, |c| c.kind);
    let name = address.name(model);
    StaticsError::new(kind, elements, format!("trimming `{name}`: {detail}"))
}

/// Finds the value of `address` that brings `marker` back to its design z under `loads`.
pub fn trim(
    model: &Model,
    address: Address,
    loads: &[PointLoad],
    marker: MarkerId,
) -> Result<Trimmed, StaticsError> {
    if marker.index() >= model.markers.len() {
        return Err(StaticsError::new(
            StaticsErrorKind::BadInput,
            vec![],
            "the trim marker is not in the model",
        ));
    }
    let target = model.marker(marker).origin().z;
    let p0 = address.get(model);
    if !p0.is_finite() {
        return Err(failure(
            model,
            address,
            "the parameter has no single numeric value".into(),
            None,
        ));
    }
    let count = std::cell::Cell::new(0usize);
    let eval = |p: f64| -> Result<f64, StaticsError> {
        count.set(count.get() + 1);
        height(model, address, p, loads, marker).map(|z| z - target)
    };
    let g0 = eval(p0).map_err(|e| {
        failure(
            model,
            address,
            format!("the untrimmed model does not solve: {}", e.detail),
            Some(&e),
        )
    })?;
    let (mut a, mut ga) = (p0, g0);
    // A first step of 0.1 % of the value (or 1e-3 of a unit) gives the slope.
    let mut b = p0 + 1e-3 * p0.abs().max(1.0);
    let mut gb = f64::NAN;
    let mut bracket: Option<((f64, f64), (f64, f64))> = None;
    let mut last_good = (a, ga);
    while count.get() < MAX_EVALUATIONS {
        if ga.abs() < TOLERANCE_MM {
            return Ok(Trimmed {
                value: a,
                initial: p0,
                target_z: target,
                z: target + ga,
                evaluations: count.get(),
            });
        }
        match eval(b) {
            Ok(g) => gb = g,
            Err(e) => {
                // Too far: back off towards the last value that solved.
                if (b - last_good.0).abs() < 1e-12 * (1.0 + b.abs()) {
                    return Err(failure(
                        model,
                        address,
                        format!("no equilibrium near `{b}`: {}", e.detail),
                        Some(&e),
                    ));
                }
                b = 0.5 * (b + last_good.0);
                continue;
            }
        }
        last_good = (b, gb);
        if gb.abs() < TOLERANCE_MM {
            return Ok(Trimmed {
                value: b,
                initial: p0,
                target_z: target,
                z: target + gb,
                evaluations: count.get(),
            });
        }
        if ga.signum() != gb.signum() {
            bracket = Some(((a, ga), (b, gb)));
        } else if let Some(((lo, glo), (hi, ghi))) = bracket {
            // Keep the bracket around the root: replace the end with b's sign.
            bracket = Some(if glo.signum() == gb.signum() {
                ((b, gb), (hi, ghi))
            } else {
                ((lo, glo), (b, gb))
            });
        }
        if gb == ga {
            return Err(failure(model, address, "the marker's height does not change with this parameter, so it cannot trim the ride height".into(), None));
        }
        let mut next = b - gb * (b - a) / (gb - ga);
        if let Some(((lo, _), (hi, _))) = bracket {
            let (l, h) = (lo.min(hi), lo.max(hi));
            if !(next > l && next < h) {
                next = 0.5 * (l + h);
            }
        }
        if !next.is_finite() {
            break;
        }
        (a, ga) = (b, gb);
        b = next;
    }
    Err(failure(
        model,
        address,
        format!(
            "no value within {MAX_EVALUATIONS} equilibria brings the marker to its design height (last height error {gb:.3e} mm)"
        ),
        None,
    ))
}
