//! Sensitivities of equilibria to model parameters, as a statics service:
//! `d(q, λ)/dp` at each converged case of a path by implicit differentiation
//! of the equilibrium `R(q, λ, p) = 0`:
//!
//! `[K, Φ_qᵀ; Φ_q, 0] d(q, λ)/dp = -∂R/∂p`,
//!
//! solved with the factorisation the case's Newton run ended with (refined
//! against the equilibrium's own matrix, which differs from it by at most the
//! last Newton step), so no matrix is factorised again. `∂R/∂p` is a central
//! difference at the fixed converged state (`h = 1e-5·max(|p|, 1)` in
//! internal units; exact up to rounding for the parameters the forces are
//! affine in: stiffnesses, rates, free lengths, preloads), never of a whole
//! solve: of the one element's force when the parameter belongs to one
//! bushing or spring, else of the whole residual (forces and constraints).
//!
//! Path-dependent elements (friction) make case `k` depend on the history
//! committed at case `k - 1`, which depends on `p` too; the per-case implicit
//! derivative misses that term. For a model with such elements
//! [`path_by_differences`] gives the documented alternative: central
//! differences of whole path solves, with the force parameters changed in
//! place in the compiled problem.
//!
//! A parameter is anything that sets a value in a [`Model`] ([`Parameter`]):
//! today's [`Address`], identification's unknowns, and the general addresses
//! of the schema work.

use super::assembly::{Workspace, col_scale};
use super::coords::State;
use super::newton::Solver;
use super::{Problem, StaticsError, StaticsErrorKind, forces};
use crate::geom::{Mat3, Vec3, skew};
use crate::model::address::Address;
use crate::model::schema::FieldId;
use crate::model::{ElementId, Model, Orientation, PartId, PointLoad};
use nalgebra::{DMatrix, DVector, Matrix3xX};

/// A value of a model that a caller can read and set (internal units).
pub trait Parameter {
    fn value(&self, model: &Model) -> f64;
    fn set_value(&self, model: &mut Model, value: f64);
    /// Whether it moves markers: then the constraint equations change with it
    /// and only a recompiled [`Problem`] holds the new geometry exactly.
    fn moves_geometry(&self, model: &Model) -> bool;
    /// The element it belongs to, for diagnostics.
    fn element(&self) -> ElementId;
    /// The one force element whose force alone it changes, when there is
    /// one (then `∂R/∂p` is that element's force difference, not the whole
    /// residual's).
    fn force_element(&self, _model: &Model) -> Option<ElementId> {
        None
    }
}

impl Parameter for Address {
    fn value(&self, model: &Model) -> f64 {
        self.get(model)
    }

    fn set_value(&self, model: &mut Model, value: f64) {
        self.set(model, value);
    }

    fn moves_geometry(&self, model: &Model) -> bool {
        match self.element {
            ElementId::Param(p) => model.markers.iter().any(|m| {
                m.position.iter().any(|v| v.param == Some(p))
                    || matches!(&m.orientation, Orientation::Euler(e) if e.iter().any(|v| v.param == Some(p)))
            }),
            // Landmarks are observations, not constraint geometry.
            ElementId::Landmark(_) => false,
            _ => self.field == FieldId::Position,
        }
    }

    fn element(&self) -> ElementId {
        Address::element(*self)
    }

    fn force_element(&self, model: &Model) -> Option<ElementId> {
        // A field bound to a declared parameter sets that parameter, and so
        // every element bound to it; a friction element's force depends on
        // its history, so the whole residual is differenced.
        let free = self.val(model).is_some_and(|v| v.param.is_none());
        match self.element {
            ElementId::Bushing(_) | ElementId::Spring(_) | ElementId::Stop(_)
                if free && self.field != FieldId::Position =>
            {
                Some(self.element)
            }
            _ => None,
        }
    }
}

impl Problem {
    /// Sets a parameter that changes force elements only, in place: the
    /// compiled constraint analysis (equations, independent subset) stays.
    /// A parameter that moves geometry is an error naming its element
    /// (compile a new [`Problem`] for it).
    pub fn set_force_parameter<P: Parameter + ?Sized>(
        &mut self,
        p: &P,
        value: f64,
    ) -> Result<(), StaticsError> {
        if p.moves_geometry(&self.model) {
            return Err(StaticsError::new(
                StaticsErrorKind::BadInput,
                vec![p.element()],
                "this parameter moves markers, so the constraint analysis must be compiled again",
            ));
        }
        p.set_value(&mut self.model, value);
        Ok(())
    }
}

/// The derivative of one converged case with respect to the parameters.
#[derive(Debug, Clone)]
pub struct CaseSensitivity {
    /// Coordinate increments per unit of each parameter (a column each):
    /// 6 rows per moving part, `dx` (mm) then `dθ` (rad, a global rotation
    /// vector, `R ← exp(dθ~) R`), per internal unit of the parameter.
    pub dq: DMatrix<f64>,
    block_of_part: Vec<Option<usize>>,
    /// Each part's reference point, whose displacement `dx` is
    /// ([`super::coords::Layout::reference`]).
    reference: Vec<Vec3>,
}

