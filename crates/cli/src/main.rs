//! `lagrange`: the command line of the lagrange workspace.
//!
//! ```text
//! lagrange scenes [--json]
//! lagrange accel <scene> [--param NAME=VALUE]... --q a,b,.. --qdot a,b,.. [--t T] [--json]
//! lagrange simulate <scene> [--param ..] [--q ..] [--qdot ..] --t-end T
//!          [--integrator rk4|adaptive|variational] [--dt H | --tol E] [--every S] [--out FILE.csv]
//! lagrange compare <scene> [--param ..] [--engine cartesian|rapier-impulse|rapier-multibody|
//!          rapier-impulse-f32|rapier-multibody-f32|all] [--dt H] [--substeps K] [--t-end T] [--json]
//! lagrange report [--scene ID]... [--quick] [--out DIR] [--t-end T] [--json]
//! ```
//!
//! Every error is one line on standard error, `error: ` and what is wrong (the flag and the
//! value of a bad argument, the path of a file that cannot be written), typed as one
//! [`error::CliError`]. The exit code says which kind: 2 for a usage error (clap's own — an
//! unknown flag, a missing argument — and a bad argument value: an unknown scene or engine, a
//! malformed or out-of-range `--param`, the wrong number of values in `--q`, a non-finite or
//! non-positive value, a step or tolerance the engine rejects), 1 for a failure at run time
//! (the engine fails on a valid request — a singular mass matrix, a diverging integration —,
//! a file cannot be written, a validation run cannot be set up), 0 on success.

mod args;
mod commands;
mod error;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

/// Exact Lagrangian mechanics of planar mechanisms, checked against closed forms.
#[derive(Parser, Debug)]
#[command(name = "lagrange", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// List every scene with its coordinates and parameters.
    Scenes(commands::scenes::Args),
    /// Generalized accelerations q̈ at one state, to full precision.
    Accel(commands::accel::Args),
    /// Integrate a scene and write t, q, q̇ and the energy as CSV.
    Simulate(commands::simulate::Args),
    /// Run the reduced solver and the maximal-coordinate engines (Cartesian with multipliers,
    /// rapier impulse and multibody joints in f64 and f32) side by side.
    Compare(commands::compare::Args),
    /// The validation report: every scene by every method (reduced RK4, adaptive and variational
    /// integrators, the Cartesian solver, rapier impulse and multibody joints in f64 and f32)
    /// over step and tolerance sweeps, against each scene's reference; writes report.json,
    /// report.md and work-precision plots to --out.
    Report(commands::report::Args),
}

fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(error) => {
            use clap::error::ErrorKind;
            if matches!(
                error.kind(),
                ErrorKind::DisplayHelp
                    | ErrorKind::DisplayVersion
                    | ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand
            ) {
                let _ = error.print();
                return ExitCode::SUCCESS;
            }
            // One line: clap's message joined up to the usage block.
            let rendered = error.render().to_string();
            let message: Vec<&str> = rendered
                .lines()
                .take_while(|l| !l.starts_with("Usage:") && !l.starts_with("For more information"))
                .map(str::trim)
                .filter(|l| !l.is_empty())
                .collect();
            eprintln!("{}", message.join(" "));
            return ExitCode::from(error::USAGE);
        }
    };
    let result = match cli.command {
        Command::Scenes(args) => commands::scenes::run(&args),
        Command::Accel(args) => commands::accel::run(&args),
        Command::Simulate(args) => commands::simulate::run(&args),
        Command::Compare(args) => commands::compare::run(&args),
        Command::Report(args) => commands::report::run(&args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) => {
            eprintln!("error: {error}");
            ExitCode::from(error.exit_code())
        }
    }
}
