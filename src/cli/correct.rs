//! `axle correct FILE --landmarks CSV|IGES... [--step N] [--loadcases SET] --case NAME -o OUT.axle`.

use super::Exit;
use crate::diagnostic::render;
use crate::source::SourceMap;
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct Args {
    /// The axle model, with its parts as measured disassembled.
    pub file: PathBuf,
    /// Landmarks of the assembled axle: CSV (step, part, landmark, x, y, z)
    /// and/or IGES files of one measured state each (see `axle locate`).
    #[arg(long, required = true, num_args = 1..)]
    pub landmarks: Vec<PathBuf>,
    /// The measured step to correct against (default: the first).
    #[arg(long)]
    pub step: Option<usize>,
    /// The load set holding the measured case (default: the file's default set).
    #[arg(long, value_name = "SET")]
    pub loadcases: Option<String>,
    /// The load case the axle was measured under.
    #[arg(long, value_name = "CASE")]
    pub case: String,
    /// Write the corrected model (designed at the measured state) here.
    #[arg(short = 'o', long = "output")]
    pub output: Option<PathBuf>,
    /// Landmark matching tolerance, mm.
    #[arg(long, default_value_t = 0.5)]
    pub tolerance: f64,
}

pub fn run(a: &Args) -> Exit {
    let mut sources = SourceMap::new();
    let text = match super::read(&a.file) {
        Ok(t) => t,
        Err(e) => return e,
    };
    let id = sources.add(super::read::shown(&a.file), text);
    let checked = crate::check::check_file(&mut sources, id);
    render::to_stderr(&sources, &checked.problems.list);
    let Some(model) = checked.model else {
        return Exit::Input;
    };
    let fail = |d: crate::diagnostic::Diagnostic| {
        render::to_stderr(&sources, &[d]);
        Exit::Input
    };
    let set = match crate::measure::inputs::pick_set(&model, a.loadcases.as_deref()) {
        Ok(s) => s,
        Err(d) => return fail(d),
    };
    let ls = &model.load_sets[set.index()];
    let Some(case) = ls.cases.iter().position(|c| c.name == a.case) else {
        let d = crate::diagnostic::Diagnostic::error(
            "E0805",
            format!("load set `{}` has no case `{}`", ls.name, a.case),
        );
        let names = ls.cases.iter().map(|c| c.name.as_str());
        let d = match crate::diagnostic::suggest::did_you_mean(&a.case, names) {
            Some(h) => d.hint(h),
            None => d,
        };
        return fail(d);
    };
    let loads = model.point_loads(set, case);
    let (data, steps) =
        match super::locate::landmarks(&mut sources, &a.landmarks, &model, a.tolerance) {
            Ok(d) => d,
            Err(code) => return code,
        };
    let measured = match data.step(&steps, a.step) {
        Ok(s) => s,
        Err(d) => {
            render::to_stderr(&sources, &[d]);
            return Exit::Input;
        }
    };
    // A part with landmarks missing at the measured step: an error, not an
    // element silently left uncorrected.
    let purpose = crate::locate::preflight::Purpose::Correct;
    let one = std::slice::from_ref(measured);
    if let Some(d) = super::locate::preflight(&data, &model, one, purpose) {
        render::to_stderr(&sources, &[d]);
        return Exit::Input;
    }
    let c = match crate::locate::correct::correct(&model, measured, &loads) {
        Ok(c) => c,
        Err(e) => {
            render::to_stderr(&sources, &[e.to_diagnostic(&model)]);
            return Exit::Input;
        }
    };
    // The output model is written first: the table on stdout is the last word.
    if let Some(out) = &a.output {
        let new = crate::locate::correct::redesign(&c.model, &c.state);
        let text = match super::model_out::edited(&sources, id, &model, &new, "correct", &[]) {
            Ok(t) => t,
            Err(code) => return code,
        };
        let code = super::input::emit(Some(out), &text);
        if code != Exit::Ok {
            return code;
        }
    }
    let mut o = format!(
        "corrected against step {} under case `{}` ({} passes)\n",
        measured.step, a.case, c.iterations
    );
    o += &format!("{:<12} {:>10}\n", "element", "moved (mm)");
    for (e, d) in &c.moved {
        o += &format!("{:<12} {d:>10.3}\n", model.describe(*e));
    }
    for (e, why) in &c.skipped {
        o += &format!("{:<12} not corrected: {why}\n", model.describe(*e));
    }
    o += &format!(
        "largest landmark misfit of the corrected equilibrium: {:.3} mm\n",
        c.misfit
    );
    super::input::emit(None, &o)
}
