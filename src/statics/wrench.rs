//! A wrench between two parts and its generalised force and tangent.
//!
//! Every element of the statics backend (joint primitives as unit reactions,
//! bushings, springs, stops, point loads) reduces to one shape: a force `g` on
//! part I applied at arm `r_i` from I's origin, the opposite force on part J at
//! arm `rho` from J's origin, a torque `m` on I and `-m` on J (a part's
//! origin here is the point its coordinates refer to,
//! [`super::coords::Layout::reference`]). With the local
//! coordinate order `[dx_I, theta_I, dx_J, theta_J]` (12), the generalised force
//! is `[g; r_i × g + m; -g; -(rho × g) - m]`. Its derivative follows from the
//! derivatives of `g, m, r_i, rho` (3×12 each), which each element supplies.

use crate::geom::{Mat3, Vec3, skew, skew_times};
use nalgebra::{DMatrix, DVector, SMatrix, SVector};

pub type M3x12 = SMatrix<f64, 3, 12>;
pub type V12 = SVector<f64, 12>;
pub type M12 = SMatrix<f64, 12, 12>;

/// A 3×12 matrix from four 3×3 blocks `[dx_I, theta_I, dx_J, theta_J]`.
pub fn blocks(b: [Mat3; 4]) -> M3x12 {
    let mut m = M3x12::zeros();
    for (k, blk) in b.iter().enumerate() {
        m.fixed_view_mut::<3, 3>(0, 3 * k).copy_from(blk);
    }
    m
}

/// The derivative of a point fixed to I at arm `r`: `[I, -r~, 0, 0]`.
pub fn d_point_i(r: &Vec3) -> M3x12 {
    blocks([Mat3::identity(), -skew(r), Mat3::zeros(), Mat3::zeros()])
}

/// The derivative of a point fixed to J at arm `r`: `[0, 0, I, -r~]`.
pub fn d_point_j(r: &Vec3) -> M3x12 {
    blocks([Mat3::zeros(), Mat3::zeros(), Mat3::identity(), -skew(r)])
}

/// The derivative of an axis `a` fixed to J: `[0, 0, 0, -a~]` (da = theta_J × a).
pub fn d_axis_j(a: &Vec3) -> M3x12 {
    blocks([Mat3::zeros(), Mat3::zeros(), Mat3::zeros(), -skew(a)])
}

/// A 3×12 derivative `[dx_I, theta_I, dx_J, theta_J]` as its four 3×3
/// blocks, each present or identically zero. Most of an element's blocks
/// are zero by its kind (a joint's unit reaction has at most two, a point
/// load none), so neither its storage nor the tangent's assembly touches
/// them. (An absent block's storage is stale, not zero: read blocks with
/// [`Blocks::get`] or [`Blocks::matrix`].)
#[derive(Debug, Clone, Copy)]
pub struct Blocks {
    b: [Mat3; 4],
    present: [bool; 4],
}

impl Default for Blocks {
    fn default() -> Blocks {
        Blocks {
            b: [Mat3::zeros(); 4],
            present: [false; 4],
        }
    }
}

impl Blocks {
    /// The blocks given, the others zero.
    pub fn new(b: [Option<Mat3>; 4]) -> Blocks {
        let mut out = Blocks::default();
        for (k, blk) in b.into_iter().enumerate() {
            if let Some(m) = blk {
                out.b[k] = m;
                out.present[k] = true;
            }
        }
        out
    }

    /// Sets block `k` (columns `3k..3k + 3`).
    pub fn set(&mut self, k: usize, m: Mat3) {
        self.b[k] = m;
        self.present[k] = true;
    }

    /// The blocks of a 3×12 matrix, those with a non-zero entry present.
    pub fn of_matrix(m: &M3x12) -> Blocks {
        Blocks::new(std::array::from_fn(|k| nonzero_block(m, 3 * k)))
    }

    /// The 3×12 matrix.
    pub fn matrix(&self) -> M3x12 {
        let mut m = M3x12::zeros();
        for k in 0..4 {
            if self.present[k] {
                m.fixed_view_mut::<3, 3>(0, 3 * k).copy_from(&self.b[k]);
            }
        }
        m
    }

    /// Block `k` (columns `3k..3k + 3`), unless all its entries are zero.
    pub fn get(&self, k: usize) -> Option<&Mat3> {
        (self.present[k] && self.b[k].iter().any(|v| *v != 0.0)).then_some(&self.b[k])
    }

    /// `self *= s`.
    pub fn scale(&mut self, s: f64) {
        for k in 0..4 {
            if self.present[k] {
                self.b[k] *= s;
            }
        }
    }

