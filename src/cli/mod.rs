//! Command-line types (clap) and the subcommands; the only place besides
//! `main.rs` that reads or writes files.

pub mod check;
pub mod fmt;
pub mod identify;

use clap::{Parser, Subcommand, ValueEnum};
use std::path::PathBuf;

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
    /// Rewrite axle files in canonical layout (comments kept).
    Fmt {
        #[arg(required = true)]
        files: Vec<PathBuf>,
        /// Only verify: exit 1 and list the files that would change.
        #[arg(long)]
        check: bool,
    },
    /// Identify stiffnesses (and other unknowns) from measured equilibria
    /// (thesis chapters 4 and 5, and least squares).
    Identify(identify::IdentifyArgs),
}

/// Exit status: 0 success, 1 the input is wrong, 2 usage or I/O error.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Exit {
    Ok = 0,
    Input = 1,
    Io = 2,
}

pub fn run(cli: Cli) -> Exit {
    match cli.cmd {
        Cmd::Check { files, format } => check::run(&files, format),
        Cmd::Fmt { files, check } => fmt::run(&files, check),
        Cmd::Identify(args) => identify::run(&args),
    }
}

/// Reads a file, printing an I/O error.
pub fn read(path: &std::path::Path) -> Option<String> {
    match std::fs::read_to_string(path) {
        Ok(t) => Some(t),
        Err(e) => {
            eprintln!("error: cannot read {}: {e}", path.display());
            None
        }
    }
}
