//! The identification input: per measured step, the applied loads and the
//! measured pose of each part (from landmark pose fits, or from solved states
//! in tests), and optionally the K&C channels measured at that step.
//!
//! Loads come from a K&C file (its `fx, fy, fz[, mx, my, mz]` columns), a
//! loads file, or a load-case set of the model matched to the steps in order.

use super::{IdentifyError, IdentifyErrorKind};
use crate::data::CsvError;
use crate::data::table;
use crate::geom::{Mat3, Vec3};
use crate::measure::poses::StepPoses;
use crate::model::{ElementId, LoadSet, LoadSetId, Model, PartId, PointLoad, WheelId};
use crate::statics::State;

/// K&C channels of one step (`interfaces.md`, "K&C rig data") of one wheel.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KcObservation {
    /// The wheel measured (the row's `wheel`, or the model's only wheel).
    pub wheel: WheelId,
    pub toe_deg: f64,
    pub camber_deg: f64,
    /// Wheel centre, mm, global.
    pub wc: Vec3,
}

#[derive(Debug, Clone, PartialEq)]
pub struct MeasuredStep {
    /// The step number of the data files.
    pub step: usize,
    pub loads: Vec<PointLoad>,
    /// Pose (origin, rotation) of each part, indexed like `Model::parts`;
    /// `None` for a part not measured at this step. Ground is the identity.
    pub poses: Vec<Option<(Vec3, Mat3)>>,
    /// The K&C channels measured at this step, one per wheel measured.
    pub kc: Vec<KcObservation>,
    /// The measured pose of the ground (chassis) at this step after the
    /// registration to the model frame, when the ground has landmarks. The
    /// registration is one rigid transform fitted from every step, so its error
    /// is common to all steps; least squares re-estimates it from these poses.
    pub ground: Option<(Vec3, Mat3)>,
}

#[derive(Debug, Clone, PartialEq, Default)]
pub struct Measured {
    pub steps: Vec<MeasuredStep>,
}

impl Measured {
    /// Steps from landmark pose fits and one load case per step, in step order.
    pub fn from_poses(
        model: &Model,
        poses: &[StepPoses],
        loads: &[(usize, Vec<PointLoad>)],
    ) -> Result<Measured, IdentifyError> {
        let mut steps = Vec::with_capacity(poses.len());
        for sp in poses {
            let Some((_, l)) = loads.iter().find(|(s, _)| *s == sp.step) else {
                return Err(IdentifyError::of(
                    IdentifyErrorKind::Data,
                    format!("step {} has landmarks but no loads", sp.step),
                    vec![],
                ));
            };
            let mut p: Vec<Option<(Vec3, Mat3)>> = vec![None; model.parts.len()];
            for (part, pose) in &sp.parts {
                p[part.index()] = Some((pose.translation, pose.rotation));
            }
            let mut ground = None;
            if let Some(g) = model.ground() {
                ground = p[g.index()];
                p[g.index()] = Some((Vec3::zeros(), Mat3::identity()));
            }
            steps.push(MeasuredStep {
                step: sp.step,
                loads: l.clone(),
                poses: p,
                kc: Vec::new(),
                ground,
            });
        }
        if steps.is_empty() {
            return Err(IdentifyError::of(
                IdentifyErrorKind::Data,
                "the landmark data give no pose",
                vec![],
            ));
        }
        Ok(Measured { steps })
    }

    /// Steps whose every part pose is taken from a solved state (synthetic data
    /// without landmarks, as the thesis' chapter 4 validations do).
    pub fn from_states(model: &Model, states: &[(State, Vec<PointLoad>)]) -> Measured {
        let steps = states
            .iter()
            .enumerate()
            .map(|(k, (st, l))| MeasuredStep {
                step: k + 1,
                loads: l.clone(),
                poses: (0..model.parts.len())
                    .map(|p| Some(st.part_pose(PartId(p as u32))))
                    .collect(),
                kc: Vec::new(),
                ground: None,
            })
            .collect();
        Measured { steps }
    }

