//! Generalised coordinates: 6 per moving part, a position and a rotation.
//!
//! A part's pose is stored as its origin `x` and rotation matrix `R` (both global;
//! at design `x = 0`, `R = I`, since every part frame is the global frame there).
//! Newton works on increments `(dx, theta)` with `x ← x + dx` and
//! `R ← exp(theta~) R` (a global rotation vector, Rodrigues' formula), so every
//! Jacobian is taken at zero increment and no parameterisation is singular.

use crate::geom::{Mat3, Vec3, skew, skew_times};
use crate::model::{FrictionId, MarkerId, Model, PartId, PointLoad};
use nalgebra::DVector;

/// Which coordinate block (6 coordinates) each part owns; ground owns none.
#[derive(Debug, Clone)]
pub struct Layout {
    pub block_of_part: Vec<Option<usize>>,
    pub moving: Vec<PartId>,
    /// Per part, the point of the part (global at design) its coordinates
    /// refer to: a twist is that point's displacement and a rotation, a
    /// generalised force the force and the moment about it. The frame
    /// origin (zero: [`Layout::new`]) for the users of marker kinematics
    /// outside the Newton solve; the centroid of the part's connection
    /// markers in a [`super::Problem`] ([`Layout::centred`],
    /// [`reference_points`]), so that the solve does not depend on where the
    /// global origin is. About the origin, a part 2.7 m
    /// away (a rear corner of a car whose origin is under the front axle)
    /// has moments that are the reactions times 2.7 m and a translation
    /// coupled to every rotation: Newton's convergence test, step limit and
    /// scaling then judge that part by its distance from the origin, and
    /// the McPherson corner moved 2.7 m back took 6 % more Newton steps and
    /// 20 % more factorisations along the random load path (one thesis
    /// case 17 steps instead of 6), the car a factorisation more a case.
    pub reference: Vec<Vec3>,
}

impl Layout {
    /// [`Layout::new`] with each moving part's coordinates and generalised
    /// forces referred to its own [`reference_points`].
    pub fn centred(model: &Model) -> Layout {
        Layout {
            reference: reference_points(model),
            ..Layout::new(model)
        }
    }

    pub fn new(model: &Model) -> Layout {
        let moving: Vec<PartId> = model.moving_parts().collect();
        let mut block_of_part = vec![None; model.parts.len()];
        for (b, p) in moving.iter().enumerate() {
            block_of_part[p.index()] = Some(b);
        }
        Layout {
            block_of_part,
            moving,
            reference: vec![Vec3::zeros(); model.parts.len()],
        }
    }

    /// Number of coordinates.
    pub fn n(&self) -> usize {
        6 * self.moving.len()
    }
}

/// A configuration of the model: the pose of every part, the loads it was
/// last brought into equilibrium with (the start of the next load sub-step),
/// and the history of path-dependent elements (friction slip offsets),
/// committed after every converged step by [`super::friction::commit`].
#[derive(Debug, PartialEq, Default)]
pub struct State {
    /// Origin and rotation of each part frame (indexed like `Model::parts`), global.
    pub(crate) poses: Vec<(Vec3, Mat3)>,
    /// Loads this state is in equilibrium with (empty at design).
    pub(crate) loads: Vec<PointLoad>,
    /// Multipliers of the independent constraint equations (warm start of the next step).
    pub(crate) lambda: Vec<f64>,
    /// Slip offset `s_p` of each friction element (indexed like
    /// `Model::frictions`; mm for a slide, rad for a rotation): the history a
    /// trial state is evaluated against, changed only when a step is accepted.
    pub(crate) slip: Vec<f64>,
}

impl Clone for State {
    fn clone(&self) -> State {
        State {
            poses: self.poses.clone(),
            loads: self.loads.clone(),
            lambda: self.lambda.clone(),
            slip: self.slip.clone(),
        }
    }