impl CaseSensitivity {
    /// Number of parameters.
    pub fn params(&self) -> usize {
        self.dq.ncols()
    }

    /// `(dx, dθ)` of `part` per unit of parameter `j` (zero for ground):
    /// the displacement of its reference point and its rotation.
    pub fn part(&self, part: PartId, j: usize) -> (Vec3, Vec3) {
        match self.block_of_part.get(part.index()).copied().flatten() {
            Some(b) => (
                Vec3::new(
                    self.dq[(6 * b, j)],
                    self.dq[(6 * b + 1, j)],
                    self.dq[(6 * b + 2, j)],
                ),
                Vec3::new(
                    self.dq[(6 * b + 3, j)],
                    self.dq[(6 * b + 4, j)],
                    self.dq[(6 * b + 5, j)],
                ),
            ),
            None => (Vec3::zeros(), Vec3::zeros()),
        }
    }

    /// d/dp of the global position of a point fixed at `local` (design
    /// coordinates) on `part`, at `state`: a column per parameter.
    pub fn point(&self, state: &State, part: PartId, local: &Vec3) -> Matrix3xX<f64> {
        let (_, r) = state.part_pose(part);
        let c = self
            .reference
            .get(part.index())
            .copied()
            .unwrap_or_default();
        let g: Mat3 = -skew(&(r * (local - c)));
        let mut out = Matrix3xX::zeros(self.params());
        for j in 0..self.params() {
            let (dx, dth) = self.part(part, j);
            out.set_column(j, &(dx + g * dth));
        }
        out
    }

    /// d/dp of a scalar output of the state (a wheel quantity, say): a
    /// central difference of `f` along each parameter's motion `dq`, of the
    /// output alone (no solve). Not finite where `f` is not.
    pub fn output(
        &self,
        problem: &Problem,
        state: &State,
        f: impl Fn(&State) -> f64,
    ) -> DVector<f64> {
        let n = self.dq.nrows();
        DVector::from_fn(self.params(), |j, _| {
            let col = self.dq.column(j);
            let amax = col.amax();
            if amax == 0.0 {
                return 0.0;
            }
            let h = 1e-6 / amax;
            let d = DVector::from_fn(n, |r, _| col[r] * h);
            let (mut sp, mut sm) = (state.clone(), state.clone());
            sp.apply(&problem.layout, &d);
            sm.apply(&problem.layout, &(-d));
            (f(&sp) - f(&sm)) / (2.0 * h)
        })
    }
}

/// The central-difference step of a parameter, internal units.
fn step_of(v: f64) -> f64 {
    1e-5 * v.abs().max(1.0)
}

/// The generalised force of one bushing or spring at `state`, scaled as the
/// residual; `None` for another kind of element.
fn element_force(
    p: &Problem,
    state: &State,
    e: ElementId,
) -> Result<Option<DVector<f64>>, StaticsError> {
    let mut q = DVector::zeros(p.layout.n());
    match e {
        ElementId::Bushing(b) => {
            forces::bushing(&p.model, &p.layout, state, &p.model.bushings[b.index()])
                .wrench
                .add_force(&mut q);
        }
        ElementId::Spring(sp) => {
            forces::spring(&p.model, &p.layout, state, sp, &p.model.springs[sp.index()])?
                .2
                .add_force(&mut q);
        }
        _ => return Ok(None),
    }
    for (i, v) in q.iter_mut().enumerate() {
        *v *= col_scale(i, p.length);
    }
    Ok(Some(q))
}

/// `-∂R/∂p` (scaled as the Newton matrix) per parameter at `state`, by
/// central differences at the fixed state on `work` (a copy of the problem,
/// restored afterwards): of the one element a parameter changes when it
/// changes one ([`Parameter::force_element`]), else of the whole residual.
/// `values[j]` is parameter `j`'s value.
fn rhs<P: Parameter>(
    work: &mut Problem,
    ws: &mut Workspace,
    state: &State,
    loads: &[PointLoad],
    params: &[P],
    values: &[f64],
) -> Result<DMatrix<f64>, StaticsError> {
    let (n, m) = (work.layout.n(), work.kept.len());
    let mut b = DMatrix::zeros(n + m, params.len());
    for (j, (p, &v)) in params.iter().zip(values).enumerate() {
        let h = step_of(v);
        let element = p.force_element(&work.model);
        let mut at = |x: f64| -> Result<Vec<f64>, StaticsError> {
            p.set_value(&mut work.model, x);
            if let Some(e) = element
                && let Some(q) = element_force(work, state, e)?
            {
                return Ok(q
                    .iter()
                    .copied()
                    .chain(std::iter::repeat_n(0.0, m))
                    .collect());
            }
            ws.eval(work, state, loads, false)?;
            Ok(ws.r.iter().chain(&ws.phi).copied().collect())
        };
        let plus = at(v + h);
        let minus = at(v - h);
        p.set_value(&mut work.model, v);
        let (plus, minus) = (plus?, minus?);
        for r in 0..n + m {
            b[(r, j)] = -(plus[r] - minus[r]) / (2.0 * h);
        }
    }
    Ok(b)
}

