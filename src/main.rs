//! The `axle` command: parse arguments, call the library, choose the exit code.

use clap::Parser;

fn main() {
    let cli = axle::cli::Cli::parse();
    let code = axle::cli::run(cli);
    std::process::exit(code as i32);
}