    /// `self += o * s`.
    pub fn add_scaled(&mut self, o: &Blocks, s: f64) {
        for k in 0..4 {
            if o.present[k] {
                if !self.present[k] {
                    self.b[k] = Mat3::zeros();
                    self.present[k] = true;
                }
                self.b[k] += o.b[k] * s;
            }
        }
    }
}

/// How the arm `rho` of the force on J moves with the increments.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RhoMotion {
    /// A point of J: `[0, 0, 0, -rho~]`.
    TurnsWithJ,
    /// The point of I at the arm `r_i`, seen from J's origin:
    /// `[I, -r_i~, -I, 0]` (a force acting at `p_I` on both parts).
    PointOfI,
}

#[derive(Debug, Clone)]
pub struct Wrench {
    /// Coordinate blocks of parts I and J (None: ground).
    pub i: Option<usize>,
    pub j: Option<usize>,
    /// Force on I (global); J receives `-g`.
    pub g: Vec3,
    /// Torque on I (global); J receives `-m`.
    pub m: Vec3,
    /// Arm of the force on I from I's origin (a point of I, turning with
    /// it: its derivative is `[0, -r_i~, 0, 0]`), and of the force on J
    /// from J's origin.
    pub r_i: Vec3,
    pub rho: Vec3,
    pub dg: Blocks,
    pub dm: Blocks,
    pub rho_motion: RhoMotion,
}

/// The 3×3 block of `m` at columns `c..c + 3`, unless all its entries are zero.
fn nonzero_block(m: &M3x12, c: usize) -> Option<Mat3> {
    let b: Mat3 = m.fixed_view::<3, 3>(0, c).into_owned();
    b.iter().any(|v| *v != 0.0).then_some(b)
}

/// `-r~`, unless `r` is zero (the derivative block of an arm `r` turning
/// with its part).
fn turning(r: &Vec3) -> Option<Mat3> {
    (*r != Vec3::zeros()).then(|| -skew(r))
}

/// The generalised force on `[I; J]` of the force `g` and torque `m` on I
/// at the arms `r_i` (I's) and `rho` (J's): [`Wrench::generalized`], for a
/// caller that holds them in registers (a wrench's arms read back just
/// after they were stored wait on the stores, see
/// [`super::constraint::evaluate_into`]).
#[inline(always)]
pub(super) fn generalized(g: &Vec3, m: &Vec3, r_i: &Vec3, rho: &Vec3) -> V12 {
    let mut q = V12::zeros();
    q.fixed_rows_mut::<3>(0).copy_from(g);
    q.fixed_rows_mut::<3>(3).copy_from(&(r_i.cross(g) + m));
    q.fixed_rows_mut::<3>(6).copy_from(&(-g));
    q.fixed_rows_mut::<3>(9).copy_from(&(-rho.cross(g) - m));
    q
}

impl Wrench {
    /// A wrench with zero derivatives, to be filled by the element.
    pub fn new(i: Option<usize>, j: Option<usize>, r_i: Vec3, rho: Vec3) -> Wrench {
        Wrench {
            i,
            j,
            g: Vec3::zeros(),
            m: Vec3::zeros(),
            r_i,
            rho,
            dg: Blocks::default(),
            dm: Blocks::default(),
            rho_motion: RhoMotion::TurnsWithJ,
        }
    }

    /// Makes this wrench [`Wrench::new`]'s, in place (the assembly refills
    /// one per joint equation rather than moving a new one).
    pub fn reset(&mut self, i: Option<usize>, j: Option<usize>, r_i: Vec3, rho: Vec3) {
        self.i = i;
        self.j = j;
        self.g = Vec3::zeros();
        self.m = Vec3::zeros();
        self.r_i = r_i;
        self.rho = rho;
        self.dg.present = [false; 4];
        self.dm.present = [false; 4];
        self.rho_motion = RhoMotion::TurnsWithJ;
    }

    /// Block `k` of the derivative of the arm `r_i`, unless zero.
    fn dr_i_block(&self, k: usize) -> Option<Mat3> {
        if k == 1 { turning(&self.r_i) } else { None }
    }

    /// Block `k` of the derivative of the arm `rho`, unless zero.
    fn drho_block(&self, k: usize) -> Option<Mat3> {
        match (self.rho_motion, k) {
            (RhoMotion::TurnsWithJ, 3) => turning(&self.rho),
            (RhoMotion::PointOfI, 0) => Some(Mat3::identity()),
            (RhoMotion::PointOfI, 1) => turning(&self.r_i),
            (RhoMotion::PointOfI, 2) => Some(-Mat3::identity()),
            _ => None,
        }
    }

