//! Command-line types (clap) and the subcommands; the only place besides
//! `main.rs` that reads or writes files.
// The command line is where results and messages reach the terminal (the
// library itself must not print: see src/lib.rs).
#![allow(clippy::print_stderr, clippy::print_stdout)]

pub mod check;
pub mod correct;
pub mod diagnose;
pub mod emit;
pub mod fmt;
pub mod identify;
pub mod import;
pub mod input;
pub mod kc;
pub mod locate;
pub mod model_out;
pub mod read;
pub mod solve;
pub mod trim;
pub mod write;

use clap::{Parser, Subcommand, ValueEnum};
use std::path::{Path, PathBuf};

#[derive(Parser)]
#[command(
    name = "axle",
    version,
    about = "A model language and compiler for car suspensions"
)]
pub struct Cli {
    #[command(subcommand)]
    pub cmd: Cmd,
}

#[derive(Copy, Clone, PartialEq, Eq, ValueEnum)]
pub enum DiagFormat {
    Human,
    Json,
}

/// Output of `solve` and `kc`.
#[derive(Copy, Clone, PartialEq, Eq, ValueEnum)]
pub enum OutFormat {
    /// Fixed-width tables for a terminal.
    Table,
    /// One JSON document (`interfaces.md`).
    Json,
    /// The K&C CSV (`interfaces.md`), one row per case and wheel.
    Csv,
}

#[derive(Subcommand)]
pub enum Cmd {
    /// Parse and check axle files; print every diagnostic.
    Check {
        #[arg(required = true)]
        files: Vec<PathBuf>,
        /// `json` prints one JSON document with every diagnostic on stdout.
        #[arg(long, value_enum, default_value = "human")]
        format: DiagFormat,
    },
    /// Joint centres and axes from landmark motion (thesis chapter 3).
    Locate(locate::Args),
    /// Geometric correction at one measured equilibrium (thesis chapter 2).
    Correct(correct::Args),
    /// Language server for editors, on stdin/stdout (see docs/editors.md).
    Lsp,
    /// Rewrite axle files in canonical layout (comments kept).
    Fmt {
        #[arg(required = true)]
        files: Vec<PathBuf>,
        /// Only verify: exit 1 and list the files that would change.
        #[arg(long)]
        check: bool,
    },
    /// Static equilibrium of each load case, in order, each from the previous state.
    Solve {
        file: PathBuf,
        /// The load-case set to solve (default: the file's `default loads`).
        #[arg(long, value_name = "SET")]
        loadcases: Option<String>,
        /// Wheel loads from a CSV file (step, fx, fy, fz [, mx, my, mz, wheel, loadcase]).
        #[arg(long, value_name = "CSV", conflicts_with = "loadcases")]
        loads: Option<PathBuf>,
        #[arg(long, value_enum, default_value = "table")]
        format: OutFormat,
        /// Write the results here instead of stdout.
        #[arg(short, long, value_name = "FILE")]
        output: Option<PathBuf>,
        /// Ride-height trim: the parameter to adjust (`spring.free_length`, `spring.preload`, a `param`).
        #[arg(long, value_name = "PARAM")]
        trim: Option<String>,
        /// The case in which the trim marker returns to its design height (default: the first).
        #[arg(long, value_name = "CASE", requires = "trim")]
        trim_case: Option<String>,
        /// The marker whose height is trimmed, `part.marker` (default: the only wheel's centre).
        #[arg(long, value_name = "PART.MARKER", requires = "trim")]
        trim_marker: Option<String>,
    },
    /// Kinematics and compliance along a load path: table, JSON or CSV, and SVG plots.
    Kc {
        file: PathBuf,
        /// `bump`, `lateral`, `longitudinal` (from `import mcpherson_loads`) or any load set of the model.
        #[arg(long, value_name = "SWEEP")]
        sweep: String,
        /// Write the K&C plots to this SVG file.
        #[arg(long, value_name = "OUT.svg")]
        plot: Option<PathBuf>,
        /// Also give each axle's roll stiffness without these force elements
        /// (bushings, springs, stops, frictions), e.g. the anti-roll bar's
        /// `bar.torsion`.
        #[arg(long, value_name = "ELEMENT", num_args = 1..)]
        without: Vec<String>,
        #[arg(long, value_enum, default_value = "table")]
        format: OutFormat,
        /// Write the results here instead of stdout.
        #[arg(short, long, value_name = "FILE")]
        output: Option<PathBuf>,
    },
    /// Write an ADAMS deck: dataset (adm), command file (acf) or Adams/Car loadcase file (lcf).
    Emit {
        #[arg(value_enum)]
        kind: emit::DeckKind,
        file: PathBuf,
        /// Load set for acf/lcf (default: the file's default set, else its first).
        #[arg(long)]
        loadcases: Option<String>,
        /// lcf vertical columns: the wheel forces, or the wheel-centre heights axle solves for.
        #[arg(long, value_enum, default_value = "force")]
        vertical: emit::VerticalMode,
        /// lcf of a model of more than two wheels: the axle of this wheel
        /// (it and the wheel on the other side nearest its mirror image).
        #[arg(long, value_name = "WHEEL")]
        axle: Option<String>,
        /// Output file (default: stdout).
        #[arg(short, long)]
        output: Option<PathBuf>,
    },
    /// Read an ADAMS deck and write axle source.
    Import {
        #[arg(value_enum)]
        kind: import::ImportKind,
        file: PathBuf,
        /// Output file (default: stdout).
        #[arg(short, long)]
        output: Option<PathBuf>,
    },
    /// Identify stiffnesses (and other unknowns) from measured equilibria
    /// (thesis chapters 4 and 5, and least squares).
    Identify(identify::IdentifyArgs),
    /// What the model gets wrong against K&C rig data, the physical cause,
    /// the extended model and its gain on held-out steps (docs/diagnose.md).
    Diagnose(diagnose::Args),
}

