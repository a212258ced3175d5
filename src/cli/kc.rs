//! `axle kc FILE --sweep bump|lateral|longitudinal|SET [--plot OUT.svg] [--format …] [-o OUT]`.

use super::input::{emit, load_model, pick_set_reported};
use super::{Exit, OutFormat};
use crate::diagnostic::Diagnostic;
use crate::kc::{AxleMetrics, ComplianceMetrics, SteeringMetrics};
use crate::kc::{
    KcRow, Motion, axle_metrics, compliance_metrics, driven_rack, kc_rows, rack_travel,
    steering_metrics,
};
use crate::model::{Component, LoadForm, LoadSet, LoadSetId, Model};
use crate::output::number::fixed;
use crate::output::plot::{Note, Quantity, Sweep, annotated_svg};
use crate::output::warning;
use crate::output::{columns, kc_table, solve_json};
use crate::statics::{self, Equilibrium, Problem};
use std::path::PathBuf;

pub struct Args {
    pub file: PathBuf,
    pub sweep: String,
    pub plot: Option<PathBuf>,
    /// Force elements to leave out for the roll stiffness "without" them.
    pub without: Vec<String>,
    pub format: OutFormat,
    pub output: Option<PathBuf>,
}

/// What the plots are drawn against: the swept channel of a sweep, else the
/// one component a table varies, else (a mixed table) the case; a vertical
/// sweep is a bump sweep.
fn sweep_kind(set: &LoadSet) -> Sweep {
    if let LoadForm::Table = set.form {
        let varies = |i: usize| {
            set.cases
                .iter()
                .any(|c| c.values[i] != set.cases[0].values[i])
        };
        if (0..set.channels.len()).filter(|&i| varies(i)).count() > 1 {
            return Sweep::Case;
        }
    }
    let comp = match &set.form {
        LoadForm::Sweep { swept } => swept
            .first()
            .and_then(|s| set.channels.get(s.channel))
            .map(|c| c.component),
        LoadForm::Table => (0..set.channels.len())
            .map(|i| {
                let (lo, hi) = set
                    .cases
                    .iter()
                    .map(|c| c.values[i])
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
                        (a.min(v), b.max(v))
                    });
                (hi - lo, i)
            })
            .max_by(|a, b| a.0.total_cmp(&b.0))
            .and_then(|(_, i)| set.channels.get(i).map(|c| c.component)),
    };
    match comp {
        Some(Component::Fz) | None => Sweep::Bump,
        Some(c) => Sweep::Force(c as usize),
    }
}

const COMPLIANCE_AXES: [&str; 3] = ["x", "y", "z"];

/// The wheel-centre compliance at the first step, per wheel: translational block, mm/kN.
fn wheel_compliances(
    problem: &Problem,
    model: &Model,
    first: &Equilibrium,
) -> Vec<(String, [[f64; 3]; 3])> {
    let centres: Vec<_> = model.wheels.iter().map(|w| w.centre).collect();
    let Ok(each) = statics::compliances(problem, first, &centres) else {
        return Vec::new();
    };
    model
        .wheels
        .iter()
        .zip(each)
        .filter_map(|(w, c)| {
            c.ok().map(|c| {
                (
                    w.name.clone(),
                    [0, 1, 2].map(|i| [0, 1, 2].map(|j| c[i][j] * 1000.0)),
                )
            })
        })
        .collect()
}

fn compliance_table(c: &[(String, [[f64; 3]; 3])]) -> String {
    let mut out = String::new();
    for (w, m) in c {
        out += &format!(
            "\nwheel-centre compliance of {w} at the first step (displacement per force at the centre, mm/kN)\n"
        );
        let cols = [
            columns::col("", "", 0),
            columns::col("Fx", "", 4),
            columns::col("Fy", "", 4),
            columns::col("Fz", "", 4),
        ];
        let rows: Vec<Vec<columns::Cell>> = m
            .iter()
            .enumerate()
            .map(|(i, r)| {
                let mut row = vec![columns::Cell::Text(format!("d{}", COMPLIANCE_AXES[i]))];
                row.extend(r.map(columns::Cell::Num));
                row
            })
            .collect();
        out += &columns::render(&cols, &rows, "  ");
    }
    out
}