    /// Field by field, into this state's allocations (the solver's trial
    /// states and the path's last end are copied once a line-search trial
    /// or a case, not made anew).
    fn clone_from(&mut self, from: &State) {
        copy_into(&mut self.poses, &from.poses);
        copy_into(&mut self.loads, &from.loads);
        copy_into(&mut self.lambda, &from.lambda);
        copy_into(&mut self.slip, &from.slip);
    }
}

/// `to = from` in `to`'s allocation: one copy of the bytes where the
/// lengths agree (`Vec::clone_from` copied a pose at a time, through the
/// stack: 1.7 % of a McPherson case).
fn copy_into<T: Copy>(to: &mut Vec<T>, from: &[T]) {
    if to.len() == from.len() {
        to.copy_from_slice(from);
    } else {
        to.clear();
        to.extend_from_slice(from);
    }
}

impl State {
    /// The design configuration: every part frame equal to the global frame.
    pub fn design(model: &Model) -> State {
        State {
            poses: vec![(Vec3::zeros(), Mat3::identity()); model.parts.len()],
            loads: Vec::new(),
            lambda: Vec::new(),
            slip: super::friction::design_slip(model),
        }
    }

    /// The committed slip offset of a friction element (mm or rad); the design
    /// value when the state does not carry it.
    pub fn slip_offset(&self, model: &Model, f: FrictionId) -> f64 {
        match self.slip.get(f.index()) {
            Some(&s) => s,
            None => super::friction::design_slip(model)
                .get(f.index())
                .copied()
                .unwrap_or(0.0),
        }
    }

    /// The part frame's origin and rotation (columns: its axes), global.
    /// An unknown part id gives the design pose.
    pub fn part_pose(&self, p: PartId) -> (Vec3, Mat3) {
        self.poses
            .get(p.index())
            .copied()
            .unwrap_or((Vec3::zeros(), Mat3::identity()))
    }

    /// This state's element history with the configuration (poses,
    /// multipliers and the loads they balanced) of `guess`: the start of a
    /// case warm-started from another solution of it, whose path-dependent
    /// elements still continue from this, the path's previous, state.
    pub fn guessed(&self, guess: &State) -> State {
        let mut s = self.clone();
        s.poses.clone_from(&guess.poses);
        s.lambda.clone_from(&guess.lambda);
        s.loads.clone_from(&guess.loads);
        s
    }

    /// The loads this state is in equilibrium with.
    pub fn loads(&self) -> &[PointLoad] {
        &self.loads
    }

    /// Applies a coordinate increment `(dx, theta)` per moving part: the
    /// displacement of its reference point ([`Layout::reference`]) and a
    /// rotation.
    pub(crate) fn apply(&mut self, layout: &Layout, dq: &DVector<f64>) {
        for (b, p) in layout.moving.iter().enumerate() {
            let dx = Vec3::new(dq[6 * b], dq[6 * b + 1], dq[6 * b + 2]);
            let th = Vec3::new(dq[6 * b + 3], dq[6 * b + 4], dq[6 * b + 5]);
            // The screw motion of the twist, not a translation then a rotation
            // about the reference point: the two agree to first order (so every
            // Jacobian holds), but the screw keeps a point the step holds still
            // (a bushing the part pivots about) exactly in place, wherever the
            // reference point is. With `x += dx` a 0.2 rad swing of a lower arm
            // whose reference is 0.5 m from its bushing misplaces that bushing
            // by millimetres, and Newton's full steps fail on the stiff bushing.
            let c = layout.reference[p.index()];
            let (origin, r) = &mut self.poses[p.index()];
            let (rot, v) = screw(&th);
            let at = *origin + *r * c + v * dx;
            *r = keep_orthonormal(rot * *r);
            // The frame origin, from the reference point moved.
            *origin = at - *r * c;
        }
    }
}

/// `exp(theta~)`: the rotation by |theta| about theta (Rodrigues' formula).
pub fn rodrigues(th: &Vec3) -> Mat3 {
    let a = th.norm();
    let k = skew(th);
    let (s, c) = rotation_coefficients(a, a.sin(), a.cos());
    Mat3::identity() + k * s + k * k * c
}

