//! `lagrange scenes`: every scene with its coordinates, parameters and default initial state
//! ([`lagrange_validation::catalogue`]).

use crate::error::CliError;
use crate::output::{outln, print};
use lagrange_validation::catalogue;
use lagrange_validation::render::terminal;

/// Arguments of `lagrange scenes`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Machine-readable output.
    #[arg(long)]
    json: bool,
}

/// Print the scene list.
pub fn run(args: &Args) -> Result<(), CliError> {
    let scenes = catalogue::entries()?;
    if args.json {
        outln!("{}", serde_json::to_string_pretty(&scenes)?)?;
    } else {
        print(&terminal::catalogue(&scenes))?;
    }
    Ok(())
}
