//! What the statics tests share: a model builder in the numbers of
//! `spec/benchmarks.md`, the independent results and their comparison, and
//! the McPherson example.

use axle::geom::{Mat3, Vec3};
use axle::model::*;
use axle::output::report::case_report;
use axle::statics::{self, Problem, State};
use axle::units::DEG;
use serde_json::Value;

/// Builds models programmatically, in the numbers of `spec/benchmarks.md`.
pub struct Builder {
    pub m: Model,
}

impl Builder {
    pub fn new(name: &str) -> Builder {
        Builder {
            m: Model {
                name: name.into(),
                ..Model::default()
            },
        }
    }
    pub fn part(&mut self, name: &str, ground: bool) -> PartId {
        self.m.parts.push(Part {
            name: name.into(),
            ground,
        });
        PartId(self.m.parts.len() as u32 - 1)
    }
    pub fn marker(&mut self, part: PartId, name: &str, p: [f64; 3], rotation: Mat3) -> MarkerId {
        self.m.markers.push(Marker {
            name: name.into(),
            part,
            position: vals(p),
            orientation: Orientation::Identity,
            rotation,
        });
        MarkerId(self.m.markers.len() as u32 - 1)
    }
    pub fn point(&mut self, part: PartId, name: &str, p: [f64; 3]) -> MarkerId {
        self.marker(part, name, p, Mat3::identity())
    }
    pub fn joint(&mut self, name: &str, kind: JointKind, i: MarkerId, j: MarkerId) {
        self.m.joints.push(Joint {
            name: name.into(),
            kind,
            i,
            j,
        });
    }
    /// `k` in N/mm, `kt` in N·mm/deg (converted to N·mm/rad).
    pub fn bushing(
        &mut self,
        name: &str,
        i: MarkerId,
        j: MarkerId,
        k: [f64; 3],
        kt_deg: [f64; 3],
    ) -> BushingId {
        self.m
            .bushings
            .push(Bushing::linear(name, i, j, k, kt_deg.map(|v| v / DEG)));
        BushingId(self.m.bushings.len() as u32 - 1)
    }
}

pub fn load(marker: MarkerId, f: [f64; 3], t: [f64; 3]) -> Vec<PointLoad> {
    vec![PointLoad {
        marker,
        force: Vec3::from(f),
        torque: Vec3::from(t),
    }]
}

pub fn expected(name: &str) -> Value {
    let path = format!(
        "{}/tests/data/expected/{name}.json",
        env!("CARGO_MANIFEST_DIR")
    );
    let text = std::fs::read_to_string(&path).expect("expected file");
    serde_json::from_str(&text).expect("expected JSON")
}

pub fn arr(v: &Value) -> Vec<f64> {
    match v {
        Value::Array(a) => a.iter().flat_map(arr).collect(),
        Value::Number(n) => vec![n.as_f64().expect("number")],
        _ => panic!("not numeric: {v}"),
    }
}

/// Largest differences between a computed and an expected case:
/// (positions mm, rotations rad, bushing translations mm, bushing angles deg,
/// bushing forces relative to the largest force component).
#[derive(Debug, Default)]
pub struct MaxErr {
    pub pos: f64,
    pub rot: f64,
    pub t: f64,
    pub ang: f64,
    pub force: f64,
    /// Position (mm) and rotation errors of the soft elements, and angle errors (deg)
    /// of their bushings: the strut's spin converges less tightly in the reference
    /// (expected/README.md).
    pub soft_pos: f64,
    pub soft_rot: f64,
    pub soft_ang: f64,
}

/// Elements on the strut's soft spin mode (McPherson); none in the other models.
pub const SOFT: [&str; 2] = ["strut", "F"];

