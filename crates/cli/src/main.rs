//! `lagrange`: the command line of the lagrange workspace.
//!
//! ```text
//! lagrange scenes [--json]
//! lagrange accel <scene> [--param NAME=VALUE]... [--q a,b,..] [--qdot a,b,..] [--hold NAME,..] [--t T] [--check] [--json]
//! lagrange simulate <scene> [--param ..] [--q ..] [--qdot ..] --t-end T
//!          [--integrator rk4|adaptive|dop853|implicit|variational|gauss] [--dt H | --tol E] [--every S] [--out FILE.csv]
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
//! a file cannot be written, a validation run cannot be set up, `accel --check` finds the engine
//! and the closed form apart), 0 on success. `lagrange` without a command is a usage error (the
//! help, on standard error). A repeated `--param`, a step below the resolution of the time
//! (`--dt 1e-320`) and a negative number (`--dt -1e-3`, read as a value, not a flag) are bad
//! argument values too.
//!
//! Standard output goes through one writer ([`output`]): a reader that goes away (`| head -1`)
//! ends the command quietly with exit 0; any other write failure (a full disk) is a one-line
//! error with exit 1.

mod args;
mod commands;
mod error;
mod output;

use clap::{CommandFactory, FromArgMatches, Parser, Subcommand};
use std::io::Write;
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
    /// List every scene with its coordinates, parameters and default initial state.
    Scenes(commands::scenes::Args),
    /// Generalized accelerations q̈ at one state (default: the scene's initial state), to full
    /// precision, beside the scene's closed form.
    Accel(commands::accel::Args),
    /// Integrate a scene and write t, q, q̇ and the energy as CSV.
    Simulate(commands::simulate::Args),
    /// Run the reduced solver and the maximal-coordinate engines (Cartesian with multipliers,
    /// rapier impulse and multibody joints in f64 and f32) side by side.
    Compare(commands::compare::Args),
    /// The validation report: every scene by every method (reduced RK4, adaptive, DOP853 and variational
    /// integrators, the Cartesian solver, rapier impulse and multibody joints in f64 and f32)
    /// over step and tolerance sweeps, against each scene's reference; writes report.json,
    /// report.md and work-precision plots to --out.
    Report(commands::report::Args),
    /// The equations of a scene file: T, V, L, Lagrange's equations, constraints, constants of
    /// the motion, derived symbolically and printed as a textbook prints them.
    Eom(commands::eom::Args),
    /// The equilibrium nearest a configuration and the normal modes about it: natural
    /// frequencies, mode shapes, zero modes, unstable directions.
    Modes(commands::modes::Args),
    /// The motion as one self-contained HTML page: the reduced solution and each maximal engine
    /// drawn over one another, their errors against time beside it; or a normal mode (--mode).
    Animate(commands::animate::Args),
}

/// The command line, with every numeric option accepting a value that starts with `-`
/// (`--dt -1e-3` reaches the range check with its value instead of being read as a flag `-1`;
/// clap's `allow_negative_numbers` does not recognize `-1e-3`).
fn command() -> clap::Command {
    use std::any::TypeId;
    let numeric = [TypeId::of::<f64>(), TypeId::of::<usize>(), TypeId::of::<u64>(), TypeId::of::<u32>()];
    Cli::command().mut_subcommands(|sub| {
        sub.mut_args(|arg| {
            let takes_a_number = numeric.iter().any(|t| arg.get_value_parser().type_id() == *t);
            if takes_a_number && !arg.is_positional() { arg.allow_hyphen_values(true) } else { arg }
        })
    })
}

fn main() -> ExitCode {
    let parsed = command().try_get_matches().and_then(|matches| Cli::from_arg_matches(&matches));
    let cli = match parsed {
        Ok(cli) => cli,
        Err(error) => {
            use clap::error::ErrorKind;
            match error.kind() {
                ErrorKind::DisplayHelp | ErrorKind::DisplayVersion => {
                    let _ = error.print();
                    return ExitCode::SUCCESS;
                }
                // `lagrange` alone: the help, on standard error, as a usage error.
                ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand => {
                    let _ = write!(std::io::stderr(), "{}", error.render());
                    return ExitCode::from(error::USAGE);
                }
                _ => {}
            }
            // One line: clap's message joined up to the usage block.
            let rendered = error.render().to_string();
            let message: Vec<&str> = rendered
                .lines()
                .take_while(|l| !l.starts_with("Usage:") && !l.starts_with("For more information"))
                .map(str::trim)
                .filter(|l| !l.is_empty())
                .collect();
            output::warn(&message.join(" "));
            return ExitCode::from(error::USAGE);
        }
    };
    let result = match cli.command {
        Command::Scenes(args) => commands::scenes::run(&args),
        Command::Accel(args) => commands::accel::run(&args),
        Command::Simulate(args) => commands::simulate::run(&args),
        Command::Compare(args) => commands::compare::run(&args),
        Command::Report(args) => commands::report::run(&args),
        Command::Eom(args) => commands::eom::run(&args),
        Command::Modes(args) => commands::modes::run(&args),
        Command::Animate(args) => commands::animate::run(&args),
    };
    match result.and_then(|()| output::flush()) {
        Ok(()) => ExitCode::SUCCESS,
        // The reader of standard output went away (`| head -1`): it has what it wanted.
        Err(error) if output::is_closed_pipe(&error) => ExitCode::SUCCESS,
        Err(error::CliError::File(file)) => {
            // The file's error drawn on its text, as rustc draws one.
            let _ = write!(std::io::stderr(), "{}", file.render());
            ExitCode::from(error::USAGE)
        }
        Err(error) => {
            output::warn(&format!("error: {error}"));
            ExitCode::from(error.exit_code())
        }
    }
}