    /// The derivatives of the two arms as 3×12 matrices.
    fn arm_derivatives(&self) -> (M3x12, M3x12) {
        let full = |f: &dyn Fn(usize) -> Option<Mat3>| {
            let mut m = M3x12::zeros();
            for k in 0..4 {
                if let Some(b) = f(k) {
                    m.fixed_view_mut::<3, 3>(0, 3 * k).copy_from(&b);
                }
            }
            m
        };
        (full(&|k| self.dr_i_block(k)), full(&|k| self.drho_block(k)))
    }

    /// Its size as a force: the force plus the torque over `length` (N),
    /// what the force scales of [`super::assembly::Workspace`] compare.
    pub fn size(&self, length: f64) -> f64 {
        self.g.norm() + self.m.norm() / length
    }

    /// The generalised force on `[I; J]`.
    pub fn generalized(&self) -> V12 {
        generalized(&self.g, &self.m, &self.r_i, &self.rho)
    }

    /// The derivative of [`Self::generalized`] with respect to the 12 local increments.
    pub fn tangent(&self) -> M12 {
        let gs = skew(&self.g);
        let (dg, dm) = (self.dg.matrix(), self.dm.matrix());
        let (dr_i, drho) = self.arm_derivatives();
        let rows = [
            dg,
            -gs * dr_i + skew(&self.r_i) * dg + dm,
            -dg,
            gs * drho - skew(&self.rho) * dg - dm,
        ];
        let mut k = M12::zeros();
        for (b, r) in rows.iter().enumerate() {
            k.fixed_view_mut::<3, 12>(3 * b, 0).copy_from(r);
        }
        k
    }

    /// Multiplies the forces, torques and their derivatives by `s` (a
    /// multiplier λ); the arms stay.
    pub fn scale_loads(&mut self, s: f64) {
        self.g *= s;
        self.m *= s;
        self.dg.scale(s);
        self.dm.scale(s);
    }

    /// Adds `s` times `w`'s forces, torques and their derivatives; the arms
    /// stay, so the sum's generalised force and tangent are the sums of the
    /// two wrenches' only when `w` has the same parts and arms.
    pub fn add_loads(&mut self, w: &Wrench, s: f64) {
        debug_assert!(
            self.i == w.i
                && self.j == w.j
                && self.r_i == w.r_i
                && self.rho == w.rho
                && self.rho_motion == w.rho_motion
        );
        self.g += w.g * s;
        self.m += w.m * s;
        self.dg.add_scaled(&w.dg, s);
        self.dm.add_scaled(&w.dm, s);
    }

    /// Global coordinate offset of each 6-block of the local order.
    pub(crate) fn offsets(&self) -> [Option<usize>; 2] {
        [self.i.map(|b| 6 * b), self.j.map(|b| 6 * b)]
    }

    /// Calls `f(global index, value)` for each entry of the generalised force.
    pub fn each_force(&self, mut f: impl FnMut(usize, f64)) {
        let loc = self.generalized();
        for (s, off) in self.offsets().iter().enumerate() {
            if let Some(o) = off {
                for a in 0..6 {
                    f(o + a, loc[6 * s + a]);
                }
            }
        }
    }

