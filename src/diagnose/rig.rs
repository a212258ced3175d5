//! The rig data of a diagnosis: one K&C file per measured load path
//! (`interfaces.md`, "K&C rig data"), its rows in measurement order, read into
//! the wheel loads to replay and the channels to compare (`super::channel`).
//! Text in (already in the source map), data or a located diagnostic out.

use super::channel::{self, Measured};
use crate::data::table;
use crate::diagnostic::Diagnostic;
use crate::diagnostic::suggest::did_you_mean;
use crate::geom::Vec3;
use crate::identify::measured::{kc_channels, loads_of_file};
use crate::model::{LandmarkId, MarkerId, Model, PointLoad, WheelId};
use crate::span::{FileId, Span};

/// One measured step of a path.
#[derive(Debug, Clone, PartialEq)]
pub struct RigStep {
    /// The step number of the file.
    pub step: usize,
    pub loads: Vec<PointLoad>,
    /// The measured channels of the path's wheel.
    pub measured: Measured,
    /// The landmarks measured at this step (`--landmarks`): each matched to
    /// its declared landmark, in the model frame ([`super::landmarks`]).
    pub landmarks: Vec<(LandmarkId, Vec3)>,
}

/// One load path as the rig ran it.
#[derive(Debug, Clone, PartialEq)]
pub struct RigPath {
    /// The file's name, for tables and the report.
    pub name: String,
    pub file: FileId,
    pub wheel: WheelId,
    /// The wheel's contact marker: where its loads apply (an axle's path
    /// also carries the other wheel's).
    pub contact: MarkerId,
    pub steps: Vec<RigStep>,
    /// What the landmarks' rigid pose fits left: the sum of squared
    /// residuals (mm²) and its degrees of freedom, for the landmark noise.
    pub pose_fit: PoseFitResidual,
    /// `part.landmark` of every landmark of the model, by id (for words).
    pub landmark_names: Vec<String>,
}

/// The residual of the pose fits of a path's landmarks.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct PoseFitResidual {
    pub sum_sq: f64,
    pub dof: usize,
}

/// Reads one K&C file for `model`: one path per wheel the file measures (an
/// axle's file has a row per wheel and step). Every path replays the loads of
/// all the file's rows (both wheels loaded, as on the rig) and compares the
/// channels of its own wheel; a file of several wheels names its paths
/// `NAME[WHEEL]`.
pub fn read(
    model: &Model,
    file: FileId,
    name: &str,
    text: &str,
) -> Result<Vec<RigPath>, Diagnostic> {
    let csv = |e: crate::data::CsvError| e.to_diagnostic(file);
    let wheels = wheels_of(model, file, text)?;
    let (loads, _) = loads_of_file(model, text).map_err(csv)?;
    let channels = kc_channels(model, text).map_err(csv)?;
    let mut paths = Vec::with_capacity(wheels.len());
    for &wheel in &wheels {
        let design = channel::design(model, wheel);
        let mut steps = Vec::with_capacity(loads.len());
        for (step, l) in &loads {
            let Some((_, obs)) = channels.iter().find(|(s, o)| s == step && o.wheel == wheel)
            else {
                continue;
            };
            steps.push(RigStep {
                step: *step,
                loads: l.clone(),
                measured: channel::of_observation(&design, obs),
                landmarks: Vec::new(),
            });
        }
        if steps.is_empty() {
            return Err(Diagnostic::error("E1301", "the K&C file has no measured step")
                .primary(Span::new(file, 0, 0), "no data row")
                .hint("a K&C file has a header row and one row per step: step, fx, fy, fz, wc_x, wc_y, wc_z, toe_deg, camber_deg"));
        }
        paths.push(RigPath {
            name: if wheels.len() == 1 {
                name.to_string()
            } else {
                format!("{name}[{}]", model.wheels[wheel.index()].name)
            },
            file,
            wheel,
            contact: model.wheels[wheel.index()].contact,
            steps,
            pose_fit: PoseFitResidual::default(),
            landmark_names: model
                .landmarks
                .iter()
                .map(|l| format!("{}.{}", model.part(l.part).name, l.name))
                .collect(),
        });
    }
    Ok(paths)
}

/// The wheels a K&C file measures, in the order they first appear: its
/// `wheel` column, or the model's only wheel.
fn wheels_of(model: &Model, file: FileId, text: &str) -> Result<Vec<WheelId>, Diagnostic> {
    let t = table::parse(text).map_err(|e| e.to_diagnostic(file))?;
    let names: Vec<&str> = model.wheels.iter().map(|w| w.name.as_str()).collect();
    let Some(col) = t.column("wheel") else {
        return match model.wheels.len() {
            1 => Ok(vec![WheelId(0)]),
            0 => Err(Diagnostic::error(
                "E1302",
                "the model has no wheel, so K&C channels cannot be compared",
            )
            .primary(Span::new(file, t.header.start, t.header.end), "K&C columns")
            .hint("declare a `wheel` with its centre and contact markers")),
            _ => Err(Diagnostic::error(
                "E1302",
                format!(
                    "the model has {} wheels and the K&C file has no `wheel` column to say which it measures",
                    model.wheels.len()
                ),
            )
            .primary(Span::new(file, t.header.start, t.header.end), "no `wheel` column")
            .hint(format!("add a `wheel` column naming one of: {}", names.join(", ")))),
        };
    };
    let mut found: Vec<WheelId> = Vec::new();
    for row in &t.rows {
        let Some(f) = row.fields.get(col) else {
            continue;
        };
        let Some(k) = names.iter().position(|n| *n == f.text) else {
            let d = Diagnostic::error("E1302", format!("the model has no wheel `{}`", f.text))
                .primary(Span::new(file, f.start, f.end), "not a wheel of the model");
            return Err(match did_you_mean(f.text, names.iter().copied()) {
                Some(s) => d.hint(format!("did you mean `{s}`?")),
                None => d.hint(format!("the model's wheels: {}", names.join(", "))),
            });
        };
        let id = WheelId(k as u32);
        if !found.contains(&id) {
            found.push(id);
        }
    }
    if found.is_empty() {
        return Err(
            Diagnostic::error("E1301", "the K&C file has no measured step")
                .primary(Span::new(file, t.header.start, t.header.end), "header only"),
        );
    }
    Ok(found)
}

impl RigPath {
    /// Whether any step carries landmarks.
    pub fn has_landmarks(&self) -> bool {
        self.steps.iter().any(|s| !s.landmarks.is_empty())
    }

    /// The component of the path's wheel load that varies most along the path
    /// (the sweep's load): its name and its value (N) at every step.
    pub fn main_load(&self) -> (&'static str, Vec<f64>) {
        let names = ["fx", "fy", "fz"];
        let series: Vec<Vec<f64>> = (0..3)
            .map(|c| {
                self.steps
                    .iter()
                    .map(|s| {
                        s.loads
                            .iter()
                            .filter(|l| l.marker == self.contact)
                            .map(|l| l.force[c])
                            .sum()
                    })
                    .collect()
            })
            .collect();
        let range = |v: &[f64]| {
            v.iter().cloned().fold(f64::NEG_INFINITY, f64::max)
                - v.iter().cloned().fold(f64::INFINITY, f64::min)
        };
        let k = (0..3)
            .max_by(|&a, &b| range(&series[a]).total_cmp(&range(&series[b])))
            .unwrap_or(2);
        (names[k], series[k].clone())
    }
}
