//! Force elements (bushings, springs, stops) and wheels.

use super::id::{JointId, MarkerId, PartId};
use super::law::{AxisLaw, AxisLaws, Table};
use super::param::{Val, Val3};

/// An ADAMS-style bushing (`conventions.md`, "Bushing"). I on the inner sleeve's
/// part, J on the outer sleeve's part; J's axes are the stiffness axes.
#[derive(Debug, Clone, PartialEq)]
pub struct Bushing {
    pub name: String,
    pub i: MarkerId,
    pub j: MarkerId,
    /// Translational laws along x_J, y_J, z_J: force (N) of deformation (mm).
    pub translational: AxisLaws,
    /// Rotational laws about x_J, y_J, z_J: torque (N·mm) of projected angle (rad).
    pub rotational: AxisLaws,
    /// Deformation offset `t0`, mm, J axes.
    pub offset: Val3,
    /// Angular offset `a0`, rad, projected angles.
    pub angle_offset: Val3,
    /// Force preload `F0` on I, N, J axes.
    pub preload: Val3,
    /// Torque preload `T0` on I, N·mm, J axes.
    pub torque_preload: Val3,
}

/// How a spring's force depends on its length.
#[derive(Debug, Clone, PartialEq)]
pub enum SpringLaw {
    /// Push-apart force `k (L0 - l) + F0` (N), with `k` in N/mm, `L0` in mm.
    Linear {
        k: Val,
        free_length: Val,
        preload: Val,
    },
    /// Push-apart force (N) as a table of length (mm), monotone decreasing.
    Table(Table),
}

/// A translational spring between two marker origins (`conventions.md`, "Spring").
#[derive(Debug, Clone, PartialEq)]
pub struct Spring {
    pub name: String,
    pub i: MarkerId,
    pub j: MarkerId,
    pub law: SpringLaw,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StopKind {
    /// Acts when `l < contact_length`, pushing I and J apart.
    Compression,
    /// Acts when `l > contact_length`, pulling I and J together.
    Rebound,
}

/// A one-sided spring along the I–J separation (bump or rebound stop).
#[derive(Debug, Clone, PartialEq)]
pub struct Stop {
    pub name: String,
    pub kind: StopKind,
    pub i: MarkerId,
    pub j: MarkerId,
    /// Length at first contact, mm.
    pub contact_length: Val,
    /// Force magnitude (N) of penetration (mm, positive into the stop).
    pub law: StopLaw,
}

#[derive(Debug, Clone, PartialEq)]
pub enum StopLaw {
    /// `f(p) = c1 p + c2 p² + …`, coefficients in N/mm, N/mm², ….
    Polynomial(Vec<Val>),
    /// `f(p)` as a monotone table starting at penetration 0 with force 0 or more.
    Table(Table),
}

impl StopLaw {
    /// `(f(p), f'(p))` for a penetration `p >= 0`.
    pub fn eval(&self, p: f64) -> (f64, f64) {
        match self {
            StopLaw::Polynomial(c) => {
                let mut f = 0.0;
                let mut df = 0.0;
                for (n, ci) in c.iter().enumerate() {
                    let e = (n + 1) as i32;
                    f += ci.value * p.powi(e);
                    df += e as f64 * ci.value * p.powi(e - 1);
                }
                (f, df)
            }
            StopLaw::Table(t) => t.eval(p),
        }
    }
}

/// What a friction element's slider follows on its joint.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FrictionMotion {
    /// The slide `s = (p_I - p_J) · z_J` of a cylindrical or translational
    /// joint: `stiffness` in N/mm, `limit` in N.
    Slide,
    /// The relative rotation of a revolute, cylindrical or spherical joint
    /// about z_J: `stiffness` in N·mm/rad, `limit` in N·mm.
    Rotation,
}

/// Dry friction on a joint (`conventions.md`, "Friction"): an elasto-plastic
/// slider, a stiffness in series with a Coulomb limit, acting between the
/// joint's I and J markers. Path-dependent: its slip offset is state carried
/// along a load path, committed after every converged step.
#[derive(Debug, Clone, PartialEq)]
pub struct Friction {
    pub name: String,
    pub joint: JointId,
    pub motion: FrictionMotion,
    /// Stick stiffness `kf` (N/mm for a slide, N·mm/rad for a rotation).
    pub stiffness: Val,
    /// Slip limit `Ff` (N for a slide, N·mm for a rotation), not negative.
    pub limit: Val,
}

/// A wheel: a centre marker whose z axis is the outboard spin axis, and a
/// contact marker where wheel loads act (`conventions.md`, "Wheel").
#[derive(Debug, Clone, PartialEq)]
pub struct Wheel {
    pub name: String,
    pub part: PartId,
    pub centre: MarkerId,
    pub contact: MarkerId,
}

impl Bushing {
    /// A linear bushing with the given diagonal stiffnesses (N/mm and N·mm/rad).
    pub fn linear(name: &str, i: MarkerId, j: MarkerId, k: [f64; 3], kt: [f64; 3]) -> Bushing {
        Bushing {
            name: name.to_string(),
            i,
            j,
            translational: AxisLaws::General(k.map(AxisLaw::linear)),
            rotational: AxisLaws::General(kt.map(AxisLaw::linear)),
            offset: [Val::ZERO; 3],
            angle_offset: [Val::ZERO; 3],
            preload: [Val::ZERO; 3],
            torque_preload: [Val::ZERO; 3],
        }
    }
}