/// The metrics written under the plots' panels: the slopes of the toe and
/// camber curves under those panels, the wheel rate and roll stiffness under
/// the load, the roll centre and the steering geometry under the half-track
/// change (`docs/kc.md`).
fn plot_notes(
    axles: &[AxleMetrics],
    events: &[ComplianceMetrics],
    steering: Option<&SteeringMetrics>,
) -> Vec<Note> {
    let mut notes = Vec::new();
    let mut note = |panel, text: String| notes.push(Note { panel, text });
    let g = |v: f64, d: usize| fixed(v, d, 0);
    for a in axles {
        let (steer, camber, unit) = match a.motion {
            Motion::Parallel => ("bump steer", "bump camber", "deg/mm"),
            Motion::Opposed => ("roll steer", "roll camber", "deg/deg"),
        };
        let d = if a.motion == Motion::Parallel { 5 } else { 4 };
        for w in &a.wheels {
            note(
                Quantity::Toe,
                format!("{steer} {}: {} {unit}", w.wheel, g(w.toe, d)),
            );
            note(
                Quantity::Camber,
                format!("{camber} {}: {} {unit}", w.wheel, g(w.camber, d)),
            );
            if let Some(k) = w.rate {
                note(
                    Quantity::Load,
                    format!("wheel rate {}: {} N/mm", w.wheel, g(k, 2)),
                );
            }
        }
        match (a.roll_centre, a.roll_stiffness) {
            (Some([_, z]), _) => note(
                Quantity::HalfTrack,
                format!("roll centre height {} mm", g(z, 1)),
            ),
            (None, Some(k)) => note(
                Quantity::Load,
                match &a.roll_stiffness_without {
                    Some((kw, names)) => format!(
                        "roll stiffness {} N*m/deg, {} without {}",
                        g(k, 1),
                        g(*kw, 1),
                        names.join(", ")
                    ),
                    None => format!("roll stiffness {} N*m/deg", g(k, 1)),
                },
            ),
            (None, None) if a.motion == Motion::Parallel => {
                note(Quantity::HalfTrack, "roll centre at infinity".to_string())
            }
            _ => {}
        }
    }
    for e in events {
        let per = e.input.per();
        let phase = e.phase.map_or(String::new(), |p| {
            format!(" ({})", p.name().replace('_', " "))
        });
        for w in &e.wheels {
            note(
                Quantity::Toe,
                format!(
                    "compliance steer {}{phase}: {} deg/{per}",
                    w.wheel,
                    g(w.toe, 5)
                ),
            );
            note(
                Quantity::Camber,
                format!(
                    "compliance camber {}{phase}: {} deg/{per}",
                    w.wheel,
                    g(w.camber, 5)
                ),
            );
        }
    }
    if let Some(s) = steering {
        for w in &s.wheels {
            note(
                Quantity::Toe,
                format!(
                    "steer/travel {}: {} deg/mm",
                    w.wheel,
                    g(w.steer_per_travel, 5)
                ),
            );
            note(
                Quantity::HalfTrack,
                format!(
                    "{}: caster {} deg, KPI {} deg, scrub {} mm, trail {} mm",
                    w.wheel,
                    g(w.caster_deg, 2),
                    g(w.kpi_deg, 2),
                    g(w.scrub_mm, 1),
                    g(w.trail_mm, 1)
                ),
            );
        }
    }
    notes
}

