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
    /// Print the scene (a built-in id or a file) as a joint-graph scene file, to start one's
    /// own from (scenes that are joint graphs).
    #[arg(long, value_name = "ID|FILE", conflicts_with = "json")]
    export: Option<String>,
}

/// Print the scene list, or one scene as a file.
pub fn run(args: &Args) -> Result<(), CliError> {
    if let Some(id) = &args.export {
        let scene = crate::args::scene(id)?;
        let params = scene.default_params();
        let text = lagrange_file::graph_file(scene, &params, &format!("my_{}", scene.id()))?
            .ok_or_else(|| CliError::NotAGraph(scene.id().to_string()))?;
        return print(&text);
    }
    let scenes = catalogue::entries()?;
    if args.json {
        outln!("{}", serde_json::to_string_pretty(&scenes)?)?;
    } else {
        print(&terminal::catalogue(&scenes))?;
    }
    Ok(())
}
