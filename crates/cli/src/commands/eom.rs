//! `lagrange eom SCENE`: the equations of a scene file or a joint-graph scene, derived
//! symbolically and printed as a textbook prints them ([`lagrange_file::symbolic`]); for a joint
//! graph, also the coordinates it chose and the body poses they give.

use crate::error::CliError;
use crate::output::{outln, print};
use lagrange_file::symbolic::text::{latex, unicode};

/// Arguments of `lagrange eom`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// A scene file (`*.toml`, docs/files.md), or the id of a built-in joint-graph scene.
    file: String,
    /// Print LaTeX (an `align*` environment).
    #[arg(long, conflicts_with_all = ["json", "unicode"])]
    latex: bool,
    /// Print Unicode, as a textbook does (the default).
    #[arg(long, conflicts_with = "json")]
    unicode: bool,
    /// Machine-readable output: every formula in Unicode, LaTeX and the scene-file expression
    /// language.
    #[arg(long)]
    json: bool,
}

/// Print the equations.
pub fn run(args: &Args) -> Result<(), CliError> {
    let equations = if args.file.ends_with(".toml") || std::path::Path::new(&args.file).is_file() {
        lagrange_file::eom(&args.file).map_err(CliError::File)?
    } else {
        let scene = crate::args::scene(&args.file)?;
        lagrange_file::scene_equations(scene, &scene.default_params())
            .map_err(CliError::File)?
            .ok_or_else(|| CliError::NotAFile(args.file.clone()))?
    };
    if args.json {
        return outln!("{}", serde_json::to_string_pretty(&equations)?);
    }
    if args.latex { print(&latex(&equations)) } else { print(&unicode(&args.file, &equations)) }
}
