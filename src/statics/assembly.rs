//! The scaled residual and Newton matrix of the equilibrium equations at one
//! state: every element's, load's and constraint's wrench evaluated and
//! scattered into buffers kept from one evaluation to the next (see
//! [`super::newton`] for the scaling and the loop that uses them).

use super::Problem;
use super::condition::largest_or_infinite;
use super::constraint::{evaluate_into, is_length};
use super::coords::{MarkerKin, State, marker_kin};
use super::error::StaticsError;
use super::forces::{for_each_element, point_load_into};
use super::newton::Homotopy;
use super::pattern::WrenchSlots;
use super::tangent::NewtonMatrix;
use super::wrench::Wrench;
use crate::geom::Vec3;
use crate::model::{JointId, PointLoad, Primitive};
use nalgebra::DMatrix;
/// `diag(1, 1, 1, 1/L, 1/L, 1/L, ...)`: the scaling of coordinates and rows.
pub(crate) fn col_scale(c: usize, length: f64) -> f64 {
    if c % 6 >= 3 { 1.0 / length } else { 1.0 }
}

/// The scaled residual and Newton matrix at one state, in buffers reused from
/// one evaluation to the next.
pub(crate) struct Workspace {
    /// Scaled residual `S (Q + Phi_q^T λ)` (n).
    pub r: Vec<f64>,
    /// Kept constraint values divided by their row scale (m, mm).
    pub phi: Vec<f64>,
    pub row_scale: Vec<f64>,
    /// Force and torque of each kept equation's unit reaction (its wrench's
    /// `g` and `m`, unscaled): times λ, the joint reactions at the state.
    pub unit_reaction: Vec<(Vec3, Vec3)>,
    /// `[S K S, J^T; J, 0]`, filled when the tangent is asked for: dense, or
    /// in the problem's sparsity pattern for a large model.
    pub a: NewtonMatrix,
    /// Largest element force (force plus moment over the length) at the state, N.
    pub element_scale: f64,
    /// Largest applied load (force plus moment over the length) evaluated, N.
    pub load_scale: f64,
    /// The coordinate scaling `col_scale` of each coordinate.
    pub(crate) scale: Vec<f64>,
    /// The two wrenches an evaluation writes in place (see `scatter`),
    /// kept from one evaluation to the next.
    wrenches: Box<[Wrench; 2]>,
    /// Each kept equation's row before it is scaled (see `scatter`).
    rows: Vec<Row>,
    /// The slots of each wrench's blocks in the sparse storage, in the
    /// order an evaluation writes them ([`Tangents`]).
    slots: Vec<WrenchSlots>,
}

/// A kept equation's value, its gradient (rotation columns times the
/// length, the six entries of each part of its wrench's `offsets`) and the
/// gradient's squared norm: what `scatter` takes from the loop over the
/// equations to the loop that scales them.
#[derive(Debug, Clone, Copy, Default)]
struct Row {
    v: f64,
    sq: f64,
    grad: [f64; 12],
    /// The offsets, [`NO_PART`] for none. (Copied as options, a pair of
    /// 16-byte loads read the narrower stores that had just written them,
    /// which stalls: 13 % of an evaluation's own time.)
    offsets: [usize; 2],
}

/// A [`Row`]'s offset where its wrench has no part (the ground).
const NO_PART: usize = usize::MAX;

impl Workspace {
    /// Buffers with the Newton matrix in the storage chosen for `p`'s size.
    pub fn new(p: &Problem) -> Workspace {
        let (n, m) = (p.layout.n(), p.kept.len());
        Workspace::with_matrix(p, NewtonMatrix::new(n + m, p.pattern.as_ref()))
    }

    /// Buffers with a dense Newton matrix.
    #[cfg(test)]
    pub fn dense(p: &Problem) -> Workspace {
        let (n, m) = (p.layout.n(), p.kept.len());
        Workspace::with_matrix(p, NewtonMatrix::dense(n + m))
    }

