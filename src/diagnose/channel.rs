//! The channels a diagnosis compares (`interfaces.md`, `diagnose --format
//! json`): toe and camber (deg), wheel travel and half-track change (mm),
//! the wheel centre's fore-aft position (mm), per `conventions.md`.
//!
//! A rig reports the wheel centre and the toe and camber angles, not a contact
//! point, so the half-track is taken the same way on both sides: the point of
//! the wheel plane one design radius below the centre (the plane through the
//! centre normal to the spin axis, straight down within it). Measured and
//! simulated values are then the same function of the same quantities, and a
//! residual is never a difference of definitions.
//!
//! With landmark data (`--landmarks`), `landmarks_mm` compares every measured
//! landmark with the same point of its part at the simulated state, per
//! coordinate in the model frame ([`super::landmarks`]).

use crate::geom::Vec3;
use crate::identify::measured::KcObservation;
use crate::kc::wheel_quantities;
use crate::model::{Model, WheelId};
use crate::statics::State;

/// A K&C channel.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Channel {
    Toe,
    Camber,
    Travel,
    HalfTrack,
    WcX,
    /// Landmark positions (mm per coordinate), when measured.
    Landmarks,
}

/// The K&C channels of one wheel at one step, in [`Channel::KC`] order.
pub type Measured = [f64; 5];

/// One figure per channel (an RMS, a gain, a noise), in [`Channel::ALL`] order.
pub type PerChannel = [f64; 6];

impl Channel {
    /// The channels a K&C rig reports for one wheel.
    pub const KC: [Channel; 5] = [
        Channel::Toe,
        Channel::Camber,
        Channel::Travel,
        Channel::HalfTrack,
        Channel::WcX,
    ];

    /// Every channel: the K&C channels, then the landmarks.
    pub const ALL: [Channel; 6] = [
        Channel::Toe,
        Channel::Camber,
        Channel::Travel,
        Channel::HalfTrack,
        Channel::WcX,
        Channel::Landmarks,
    ];

    /// The name in tables and JSON.
    pub fn name(self) -> &'static str {
        match self {
            Channel::Toe => "toe_deg",
            Channel::Camber => "camber_deg",
            Channel::Travel => "travel_mm",
            Channel::HalfTrack => "half_track_mm",
            Channel::WcX => "wc_x_mm",
            Channel::Landmarks => "landmarks_mm",
        }
    }

    /// Words for sentences ("toe", "half-track change").
    pub fn words(self) -> &'static str {
        match self {
            Channel::Toe => "toe",
            Channel::Camber => "camber",
            Channel::Travel => "wheel travel",
            Channel::HalfTrack => "half-track change",
            Channel::WcX => "wheel-centre x",
            Channel::Landmarks => "landmark position",
        }
    }

    pub fn unit(self) -> &'static str {
        match self {
            Channel::Toe | Channel::Camber => "deg",
            _ => "mm",
        }
    }

    pub fn parse(name: &str) -> Option<Channel> {
        Channel::ALL.into_iter().find(|c| c.name() == name)
    }

    pub fn index(self) -> usize {
        self as usize
    }
}

/// What a wheel's channels are measured against: its design centre height,
/// its design radius (centre to contact) and design half-track.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Design {
    pub centre_z: f64,
    pub radius: f64,
    pub half_track: f64,
    /// A right wheel (centre at negative y): its toe and spin axis are mirrored.
    pub right: bool,
}

/// The design reference of `wheel`.
pub fn design(model: &Model, wheel: WheelId) -> Design {
    let w = &model.wheels[wheel.index()];
    let c = model.marker(w.centre).origin();
    let k = model.marker(w.contact).origin();
    let q = wheel_quantities(model, &State::design(model), w);
    let radius = (c - k).norm();
    let s = Vec3::from(q.spin_axis);
    Design {
        centre_z: c.z,
        radius,
        half_track: ground_point(c, s, radius).y.abs(),
        right: c.y < 0.0,
    }
}

/// The wheel plane's lowest point one radius from the centre.
fn ground_point(centre: Vec3, spin: Vec3, radius: f64) -> Vec3 {
    let down = -Vec3::z() + spin * spin.z;
    let n = down.norm();
    if n < 1e-12 {
        return centre;
    }
    centre + down * (radius / n)
}

/// The spin axis of a wheel of the given toe and camber (inverse of
/// `kc::wheel_quantities`).
fn spin_axis(d: &Design, toe_deg: f64, camber_deg: f64) -> Vec3 {
    let (c, t) = (camber_deg.to_radians(), toe_deg.to_radians());
    if d.right {
        Vec3::new(t.sin() * c.cos(), -t.cos() * c.cos(), -c.sin())
    } else {
        let steer = -t;
        Vec3::new(-steer.sin() * c.cos(), steer.cos() * c.cos(), -c.sin())
    }
}

fn channels(d: &Design, centre: Vec3, spin: Vec3, toe: f64, camber: f64) -> Measured {
    let g = ground_point(centre, spin, d.radius);
    [
        toe,
        camber,
        centre.z - d.centre_z,
        g.y.abs() - d.half_track,
        centre.x,
    ]
}

/// The channels of a rig measurement.
pub fn of_observation(d: &Design, o: &KcObservation) -> Measured {
    let s = spin_axis(d, o.toe_deg, o.camber_deg);
    channels(d, o.wc, s, o.toe_deg, o.camber_deg)
}

/// The channels of `wheel` at a solved state.
pub fn of_state(model: &Model, d: &Design, wheel: WheelId, state: &State) -> Measured {
    let q = wheel_quantities(model, state, &model.wheels[wheel.index()]);
    channels(
        d,
        Vec3::from(q.center),
        Vec3::from(q.spin_axis),
        q.toe_deg,
        q.camber_deg,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The spin axis rebuilt from toe and camber is the one they came from,
    /// on both sides, so measured and simulated half-tracks agree exactly.
    #[test]
    fn spin_axis_inverts_toe_and_camber() {
        for right in [false, true] {
            let d = Design {
                centre_z: 0.0,
                radius: 300.0,
                half_track: 0.0,
                right,
            };
            let side = if right { -1.0 } else { 1.0 };
            let s = Vec3::new(0.03, side * 0.99, -0.08).normalize();
            let h = if right {
                Vec3::z().cross(&s)
            } else {
                s.cross(&Vec3::z())
            };
            let steer = h.y.atan2(h.x);
            let toe = if right { steer } else { -steer };
            let camber = (-s.z).asin();
            let back = spin_axis(&d, toe.to_degrees(), camber.to_degrees());
            assert!((back - s).norm() < 1e-12, "{back} vs {s}");
        }
    }

    #[test]
    fn ground_point_is_one_radius_below_in_the_wheel_plane() {
        let s = Vec3::new(0.0, 0.1f64.cos(), -(0.1f64.sin()));
        let g = ground_point(Vec3::new(0.0, 700.0, 300.0), s, 300.0);
        assert!(((g - Vec3::new(0.0, 700.0, 300.0)).norm() - 300.0).abs() < 1e-9);
        assert!((g - Vec3::new(0.0, 700.0, 300.0)).dot(&s).abs() < 1e-9);
        // Camber 0.1 rad with the top outboard: the ground point moves inboard.
        assert!(g.y < 700.0);
    }
}
