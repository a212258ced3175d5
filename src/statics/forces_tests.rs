//! The force elements' tangent stiffness against finite differences of
//! their forces, and the conservative elements' forces against their
//! potential (virtual work).

use super::super::testkit::{
    Lcg, assert_tangent_by_central_differences, force_model, perturbed, random_state,
};
use super::*;
use crate::model::{AxisLaw, MarkerId};
use nalgebra::{DMatrix, DVector};

fn total(
    model: &Model,
    layout: &Layout,
    state: &State,
    loads: &[PointLoad],
) -> (DVector<f64>, DMatrix<f64>) {
    let mut q = DVector::zeros(layout.n());
    let mut k = DMatrix::zeros(layout.n(), layout.n());
    let ws = element_wrenches(model, layout, state).expect("nondegenerate");
    for (_, w) in ws.iter() {
        w.add_force(&mut q);
        w.add_tangent(&mut k);
    }
    for l in loads {
        if let Some(w) = point_load(model, layout, state, l) {
            w.add_force(&mut q);
            w.add_tangent(&mut k);
        }
    }
    (q, k)
}

/// The analytic tangent of every force element equals a central difference of
/// its generalised force, at random poses (both parts moving, and J on ground).
#[test]
fn tangent_stiffness_matches_finite_differences() {
    for seed in 0..6u64 {
        for ground_j in [false, true] {
            let model = force_model(ground_j, seed);
            let layout = Layout::new(&model);
            let state = random_state(&model, 100 + seed);
            let loads = [PointLoad {
                marker: MarkerId(0),
                force: Vec3::new(100.0, -50.0, 30.0),
                torque: Vec3::new(1e3, 2e3, -5e2),
            }];
            let (_, k) = total(&model, &layout, &state, &loads);
            assert_tangent_by_central_differences(
                &layout,
                &state,
                &k,
                |st| total(&model, &layout, st, &loads).0,
                &format!("seed {seed}"),
            );
        }
    }
}

/// Springs, stops, the translational part of a bushing and constant point
/// forces are conservative: their generalised force is minus the gradient of
/// the potential energy written independently here.
#[test]
fn conservative_elements_do_virtual_work_of_their_potential() {
    for seed in 0..4u64 {
        let mut model = force_model(seed % 2 == 0, seed);
        let b = &mut model.bushings[0];
        b.rotational = crate::model::AxisLaws::General([
            AxisLaw::linear(0.0),
            AxisLaw::linear(0.0),
            AxisLaw::linear(0.0),
        ]);
        b.torque_preload = crate::model::vals([0.0; 3]);
        let layout = Layout::new(&model);
        let mut rng = Lcg::new(seed);
        let loads = [PointLoad {
            marker: MarkerId(0),
            force: rng.vec(200.0),
            torque: Vec3::zeros(),
        }];
        let energy = |st: &State| -> f64 {
            let mut v = 0.0;
            let b = &model.bushings[0];
            let ev = bushing_state(&model, &layout, st, b);
            for k in 0..3 {
                let d = ev.t[k] - b.offset[k].value;
                let (k1, k3) = match &b.translational[k] {
                    AxisLaw::Linear { k, k3 } => (k.value, k3.value),
                    AxisLaw::Table(_) => unreachable!("the test bushing is polynomial"),
                };
                v += 0.5 * k1 * d * d + 0.25 * k3 * d.powi(4) - b.preload[k].value * ev.t[k];
            }
            for (k, s) in model.springs.iter().enumerate() {
                let (l, _, _) = spring(&model, &layout, st, SpringId(k as u32), s).expect("spring");
                v += match &s.law {
                    SpringLaw::Linear {
                        k,
                        free_length,
                        preload,
                    } => 0.5 * k.value * (l - free_length.value).powi(2) - preload.value * l,
                    // Push-apart table (0,5000) (200,1000) (500,-200), linear
                    // beyond its ends: the trapezoid rule is exact between kinks.
                    SpringLaw::Table(t) => {
                        let mut xs = vec![0.0];
                        if l > 200.0 {
                            xs.push(200.0);
                        }
                        xs.push(l);
                        -xs.windows(2)
                            .map(|w| (w[1] - w[0]) * (t.eval(w[0]).0 + t.eval(w[1]).0) / 2.0)
                            .sum::<f64>()
                    }
                };
            }
            for s in &model.stops {
                let mi = marker_kin(&model, &layout, st, s.i).p;
                let mj = marker_kin(&model, &layout, st, s.j).p;
                let l = (mi - mj).norm();
                let lc = s.contact_length.value;
                let pen = match s.kind {
                    StopKind::Compression => lc - l,
                    StopKind::Rebound => l - lc,
                };
                if pen > 0.0 {
                    v += 100.0 * pen * pen / 2.0 + 5.0 * pen.powi(3) / 3.0;
                }
            }
            v - loads[0]
                .force
                .dot(&marker_kin(&model, &layout, st, MarkerId(0)).p)
        };
        let state = random_state(&model, 7 + seed);
        let (q, _) = total(&model, &layout, &state, &loads);
        let h = 1e-5;
        for c in 0..layout.n() {
            let fd = -(energy(&perturbed(&layout, &state, c, h))
                - energy(&perturbed(&layout, &state, c, -h)))
                / (2.0 * h);
            assert!(
                (fd - q[c]).abs() < 1e-4 * (1.0 + q[c].abs()),
                "seed {seed} coord {c}: -dV {fd} vs Q {}",
                q[c]
            );
        }
    }
}