/// `sin a / a` and `(1 - cos a) / a²` of [`rodrigues`], given `a`'s sine
/// and cosine. A series near zero keeps them accurate where `sin(a)/a`
/// loses digits.
fn rotation_coefficients(a: f64, sin: f64, cos: f64) -> (f64, f64) {
    if a < 1e-6 {
        (1.0 - a * a / 6.0, 0.5 - a * a / 24.0)
    } else {
        (sin / a, (1.0 - cos) / (a * a))
    }
}

/// `(1 - cos a) / a²` and `(a - sin a) / a³` of [`screw_translation`],
/// given `a`'s sine and cosine (a series below 1e-4, where the second
/// loses its digits).
fn translation_coefficients(a: f64, sin: f64, cos: f64) -> (f64, f64) {
    if a < 1e-4 {
        (0.5 - a * a / 24.0, 1.0 / 6.0 - a * a / 120.0)
    } else {
        ((1.0 - cos) / (a * a), (a - sin) / (a * a * a))
    }
}

/// [`rodrigues`] and [`screw_translation`] of one twist, sharing its
/// angle's norm, sine and cosine and `theta~²` (the same values as theirs).
fn screw(th: &Vec3) -> (Mat3, Mat3) {
    let a = th.norm();
    let k = skew(th);
    let kk = skew_times(th, &k);
    let (sin, cos) = a.sin_cos();
    let (s, c) = rotation_coefficients(a, sin, cos);
    let (c1, c2) = translation_coefficients(a, sin, cos);
    (
        Mat3::identity() + k * s + kk * c,
        Mat3::identity() + k * c1 + kk * c2,
    )
}

/// `V(theta) = I + (1 - cos a)/a² theta~ + (a - sin a)/a³ theta~²`: the origin
/// moves by `V dx` under the screw motion whose origin velocity is `dx` and
/// angular velocity `theta` (the exponential map of SE(3)).
pub fn screw_translation(th: &Vec3) -> Mat3 {
    let a = th.norm();
    let k = skew(th);
    let (c1, c2) = translation_coefficients(a, a.sin(), a.cos());
    Mat3::identity() + k * c1 + k * k * c2
}

/// How far a rotation's columns may drift from unit length and from
/// perpendicular (`|x·x - 1|`, `|x·y|`, … for its columns `x, y, z`)
/// before [`keep_orthonormal`] restores them: some fifty roundings.
const ORTHONORMAL_WITHIN: f64 = 1e-14;

/// `r` (a product of rotations), orthonormalised once its rounding drift
/// passes [`ORTHONORMAL_WITHIN`]. A product of two rotations is
/// orthonormal to a few roundings, and a path's drift grows by about one a
/// step; restoring it every step put two square roots and two divisions,
/// each waiting on the last, on every part at every Newton trial (4 % of
/// a McPherson case). The check is `RᵀR - I`'s six distinct entries.
fn keep_orthonormal(r: Mat3) -> Mat3 {
    let (x, y, z) = (r.column(0), r.column(1), r.column(2));
    let drift = [
        x.dot(&x) - 1.0,
        y.dot(&y) - 1.0,
        z.dot(&z) - 1.0,
        x.dot(&y),
        x.dot(&z),
        y.dot(&z),
    ]
    .iter()
    .fold(0.0f64, |m, d| m.max(d.abs()));
    // (`max` passes over a NaN: a rotation that is not a number stays
    // one, as under Gram-Schmidt, and the line search refuses the trial.)
    if drift <= ORTHONORMAL_WITHIN {
        r
    } else {
        orthonormalize(&r)
    }
}

/// Removes rounding drift so a rotation matrix stays orthonormal over long load paths.
fn orthonormalize(r: &Mat3) -> Mat3 {
    let x = r.column(0).normalize();
    let y0 = r.column(1) - x * x.dot(&r.column(1));
    let y = y0.normalize();
    let z = x.cross(&y);
    Mat3::from_columns(&[x, y, z])
}