    /// Whether `part` has a pose at every step.
    pub fn has_part(&self, part: PartId) -> bool {
        self.steps
            .iter()
            .all(|s| s.poses.get(part.index()).is_some_and(|p| p.is_some()))
    }

    /// The first moving part without a pose at some step.
    pub fn missing_part(&self, model: &Model) -> Option<PartId> {
        model.moving_parts().find(|p| !self.has_part(*p))
    }

    /// The measured configuration of step `k` as a statics state (parts
    /// without a pose at their design pose).
    pub fn state(&self, k: usize) -> State {
        let s = &self.steps[k];
        State {
            poses: s
                .poses
                .iter()
                .map(|p| p.unwrap_or((Vec3::zeros(), Mat3::identity())))
                .collect(),
            loads: Vec::new(),
            lambda: Vec::new(),
            slip: Vec::new(),
        }
    }
}

/// The loads of every case of a model's load set, numbered 1, 2, … (matched to
/// the landmark steps in order).
pub fn loads_of_set(model: &Model, set: LoadSetId) -> Vec<(usize, Vec<PointLoad>)> {
    let n = model
        .load_sets
        .get(set.index())
        .map_or(0, |s| s.cases.len());
    (0..n).map(|c| (c, model.point_loads(set, c))).collect()
}

/// Renumbers loads given in order to the measured steps in order.
pub fn match_in_order(
    loads: Vec<(usize, Vec<PointLoad>)>,
    steps: &[usize],
) -> Result<Vec<(usize, Vec<PointLoad>)>, IdentifyError> {
    if loads.len() != steps.len() {
        return Err(IdentifyError::of(
            IdentifyErrorKind::Data,
            format!(
                "the load-case set has {} cases but the landmarks have {} steps; they are matched in order",
                loads.len(),
                steps.len()
            ),
            vec![],
        ));
    }
    Ok(steps.iter().zip(loads).map(|(s, (_, l))| (*s, l)).collect())
}

/// The loads of a loads or K&C file, by step number.
pub fn loads_of_file(
    model: &Model,
    text: &str,
) -> Result<(Vec<(usize, Vec<PointLoad>)>, LoadSet), CsvError> {
    let set = crate::data::loads::read(text, "measured", model)?;
    let steps = step_numbers(text)?;
    let mut m = model.clone();
    m.load_sets.push(set.clone());
    let id = LoadSetId((m.load_sets.len() - 1) as u32);
    let out = steps
        .iter()
        .enumerate()
        .take(set.cases.len())
        .map(|(c, s)| (*s, m.point_loads(id, c)))
        .collect();
    Ok((out, set))
}

/// Distinct step numbers in order of first appearance (the order in which the
/// loads reader makes its cases).
fn step_numbers(text: &str) -> Result<Vec<usize>, CsvError> {
    let t = table::parse(text)?;
    let Some(c) = t.column("step") else {
        return Ok(Vec::new());
    };
    let mut out: Vec<usize> = Vec::new();
    for row in &t.rows {
        if let Some(f) = row.fields.get(c) {
            if let Ok(s) = f.text.parse::<usize>() {
                if !out.contains(&s) {
                    out.push(s);
                }
            }
        }
    }
    Ok(out)
}