    /// Buffers with the Newton matrix in the slots of `pattern` (which may
    /// lack entries of `p`'s matrix: the fallback's test).
    #[cfg(test)]
    pub fn with_pattern(
        p: &Problem,
        pattern: &std::sync::Arc<super::pattern::Pattern>,
    ) -> Workspace {
        let (n, m) = (p.layout.n(), p.kept.len());
        Workspace::with_matrix(p, NewtonMatrix::new(n + m, Some(pattern)))
    }

    /// Buffers around the matrix `a` (made once: a dense matrix of the car's
    /// 348 unknowns, made and dropped, was 3 % of a case from a new solver).
    fn with_matrix(p: &Problem, a: NewtonMatrix) -> Workspace {
        let (n, m) = (p.layout.n(), p.kept.len());
        Workspace {
            r: vec![0.0; n],
            phi: vec![0.0; m],
            row_scale: vec![1.0; m],
            unit_reaction: vec![(Vec3::zeros(), Vec3::zeros()); m],
            a,
            element_scale: 0.0,
            load_scale: 0.0,
            scale: (0..n).map(|c| col_scale(c, p.length)).collect(),
            wrenches: Box::new(std::array::from_fn(|_| {
                Wrench::new(None, None, Vec3::zeros(), Vec3::zeros())
            })),
            rows: vec![Row::default(); m],
            slots: Vec::new(),
        }
    }

    /// Evaluates the residual at `st` under `loads`, and the Newton matrix when
    /// `tangent` is set (otherwise `a` is left as it was).
    pub fn eval(
        &mut self,
        p: &Problem,
        st: &State,
        loads: &[PointLoad],
        tangent: bool,
    ) -> Result<(), StaticsError> {
        if self.scatter(p, st, loads, tangent)? {
            return Ok(());
        }
        // An entry outside the pattern (not expected: the pattern is
        // structural): the dense storage holds any entry.
        self.a = NewtonMatrix::dense(self.a.dim());
        self.scatter(p, st, loads, tangent).map(|_| ())
    }