/// The centroid of a part's markers at design (the origin for a part
/// without markers).
pub fn marker_centroid(model: &Model, part: PartId) -> Vec3 {
    centroid(
        model
            .markers
            .iter()
            .filter(|m| m.part == part)
            .map(|m| m.origin()),
    )
}

/// Per part (indexed like `Model::parts`), the point its solver
/// coordinates refer to ([`Layout::reference`]): the centroid at design of
/// its connection markers (those of joints and force elements, which alone
/// carry its stiffness), of all its markers when it has none, the origin
/// when it has no marker. A marker that connects nothing (a wheel centre
/// written 30 m away) does not move it.
pub fn reference_points(model: &Model) -> Vec<Vec3> {
    reference_points_of(model, &connection_markers(model))
}

/// [`reference_points`] with the model's [`connection_markers`] at hand.
pub(crate) fn reference_points_of(model: &Model, connected: &[bool]) -> Vec<Vec3> {
    (0..model.parts.len())
        .map(|p| {
            let on = |only: bool| {
                model
                    .markers
                    .iter()
                    .zip(connected)
                    .filter(move |(m, c)| m.part.index() == p && (!only || **c))
                    .map(|(m, _)| m.origin())
            };
            if on(true).next().is_some() {
                centroid(on(true))
            } else {
                centroid(on(false))
            }
        })
        .collect()
}

/// Per marker, whether a joint or a force element attaches to it.
pub fn connection_markers(model: &Model) -> Vec<bool> {
    let mut connected = vec![false; model.markers.len()];
    let pairs = model
        .joints
        .iter()
        .map(|j| (j.i, j.j))
        .chain(model.bushings.iter().map(|b| (b.i, b.j)))
        .chain(model.springs.iter().map(|s| (s.i, s.j)))
        .chain(model.stops.iter().map(|s| (s.i, s.j)));
    for (i, j) in pairs {
        for m in [i, j] {
            if let Some(c) = connected.get_mut(m.index()) {
                *c = true;
            }
        }
    }
    connected
}

/// The mean of `points` (the origin for none).
fn centroid(points: impl Iterator<Item = Vec3>) -> Vec3 {
    let (sum, n) = points.fold((Vec3::zeros(), 0usize), |(s, n), p| (s + p, n + 1));
    if n == 0 { sum } else { sum / n as f64 }
}

/// A marker's current frame and how it moves with its part.
#[derive(Debug, Clone, Copy)]
pub struct MarkerKin {
    /// Coordinate block of the marker's part (None on ground).
    pub block: Option<usize>,
    /// Origin, global.
    pub p: Vec3,
    /// Arm from the part's reference point to the marker origin, global (`p - x`).
    pub r: Vec3,
    /// Axes as columns, global.
    pub axes: Mat3,
    /// The part's reference point ([`Layout::reference`]), global.
    pub x: Vec3,
}

pub fn marker_kin(model: &Model, layout: &Layout, state: &State, id: MarkerId) -> MarkerKin {
    marker_kin_inlined(model, layout, state, id)
}

