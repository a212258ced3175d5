//! Model + load set → Adams/Solver command file (`.acf`): the dataset file, the
//! output prefix, equilibrium settings, then per load case the VARIABLE values
//! of the loads and one static equilibrium. Cases run in order, each from the
//! previous equilibrium, as `axle solve` does.

use super::error::EmitError;
use super::plan::Plan;
use super::writer::num;
use crate::model::{LoadSetId, Model};

/// `adm_file`: the dataset name written on line 1; `prefix`: the output prefix.
pub fn emit_acf(
    m: &Model,
    set: LoadSetId,
    adm_file: &str,
    prefix: &str,
) -> Result<String, EmitError> {
    let plan = Plan::new(m)?;
    let mut o = String::new();
    o.push_str(adm_file);
    o.push('\n');
    o.push_str(prefix);
    o.push('\n');
    // Tolerances: ERROR on the state change, IMBALANCE on forces (N); TLIMIT (mm)
    // and ALIMIT cap each Newton step, which keeps stops and tables stable.
    o.push_str(&format!(
        "EQUILIBRIUM/MAXIT=100, ERROR={}, IMBALANCE={}, TLIMIT={}, ALIMIT={}D\n",
        num(1.0e-6),
        num(1.0e-4),
        num(5.0),
        num(5.0)
    ));
    let Some(ls) = m.load_sets.get(set.index()) else {
        return Err(EmitError::NoLoadSet);
    };
    for case in 0..ls.cases.len() {
        for (v, val) in plan.variable_values(m, set, case) {
            if !val.is_finite() {
                return Err(EmitError::NotFinite {
                    element: format!("load case `{}`", ls.cases[case].name),
                    what: "a load".into(),
                });
            }
            o.push_str(&format!("VARIABLE/{v}, FUNCTION={}\n", num(val)));
        }
        o.push_str("SIMULATE/STATICS\n");
    }
    o.push_str("STOP\n");
    Ok(o)
}