    /// [`Self::eval`] in the current storage; false if a derivative fell
    /// outside the sparsity pattern (the matrix is then incomplete).
    fn scatter(
        &mut self,
        p: &Problem,
        st: &State,
        loads: &[PointLoad],
        tangent: bool,
    ) -> Result<bool, StaticsError> {
        let n = p.layout.n();
        let l = p.length;
        let Workspace {
            r,
            phi,
            row_scale,
            unit_reaction,
            a,
            element_scale,
            load_scale,
            scale,
            wrenches,
            rows,
            slots,
        } = self;
        let scale: &[f64] = scale;
        r.iter_mut().for_each(|v| *v = 0.0);
        if tangent {
            a.clear();
        }
        let mut elem = 0.0f64;
        // (The wrenches come whole: a joint's unit reactions are summed times
        // their multipliers before, see `group` below.)
        let mut tangents = Tangents {
            a,
            scale,
            slots,
            next: 0,
            inside: true,
        };
        fn add(w: &Wrench, r: &mut [f64], tangents: &mut Tangents, tangent: bool) {
            let scale = tangents.scale;
            w.each_force(|i, v| r[i] += v * scale[i]);
            if tangent {
                tangents.add(w);
            }
        }
        for_each_element(&p.model, &p.layout, st, |_, w| {
            elem = elem.max(w.size(l));
            add(w, r, &mut tangents, tangent);
        })?;
        *element_scale = elem;
        // Two wrenches written in place (each whole: `Wrench::reset`), not
        // returned and copied, nor made afresh (700 bytes each). The loads'
        // wrenches come in the first. For the constraints they swap roles:
        // one receives each equation's unit reaction, the other holds its
        // group's sum. A group starts from its first equation's wrench where
        // it lies (scaled by λ), and the previous sum's buffer receives the
        // next equation.
        let [w0, w1] = &mut **wrenches;
        *load_scale = 0.0;
        for ld in loads {
            let w = &mut *w0;
            if point_load_into(&p.model, &p.layout, st, ld, w) {
                *load_scale = load_scale.max(w.size(l));
                add(w, r, &mut tangents, tangent);
            }
        }
        // A joint's equations are consecutive and share its marker frames
        // (computed once a joint, each written where it lies, and borrowed,
        // not copied, by each equation).
        let frame = |m| marker_kin(&p.model, &p.layout, st, m);
        let mut frames: Option<(JointId, MarkerKin, MarkerKin)> = p.kept.first().map(|&e| {
            let joint = p.equations[e].joint;
            let j = &p.model.joints[joint.index()];
            (joint, frame(j.i), frame(j.j))
        });
        let (mut w, mut sum) = (w0, w1);
        // The λ-weighted sum of the unit reactions of consecutive equations
        // of one joint whose wrenches share their arms (see `Arms`), whose
        // tangent is the sum of theirs: the tangent is linear in the forces
        // and their derivatives once the arms are fixed. One tangent a group
        // instead of one an equation (a revolute joint's five equations
        // scatter 4 blocks instead of 14).
        let mut group: Option<(JointId, Arms)> = None;
        for (idx, &e) in p.kept.iter().enumerate() {
            let lam = st.lambda.get(idx).copied().unwrap_or(0.0);
            let eq = &p.equations[e];
            // (Set before the loop from its first equation.)
            let Some(f) = frames.as_mut() else { break };
            if f.0 != eq.joint {
                let j = &p.model.joints[eq.joint.index()];
                f.0 = eq.joint;
                f.1 = frame(j.i);
                f.2 = frame(j.j);
            }
            let (_, mi, mj) = &*f;
            let (v, force) = evaluate_into(mi, mj, eq.primitive, w);
            // The gradient row with rotation columns times the length, as in
            // `redundancy::scaled_jacobian`, and the generalised force it
            // scales (computed once for both uses), part by part: the six
            // entries of I's part, then J's (none for the ground). A part's
            // entries are found by one look-up, not by dividing each
            // entry's coordinate by six.
            let force = force.as_slice();
            let offsets = w.offsets();
            let row = &mut rows[idx];
            row.v = v;
            row.offsets = offsets.map(|o| o.unwrap_or(NO_PART));
            let mut sq = 0.0f64;
            // (A part's six entries by slices: one bounds check a part.)
            for (side, o) in offsets.iter().enumerate() {
                let Some(o) = *o else { continue };
                let (g6, f6) = (
                    &mut row.grad[6 * side..6 * side + 6],
                    &force[6 * side..6 * side + 6],
                );
                for ((g, f), s) in g6.iter_mut().zip(f6).zip(&scale[o..o + 6]) {
                    *g = f * s;
                    sq += *g * *g;
                }
                // `add` of the unit reaction times λ, from the force above.
                for ((x, f), s) in r[o..o + 6].iter_mut().zip(f6).zip(&scale[o..o + 6]) {
                    *x += lam * f * s;
                }
            }
            row.sq = sq;
            unit_reaction[idx] = (w.g, w.m);
            if tangent {
                let key = (eq.joint, Arms::of(eq.primitive));
                if group == Some(key) {
                    sum.add_loads(w, lam);
                } else {
                    if group.is_some() {
                        tangents.add(sum);
                    }
                    w.scale_loads(lam);
                    std::mem::swap(&mut w, &mut sum);
                    group = Some(key);
                }
            }
        }
        if group.is_some() {
            tangents.add(sum);
        }
        let Tangents { a, mut inside, .. } = tangents;
        // Each row scaled by its gradient's norm, once every row is known:
        // a row's square root and division wait on the sum of its squares,
        // and taken in the loop above they held up the equations after
        // them; here the rows' chains overlap (`docs/performance.md`).
        for (idx, (row, &e)) in rows.iter().zip(&p.kept).enumerate() {
            let norm = row.sq.sqrt();
            let s = if norm > 0.0 {
                norm
            } else if is_length(p.equations[e].primitive) {
                1.0
            } else {
                1.0 / l
            };
            row_scale[idx] = s;
            // One division a row (its entries are multiplied by the
            // reciprocal: a dozen divisions a row cost more than the row's
            // other arithmetic).
            let inv = 1.0 / s;
            phi[idx] = row.v * inv;
            if !tangent {
                continue;
            }
            for (side, &o) in row.offsets.iter().enumerate() {
                if o == NO_PART {
                    continue;
                }
                let g = &row.grad[6 * side..6 * side + 6];
                match a {
                    NewtonMatrix::Dense(a) => {
                        for (c, g) in g.iter().enumerate() {
                            a[(n + idx, o + c)] += g * inv;
                            a[(o + c, n + idx)] += g * inv;
                        }
                    }
                    NewtonMatrix::Sparse(pat, vals) => match pat.constraint_block(idx, o / 6) {
                        Some(b) => b.add(vals, g, inv),
                        None => inside = false,
                    },
                }
            }
        }
        Ok(inside)
    }

