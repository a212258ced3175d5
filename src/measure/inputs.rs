//! Assembling measurements from data file texts, shared by `identify`,
//! `locate`, `correct` (and `diagnose`): landmark CSV and IGES files read into
//! observations with their steps numbered, part poses fitted, load cases
//! matched to the steps, K&C channels attached. Text in (already in the
//! [`SourceMap`], so diagnostics can quote it), data and diagnostics out: no
//! file system, no printing.

use crate::diagnostic::suggest::did_you_mean;
use crate::diagnostic::{Diagnostic, Severity};
use crate::identify::measured::{self, Measured};
use crate::measure::poses::{MeasureIssue, Observation, StepPoses};
use crate::model::{LoadSetId, Model};
use crate::source::SourceMap;
use crate::span::{FileId, Span};

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LandmarkFormat {
    /// `step, part, landmark, x, y, z`: keeps its step column.
    Csv,
    /// One measured state per file (points named `part.landmark`).
    Iges,
}

/// A landmark file already in the source map (IGES as its 80-column text).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LandmarkFile {
    pub id: FileId,
    pub format: LandmarkFormat,
}

/// What reading found besides its result: warnings about data left out, and
/// notes (which step an IGES file is, what else it holds).
#[derive(Debug, Clone, Default)]
pub struct Remarks {
    pub warnings: Vec<Diagnostic>,
    pub notes: Vec<String>,
}

/// Landmark observations from every file, with where each came from.
pub struct Landmarks {
    pub observations: Vec<Observation>,
    /// The file of each observation (parallel to `observations`).
    files: Vec<FileId>,
    names: Vec<String>,
}

/// Byte range of 1-based line `n` of `text`.
fn line_span(text: &str, n: usize) -> (usize, usize) {
    let start: usize = text
        .split_inclusive('\n')
        .take(n.saturating_sub(1))
        .map(str::len)
        .sum();
    let len = text[start..].find('\n').unwrap_or(text.len() - start);
    (start, start + len)
}

fn skipped_warning(id: FileId, s: &crate::data::landmarks::Skipped) -> Diagnostic {
    Diagnostic::warning("W0710", s.message.clone())
        .primary(Span::new(id, s.start, s.end), "left out")
}

/// Reads landmark files: CSV files keep their `step` column; IGES files are one
/// measured state each, numbered in the order given after the last CSV step.
pub fn read_landmarks(
    sources: &SourceMap,
    files: &[LandmarkFile],
    model: &Model,
    remarks: &mut Remarks,
) -> Result<Landmarks, Diagnostic> {
    let mut out = Landmarks {
        observations: Vec::new(),
        files: Vec::new(),
        names: files
            .iter()
            .map(|f| sources.name(f.id).to_string())
            .collect(),
    };
    for f in files.iter().filter(|f| f.format == LandmarkFormat::Csv) {
        let (obs, skipped) = crate::data::landmarks::read(sources.text(f.id), model)
            .map_err(|e| e.to_diagnostic(f.id))?;
        remarks
            .warnings
            .extend(skipped.iter().map(|s| skipped_warning(f.id, s)));
        out.files.extend(obs.iter().map(|_| f.id));
        out.observations.extend(obs);
    }
    let first = out.observations.iter().map(|o| o.step).max().unwrap_or(0) + 1;
    let iges = files.iter().filter(|f| f.format == LandmarkFormat::Iges);
    for (k, f) in iges.enumerate() {
        let text = sources.text(f.id);
        let file = crate::data::iges::parse(text).map_err(|e| e.to_diagnostic(f.id))?;
        remarks.warnings.extend(file.warnings.iter().map(|w| {
            let mut d = w.to_diagnostic(f.id);
            d.severity = Severity::Warning;
            d
        }));
        let step = first + k;
        let (obs, skipped) = crate::data::landmarks::from_iges(&file, step, text, model);
        remarks
            .warnings
            .extend(skipped.iter().map(|s| skipped_warning(f.id, s)));
        remarks.notes.push(format!(
            "{} is step {step}: {} landmark points",
            sources.name(f.id),
            obs.len()
        ));
        remarks
            .notes
            .extend(geometry_notes(&file).into_iter().map(|l| format!("  {l}")));
        out.files.extend(obs.iter().map(|_| f.id));
        out.observations.extend(obs);
    }
    Ok(out)
}