/// The K&C channels of a K&C file, by step and wheel (the first row of each
/// step and wheel): the `wheel` column names the wheel of each row, required
/// when the model has several (an axle's file has a row per wheel and step).
pub fn kc_channels(model: &Model, text: &str) -> Result<Vec<(usize, KcObservation)>, CsvError> {
    let t = table::parse(text)?;
    let wheel_col = t.column("wheel");
    let names = ["step", "toe_deg", "camber_deg", "wc_x", "wc_y", "wc_z"];
    let mut cols = [0usize; 6];
    for (k, n) in names.iter().enumerate() {
        cols[k] = t.column(n).ok_or_else(|| {
            CsvError::new(
                "E0703",
                format!("the K&C file has no column `{n}`"),
                (t.header.start, t.header.end),
                "header row",
            )
            .with_hint(Some(
                "a K&C file has the columns step, fx, fy, fz, wc_x, wc_y, wc_z, toe_deg, camber_deg"
                    .into(),
            ))
        })?;
    }
    let mut out: Vec<(usize, KcObservation)> = Vec::new();
    for row in &t.rows {
        let mut v = [0.0; 6];
        for k in 0..6 {
            let Some(f) = row.fields.get(cols[k]) else {
                return Err(CsvError::new(
                    "E0704",
                    format!("line {} has fewer fields than the header", row.line),
                    (row.start, row.end),
                    "this row",
                ));
            };
            v[k] = match f.text.parse::<f64>() {
                Ok(x) if x.is_finite() => x,
                _ => {
                    return Err(CsvError::new(
                        "E0705",
                        format!("`{}` is not a number (column `{}`)", f.text, names[k]),
                        (f.start, f.end),
                        "not a number",
                    ));
                }
            };
        }
        let step = v[0] as usize;
        if v[0] < 0.0 || v[0].fract() != 0.0 {
            let f = &row.fields[cols[0]];
            return Err(CsvError::new(
                "E0705",
                format!("`{}` is not a step number", f.text),
                (f.start, f.end),
                "in column `step`",
            ));
        }
        let wheel =
            crate::data::loads::wheel_of(model, wheel_col.and_then(|c| row.fields.get(c)), row)?;
        if out.iter().all(|(s, o)| *s != step || o.wheel != wheel) {
            out.push((
                step,
                KcObservation {
                    wheel,
                    toe_deg: v[1],
                    camber_deg: v[2],
                    wc: Vec3::new(v[3], v[4], v[5]),
                },
            ));
        }
    }
    Ok(out)
}

/// The K&C file and the landmarks must measure the same steps: a step of one
/// missing from the other is a file of another run, or rows lost.
pub fn same_steps(kc: &[(usize, KcObservation)], landmark_steps: &[usize]) -> Result<(), String> {
    let kc_steps: std::collections::BTreeSet<usize> = kc.iter().map(|(s, _)| *s).collect();
    let lm: std::collections::BTreeSet<usize> = landmark_steps.iter().copied().collect();
    if kc_steps == lm {
        return Ok(());
    }
    let list = |v: Vec<&usize>| {
        let shown: Vec<String> = v.iter().take(8).map(|s| s.to_string()).collect();
        let more = if v.len() > 8 { ", ..." } else { "" };
        format!("{}{more}", shown.join(", "))
    };
    let only_kc: Vec<&usize> = kc_steps.difference(&lm).collect();
    let only_lm: Vec<&usize> = lm.difference(&kc_steps).collect();
    let mut why = format!(
        "the K&C file has {} steps and the landmarks {}",
        kc_steps.len(),
        lm.len()
    );
    if !only_kc.is_empty() {
        why += &format!("; steps {} have no landmarks", list(only_kc));
    }
    if !only_lm.is_empty() {
        why += &format!("; steps {} have no K&C row", list(only_lm));
    }
    Err(why)
}

/// Attaches K&C channels to the steps with the same number.
pub fn attach_kc(measured: &mut Measured, kc: &[(usize, KcObservation)]) {
    for s in &mut measured.steps {
        s.kc = kc
            .iter()
            .filter(|(k, _)| *k == s.step)
            .map(|(_, o)| *o)
            .collect();
    }
}

/// The error for a part every step must measure.
pub fn unmeasured(model: &Model, part: PartId, method: &str) -> IdentifyError {
    IdentifyError::of(
        IdentifyErrorKind::Method,
        format!(
            "the {method} method needs the pose of every moving part at every step, and part `{}` has none (no landmarks, or too few matched); identify with a model without it (thesis §4.3.3 replaces the strut by an inline joint) or use --method iterative or lsq",
            model.part(part).name
        ),
        vec![ElementId::Part(part)],
    )
}
