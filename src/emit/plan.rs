//! Deterministic ADAMS ids for a model, and the auxiliary markers a deck needs
//! (part CM markers, a global reference marker, floating reaction markers, wheel
//! spin-axis markers). Every id follows model order, so the same model always
//! gives the same deck. Auxiliary markers get names starting with `axle_`, which
//! the importer recognises and drops.

use super::error::EmitError;
use crate::geom::{Mat3, Vec3};
use crate::model::*;

/// Placeholder mass of a moving part, kg. Statics ignore it (no gravity is
/// written), but Adams/Solver requires a mass on every moving part.
pub const PLACEHOLDER_MASS: f64 = 1.0e-3;
/// Placeholder principal inertia of a moving part, kg·mm².
pub const PLACEHOLDER_INERTIA: f64 = 1.0;
/// Distance of a wheel's spin-axis marker from its centre, mm.
pub const SPIN_ARM: f64 = 100.0;

/// A marker that exists only in the deck.
#[derive(Debug, Clone)]
pub struct AuxMarker {
    pub id: u32,
    pub part: PartId,
    pub name: String,
    pub position: Vec3,
    pub rotation: Option<Mat3>,
    pub floating: bool,
}

/// How a bushing is written.
#[derive(Debug, Clone)]
pub enum BushingForm {
    /// `BUSHING/id`: all six laws linear without cubic term.
    Linear { id: u32 },
    /// `GFORCE/id` with a floating reaction marker and one SPLINE per tabulated axis.
    General {
        id: u32,
        float: u32,
        splines: [Option<u32>; 6],
    },
}

/// External loads at one marker: VFORCE/VTORQUE ids and their VARIABLE ids.
#[derive(Debug, Clone)]
pub struct LoadGroup {
    pub marker: MarkerId,
    pub float: u32,
    pub vforce: Option<(u32, [u32; 3])>,
    pub vtorque: Option<(u32, [u32; 3])>,
}

#[derive(Debug, Clone)]
pub struct Plan {
    pub part: Vec<u32>,
    pub marker: Vec<u32>,
    pub global: u32,
    pub aux: Vec<AuxMarker>,
    pub cm: Vec<Option<u32>>,
    pub bushings: Vec<BushingForm>,
    /// Per spring: Some(spline id) when tabulated (SFORCE), None for SPRINGDAMPER.
    pub spring_splines: Vec<Option<u32>>,
    pub stop_splines: Vec<Option<u32>>,
    pub loads: Vec<LoadGroup>,
    /// Per wheel: the spin-axis marker id.
    pub spin: Vec<u32>,
    /// Per friction: its GFORCE id and the floating marker on its J part.
    pub frictions: Vec<(u32, u32)>,
}

/// The marker each channel of a set acts at, or an error naming the channel.
pub fn channel_marker(m: &Model, set: &LoadSet, ch: &Channel) -> Result<MarkerId, EmitError> {
    match ch.target {
        LoadTarget::Marker(mk) => Ok(mk),
        LoadTarget::Wheel(w) => Ok(m.wheels[w.index()].contact),
        LoadTarget::DefaultWheel => match m.wheels.as_slice() {
            [w] => Ok(w.contact),
            _ => Err(EmitError::UnresolvedLoad {
                set: set.name.clone(),
                channel: ch.component.name().to_string(),
            }),
        },
    }
}

/// Where a part's placeholder CM goes: at its first marker, a position that is
/// already in the deck (a centroid would change in its last digit on re-import).
fn cm_position(m: &Model, p: PartId) -> Vec3 {
    m.markers
        .iter()
        .find(|k| k.part == p)
        .map_or(Vec3::zeros(), |k| k.origin())
}