/// `x` solving `lu x = b` column by column; false if the solve fails.
fn lu_solve(sv: &mut Solver, x: &mut DMatrix<f64>) -> bool {
    for mut col in x.column_iter_mut() {
        if !sv.lu.solve(col.as_mut_slice()) {
            return false;
        }
    }
    true
}

/// Solves the Newton system at the equilibrium for every column of `b` with
/// the factorisation at hand (`sv.lu`, of the last Newton iterate's matrix,
/// which differs from the equilibrium's by the last step), refined once
/// against the equilibrium's own matrix `sv.ws.a`; factorises that matrix
/// when the refined residual is not at rounding level.
fn solve_refined(sv: &mut Solver, b: &DMatrix<f64>) -> Option<DMatrix<f64>> {
    let nn = b.nrows();
    let a = sv.ws.matrix();
    let mut x = b.clone();
    if !lu_solve(sv, &mut x) {
        return None;
    }
    let mut r = b - &a * &x;
    if !lu_solve(sv, &mut r) {
        return None;
    }
    x += r;
    let res = (b - &a * &x).amax();
    // Rounding level of the product `A x` itself.
    if res <= 1e-13 * (b.amax() + a.amax() * x.amax()) * nn as f64 {
        return Some(x);
    }
    if !sv.factor_matrix() {
        return None;
    }
    let mut x = b.clone();
    lu_solve(sv, &mut x).then_some(x)
}

/// The sensitivity of the case `sv` just converged to (`state` under
/// `loads`), `sv.ws` holding the equilibrium's matrix; `work` is a copy of
/// the problem the parameters are varied on.
pub(crate) fn at_equilibrium<P: Parameter>(
    problem: &Problem,
    work: &mut Problem,
    ws: &mut Workspace,
    sv: &mut Solver,
    state: &State,
    loads: &[PointLoad],
    params: &[P],
    values: &[f64],
) -> Result<CaseSensitivity, StaticsError> {
    let n = problem.layout.n();
    let b = rhs(work, ws, state, loads, params, values)?;
    let x = solve_refined(sv, &b).ok_or_else(|| {
        StaticsError::new(
            StaticsErrorKind::Unrestrained,
            vec![],
            "the equilibrium is singular, so its sensitivity to the parameters is undefined",
        )
    })?;
    let dq = DMatrix::from_fn(n, params.len(), |r, c| {
        x[(r, c)] * col_scale(r, problem.length)
    });
    Ok(CaseSensitivity {
        dq,
        block_of_part: problem.layout.block_of_part.clone(),
        reference: problem.layout.reference.clone(),
    })
}

/// The sensitivities along a path by central differences of whole path
/// solves (for models with path-dependent elements): `h = 1e-5·max(|p|, 1)`;
/// force parameters are changed in place in copies of `problem`, geometric
/// ones in recompiled problems. `None` per case where a perturbed path fails.
pub fn path_by_differences<P: Parameter, L: AsRef<[PointLoad]>>(
    problem: &Problem,
    cases: &[L],
    start: &State,
    params: &[P],
) -> Result<Vec<CaseSensitivity>, StaticsError> {
    let n = problem.layout.n();
    let mut dq = vec![DMatrix::zeros(n, params.len()); cases.len()];
    for (j, p) in params.iter().enumerate() {
        let v = p.value(&problem.model);
        let h = step_of(v);
        let run = |x: f64| -> Result<Vec<State>, StaticsError> {
            let pr = if p.moves_geometry(&problem.model) {
                let mut m = problem.model.clone();
                p.set_value(&mut m, x);
                Problem::new(&m)?
            } else {
                let mut pr = problem.clone();
                pr.set_force_parameter(p, x)?;
                pr
            };
            let run = super::path::simulate(&pr, cases, start).into_result();
            Ok(run
                .map_err(|e| e.error)?
                .into_iter()
                .map(|e| e.state)
                .collect())
        };
        let (plus, minus) = (run(v + h)?, run(v - h)?);
        for (k, (sp, sm)) in plus.iter().zip(&minus).enumerate() {
            for (b, part) in problem.layout.moving.iter().enumerate() {
                let ((xp, rp), (xm, rm)) = (sp.part_pose(*part), sm.part_pose(*part));
                let dx = (xp - xm) / (2.0 * h);
                let rot = nalgebra::Rotation3::from_matrix_unchecked(rp * rm.transpose());
                let dth = rot.scaled_axis() / (2.0 * h);
                for c in 0..3 {
                    dq[k][(6 * b + c, j)] = dx[c];
                    dq[k][(6 * b + 3 + c, j)] = dth[c];
                }
            }
        }
    }
    Ok(dq
        .into_iter()
        .map(|dq| CaseSensitivity {
            dq,
            block_of_part: problem.layout.block_of_part.clone(),
            reference: problem.layout.reference.clone(),
        })
        .collect())
}
