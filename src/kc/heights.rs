//! Wheel-centre heights of every case of a load set, for an Adams/Car loadcase
//! file in `wheel_center_height` mode: axle solves the set in order (each case
//! from the previous equilibrium, as `axle solve` does) and the rig then drives
//! the wheel centres to those heights instead of applying the vertical forces.

use crate::emit::EmitError;
use crate::model::{LoadSetId, Model};
use crate::statics::path::run_set;
use crate::statics::{Problem, State};

/// Per case, per wheel (model order): the wheel-centre z at equilibrium, mm.
pub fn centre_heights(m: &Model, set: LoadSetId) -> Result<Vec<Vec<f64>>, EmitError> {
    let ls = m.load_sets.get(set.index()).ok_or(EmitError::NoLoadSet)?;
    let failed = |case: &str, e: String| EmitError::NotSolved {
        set: ls.name.clone(),
        case: case.to_string(),
        detail: e,
    };
    let problem = Problem::new(m).map_err(|e| failed("(model)", e.message(m)))?;
    let run = run_set(&problem, set, &State::design(m));
    if let Some(e) = &run.failure {
        let case = ls.cases.get(e.case).map_or("?", |c| c.name.as_str());
        return Err(failed(case, e.error.message(m)));
    }
    Ok(run
        .steps
        .iter()
        .map(|eq| {
            m.wheels
                .iter()
                .map(|w| {
                    let c = m.marker(w.centre);
                    let (x, r) = eq.state.part_pose(c.part);
                    (x + r * c.origin()).z
                })
                .collect()
        })
        .collect())
}