    /// The residual of the state last evaluated (under `old`, with no
    /// homotopy) under the loads `new` instead: the loads' generalised
    /// forces exchanged, the element forces and constraints kept. A load
    /// has no part in the constraints or the element scale, so this is the
    /// evaluation's residual without evaluating a single element (to the
    /// rounding of the exchanged sums). The matrix is left as it was: it
    /// carries the old loads' stiffness, which Newton re-evaluates if it
    /// needs the matrix. `st` is the state evaluated.
    pub(crate) fn exchange_loads(
        &mut self,
        p: &Problem,
        st: &State,
        old: &[PointLoad],
        new: &[PointLoad],
    ) {
        let l = p.length;
        let (r, scale) = (&mut self.r, &self.scale);
        let w = &mut self.wrenches[0];
        for ld in old {
            if point_load_into(&p.model, &p.layout, st, ld, w) {
                w.each_force(|i, v| r[i] -= v * scale[i]);
            }
        }
        let mut big = 0.0f64;
        for ld in new {
            if point_load_into(&p.model, &p.layout, st, ld, w) {
                big = big.max(w.size(l));
                w.each_force(|i, v| r[i] += v * scale[i]);
            }
        }
        self.load_scale = big;
    }

    /// Applies the homotopy of a sub-step to the residual.
    pub(crate) fn release(&mut self, h: &Homotopy) {
        if h.remaining > 0.0 && h.r0.len() == self.r.len() && h.phi0.len() == self.phi.len() {
            for (v, v0) in self.r.iter_mut().zip(&h.r0) {
                *v -= v0 * h.remaining;
            }
            for (v, v0) in self.phi.iter_mut().zip(&h.phi0) {
                *v -= v0 * h.remaining;
            }
        }
    }

    /// The force scale convergence is judged against: the largest force in
    /// the balance at the state evaluated (element forces and applied loads,
    /// at least 1 N). Not the scale of the start: a previous case's huge load
    /// (or its element forces) must not make the next case's residual look
    /// negligible, so a stale pose is never accepted as converged.
    pub fn force_scale(&self) -> f64 {
        let f = self.element_scale.max(self.load_scale);
        // `max` drops a NaN: an undefined force makes the scale infinite.
        if f.is_nan() {
            f64::INFINITY
        } else {
            f.max(1.0)
        }
    }

    /// Scaled residual norms: force (of [`Workspace::force_scale`]) and
    /// constraint (of the length). A residual or scale that is not finite
    /// (a force overflowing) is an infinite error, never a converged one.
    pub fn errors(&self, p: &Problem) -> (f64, f64) {
        let force = self.force_scale();
        let (r, phi) = (largest_or_infinite(&self.r), largest_or_infinite(&self.phi));
        if !force.is_finite() || !r.is_finite() || !phi.is_finite() {
            return (f64::INFINITY, f64::INFINITY);
        }
        (r / force, phi / p.length)
    }

