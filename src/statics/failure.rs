//! The errors of a solve that found no equilibrium, naming what is
//! responsible: the part with the largest residual and the element
//! contributing most to it, a nearly unrestrained motion, a friction at its
//! limit (`brief`: every numeric failure names the model element).

use super::coords::State;
use super::error::{StaticsError, StaticsErrorKind};
use super::system::{assemble, errors, kkt, softest_motion};
use super::{Problem, forces, friction};
use crate::model::{ElementId, PointLoad};

/// The error of a path that used up its budget of load sub-steps: the model
/// is near a limit of its equilibria there (a caller exploring parameters
/// takes that as "too far", not as a result).
pub(super) fn over_budget() -> StaticsError {
    StaticsError::new(
        StaticsErrorKind::NotConverged,
        vec![],
        "the load path needed more load sub-steps than its budget: the model is close to a limit of its equilibria here",
    )
}

/// The error for a load step that would not converge: the part with the largest
/// residual and the element contributing most to it.
pub(super) fn not_converged(
    p: &Problem,
    st: &State,
    loads: &[PointLoad],
    force: f64,
) -> StaticsError {
    let detail = "Newton did not converge even with the smallest load sub-step".to_string();
    let Ok(sys) = assemble(p, st, loads) else {
        return StaticsError::new(StaticsErrorKind::NotConverged, vec![], detail);
    };
    let (ef, ec) = errors(p, &sys, force);
    let mut elements = Vec::new();
    // A nearly singular Newton matrix is the usual cause: name its motion first.
    if let Some((ratio, motion)) = softest_motion(p, &kkt(&sys)) {
        if ratio < 1e-6 {
            return StaticsError::new(
                StaticsErrorKind::NotConverged,
                std::iter::once(ElementId::Part(motion.part))
                    .chain(
                        friction::near_limit(&p.model, &p.layout, st)
                            .into_iter()
                            .map(ElementId::Friction),
                    )
                    .collect(),
                format!(
                    "{detail}: the {} is nearly unrestrained (stiffness ratio {ratio:.1e}) (residual {ef:.2e} of the force scale, {ec:.2e} of the length)",
                    motion.words
                ),
            );
        }
    }
    if ec * force > ef * p.length && !sys.phi.is_empty() {
        let k = sys.phi.iamax();
        elements.push(ElementId::Joint(p.equations[p.kept[k]].joint));
    } else {
        let c = sys.r.iamax();
        let part = p.layout.moving[c / 6];
        elements.push(ElementId::Part(part));
        let mut best = (0.0, None);
        if let Ok(ws) = forces::element_wrenches(&p.model, &p.layout, st) {
            for (id, w) in ws {
                let mut g = nalgebra::DVector::zeros(p.layout.n());
                w.add_force(&mut g);
                if g[c].abs() > best.0 {
                    best = (g[c].abs(), Some(id));
                }
            }
        }
        if let (_, Some(id)) = best {
            elements.push(id);
        }
    }
    // A friction at its limit switches between stick and slip from one
    // iteration to the next, the usual way a path with friction fails: name it.
    let slipping = friction::near_limit(&p.model, &p.layout, st);
    elements.extend(slipping.iter().map(|&f| ElementId::Friction(f)));
    StaticsError::new(
        StaticsErrorKind::NotConverged,
        elements,
        format!(
            "{detail} (residual {:.2e} of the force scale, {:.2e} of the length)",
            ef, ec
        ),
    )
}