    /// Calls `f(local, first row, first column, block)` for each 3×3 block
    /// of the tangent that couples two moving parts and is not identically
    /// zero; `local` is the block's place in the 12×12 local tangent,
    /// `4 * row block + column block`, each block `2 * side + half` (side
    /// I or J, half translations or rotations): where a caller that has
    /// the wrench's blocks' slots at hand finds them
    /// ([`super::pattern::WrenchSlots`]).
    ///
    /// The same entries as [`Self::tangent`], computed only for the columns of
    /// moving parts, and only from the 3×3 blocks of `dg`, `dm` and the arms'
    /// derivatives that are not zero: a joint's unit reaction has constant
    /// `g` (no `dg`) and arms that turn with one part each, so most of its
    /// 6×6 blocks are empty. The Newton matrix is assembled from dozens of
    /// wrenches per evaluation. A skipped block contributes exact zeros, and
    /// the terms present are combined in the order of [`Self::tangent`], its
    /// products with skew matrices as cross products ([`skew_times`]), so
    /// every entry is the same to the bit but for the sign of a zero.
    pub fn each_tangent(&self, mut f: impl FnMut(usize, usize, usize, &Mat3)) {
        let offs = self.offsets();
        let minus_g = -self.g;
        for (sc, co) in offs.iter().enumerate() {
            let Some(co) = *co else { continue };
            for half in 0..2 {
                let k = 2 * sc + half;
                let dg = self.dg.get(k);
                let dm = self.dm.get(k);
                let col = co + 3 * half;
                // Rows of I: [dg; -g~ dr_i + r_i~ dg + dm]; of J: [-dg; g~ drho - rho~ dg - dm].
                if let Some(ro) = offs[0] {
                    if let Some(dg) = dg {
                        f(k, ro, col, dg);
                    }
                    let dr = self.dr_i_block(k);
                    if dr.is_some() || dg.is_some() || dm.is_some() {
                        let mut b = Mat3::zeros();
                        if let Some(dr) = &dr {
                            b = skew_times(&minus_g, dr);
                        }
                        if let Some(dg) = dg {
                            b += skew_times(&self.r_i, dg);
                        }
                        if let Some(dm) = dm {
                            b += dm;
                        }
                        f(4 + k, ro + 3, col, &b);
                    }
                }
                if let Some(ro) = offs[1] {
                    if let Some(dg) = dg {
                        f(8 + k, ro, col, &(-dg));
                    }
                    let dr = self.drho_block(k);
                    if dr.is_some() || dg.is_some() || dm.is_some() {
                        let mut b = Mat3::zeros();
                        if let Some(dr) = &dr {
                            b = skew_times(&self.g, dr);
                        }
                        if let Some(dg) = dg {
                            b -= skew_times(&self.rho, dg);
                        }
                        if let Some(dm) = dm {
                            b -= dm;
                        }
                        f(12 + k, ro + 3, col, &b);
                    }
                }
            }
        }
    }

    /// Adds the generalised force into a global vector.
    pub fn add_force(&self, q: &mut DVector<f64>) {
        let loc = self.generalized();
        for (s, off) in self.offsets().iter().enumerate() {
            if let Some(o) = off {
                for a in 0..6 {
                    q[o + a] += loc[6 * s + a];
                }
            }
        }
    }

    /// Adds the tangent into a global matrix.
    pub fn add_tangent(&self, k: &mut DMatrix<f64>) {
        let loc = self.tangent();
        let offs = self.offsets();
        for (sr, ro) in offs.iter().enumerate() {
            let Some(ro) = ro else { continue };
            for (sc, co) in offs.iter().enumerate() {
                let Some(co) = co else { continue };
                for a in 0..6 {
                    for b in 0..6 {
                        k[(ro + a, co + b)] += loc[(6 * sr + a, 6 * sc + b)];
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::ops::AddAssign;

    /// The block-restricted scatter gives exactly the entries of the full
    /// 12×12 tangent (itself checked against finite differences in `forces`),
    /// for a wrench between two parts and for one on ground at either end.
    #[test]
    fn scattered_tangent_equals_the_full_tangent() {
        let mut s = 7u64;
        let mut rnd = || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        for (i, j, motion) in [
            (Some(0), Some(2), RhoMotion::PointOfI),
            (Some(0), Some(2), RhoMotion::TurnsWithJ),
            (Some(1), None, RhoMotion::TurnsWithJ),
            (None, Some(0), RhoMotion::PointOfI),
        ] {
            let mut w = Wrench::new(
                i,
                j,
                Vec3::new(rnd(), rnd(), rnd()),
                Vec3::new(rnd(), rnd(), rnd()),
            );
            w.g = Vec3::new(rnd(), rnd(), rnd());
            w.m = Vec3::new(rnd(), rnd(), rnd());
            w.dg = Blocks::of_matrix(&M3x12::from_fn(|_, _| rnd()));
            // Some blocks absent, as in a joint's unit reaction.
            w.dm = Blocks::new([None, Some(Mat3::from_fn(|_, _| rnd())), None, None]);
            w.rho_motion = motion;
            let full = w.tangent();
            let mut got = DMatrix::zeros(18, 18);
            w.each_tangent(|k, r, c, b| {
                // The local index names the block's place in `[I; J]`.
                let place = |b: usize, o: [Option<usize>; 2]| o[b / 2].map(|o| o + 3 * (b % 2));
                assert_eq!(place(k / 4, w.offsets()), Some(r));
                assert_eq!(place(k % 4, w.offsets()), Some(c));
                got.view_mut((r, c), (3, 3)).add_assign(b);
            });
            let mut want = DMatrix::zeros(18, 18);
            w.add_tangent(&mut want);
            // Bit for bit (`==`, a zero of either sign): skipped blocks are zeros.
            assert_eq!(got, want);
            assert!(full.amax() > 0.0);
        }
    }
}