/// The roll stiffness of every axle the path rolls, on the model without the
/// force elements `names` (`kc::without`), solved along the steps `rows`
/// (the K&C rows of the model with them) reach. A name that is no force element is a usage error; a
/// path that rolls no axle is warned about.
fn roll_stiffness_without(
    loaded: &super::input::Loaded,
    set: LoadSetId,
    names: &[String],
    rows: &[KcRow],
    axles: &mut [AxleMetrics],
) -> Result<(), Exit> {
    let solved = rows.iter().map(|r| r.step).max().unwrap_or(0);
    let model = &loaded.model;
    let bare = crate::kc::without::without(model, names).map_err(|d| {
        loaded.report(&[d]);
        Exit::Io
    })?;
    if !axles.iter().any(|a| a.motion == Motion::Opposed) {
        loaded.report(&[Diagnostic::warning(
            "W0812",
            format!(
                "--without {}: the path rolls no axle (no opposed wheel travel), so there is no roll stiffness to give without them",
                names.join(" ")
            ),
        )]);
        return Ok(());
    }
    let note = format!("in the model without {}", names.join(", "));
    let problem = Problem::new(&bare).map_err(|e| {
        loaded.report(&[e.to_diagnostic(&bare).note(note.clone())]);
        Exit::Input
    })?;
    let run = crate::statics::path::run_set(&problem, set, &crate::statics::State::design(&bare));
    if let Some(e) = run.failure.filter(|e| e.case < solved) {
        loaded.report(&[e
            .error
            .to_diagnostic(&bare)
            .note(format!("{note}, at step {}", e.case + 1))]);
        return Err(Exit::Input);
    }
    // What the path's warnings say of the model without them (a bushing
    // deformed past any rubber's travel, a wheel below the ground) is said
    // of the figure given for it.
    let cases: Vec<String> = bare.load_sets[set.index()]
        .cases
        .iter()
        .map(|c| c.name.clone())
        .collect();
    let eqs = &run.steps[..solved.min(run.steps.len())];
    let warnings: Vec<Diagnostic> = warning::of_path(&bare, &cases, eqs)
        .into_iter()
        .map(|w| w.note(note.clone()))
        .collect();
    loaded.report(&warnings);
    let states: Vec<_> = eqs.iter().map(|e| &e.state).collect();
    let their_rows = kc_rows(&bare, set, &states);
    let theirs = axle_metrics(&bare, &their_rows);
    for a in axles.iter_mut().filter(|a| a.motion == Motion::Opposed) {
        let same = theirs.iter().find(|b| {
            b.motion == Motion::Opposed
                && b.wheels[0].wheel == a.wheels[0].wheel
                && b.wheels[1].wheel == a.wheels[1].wheel
        });
        let Some((b, k)) = same.and_then(|b| b.roll_stiffness.map(|k| (b, k))) else {
            continue;
        };
        // A slope at another ride height is another suspension's: say so.
        let rise = mean_travel(&their_rows, b) - mean_travel(rows, a);
        if rise.abs() > 1.0 {
            loaded.report(&[Diagnostic::warning(
                "W0813",
                format!(
                    "without {} the wheels {} / {} stand {} mm {} at the reference step: the roll stiffness without them is taken at another ride height",
                    names.join(", "),
                    a.wheels[0].wheel,
                    a.wheels[1].wheel,
                    fixed(rise.abs(), 1, 0),
                    if rise > 0.0 { "higher" } else { "lower" }
                ),
            )]);
        }
        a.roll_stiffness_without = Some((k, names.to_vec()));
    }
    Ok(())
}

/// The mean wheel travel of an axle's two wheels at its metrics' reference step.
fn mean_travel(rows: &[KcRow], a: &AxleMetrics) -> f64 {
    let travel = |w: &str| {
        rows.iter()
            .find(|r| r.step == a.step && r.wheel == w)
            .map_or(0.0, |r| r.quantities.travel_mm)
    };
    0.5 * (travel(&a.wheels[0].wheel) + travel(&a.wheels[1].wheel))
}

pub fn run(args: &Args) -> Exit {
    match kc(args) {
        Ok(e) | Err(e) => e,
    }
}

