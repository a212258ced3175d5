//! Synthetic measurements from a truth model: solve its load set, place every
//! landmark with its part's pose, add seeded Gaussian noise, and write the
//! landmark and K&C files of `interfaces.md`. Tests and benchmarks of
//! localisation and identification use these as data whose answer is known.

use crate::geom::Vec3;
use crate::model::{LoadSetId, Model, values};
use crate::statics::{self, StaticsError};
use std::fmt::Write;

/// A small, seeded normal-variate source (splitmix64 + Box–Muller), so that
/// synthetic data are reproducible without a random-number dependency.
pub struct Noise {
    state: u64,
    spare: Option<f64>,
}

impl Noise {
    pub fn new(seed: u64) -> Noise {
        Noise {
            state: seed ^ 0x9E37_79B9_7F4A_7C15,
            spare: None,
        }
    }

    fn uniform(&mut self) -> f64 {
        self.state = self.state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        // 53 random bits in (0, 1].
        ((z >> 11) as f64 + 1.0) / (1u64 << 53) as f64
    }

    /// A standard normal variate.
    pub fn normal(&mut self) -> f64 {
        if let Some(s) = self.spare.take() {
            return s;
        }
        let (u, v) = (self.uniform(), self.uniform());
        let r = (-2.0 * u.ln()).sqrt();
        let t = std::f64::consts::TAU * v;
        self.spare = Some(r * t.sin());
        r * t.cos()
    }
}

/// One measured landmark: part name, landmark name, position.
type Point = (String, String, Vec3);

/// Measured landmark positions of every case of a load set, in case order:
/// `(part, landmark, position)`, with noise of standard deviation `sigma` mm
/// per coordinate drawn in that order (so the CSV and IGES forms of the same
/// seed carry the same numbers).
fn measured(
    model: &Model,
    set: LoadSetId,
    sigma: f64,
    seed: u64,
) -> Result<Vec<Vec<Point>>, StaticsError> {
    let eqs = statics::solve_set(model, set)?;
    let mut noise = Noise::new(seed);
    Ok(eqs
        .iter()
        .map(|eq| {
            model
                .landmarks
                .iter()
                .map(|l| {
                    let (t, r) = eq.state.part_pose(l.part);
                    let x: Vec3 = t + r * values(&l.position);
                    let x = x.map(|c| c + sigma * noise.normal());
                    (model.part(l.part).name.clone(), l.name.clone(), x)
                })
                .collect()
        })
        .collect())
}

/// Landmark CSV (`step, part, landmark, x, y, z`) of every case of a load set,
/// steps numbered from 1, with noise of standard deviation `sigma` mm per coordinate.
pub fn landmarks_csv(
    model: &Model,
    set: LoadSetId,
    sigma: f64,
    seed: u64,
) -> Result<String, StaticsError> {
    let mut out = String::from("step,part,landmark,x,y,z\n");
    for (k, step) in measured(model, set, sigma, seed)?.iter().enumerate() {
        for (part, name, x) in step {
            let _ = writeln!(out, "{},{part},{name},{},{},{}", k + 1, x.x, x.y, x.z);
        }
    }
    Ok(out)
}

/// The same measurements as [`landmarks_csv`] (same seed, same numbers) as
/// IGES files, one per case, the way a measuring arm saves each state: points
/// labelled with their part (8 characters) and subscript, named
/// `<part>.<landmark>` by a Name property.
pub fn landmarks_iges(
    model: &Model,
    set: LoadSetId,
    sigma: f64,
    seed: u64,
) -> Result<Vec<String>, StaticsError> {
    use crate::data::iges::{Geometry, Item, write};
    let set_name = &model.load_sets[set.index()].name;
    Ok(measured(model, set, sigma, seed)?
        .into_iter()
        .enumerate()
        .map(|(k, step)| {
            let items: Vec<Item> = step
                .into_iter()
                .enumerate()
                .map(|(i, (part, name, x))| Item {
                    name: format!("{part}.{name}"),
                    label: part.chars().take(8).collect(),
                    subscript: i as i64 + 1,
                    geometry: Geometry::Point(x),
                })
                .collect();
            write(
                &format!("{set_name}_{}.igs", k + 1),
                &format!(
                    "axle synthetic landmarks, load set {set_name}, case {}",
                    k + 1
                ),
                &items,
            )
        })
        .collect())
}

/// The K&C file of a load set of a truth model, solved as a path in order,
/// with seeded noise: `angle_sigma` deg on toe and camber, `position_sigma`
/// mm on each wheel-centre coordinate (drawn per row in that order). Tests
/// and benchmarks of diagnosis use it as rig data whose cause is known.
pub fn kc_csv(
    model: &Model,
    set: LoadSetId,
    angle_sigma: f64,
    position_sigma: f64,
    seed: u64,
) -> Result<String, StaticsError> {
    let problem = statics::Problem::new(model)?;
    let eqs = statics::path::solve_path(&problem, set).map_err(|e| e.error)?;
    let states: Vec<&statics::State> = eqs.iter().map(|e| &e.state).collect();
    let mut rows = crate::kc::kc_rows(model, set, &states);
    let mut noise = Noise::new(seed);
    for r in &mut rows {
        let q = &mut r.quantities;
        q.toe_deg += angle_sigma * noise.normal();
        q.camber_deg += angle_sigma * noise.normal();
        for c in &mut q.center {
            *c += position_sigma * noise.normal();
        }
    }
    Ok(crate::output::kc_table::csv(&rows))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn noise_has_unit_variance_and_is_reproducible() {
        let mut a = Noise::new(7);
        let xs: Vec<f64> = (0..20000).map(|_| a.normal()).collect();
        let mean = xs.iter().sum::<f64>() / xs.len() as f64;
        let var = xs.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / xs.len() as f64;
        assert!(mean.abs() < 0.03, "{mean}");
        assert!((var - 1.0).abs() < 0.03, "{var}");
        let mut b = Noise::new(7);
        assert_eq!(b.normal(), xs[0]);
    }
}