/// What an IGES file holds besides points: lines and planes are listed (the
/// thesis measures joint axes and faces with them; `locate` finds axes from
/// motion instead), other entity types counted.
fn geometry_notes(file: &crate::data::iges::Iges) -> Vec<String> {
    use crate::data::iges::Geometry;
    let f = |v: crate::geom::Vec3| format!("({:.3}, {:.3}, {:.3})", v.x, v.y, v.z);
    let mut notes = Vec::new();
    let mut other: std::collections::BTreeMap<i64, usize> = Default::default();
    for e in &file.entities {
        let name = e.name().unwrap_or("(unnamed)");
        match &e.geometry {
            Some(Geometry::Line { from, to }) => notes.push(format!(
                "line `{name}` (D {}) from {} to {}: read, not used by locate",
                e.de,
                f(*from),
                f(*to)
            )),
            Some(Geometry::Plane { normal, offset }) => notes.push(format!(
                "plane `{name}` (D {}) normal {} at {offset:.3} mm: read, not used by locate",
                e.de,
                f(*normal)
            )),
            Some(Geometry::Point(_)) => {}
            None if matches!(e.kind, 124 | 406) => {}
            None => *other.entry(e.kind).or_default() += 1,
        }
    }
    for (kind, n) in other {
        notes.push(format!(
            "{n} entit{} of IGES type {kind} ignored",
            if n == 1 { "y" } else { "ies" }
        ));
    }
    notes
}

impl Landmarks {
    /// The files, for messages.
    pub fn shown(&self) -> String {
        self.names.join(", ")
    }

    /// The line of the first observation of `step` (for a diagnostic).
    pub fn span_of_step(&self, sources: &SourceMap, step: usize) -> Option<Span> {
        self.observations
            .iter()
            .zip(&self.files)
            .find(|(o, _)| o.step == step)
            .map(|(o, id)| {
                let (a, b) = line_span(sources.text(*id), o.line);
                Span::new(*id, a, b)
            })
    }

    /// Fits every part's pose at every step; what was left out becomes a
    /// warning pointing at the line of the data file it came from.
    pub fn fit(
        &self,
        sources: &SourceMap,
        model: &Model,
        tolerance: f64,
        remarks: &mut Remarks,
    ) -> Vec<StepPoses> {
        let (steps, issues) =
            crate::measure::poses::fit_poses(model, &self.observations, tolerance);
        let at = |step: usize, line: usize| {
            self.observations
                .iter()
                .zip(&self.files)
                .find(|(o, _)| o.step == step && o.line == line)
                .map(|(_, id)| {
                    let (a, b) = line_span(sources.text(*id), line);
                    Span::new(*id, a, b)
                })
        };
        remarks.warnings.extend(issues.iter().map(|i| {
            let d = Diagnostic::warning("W0711", i.message(model));
            let (span, label) = match i {
                MeasureIssue::LeftOut { step, line, .. } => (at(*step, *line), "left out"),
                MeasureIssue::NoPose { step, lines, .. } => {
                    (lines.first().and_then(|l| at(*step, *l)), "no pose")
                }
            };
            match span {
                Some(s) => d.primary(s, label),
                None => d,
            }
        }));
        steps
    }