    pub(crate) fn merit(&self, p: &Problem, force: f64) -> f64 {
        let sq = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>();
        sq(&self.r) / (force * force) + sq(&self.phi) / (p.length * p.length)
    }

    /// The Newton matrix as a nalgebra matrix (for the SVD of error paths).
    pub fn matrix(&self) -> DMatrix<f64> {
        self.a.to_dense()
    }
}

/// The tangents of an evaluation's wrenches added into the Newton matrix
/// `a`, scaled by `scale`; `inside` false once a block fell outside the
/// sparsity pattern. An evaluation writes its wrenches in the same order
/// every time (the elements, the loads, the joints' groups of equations),
/// each between the same parts: the `next`-th wrench's blocks' slots are
/// found once and kept in `slots`, checked against its parts. The slots
/// depend on the parts alone, so the check is all correctness needs:
/// where the order shifts (a case with another number of loads, a load
/// on another part), a kept entry for other parts is found again.
struct Tangents<'a> {
    a: &'a mut NewtonMatrix,
    scale: &'a [f64],
    slots: &'a mut Vec<WrenchSlots>,
    next: usize,
    inside: bool,
}

impl Tangents<'_> {
    /// Adds `w`'s tangent. A 3×3 block's rows are three translations or
    /// three rotations of one part, and so are its columns: one scale for
    /// its rows, one for its columns, each entry `v * si * sj` as before
    /// they were hoisted.
    fn add(&mut self, w: &Wrench) {
        let scale = self.scale;
        match &mut *self.a {
            // Column by column: one bounds check per column of a block.
            NewtonMatrix::Dense(a) => w.each_tangent(|_, ro, co, blk| {
                let (si, sj) = (scale[ro], scale[co]);
                for b in 0..3 {
                    let col = &mut a.col_as_slice_mut(co + b)[ro..ro + 3];
                    for (x, v) in col.iter_mut().zip(blk.column(b).iter()) {
                        *x += v * si * sj;
                    }
                }
            }),
            // The same products and sums into the pattern's slots: rows
            // `ro..ro + 3` are one half of a part's rows, contiguous there.
            // (The values as a slice: through the vector, every store
            // made its pointer and length be read again.)
            NewtonMatrix::Sparse(pat, vals) => {
                let offsets = w.offsets();
                let k = self.next;
                self.next += 1;
                // (`k` is at most the wrenches kept: each call keeps one.)
                match self.slots.get_mut(k) {
                    Some(s) if s.are_for(offsets) => {}
                    Some(s) => *s = pat.wrench_slots(offsets),
                    None => self.slots.push(pat.wrench_slots(offsets)),
                }
                let (slots, vals) = (&self.slots[k], vals.as_mut_slice());
                let inside = &mut self.inside;
                w.each_tangent(|local, ro, co, blk| {
                    let Some(at) = slots.block(local) else {
                        *inside = false;
                        return;
                    };
                    let (si, sj) = (scale[ro], scale[co]);
                    for (b, &at) in at.iter().enumerate() {
                        for (x, v) in vals[at..at + 3].iter_mut().zip(blk.column(b).iter()) {
                            *x += v * si * sj;
                        }
                    }
                })
            }
        }
    }
}

/// Which arms a joint primitive's unit reaction acts at
/// ([`super::constraint::evaluate_into`]): coincidence and perpendicularity
/// at the two markers' points, each turning with its part; in-plane at
/// `p_I` on both parts. Equations of one joint with the same arms have
/// wrenches that differ only in their forces, torques and derivatives.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Arms {
    Markers,
    PointOfI,
}

impl Arms {
    fn of(p: Primitive) -> Arms {
        match p {
            Primitive::Coincident(_) | Primitive::Perpendicular(..) => Arms::Markers,
            Primitive::InPlane(_) => Arms::PointOfI,
        }
    }
}