/// [`marker_kin`] inlined into its caller: one that reads the frame back at
/// once in wider loads than the call's stores (a bushing's first products),
/// which wait on those stores.
#[inline(always)]
pub(super) fn marker_kin_inlined(
    model: &Model,
    layout: &Layout,
    state: &State,
    id: MarkerId,
) -> MarkerKin {
    let m = model.marker(id);
    let (x, rot) = state.part_pose(m.part);
    let c = layout
        .reference
        .get(m.part.index())
        .copied()
        .unwrap_or_default();
    let x = x + rot * c;
    let r = rot * (m.origin() - c);
    MarkerKin {
        block: layout.block_of_part[m.part.index()],
        p: x + r,
        r,
        axes: rot * m.rotation,
        x,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rodrigues_is_a_rotation_about_its_vector() {
        for th in [
            Vec3::new(0.3, -0.2, 0.9),
            Vec3::new(1e-8, 0.0, 2e-8),
            Vec3::zeros(),
        ] {
            let r = rodrigues(&th);
            assert!((r.transpose() * r - Mat3::identity()).abs().max() < 1e-14);
            assert!((r * th - th).norm() < 1e-14);
            let na = nalgebra::Rotation3::new(th);
            assert!((r - na.matrix()).abs().max() < 1e-14);
        }
    }

    /// `State::apply`'s shared computation gives Rodrigues' rotation and the
    /// screw's translation map to the bit, on both sides of their series'
    /// thresholds.
    #[test]
    fn screw_is_rodrigues_and_the_screw_translation() {
        for th in [
            Vec3::new(0.3, -0.2, 0.9),
            Vec3::new(3e-5, -2e-5, 1e-5),
            Vec3::new(1e-8, 0.0, 2e-8),
            Vec3::zeros(),
        ] {
            assert_eq!(screw(&th), (rodrigues(&th), screw_translation(&th)));
        }
    }

    /// `RᵀR - I`'s largest entry.
    fn drift(r: &Mat3) -> f64 {
        (r.transpose() * r - Mat3::identity()).abs().max()
    }

    /// A rotation within the drift allowed is kept to the bit; beyond it,
    /// orthonormalised; and along 200 000 products of small rotations (a
    /// long path's updates) the drift never passes the allowance by more
    /// than the last product's roundings, restored where it would.
    #[test]
    fn rotations_are_kept_orthonormal_along_long_paths() {
        let exact = rodrigues(&Vec3::new(0.3, -0.2, 0.9));
        assert_eq!(keep_orthonormal(exact), exact);
        let drifted = exact * (1.0 + 1e-12);
        assert!(drift(&drifted) > 1e-12);
        assert!(drift(&keep_orthonormal(drifted)) < 1e-15);
        let (mut r, mut seed, mut restored, mut worst) = (exact, 3u64, 0, 0.0f64);
        let mut next = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        for _ in 0..200_000 {
            let th = Vec3::new(next(), next(), next()) * 0.02;
            let product = rodrigues(&th) * r;
            r = keep_orthonormal(product);
            restored += usize::from(r != product);
            worst = worst.max(drift(&r));
        }
        assert!(worst <= ORTHONORMAL_WITHIN + 1e-15, "{worst:e}");
        assert!(restored > 0, "the drift never reached the allowance");
        // (64 times: a restoration every few thousand products.)
        assert!(restored < 1_000, "restored {restored} times");
    }

    /// The screw update keeps the point the twist holds still in place: a part
    /// turned by 0.3 rad about a pivot 500 mm from its frame origin.
    #[test]
    fn screw_update_turns_about_the_point_the_step_holds_still() {
        use crate::model::PartId;
        let mut model = crate::model::Model::default();
        for (name, ground) in [("g", true), ("arm", false)] {
            model.parts.push(crate::model::Part {
                name: name.into(),
                ground,
            });
        }
        let layout = Layout::new(&model);
        let pivot = Vec3::new(100.0, 500.0, -40.0);
        let th = Vec3::new(0.3, -0.1, 0.2);
        // Origin velocity of a rotation about `pivot`: v(x) = theta × (x - pivot).
        let dx = th.cross(&(Vec3::zeros() - pivot));
        let mut dq = DVector::zeros(6);
        dq.rows_mut(0, 3).copy_from(&dx);
        dq.rows_mut(3, 3).copy_from(&th);
        let mut st = State::design(&model);
        st.apply(&layout, &dq);
        let (x, r) = st.part_pose(PartId(1));
        assert!((x + r * pivot - pivot).norm() < 1e-12);
        // The exact rotation about the pivot, by Rodrigues.
        let want = pivot + rodrigues(&th) * (Vec3::new(7.0, 8.0, 9.0) - pivot);
        assert!((x + r * Vec3::new(7.0, 8.0, 9.0) - want).norm() < 1e-12);
    }
}