    /// The fitted step numbered `step`, or the first; E0808 when there is none.
    pub fn step<'a>(
        &self,
        steps: &'a [StepPoses],
        step: Option<usize>,
    ) -> Result<&'a StepPoses, Diagnostic> {
        let found = match step {
            Some(n) => steps.iter().find(|s| s.step == n),
            None => steps.first(),
        };
        found.ok_or_else(|| {
            let have: Vec<String> = steps.iter().map(|s| s.step.to_string()).collect();
            let d = match step {
                Some(n) => {
                    Diagnostic::error("E0808", format!("no measured step {n} in {}", self.shown()))
                }
                None => Diagnostic::error(
                    "E0807",
                    format!("no step of {} gives a part pose", self.shown()),
                ),
            };
            match have.is_empty() {
                true => d.note("no step has enough matched landmarks on any part"),
                false => d.note(format!("the steps with poses: {}", have.join(", "))),
            }
        })
    }
}

/// The set named `name`, or the model's default set. An unknown name gets a
/// did-you-mean and the list of sets (E0801; E0802 without a default).
pub fn pick_set(m: &Model, name: Option<&str>) -> Result<LoadSetId, Diagnostic> {
    let names = || m.load_sets.iter().map(|s| s.name.as_str());
    let listing = || {
        let all: Vec<&str> = names().collect();
        if all.is_empty() {
            "the model has no load-case sets (write a `loads` block, or `import mcpherson_loads`)"
                .to_string()
        } else {
            format!("the model's load-case sets: {}", all.join(", "))
        }
    };
    match name {
        Some(n) => m.load_set_named(n).ok_or_else(|| {
            let d = Diagnostic::error("E0801", format!("the model has no load-case set `{n}`"))
                .note(listing());
            match did_you_mean(n, names()) {
                Some(h) => d.hint(h),
                None if ["bump", "lateral", "longitudinal"].contains(&n) => {
                    d.hint("the K&C sweeps come with `import mcpherson_loads`")
                }
                None => d,
            }
        }),
        None => m.default_load_set.ok_or_else(|| {
            Diagnostic::error(
                "E0802",
                "no load-case set named and the model has no `default loads`",
            )
            .note(listing())
            .hint("name one with --loadcases SET, or give loads with --loads CSV")
        }),
    }
}

/// Where the loads of the measured steps come from.
#[derive(Debug, Clone, Copy)]
pub enum LoadSource<'a> {
    /// A K&C CSV: its forces are the loads and its channels are attached.
    Kc(FileId),
    /// A loads CSV: step, fx, fy, fz [, mx, my, mz].
    Loads(FileId),
    /// A load-case set of the model (or its default), matched to the steps in order.
    Set(Option<&'a str>),
}

/// The measured steps: poses and, per step, the loads (and K&C channels).
pub fn assemble(
    sources: &SourceMap,
    model: &Model,
    poses: &[StepPoses],
    loads: LoadSource,
) -> Result<Measured, Diagnostic> {
    let steps: Vec<usize> = poses.iter().map(|p| p.step).collect();
    let mut kc = Vec::new();
    let loads = match loads {
        LoadSource::Kc(id) | LoadSource::Loads(id) => {
            let text = sources.text(id);
            let (l, _) = measured::loads_of_file(model, text).map_err(|e| e.to_diagnostic(id))?;
            if let LoadSource::Kc(_) = loads {
                kc = measured::kc_channels(model, text).map_err(|e| e.to_diagnostic(id))?;
                // Every step measured by both, or the files are of two runs.
                measured::same_steps(&kc, &steps).map_err(|why| {
                    Diagnostic::error("E0809", why).primary(Span::new(id, 0, 0), "this K&C file")
                })?;
            }
            l
        }
        LoadSource::Set(name) => {
            let set = pick_set(model, name)?;
            measured::match_in_order(measured::loads_of_set(model, set), &steps)
                .map_err(|e| e.to_diagnostic(model))?
        }
    };
    let mut data =
        Measured::from_poses(model, poses, &loads).map_err(|e| e.to_diagnostic(model))?;
    measured::attach_kc(&mut data, &kc);
    Ok(data)
}