pub fn compare(got: &Value, want: &Value, e: &mut MaxErr) {
    for (part, w) in want["parts"].as_object().expect("parts") {
        let g = &got["parts"][part];
        let d = |k: &str| {
            arr(&g[k])
                .iter()
                .zip(arr(&w[k]))
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max)
        };
        // Rotation entries differ by the angle between the rotations, to first order.
        if SOFT.contains(&part.as_str()) {
            e.soft_pos = e.soft_pos.max(d("position"));
            e.soft_rot = e.soft_rot.max(d("rotation"));
        } else {
            e.pos = e.pos.max(d("position"));
            e.rot = e.rot.max(d("rotation"));
        }
    }
    for (name, w) in want["bushings"].as_object().expect("bushings") {
        let g = &got["bushings"][name];
        let (gd, wd) = (arr(&g["deformation"]), arr(&w["deformation"]));
        for k in 0..3 {
            e.t = e.t.max((gd[k] - wd[k]).abs());
            let a = (gd[k + 3] - wd[k + 3]).abs();
            if SOFT.contains(&name.as_str()) {
                e.soft_ang = e.soft_ang.max(a);
            } else {
                e.ang = e.ang.max(a);
            }
        }
        let (gf, wf) = (arr(&g["force"]), arr(&w["force"]));
        let scale = wf.iter().fold(1.0f64, |a, b| a.max(b.abs()));
        for k in 0..6 {
            e.force = e.force.max((gf[k] - wf[k]).abs() / scale);
        }
    }
}

pub fn assert_within(e: &MaxErr, what: &str) {
    eprintln!("{what}: {e:?}");
    assert!(e.pos < 1e-5, "{what}: position error {} mm", e.pos);
    assert!(
        e.rot < 1e-6 * DEG * 10.0,
        "{what}: rotation error {} rad",
        e.rot
    );
    assert!(e.t < 1e-5, "{what}: bushing deformation error {} mm", e.t);
    assert!(
        e.ang < 1e-6 * 10.0,
        "{what}: bushing angle error {} deg",
        e.ang
    );
    assert!(
        e.force < 1e-6,
        "{what}: relative bushing force error {}",
        e.force
    );
}

/// Solves cases in order (each from the previous state, or each from design) and
/// compares them with an expected file.
pub fn check_against(model: &Model, name: &str, cases: &[Vec<PointLoad>], from_design: bool) {
    let want = expected(name);
    let problem = Problem::new(model).expect("problem");
    let mut state = State::design(model);
    let mut err = MaxErr::default();
    for (k, loads) in cases.iter().enumerate() {
        let start = if from_design {
            State::design(model)
        } else {
            state.clone()
        };
        let eq = statics::solve(&problem, loads, &start).expect("converges");
        assert!(eq.residual < 1e-9, "case {k}: residual {}", eq.residual);
        let got = serde_json::to_value(case_report(model, &format!("c{}", k + 1), k + 1, &eq))
            .expect("json");
        compare(&got, &want["cases"][k], &mut err);
        state = eq.state;
    }
    assert_within(&err, name);
}

// ---------------------------------------------------------------------------
// McPherson (benchmarks.md §4): the shipped example, so that the example file
// itself is checked against the independent results.

pub struct McPherson {
    pub model: Model,
    pub contact: MarkerId,
}

/// `examples/mcpherson.axle`, with the strut top mount's kt_z (N·mm/deg) replaced.
pub fn mcpherson(kt_z_f: f64) -> McPherson {
    let text = include_str!("../../examples/mcpherson.axle");
    let nominal = "    kt_axial 1000 N*mm/deg\n";
    assert_eq!(
        text.matches(nominal).count(),
        1,
        "the example's strut mount line"
    );
    let text = text.replace(nominal, &format!("    kt_axial {kt_z_f} N*mm/deg\n"));
    let (_, checked) = axle::check::check_str("mcpherson.axle", &text);
    let model = checked.model.expect("the McPherson example checks");
    let contact = model.wheels[0].contact;
    McPherson { model, contact }
}

/// Wheel loads (fx, fy, fz) at the contact point.
pub fn wheel(m: &McPherson, fx: f64, fy: f64, fz: f64) -> Vec<PointLoad> {
    load(m.contact, [fx, fy, fz], [0.0; 3])
}