fn kc(args: &Args) -> Result<Exit, Exit> {
    let loaded = load_model(&args.file)?;
    let fail = |d: Diagnostic| {
        loaded.report(&[d]);
        Exit::Input
    };
    let model = &loaded.model;
    if model.wheels.is_empty() {
        return Err(fail(
            Diagnostic::error(
                "E0806",
                "K&C quantities need a wheel, and the model has none",
            )
            .hint("declare a `wheel` with a centre and a contact marker"),
        ));
    }
    let set: LoadSetId = pick_set_reported(&loaded, Some(&args.sweep))?;
    let problem = Problem::new(model).map_err(|e| fail(e.to_diagnostic(model)))?;
    let ls = &model.load_sets[set.index()];
    let solved = super::input::solve_reporting(&loaded, &problem, set);
    let (eqs, failed) = (&solved.eqs, solved.failed.as_ref());
    let names: Vec<String> = ls.cases.iter().map(|c| c.name.clone()).collect();
    loaded.report(&warning::of_path(model, &names, eqs));
    let states: Vec<_> = eqs.iter().map(|e| &e.state).collect();
    let mut rows: Vec<KcRow> = kc_rows(model, set, &states);
    let mut axles = axle_metrics(model, &rows);
    if !args.without.is_empty() {
        roll_stiffness_without(&loaded, set, &args.without, &rows, &mut axles)?;
    }
    let events = compliance_metrics(model, &rows);
    // A path that drives a steering rack: its travel on every row, and the
    // wheels' steering geometry.
    let rack = driven_rack(model, set);
    let steering = rack.and_then(|r| steering_metrics(model, set, r, &states));
    if let Some(r) = rack {
        let nw = model.wheels.len();
        for (k, st) in states.iter().enumerate() {
            let s = rack_travel(model, st, r);
            for row in &mut rows[k * nw..(k + 1) * nw] {
                row.rack_mm = Some(s);
            }
        }
    }
    let comp = eqs
        .first()
        .map_or_else(Vec::new, |e| wheel_compliances(&problem, model, e));

    // "13 steps", or "9 of 13 steps" when the path stopped.
    let steps = match failed {
        None => format!("{} steps", ls.cases.len()),
        Some(_) => format!("{} of {} steps", eqs.len(), ls.cases.len()),
    };
    if let Some(path) = &args.plot {
        let title = format!("{}: K&C, {} ({steps})", model.name, ls.name);
        // Opposed travel of an axle is drawn against the roll angle.
        // A steering path against the rack's travel.
        // A compliance event against each wheel's own load.
        let kind = if rack.is_some() {
            Sweep::Steer
        } else if axles.iter().any(|a| a.motion == Motion::Opposed) {
            Sweep::Roll
        } else if let Some(e) = events.first() {
            Sweep::Compliance(e.input)
        } else {
            sweep_kind(ls)
        };
        let notes = plot_notes(&axles, &events, steering.as_ref());
        let text = annotated_svg(&title, &rows, kind, &notes).map_err(|e| {
            eprintln!("error: cannot draw the plots: {e}");
            Exit::Io
        })?;
        if emit(Some(path), &text) != Exit::Ok {
            return Err(Exit::Io);
        }
    }
    let text = match args.format {
        OutFormat::Csv => kc_table::csv(&rows),
        OutFormat::Table => {
            let head = format!("model {}, K&C along {}: {steps}\n", model.name, ls.name);
            format!(
                "{head}{}{}{}{}{}{}",
                kc_table::table(&rows),
                failed.map_or(String::new(), |f| f.line()),
                compliance_table(&comp),
                kc_table::axle_table(&axles),
                kc_table::compliance_table(&events),
                steering
                    .as_ref()
                    .map_or(String::new(), kc_table::steering_table)
            )
        }
        OutFormat::Json => {
            let iterations: Vec<usize> = eqs.iter().map(|e| e.iterations).collect();
            solve_json::kc(
                &model.name,
                &ls.name,
                &rows,
                &comp,
                &solve_json::PathMetrics {
                    axles: &axles,
                    events: &events,
                    steering: steering.as_ref(),
                },
                &iterations,
                failed,
            )
        }
    };
    match emit(args.output.as_deref(), &text) {
        // The converged steps are written (and plotted); the failing one was reported.
        Exit::Ok if failed.is_some() => Ok(Exit::Input),
        e => Ok(e),
    }
}