impl Plan {
    pub fn new(m: &Model) -> Result<Plan, EmitError> {
        let ground = m.ground().ok_or(EmitError::NoGround)?;
        let part: Vec<u32> = (0..m.parts.len() as u32).map(|k| k + 1).collect();
        let marker: Vec<u32> = (0..m.markers.len() as u32).map(|k| k + 1).collect();
        let mut next = m.markers.len() as u32 + 1;
        let mut aux = Vec::new();
        let mut add = |aux: &mut Vec<AuxMarker>,
                       part: PartId,
                       name: String,
                       position: Vec3,
                       rotation: Option<Mat3>,
                       floating: bool| {
            let id = next;
            next += 1;
            aux.push(AuxMarker {
                id,
                part,
                name,
                position,
                rotation,
                floating,
            });
            id
        };
        let global = add(
            &mut aux,
            ground,
            "axle_global".into(),
            Vec3::zeros(),
            Some(Mat3::identity()),
            false,
        );
        let mut cm = vec![None; m.parts.len()];
        for p in m.moving_parts() {
            cm[p.index()] = Some(add(
                &mut aux,
                p,
                "axle_cm".into(),
                cm_position(m, p),
                None,
                false,
            ));
        }
        let mut spin = Vec::new();
        for w in &m.wheels {
            let c = m.marker(w.centre);
            // cos(90°) leaves 6e-17 in an axis; it would print as a stray 1E-14 mm.
            let s: Vec3 =
                Vec3::from(c.rotation.column(2)).map(|v| if v.abs() < 1e-12 { 0.0 } else { v });
            spin.push(add(
                &mut aux,
                c.part,
                format!("axle_spin_{}", w.name),
                c.origin() + s * SPIN_ARM,
                None,
                false,
            ));
        }
        let (mut bushing_n, mut gforce_n, mut spline_n) = (0, 0, 0);
        let mut bushings = Vec::new();
        for b in &m.bushings {
            let linear = b.translational.iter().chain(&b.rotational).all(
                |l| matches!(l, AxisLaw::Linear { k, k3 } if k3.value == 0.0 && k.value >= 0.0),
            );
            if linear {
                bushing_n += 1;
                bushings.push(BushingForm::Linear { id: bushing_n });
            } else {
                gforce_n += 1;
                let jpart = m.marker(b.j).part;
                let float = add(
                    &mut aux,
                    jpart,
                    format!("axle_float_{}", b.name),
                    Vec3::zeros(),
                    None,
                    true,
                );
                let splines = std::array::from_fn(|k| {
                    let law = if k < 3 {
                        &b.translational[k]
                    } else {
                        &b.rotational[k - 3]
                    };
                    matches!(law, AxisLaw::Table(_)).then(|| {
                        spline_n += 1;
                        spline_n
                    })
                });
                bushings.push(BushingForm::General {
                    id: gforce_n,
                    float,
                    splines,
                });
            }
        }
        let mut table = |is_table: bool| {
            is_table.then(|| {
                spline_n += 1;
                spline_n
            })
        };
        let spring_splines = m
            .springs
            .iter()
            .map(|s| table(matches!(s.law, SpringLaw::Table(_))))
            .collect();
        let stop_splines = m
            .stops
            .iter()
            .map(|s| table(matches!(s.law, StopLaw::Table(_))))
            .collect();
        // Load groups: every marker any set loads, in first-use order; force and
        // torque components only when some set uses them. Loads on ground do nothing.
        let mut used: Vec<(MarkerId, bool, bool)> = Vec::new();
        for set in &m.load_sets {
            for ch in &set.channels {
                let mk = channel_marker(m, set, ch)?;
                if m.part(m.marker(mk).part).ground {
                    continue;
                }
                let pos = match used.iter().position(|u| u.0 == mk) {
                    Some(p) => p,
                    None => {
                        used.push((mk, false, false));
                        used.len() - 1
                    }
                };
                if ch.component.is_torque() {
                    used[pos].2 = true
                } else {
                    used[pos].1 = true
                }
            }
        }
        let (mut var_n, mut vf_n, mut vt_n) = (0, 0, 0);
        let mut vars = || {
            let v = [var_n + 1, var_n + 2, var_n + 3];
            var_n += 3;
            v
        };
        let mut loads = Vec::new();
        for (mk, f, t) in used {
            let float = add(
                &mut aux,
                ground,
                format!("axle_float_{}", m.marker_path(mk).replace('.', "_")),
                Vec3::zeros(),
                None,
                true,
            );
            let vforce = f.then(|| {
                vf_n += 1;
                (vf_n, vars())
            });
            let vtorque = t.then(|| {
                vt_n += 1;
                (vt_n, vars())
            });
            loads.push(LoadGroup {
                marker: mk,
                float,
                vforce,
                vtorque,
            });
        }
        // Frictions: a GFORCE each (numbered after the bushings'), its reaction
        // on a floating marker of the joint's J part.
        let mut frictions = Vec::new();
        for f in &m.frictions {
            let jpart = m
                .joints
                .get(f.joint.index())
                .map_or(ground, |j| m.marker(j.j).part);
            gforce_n += 1;
            let float = add(
                &mut aux,
                jpart,
                format!("axle_float_{}", f.name),
                Vec3::zeros(),
                None,
                true,
            );
            frictions.push((gforce_n, float));
        }
        Ok(Plan {
            frictions,
            part,
            marker,
            global,
            aux,
            cm,
            bushings,
            spring_splines,
            stop_splines,
            loads,
            spin,
        })
    }

    pub fn marker(&self, m: MarkerId) -> u32 {
        self.marker[m.index()]
    }

    /// The VARIABLE id and value of every load component for one case of a set.
    pub fn variable_values(&self, m: &Model, set: LoadSetId, case: usize) -> Vec<(u32, f64)> {
        let pls = m.point_loads(set, case);
        let mut out = Vec::new();
        for g in &self.loads {
            let pl = pls.iter().find(|l| l.marker == g.marker);
            if let Some((_, v)) = g.vforce {
                for (k, id) in v.iter().enumerate() {
                    out.push((*id, pl.map_or(0.0, |l| l.force[k])));
                }
            }
            if let Some((_, v)) = g.vtorque {
                for (k, id) in v.iter().enumerate() {
                    out.push((*id, pl.map_or(0.0, |l| l.torque[k])));
                }
            }
        }
        out
    }
}