/// Exit status: 0 success, 1 the input is wrong, 2 usage or I/O error (the
/// order is severity: a run's status is the worst of its steps).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Exit {
    Ok = 0,
    Input = 1,
    Io = 2,
}

impl Cmd {
    /// The files the command line names as inputs and as outputs.
    fn files(&self) -> (Vec<&Path>, Vec<&Path>) {
        match self {
            Cmd::Check { .. } | Cmd::Fmt { .. } | Cmd::Lsp => (vec![], vec![]),
            Cmd::Solve {
                file,
                loads,
                output,
                ..
            } => ([vec![file.as_path()], opt(loads)].concat(), opt(output)),
            Cmd::Kc {
                file, plot, output, ..
            } => (vec![file], [opt(plot), opt(output)].concat()),
            Cmd::Emit { file, output, .. } | Cmd::Import { file, output, .. } => {
                (vec![file], opt(output))
            }
            Cmd::Locate(a) => (
                [vec![a.file.as_path()], all(&a.landmarks)].concat(),
                opt(&a.output),
            ),
            Cmd::Correct(a) => (
                [vec![a.file.as_path()], all(&a.landmarks)].concat(),
                opt(&a.output),
            ),
            Cmd::Identify(a) => (
                [
                    vec![a.file.as_path()],
                    all(&a.landmarks),
                    opt(&a.kc),
                    opt(&a.loads),
                ]
                .concat(),
                [opt(&a.output), opt(&a.report)].concat(),
            ),
            Cmd::Diagnose(a) => (
                [vec![a.file.as_path()], all(&a.kc)].concat(),
                [opt(&a.output), opt(&a.report)].concat(),
            ),
        }
    }
}

fn opt(o: &Option<PathBuf>) -> Vec<&Path> {
    o.iter().map(PathBuf::as_path).collect()
}

fn all(v: &[PathBuf]) -> Vec<&Path> {
    v.iter().map(PathBuf::as_path).collect()
}

pub fn run(cli: Cli) -> Exit {
    let (inputs, outputs) = cli.cmd.files();
    if let Err(e) = write::refuse_overlap(&inputs, &outputs) {
        eprintln!("error: {e}");
        return Exit::Io;
    }
    match cli.cmd {
        Cmd::Check { files, format } => check::run(&files, format),
        Cmd::Fmt { files, check } => fmt::run(&files, check),
        Cmd::Lsp => match crate::lsp::run_stdio() {
            0 => Exit::Ok,
            _ => Exit::Input,
        },
        Cmd::Solve {
            file,
            loadcases,
            loads,
            format,
            output,
            trim,
            trim_case,
            trim_marker,
        } => solve::run(&solve::Args {
            file,
            loadcases,
            loads,
            format,
            output,
            trim: trim.map(|param| solve::TrimArgs {
                param,
                case: trim_case,
                marker: trim_marker,
            }),
        }),
        Cmd::Kc {
            file,
            sweep,
            plot,
            without,
            format,
            output,
        } => kc::run(&kc::Args {
            file,
            sweep,
            plot,
            without,
            format,
            output,
        }),
        Cmd::Locate(args) => locate::run(&args),
        Cmd::Correct(args) => correct::run(&args),
        Cmd::Emit {
            kind,
            file,
            loadcases,
            vertical,
            axle,
            output,
        } => emit::run(
            kind,
            &file,
            loadcases.as_deref(),
            vertical,
            axle.as_deref(),
            output.as_ref(),
        ),
        Cmd::Import {
            kind: _,
            file,
            output,
        } => import::run(&file, output.as_ref()),
        Cmd::Identify(args) => identify::run(&args),
        Cmd::Diagnose(args) => diagnose::run(&args),
    }
}

/// Reads a text file (`-` is stdin), printing a failure as a diagnostic;
/// `Err` is the exit status (2 unreadable, 1 not UTF-8).
pub fn read(path: &std::path::Path) -> Result<String, Exit> {
    read::read(path)
}
