//! A model compiled for the statics backend ([`Problem`]): what every solve
//! of the model shares, made once.

use super::constraint::{self, Equation};
use super::coords::{Layout, State};
use super::error::{StaticsError, StaticsErrorKind};
use super::redundancy::{RedundantEquation, independence, scaled_jacobian};
use super::{pattern, tangent};
use crate::geom::Vec3;
use crate::model::Model;

/// A model compiled for the statics backend: coordinate layout, constraint
/// equations, the independent subset, and the characteristic length.
#[derive(Debug, Clone)]
pub struct Problem {
    pub(crate) model: Model,
    pub(crate) layout: Layout,
    pub(crate) equations: Vec<Equation>,
    /// Indices (into `equations`) of the independent equations the solver uses.
    pub(crate) kept: Vec<usize>,
    /// Equations implied by earlier ones at design; left out, checked after solving.
    pub redundant: Vec<RedundantEquation>,
    /// Largest distance of a marker from the markers' centroid (mm, at least 1):
    /// the radius that makes rotations comparable with translations.
    pub length: f64,
    /// The Newton matrix's sparsity pattern, for a model large enough for
    /// the sparse path ([`tangent::SPARSE_FROM`]).
    pub(crate) pattern: Option<std::sync::Arc<pattern::Pattern>>,
}

/// A model's constraint equations, which of them are independent at design,
/// its layout and characteristic length: a [`Problem`] without its copy of
/// the model and its sparsity pattern, which the mobility analysis
/// ([`super::mobility::analyse`]) does not need. The checker analyses every
/// model a command checks, and the language server's on every save: the
/// copy and the pattern's ordering were a third of that analysis.
pub(crate) struct Equations {
    pub layout: Layout,
    pub equations: Vec<Equation>,
    pub kept: Vec<usize>,
    pub redundant: Vec<RedundantEquation>,
    pub length: f64,
}

impl Equations {
    /// Compiled without requiring a ground (the mobility analysis reports
    /// the floating motions).
    pub fn of(model: &Model) -> Equations {
        let layout = Layout::centred(model);
        let equations = constraint::equations(model);
        let pts: Vec<Vec3> = model.markers.iter().map(|m| m.origin()).collect();
        let c = if pts.is_empty() {
            Vec3::zeros()
        } else {
            pts.iter().sum::<Vec3>() / pts.len() as f64
        };
        let length = pts.iter().map(|p| (p - c).norm()).fold(1.0, f64::max);
        let all: Vec<usize> = (0..equations.len()).collect();
        let design = State::design(model);
        let sj = scaled_jacobian(model, &layout, &design, &equations, &all, length);
        let ind = independence(&equations, &sj.jac);
        Equations {
            layout,
            equations,
            kept: ind.kept,
            redundant: ind.redundant,
            length,
        }
    }
}

impl Problem {
    pub fn new(model: &Model) -> Result<Problem, StaticsError> {
        if model.ground().is_none() {
            return Err(StaticsError::new(
                StaticsErrorKind::NoGround,
                vec![],
                "the model has no ground part, so nothing holds it in place",
            ));
        }
        let Equations {
            layout,
            equations,
            kept,
            redundant,
            length,
        } = Equations::of(model);
        let mut p = Problem {
            model: model.clone(),
            layout,
            equations,
            kept,
            redundant,
            length,
            pattern: None,
        };
        if p.layout.n() + p.kept.len() >= tangent::SPARSE_FROM {
            p.pattern = pattern::Pattern::new(&p).map(std::sync::Arc::new);
        }
        Ok(p)
    }

    pub fn model(&self) -> &Model {
        &self.model
    }
}
